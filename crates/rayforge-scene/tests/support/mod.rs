//! What the scene reader's tests share: a scene path traced into a film.

use rayforge::film::{Film, SharedFilm};
use rayforge::render::path::{render_path, PathJob};
use rayforge_scene::Scene;

/// The film of `scene` path traced at `width` × `height` with `spp` samples per pixel.
pub fn render(scene: &Scene, width: usize, height: usize, spp: u64) -> Film {
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
    render_path(&camera, &scene.world, &job, &film, None, &mut done).unwrap();
    film.into_film()
}
