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

use crate::items::{finish_camera, CameraItem};
use crate::source::{check_keys, Entry, Node, Source};
use crate::SceneError;
use rayforge::math::scaling;
use rayforge::Camera;

/// The largest `anti-alias` accepted (its square is the rays per pixel).
const MAX_ANTI_ALIAS: u64 = 64;

/// The zoom camera of an `add: camera` item that has `zoom:`.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<CameraItem, SceneError> {
    check_keys(
        source,
        entries,
        "a zoom camera",
        &["add", "width", "height", "zoom", "anti-alias", "shutter"],
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
    let anti_alias = match get("anti-alias") {
        Some(n) => source.integer(n, "anti-alias", 1)?.min(MAX_ANTI_ALIAS + 1),
        None => 1,
    };
    if anti_alias > MAX_ANTI_ALIAS {
        let node = get("anti-alias").unwrap_or(item);
        return Err(source.error(
            node,
            "anti-alias",
            format!(
                "at most {MAX_ANTI_ALIAS} (an {MAX_ANTI_ALIAS} × {MAX_ANTI_ALIAS} grid per pixel)"
            ),
        ));
    }
    // The field of view spans the longer side: half of it is (longer/2) / (zoom · shorter)
    // at distance 1.
    let (longer, shorter) = (width.max(height) as f64, width.min(height) as f64);
    let field_of_view = 2.0 * (longer / (2.0 * zoom * shorter)).atan();
    let camera = Camera::new(width as usize, height as usize, field_of_view)
        .with_transform(scaling(-1.0, 1.0, 1.0));
    let (camera, _) = finish_camera(source, entries, camera)?;
    let n = anti_alias as u32;
    Ok(CameraItem {
        camera,
        samples: n * n,
        anti_alias: Some(n),
    })
}
