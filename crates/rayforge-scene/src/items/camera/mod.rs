//! `add: camera`: the cameras of the three books, told apart by their keys (`zoom:` for
//! Fundamentals of Ray Tracing's, `viewport:` for Computer Graphics from Scratch's, otherwise
//! The Ray Tracer Challenge's), and what every one of them accepts (`samples`, `shutter`).
//!
//! Separate from the other items because a camera builds no object: a scene has exactly one,
//! and besides the camera it says how to sample each pixel.

mod pinhole;
mod viewport;
mod zoom;

use crate::error::SceneError;
use crate::source::{Entry, Node, Source};
pub use pinhole::LookAt;
use rayforge::Camera;

/// What `add: camera` gives: the camera and how to sample its pixels.
pub struct CameraItem {
    /// The camera.
    pub camera: Camera,
    /// Samples per pixel (`samples`, default 1).
    pub samples: u32,
    /// A zoom camera's `anti-alias` grid size.
    pub anti_alias: Option<u32>,
    /// The book's camera's `from`, `to` and `up`.
    pub look_at: Option<LookAt>,
}

/// The most camera rays per pixel a scene may ask for.
const MAX_SAMPLES_PER_PIXEL: u64 = 4096;

/// The camera from `add: camera`: the book's (`field-of-view`, `from`, `to`, `up`), Computer
/// Graphics from Scratch's (`viewport`) or Fundamentals of Ray Tracing's (`zoom`).
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<CameraItem, SceneError> {
    if entries.iter().any(|e| e.name == "zoom") {
        let (camera, grid) = zoom::camera(source, entries, item)?;
        // A zoom camera refuses `samples`: its rays per pixel are its anti-aliasing grid.
        let camera = shutter(source, entries, camera)?;
        return Ok(CameraItem {
            camera,
            samples: grid * grid,
            anti_alias: Some(grid),
            look_at: None,
        });
    }
    let (camera, look_at) = if entries.iter().any(|e| e.name == "viewport") {
        (viewport::camera(source, entries, item)?, None)
    } else {
        let (camera, look_at) = pinhole::camera(source, entries, item)?;
        (camera, Some(look_at))
    };
    let samples = samples(source, entries)?;
    let camera = shutter(source, entries, camera)?;
    Ok(CameraItem {
        camera,
        samples,
        anti_alias: None,
        look_at,
    })
}

/// Camera rays per pixel: `samples` (default 1), at most [`MAX_SAMPLES_PER_PIXEL`].
fn samples(source: &Source<'_>, entries: &[Entry<'_, '_>]) -> Result<u32, SceneError> {
    let Some(e) = entries.iter().find(|e| e.name == "samples") else {
        return Ok(1);
    };
    let n = source.integer(e.value, "samples", 1)?;
    if n > MAX_SAMPLES_PER_PIXEL {
        return Err(source.error(
            e.value,
            "samples",
            format!("{n} samples per pixel is more than the limit {MAX_SAMPLES_PER_PIXEL}"),
        ));
    }
    Ok(n as u32)
}

/// The camera with the `shutter: [open, close]` interval, when it has one.
fn shutter(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    camera: Camera,
) -> Result<Camera, SceneError> {
    let Some(shutter) = entries.iter().find(|e| e.name == "shutter") else {
        return Ok(camera);
    };
    let times = source.sequence(shutter.value, "shutter")?;
    let [open, close] = times else {
        return Err(source.error(
            shutter.value,
            "shutter",
            format!(
                "expected [open, close], two instants, found {} items",
                times.len()
            ),
        ));
    };
    let (open, close) = (
        source.number(open, "shutter")?,
        source.number(close, "shutter")?,
    );
    if close < open {
        return Err(source.error(
            shutter.value,
            "shutter",
            "the shutter closes before it opens",
        ));
    }
    Ok(camera.with_shutter(open, close))
}
