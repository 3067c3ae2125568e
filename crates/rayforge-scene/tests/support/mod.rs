//! What the scene reader's tests share: a scene path traced into a film, the first lines of a
//! path-traced test scene, and for the key tests a camera to load items after and the check of
//! a located error. Each test file uses some of them.
#![allow(dead_code)]

use rayforge::film::{Film, SharedFilm};
use rayforge::render::path::{render_path, PathJob, PathStats};
use rayforge::Camera;
use rayforge_scene::{load_str, Scene, SceneError};
use std::ops::Range;
use std::path::Path;

/// The film of `scene` path traced at `width` × `height` with `spp` samples per pixel, every
/// sample of it finite: the path tracer leaves a NaN or infinite sample out of its pixel (so
/// the film's pixels are finite whatever happens) and counts it, and here that count must be
/// nought.
pub fn render(scene: &Scene, width: usize, height: usize, spp: u64) -> Film {
    let (film, stats) = render_counted(scene, width, height, spp);
    assert_eq!(
        stats.discarded, 0,
        "{} of {} samples were not finite and were left out",
        stats.discarded, stats.samples
    );
    film
}

/// [`render`] without the check: the film and the render's statistics.
pub fn render_counted(scene: &Scene, width: usize, height: usize, spp: u64) -> (Film, PathStats) {
    render_samples(scene, &scene.camera.resized(width, height), 0..spp)
}

/// The film of `scene` path traced through `camera` (at its size) with the samples `samples`
/// of each pixel, and the render's statistics; no check.
pub fn render_samples(scene: &Scene, camera: &Camera, samples: Range<u64>) -> (Film, PathStats) {
    let (width, height) = (camera.hsize(), camera.vsize());
    let job = PathJob::new(scene.path.unwrap_or_default(), samples);
    let film = SharedFilm::from(Film::with_filter(width, height, job.options.filter).unwrap());
    let mut done = vec![false; height];
    let stats = render_path(camera, &scene.world, &job, &film, None, &mut done).unwrap();
    (film.into_film(), stats)
}

/// The first lines of a path-traced test scene: a camera of `width` × `height` pixels and
/// `field_of_view` (radians), its eye at `from` looking at `to` with +y up, and a `world:`
/// asking for the path tracer, to which the world's other keys (indented by four spaces) and
/// the items follow.
pub fn path_scene_head(
    width: usize,
    height: usize,
    field_of_view: f64,
    from: [f64; 3],
    to: [f64; 3],
) -> String {
    format!(
        "- add: camera\n  width: {width}\n  height: {height}\n  field-of-view: {field_of_view}\n  \
         from: {from:?}\n  to: {to:?}\n  up: [0, 1, 0]\n- world:\n    renderer: path\n"
    )
}

/// A camera of 10 × 10 pixels in seven lines: what a key test adds after it begins on line 8.
pub const CAMERA: &str = "- add: camera
  width: 10
  height: 10
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

/// `body` loaded as `scene.yml` after [`CAMERA`].
pub fn load_after_camera(body: &str) -> Result<Scene, SceneError> {
    load_str(&format!("{CAMERA}{body}"), Path::new("scene.yml"))
}

/// Checks that `result` is an error at `line`:`column` of `scene.yml` naming `key`, whose
/// message holds `words`, and gives the error.
#[track_caller]
pub fn assert_located(
    result: Result<impl std::fmt::Debug, SceneError>,
    line: usize,
    column: usize,
    key: &str,
    words: &str,
) -> SceneError {
    let e = result.expect_err("the scene must be rejected");
    let span = e.span.unwrap_or_else(|| panic!("no position in: {e}"));
    assert_eq!((span.line, span.column), (line, column), "{e}");
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert!(e.message.contains(words), "{e}");
    assert!(
        e.to_string()
            .starts_with(&format!("scene.yml:{line}:{column}: ")),
        "{e}"
    );
    e
}

/// Writes a PFM image `width × height` to `path` whose texel in `column` and `row` (from the
/// top) is `texel(column, row)`.
pub fn write_pfm(
    path: &std::path::Path,
    width: usize,
    height: usize,
    texel: impl Fn(usize, usize) -> [f32; 3],
) {
    let mut bytes = format!("PF\n{width} {height}\n-1\n").into_bytes();
    // PFM stores rows from the bottom.
    for row in (0..height).rev() {
        for column in 0..width {
            for v in texel(column, row) {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    std::fs::write(path, bytes).unwrap();
}
