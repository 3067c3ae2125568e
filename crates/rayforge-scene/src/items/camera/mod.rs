//! `add: camera`: the cameras of the three books, told apart by their keys (`zoom:` for
//! Fundamentals of Ray Tracing's, `viewport:` for Computer Graphics from Scratch's, otherwise
//! The Ray Tracer Challenge's), and what every one of them accepts (`samples`, `shutter`).
//!
//! Separate from the other items because a camera builds no object: a scene has exactly one,
//! and besides the camera it says how to sample each pixel.

mod pinhole;
mod viewport;
mod zoom;

use crate::error::{SceneError, Span};
use crate::source::{Entry, Node, Source};
pub use pinhole::LookAt;
use rayforge::Camera;

/// What `add: camera` gives: the camera and how to sample its pixels.
pub struct CameraItem {
    /// The camera.
    pub camera: Camera,
    /// Samples per pixel (`samples`, default 1).
    pub samples: u32,
    /// Where `samples` is written, when it is.
    pub samples_at: Option<Span>,
    /// A zoom camera's `anti-alias` grid size.
    pub anti_alias: Option<u32>,
    /// The book's camera's `from`, `to` and `up`.
    pub look_at: Option<LookAt>,
}

/// The most samples per pixel the ray tracer takes, from the camera's `samples` as from
/// `--spp`: as many as its grid of 64 × 64, each sample a tree of rays.
pub const MAX_RAY_SAMPLES: u32 = 4096;

/// The most samples per pixel the path tracer takes (2²⁰), from `samples` as from `--spp`:
/// one path a sample, and its references go far beyond the ray tracer's.
pub const MAX_PATH_SAMPLES: u32 = 1 << 20;

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
        let camera = shutter(source, entries, pinhole::film(source, entries, camera)?)?;
        return Ok(CameraItem {
            camera,
            samples: grid * grid,
            samples_at: None,
            anti_alias: Some(grid),
            look_at: None,
        });
    }
    let (camera, look_at) = if entries.iter().any(|e| e.name == "viewport") {
        // The film keys mean on every camera what they mean on the book's.
        let camera = viewport::camera(source, entries, item)?;
        (pinhole::film(source, entries, camera)?, None)
    } else {
        let (camera, look_at) = pinhole::camera(source, entries, item)?;
        (camera, Some(look_at))
    };
    let (samples, samples_at) = samples(source, entries)?;
    let camera = shutter(source, entries, camera)?;
    Ok(CameraItem {
        camera,
        samples,
        samples_at,
        anti_alias: None,
        look_at,
    })
}

/// Samples per pixel: `samples` (default 1) and where it is written. Here it is held to
/// the most any renderer takes, [`MAX_PATH_SAMPLES`]; which renderer draws the scene is known
/// only once the command line is read too (`--renderer` wins over the scene's `renderer:`),
/// so the ray tracer's lower [`MAX_RAY_SAMPLES`] is checked there, at the same place.
fn samples(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
) -> Result<(u32, Option<Span>), SceneError> {
    let Some(e) = entries.iter().find(|e| e.name == "samples") else {
        return Ok((1, None));
    };
    let n = source.integer(e.value, "samples", 1)?;
    if n > u64::from(MAX_PATH_SAMPLES) {
        return Err(source.error(
            e.value,
            "samples",
            format!(
                "{n} samples per pixel is more than {MAX_PATH_SAMPLES}, the most the path \
                 tracer takes (the ray tracer takes up to {MAX_RAY_SAMPLES})"
            ),
        ));
    }
    Ok((n as u32, Some(source.span(e.value))))
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
