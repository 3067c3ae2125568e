//! What the path tracer's statistical tests share: a render of a world through a camera into
//! a film (all its samples or a range of them), every row of it done. Included by `mod path_support;`.

use rayforge::film::{Film, SharedFilm};
use rayforge::options::PathOptions;
use rayforge::render::path::{render_path, PathJob, PathStats};
use rayforge::{Camera, World};
use std::ops::Range;

/// Renders `world` through `camera` at `spp` samples per pixel with `options`: the film and
/// the render's statistics.
pub fn render_counted(
    world: &World,
    camera: &Camera,
    spp: u64,
    options: PathOptions,
) -> (Film, PathStats) {
    render_samples(world, camera, 0..spp, options)
}

/// Renders the samples `samples` of every pixel (by index) of `world` through `camera` with
/// `options`: the film and the statistics. Disjoint ranges are independent estimates of the
/// same image.
pub fn render_samples(
    world: &World,
    camera: &Camera,
    samples: Range<u64>,
    options: PathOptions,
) -> (Film, PathStats) {
    let job = PathJob::new(options, samples);
    let film = SharedFilm::from(Film::new(camera.hsize(), camera.vsize()));
    let mut done = vec![false; camera.vsize()];
    let stats = render_path(camera, world, &job, &film, None, &mut done).unwrap();
    assert!(done.iter().all(|&d| d), "every row is rendered");
    (film.into_film(), stats)
}
