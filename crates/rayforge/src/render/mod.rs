//! The parallel render loop: rows of the image traced on every core into a [`Canvas`].
//!
//! Each pixel is a pure function of the scene, so the image is identical for any thread count
//! and any order in which rows finish.

mod sampler;

pub use sampler::{CameraSample, Sampling};

use crate::scene::WorldIndex;
use crate::{Camera, Canvas, Color, Tracer, World, DEFAULT_MAX_DEPTH};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// How to render: recursion depth, anti-aliasing and an optional progress callback.
pub struct RenderOptions<'p> {
    /// How many reflection/refraction bounces to follow.
    pub max_depth: u32,
    /// Where in each pixel the camera rays go.
    pub sampling: Sampling,
    /// Called with the number of rows just finished (from any thread).
    pub progress: Option<&'p (dyn Fn(usize) + Sync)>,
    /// Computer Graphics from Scratch's subsampling: trace only every other pixel of a row and
    /// fill each pixel between two traced ones with their average when no channel of the two
    /// differs by more than this threshold (trace it otherwise). `None` traces every pixel.
    pub subsample: Option<f64>,
}

impl Default for RenderOptions<'_> {
    fn default() -> Self {
        Self {
            max_depth: DEFAULT_MAX_DEPTH,
            sampling: Sampling::Centre,
            progress: None,
            subsample: None,
        }
    }
}

/// What a render produced besides the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderStats {
    /// Every ray cast: camera, reflected, refracted and shadow rays.
    pub rays: u64,
}

/// Renders `world` through `camera` on the current rayon thread pool.
pub fn render(
    camera: &Camera,
    world: &World,
    options: &RenderOptions<'_>,
) -> (Canvas, RenderStats) {
    let (width, height) = (camera.hsize(), camera.vsize());
    let mut canvas = Canvas::new(width, height);
    let rays = AtomicU64::new(0);
    let index = WorldIndex::build(world);
    canvas
        .pixels_mut()
        .par_chunks_mut(width.max(1))
        .enumerate()
        .for_each_init(
            || Tracer::new(world, &index),
            |tracer, (y, row)| {
                let before = tracer.rays_cast();
                let mut trace = |x: usize| {
                    let seed = (y * width + x) as u64;
                    tracer.reseed(seed);
                    options.sampling.pixel(x, y, seed, |sample| {
                        tracer.color_at(&camera.ray_for_sample(&sample), options.max_depth)
                    })
                };
                match options.subsample {
                    None => {
                        for (x, pixel) in row.iter_mut().enumerate() {
                            *pixel = trace(x);
                        }
                    }
                    Some(threshold) => subsample_row(row, threshold, trace),
                }
                rays.fetch_add(tracer.rays_cast() - before, Ordering::Relaxed);
                if let Some(progress) = options.progress {
                    progress(1);
                }
            },
        );
    let stats = RenderStats {
        rays: rays.into_inner(),
    };
    (canvas, stats)
}

/// Fills a row by tracing its even pixels (and the last), then each odd pixel from its two
/// neighbours when they agree within `threshold`, by tracing it when they do not.
fn subsample_row(row: &mut [Color], threshold: f64, mut trace: impl FnMut(usize) -> Color) {
    let last = row.len().saturating_sub(1);
    for x in (0..row.len()).filter(|&x| x % 2 == 0 || x == last) {
        row[x] = trace(x);
    }
    for x in (1..last).step_by(2) {
        let (left, right) = (row[x - 1], row[x + 1]);
        let d = left - right;
        let agree = d.red.abs().max(d.green.abs()).max(d.blue.abs()) <= threshold;
        row[x] = if agree {
            (left + right) * 0.5
        } else {
            trace(x)
        };
    }
}

impl Camera {
    /// The book's `render(camera, world)`, with the default recursion depth.
    pub fn render(&self, world: &World) -> Canvas {
        render(self, world, &RenderOptions::default()).0
    }
}

/// The colour of one pixel (for tests and tools that need a single sample).
pub fn render_pixel(camera: &Camera, world: &World, x: usize, y: usize, max_depth: u32) -> Color {
    let index = WorldIndex::build(world);
    Tracer::new(world, &index).color_at(&camera.ray_for_pixel(x, y), max_depth)
}
