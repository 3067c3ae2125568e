//! What the scene reader's tests share: a scene path traced into a film, and the first lines
//! of a path-traced test scene. Each test file uses some of them.
#![allow(dead_code)]

use rayforge::film::{Film, SharedFilm};
use rayforge::render::path::{render_path, PathJob, PathStats};
use rayforge::Camera;
use rayforge_scene::Scene;
use std::ops::Range;

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
    let job = PathJob {
        options: scene.path.unwrap_or_default(),
        samples,
        plan: None,
        progress: None,
        cancel: None,
        on_row: None,
        roulette: None,
    };
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
