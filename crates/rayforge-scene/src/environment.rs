//! The `world:` item's `environment:`: an equirectangular sky the path tracer is lit by.
//!
//! ```yaml
//! - world:
//!     renderer: path
//!     environment:
//!       file: sky.exr          # .exr, .hdr or .pfm, in the scene file's folder
//!       scale: 1               # multiplies every texel (default 1)
//!       rotate-y-degrees: 90   # turns the sky about the vertical axis (default 0)
//! ```
//!
//! Texel (i, j) of a W × H map holds the radiance arriving from the direction
//! (sin φ sin θ, cos θ, −cos φ sin θ) with φ = 2π (i + ½) / W and θ = π j / (H − 1): row 0 is
//! the zenith, the last row the nadir, interpolated bilinearly between texel centres.

use crate::assets::Assets;
use crate::error::SceneError;
use crate::source::{check_keys, required, Node, Source};
use rayforge::shading::EnvironmentMap;
use std::sync::Arc;

/// The map an `environment:` mapping names, read and checked.
pub fn environment(
    source: &Source<'_>,
    node: &Node<'_>,
    assets: &mut Assets,
) -> Result<Arc<EnvironmentMap>, SceneError> {
    let entries = source.entries(node, "environment")?;
    check_keys(
        source,
        &entries,
        "`environment`",
        &["file", "scale", "rotate-y-degrees"],
    )?;
    let file_node = required(source, &entries, node, "file", "an environment")?;
    let name = source.string(file_node, "file")?;
    let path = assets.resolve(name);
    let image = assets
        .environment_image(&path)
        .map_err(|e| source.error(file_node, "file", e))?;
    let mut scale = 1.0;
    let mut turn = 0.0;
    for e in &entries {
        match e.name {
            "scale" => {
                scale = source.number(e.value, "scale")?;
                if !(scale.is_finite() && scale >= 0.0) {
                    return Err(source.error(
                        e.value,
                        "scale",
                        format!("an environment's scale is a number of at least 0, found {scale}"),
                    ));
                }
            }
            "rotate-y-degrees" => turn = source.number(e.value, "rotate-y-degrees")?,
            _ => {}
        }
    }
    let map = EnvironmentMap::new(image.width, image.height, image.texels, scale)
        .map_err(|e| source.error(file_node, "file", format!("`{name}`: {e}")))?;
    // The map turned by `turn` about +y: world directions go into it turned back.
    let to_local = glam::DMat3::from_rotation_y(-turn.to_radians());
    let map = map
        .with_transform(to_local)
        .map_err(|e| source.error(node, "rotate-y-degrees", e.to_string()))?;
    Ok(Arc::new(map))
}
