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
        &["lighting", "background", "max-depth"],
    )?;
    let mut max_depth = None;
    for e in &entries {
        match e.name {
            "lighting" => {
                world.lighting = match source.string(e.value, "lighting")? {
                    "phong" => LightingModel::Phong,
                    "flat" => LightingModel::Flat,
                    "cgfs" => LightingModel::Cgfs,
                    other => {
                        return Err(source.error(
                            e.value,
                            "lighting",
                            format!(
                                "unknown lighting model `{other}`; expected phong, flat or cgfs"
                            ),
                        ))
                    }
                }
            }
            "background" => world.background = color(source, e.value, "background")?,
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
