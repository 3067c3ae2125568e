//! The `world:` item: settings of the whole scene.
//!
//! ```yaml
//! - world:
//!     lighting: cgfs          # phong (the default), flat or cgfs
//!     background: [0, 0, 0]   # the colour of rays that hit nothing (default black)
//!     max-depth: 3            # reflection and refraction bounces (default 5; `--max-depth` wins)
//!     renderer: raster        # ray (the default) or raster; then optionally `shading`,
//!                             # `sphere-divisions`, `wireframe` and `texture-filter`
//! ```

use crate::error::SceneError;
use crate::material::color;
use crate::source::{check_keys, Entry, Node, Source};
use rayforge::options::{RasterOptions, Shading, TextureFilter};
use rayforge::{LightingModel, World};

/// The deepest recursion a scene may ask for (as `--max-depth` allows).
pub const MAX_DEPTH: u64 = 64;

/// What a `world:` item says besides what goes into the world.
#[derive(Debug, Default)]
pub struct Settings {
    /// `max-depth`, if given.
    pub max_depth: Option<u32>,
    /// The rasterizer's options, when `renderer: raster`.
    pub raster: Option<RasterOptions>,
}

/// The keys that only the rasterizer reads.
const RASTER_KEYS: &[&str] = &["shading", "sphere-divisions", "wireframe", "texture-filter"];

/// Applies a `world:` mapping to `world`; returns the rest of what it says.
pub fn apply(
    source: &Source<'_>,
    node: &Node<'_>,
    world: &mut World,
) -> Result<Settings, SceneError> {
    let entries = source.entries(node, "world")?;
    let raster = match entries.iter().find(|e| e.name == "renderer") {
        Some(e) => match source.string(e.value, "renderer")? {
            "ray" => None,
            "raster" => Some(raster_options(source, &entries)?),
            other => {
                return Err(source.error(
                    e.value,
                    "renderer",
                    format!("unknown renderer `{other}`; expected ray or raster"),
                ))
            }
        },
        None => None,
    };
    if raster.is_none() {
        if let Some(e) = entries.iter().find(|e| RASTER_KEYS.contains(&e.name)) {
            return Err(source.error(
                e.key,
                e.name,
                format!(
                    "`{}` applies to the rasterizer: add `renderer: raster`",
                    e.name
                ),
            ));
        }
    }
    check_keys(
        source,
        &entries,
        "`world`",
        &[
            "lighting",
            "background",
            "max-depth",
            "ambient-index",
            "renderer",
            "shading",
            "sphere-divisions",
            "wireframe",
            "texture-filter",
        ],
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
            "max-depth" => {
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
            _ => {} // the renderer's keys, read above
        }
    }
    Ok(Settings { max_depth, raster })
}

/// The rasterizer's options from `shading`, `sphere-divisions`, `wireframe`, `texture-filter`.
fn raster_options(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
) -> Result<RasterOptions, SceneError> {
    let mut options = RasterOptions::default();
    for e in entries {
        match e.name {
            "shading" => {
                options.shading = match source.string(e.value, "shading")? {
                    "flat" => Shading::Flat,
                    "gouraud" => Shading::Gouraud,
                    "phong" => Shading::Phong,
                    other => {
                        return Err(source.error(
                            e.value,
                            "shading",
                            format!("unknown shading `{other}`; expected flat, gouraud or phong"),
                        ))
                    }
                }
            }
            "sphere-divisions" => {
                let n = source.integer(e.value, "sphere-divisions", 3)?;
                if n > 4096 {
                    return Err(source.error(e.value, "sphere-divisions", "at most 4096"));
                }
                options.sphere_divisions = n as u32;
            }
            "wireframe" => options.wireframe = source.boolean(e.value, "wireframe")?,
            "texture-filter" => {
                options.filter = match source.string(e.value, "texture-filter")? {
                    "nearest" => TextureFilter::Nearest,
                    "bilinear" => TextureFilter::Bilinear,
                    "trilinear" => TextureFilter::Trilinear,
                    other => {
                        return Err(source.error(
                            e.value,
                            "texture-filter",
                            format!(
                        "unknown texture filter `{other}`; expected nearest, bilinear or trilinear"
                    ),
                        ))
                    }
                }
            }
            _ => {}
        }
    }
    Ok(options)
}
