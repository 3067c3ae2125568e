//! The `world:` item: settings of the whole scene.
//!
//! ```yaml
//! - world:
//!     lighting: cgfs          # phong (the default), flat or cgfs
//!     background: [0, 0, 0]   # the colour of rays that hit nothing (default black)
//!     max-depth: 3            # reflection and refraction bounces (default 5; `--max-depth` wins)
//! ```

use crate::material::color;
use crate::source::{check_keys, Node, Source};
use crate::SceneError;
use rayforge::{LightingModel, World};

/// The deepest recursion a scene may ask for (as `--max-depth` allows).
pub const MAX_DEPTH: u64 = 64;

/// Applies a `world:` mapping to `world`; returns its `max-depth`, if given.
pub fn apply(
    source: &Source<'_>,
    node: &Node<'_>,
    world: &mut World,
) -> Result<Option<u32>, SceneError> {
    let entries = source.entries(node, "world")?;
    check_keys(
        source,
        &entries,
        "`world`",
        &["lighting", "background", "max-depth", "ambient-index"],
    )?;
    let mut max_depth = None;
    for e in &entries {
        match e.name {
            "lighting" => {
                world.lighting = match source.string(e.value, "lighting")? {
                    "phong" => LightingModel::Phong,
                    "flat" => LightingModel::Flat,
                    "cgfs" => LightingModel::Cgfs,
                    "optics" => LightingModel::Optics,
                    other => {
                        return Err(source.error(
                            e.value,
                            "lighting",
                            format!(
                        "unknown lighting model `{other}`; expected phong, flat, cgfs or optics"
                    ),
                        ))
                    }
                }
            }
            "background" => world.background = color(source, e.value, "background")?,
            "ambient-index" => {
                let index = source.number(e.value, "ambient-index")?;
                if !(1.0..=9.0).contains(&index) {
                    return Err(source.error(
                        e.value,
                        "ambient-index",
                        "a refractive index lies between 1 and 9",
                    ));
                }
                world.ambient_index = index;
            }
            _ => {
                let depth = source.integer(e.value, "max-depth", 0)?;
                if depth > MAX_DEPTH {
                    return Err(source.error(
                        e.value,
                        "max-depth",
                        format!("{depth} bounces is more than the limit {MAX_DEPTH}"),
                    ));
                }
                max_depth = Some(depth as u32);
            }
        }
    }
    Ok(max_depth)
}
