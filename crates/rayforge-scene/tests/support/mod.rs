//! What the scene reader's tests share: a scene path traced into a film.

use rayforge::film::{Film, SharedFilm};
use rayforge::render::path::{render_path, PathJob, PathStats};
use rayforge_scene::Scene;

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
    let camera = scene.camera.resized(width, height);
    let job = PathJob {
        options: scene.path.unwrap_or_default(),
        samples: 0..spp,
        plan: None,
        progress: None,
        cancel: None,
        on_row: None,
        roulette: None,
    };
    let film = SharedFilm::from(Film::with_filter(width, height, job.options.filter).unwrap());
    let mut done = vec![false; height];
    let stats = render_path(&camera, &scene.world, &job, &film, None, &mut done).unwrap();
    (film.into_film(), stats)
}
