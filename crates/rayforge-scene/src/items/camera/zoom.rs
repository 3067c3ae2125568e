//! Fundamentals of Ray Tracing's camera in a scene file: `add: camera` with `zoom:`.
//!
//! ```yaml
//! - add: camera
//!   width: 300
//!   height: 300
//!   zoom: 3.0          # magnification: the view's half-width at distance d is d·W/(2·zoom·min(W, H))
//!   anti-alias: 2      # an N × N grid of rays per pixel, from its corner, averaged (default 1)
//! ```
//!
//! The eye is at the origin looking down -z with +y up and +x to the right (the book's
//! right-handed frame). This crate's cameras see +x on the left of the image when they look
//! down -z, so the camera is this crate's with a mirror in x, and the book's scenes need no
//! change of coordinates.
//!
//! Separate from the other books' cameras: it is sized by magnification rather than a field of
//! view, mirrored, and sampled on a grid instead of by `samples`.

use crate::error::SceneError;
use crate::source::{check_keys, Entry, Node, Source};
use rayforge::math::scaling;
use rayforge::Camera;

/// The largest `anti-alias` accepted (its square is the rays per pixel).
const MAX_ANTI_ALIAS: u64 = 64;

/// The zoom camera of an `add: camera` item that has `zoom:`, and its `anti-alias` grid size.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<(Camera, u32), SceneError> {
    check_keys(
        source,
        entries,
        "a zoom camera",
        &[
            "add",
            "width",
            "height",
            "zoom",
            "anti-alias",
            "shutter",
            "iso",
            "exposure-time",
            "white-balance",
            "max-component",
        ],
    )?;
    let get = |k: &str| entries.iter().find(|e| e.name == k).map(|e| e.value);
    let required =
        |k: &str| get(k).ok_or_else(|| source.error(item, k, format!("the camera needs `{k}:`")));
    let width = source.integer(required("width")?, "width", 1)?;
    let height = source.integer(required("height")?, "height", 1)?;
    let zoom_node = required("zoom")?;
    let zoom = source.number(zoom_node, "zoom")?;
    if zoom <= 0.0 {
        return Err(source.error(zoom_node, "zoom", "the zoom must be positive"));
    }
    let anti_alias = anti_alias(source, get("anti-alias"))?;
    // The field of view spans the longer side: half of it is (longer/2) / (zoom · shorter)
    // at distance 1.
    let (longer, shorter) = (width.max(height) as f64, width.min(height) as f64);
    let field_of_view = 2.0 * (longer / (2.0 * zoom * shorter)).atan();
    let camera = Camera::new(width as usize, height as usize, field_of_view)
        .with_transform(scaling(-1.0, 1.0, 1.0));
    Ok((camera, anti_alias))
}

/// `anti-alias` (default 1), at most [`MAX_ANTI_ALIAS`].
fn anti_alias(source: &Source<'_>, node: Option<&Node<'_>>) -> Result<u32, SceneError> {
    let Some(node) = node else {
        return Ok(1);
    };
    let grid = source.integer(node, "anti-alias", 1)?;
    if grid > MAX_ANTI_ALIAS {
        return Err(source.error(
            node,
            "anti-alias",
            format!(
                "at most {MAX_ANTI_ALIAS} (an {MAX_ANTI_ALIAS} × {MAX_ANTI_ALIAS} grid per pixel)"
            ),
        ));
    }
    Ok(grid as u32)
}
