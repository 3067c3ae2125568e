//! The parallel render loop: rows of the image traced on every core into a [`Film`].
//!
//! Each pixel is a pure function of the scene, so the image is identical for any thread count
//! and any order in which rows finish. That also makes renders resumable: a render can be
//! cancelled between rows ([`RenderOptions::cancel`]) and continued later from the rows it
//! finished ([`RenderOptions::finished`]), giving exactly the image of an uninterrupted run.
//! The film is developed into the image ([`develop`]) once the render is complete.

mod sampler;

pub use sampler::{CameraSample, Sampling};

use crate::camera::Camera;
use crate::canvas::Canvas;
use crate::color::Color;
use crate::film::{develop, Exposure, Film, SharedFilm};
use crate::scene::{LightingModel, Tracer, World, WorldIndex, DEFAULT_MAX_DEPTH};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Called with a finished row's index and pixels.
pub type RowCallback<'a> = dyn Fn(usize, &[Color]) + Sync + 'a;

/// How to render: recursion depth, anti-aliasing, and optional progress, cancellation and
/// resumption.
pub struct RenderOptions<'p> {
    /// How many reflection/refraction bounces to follow.
    pub max_depth: u32,
    /// Adaptive depth control: secondary rays weighing less than this are not traced (see
    /// [`Tracer::set_bailout`]); 0 follows every bounce.
    pub bailout: f64,
    /// Where in each pixel the camera rays go.
    pub sampling: Sampling,
    /// Called with the number of rows just finished (from any thread).
    pub progress: Option<&'p (dyn Fn(usize) + Sync)>,
    /// Computer Graphics from Scratch's subsampling: trace only every other pixel of a row and
    /// fill each pixel between two traced ones with their average when no channel of the two
    /// differs by more than this threshold (trace it otherwise). `None` traces every pixel.
    pub subsample: Option<f64>,
    /// Checked before each row is started: once it is set, no more rows are started, and the
    /// render returns when the rows in progress are done ([`render_rows`] says which).
    pub cancel: Option<&'p AtomicBool>,
    /// Rows already rendered (read back from a checkpoint, say), copied instead of traced. A
    /// partial image of another size than the camera's is ignored.
    pub finished: Option<&'p PartialImage>,
    /// Called with each row as it is finished, its index and its pixels (from any thread), so
    /// a caller can save rows as they come.
    pub on_row: Option<&'p RowCallback<'p>>,
}

impl Default for RenderOptions<'_> {
    fn default() -> Self {
        Self {
            max_depth: DEFAULT_MAX_DEPTH,
            bailout: 0.0,
            sampling: Sampling::Centre,
            progress: None,
            subsample: None,
            cancel: None,
            finished: None,
            on_row: None,
        }
    }
}

/// What a render produced besides the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderStats {
    /// Every ray cast: camera, reflected, refracted and shadow rays.
    pub rays: u64,
    /// Pixels none of whose samples could be traced (the optics model's ties between two
    /// surfaces), repaired from their neighbours.
    pub ambiguous: u64,
}

/// An image whose rows may not all be rendered yet: a film and which of its rows are done.
#[derive(Debug, Clone, PartialEq)]
pub struct PartialImage {
    film: Film,
    done: Vec<bool>,
}

impl PartialImage {
    /// A `width` × `height` image with no rows done.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            film: Film::new(width, height),
            done: vec![false; height],
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.film.width()
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.film.height()
    }

    /// Whether row `y` is done (false past the last row).
    pub fn is_done(&self, y: usize) -> bool {
        self.done.get(y).copied().unwrap_or(false)
    }

    /// Row `y`'s sums of weighted colours, if it is done: the ray tracer gives each pixel one
    /// estimate of weight 1 (see [`render_rows`]), so these are the row's pixels as
    /// [`RenderOptions::on_row`] handed them out.
    pub fn row(&self, y: usize) -> Option<&[Color]> {
        self.is_done(y).then(|| self.film.row_sums(y))
    }

    /// Marks row `y` done with these pixels, each an estimate of weight 1 (replacing whatever
    /// the row held). False (and nothing changes) when `y` is past the last row or `pixels` is
    /// not one row long.
    pub fn set_row(&mut self, y: usize, pixels: &[Color]) -> bool {
        if y >= self.height() || pixels.len() != self.width() {
            return false;
        }
        self.film.replace_row(y, pixels);
        self.done[y] = true;
        true
    }

    /// How many rows are done.
    pub fn finished_rows(&self) -> usize {
        self.done.iter().filter(|&&d| d).count()
    }

    /// Whether every row is done.
    pub fn is_complete(&self) -> bool {
        self.done.iter().all(|&d| d)
    }

    /// The film so far (rows not done have no samples).
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// The film, whether complete or not.
    pub fn into_film(self) -> Film {
        self.film
    }
}

/// How `world`'s films are developed: the optics model exposes automatically (and repairs
/// the pixels its ties left without a sample); the book's other models keep their colours.
pub fn exposure(world: &World) -> Exposure {
    match world.lighting {
        LightingModel::Optics => Exposure::Automatic,
        _ => Exposure::Fixed,
    }
}

/// Renders `world` through `camera` on the current rayon thread pool and develops the film.
///
/// With a [`RenderOptions::cancel`] flag that gets set, the canvas holds only the rows that
/// were finished, not exposed; [`render_rows`] says which.
pub fn render(
    camera: &Camera,
    world: &World,
    options: &RenderOptions<'_>,
) -> (Canvas, RenderStats) {
    let (image, stats) = render_rows(camera, world, options);
    let exposure = if image.is_complete() {
        exposure(world)
    } else {
        Exposure::Fixed
    };
    (develop(image.film(), exposure), stats)
}

/// Renders the rows of the image not already in [`RenderOptions::finished`], until done or
/// cancelled, into a film to develop ([`develop`] with [`exposure`]); the image says which
/// rows are done. The statistics count the rays of this call only.
///
/// Each pixel's samples are averaged as they always were ([`Sampling::pixel`]) and the film
/// receives that estimate as one sample of weight 1 at the pixel (weight 0 when none of its
/// samples was usable, for developing to repair), under the box filter. Splatting each camera
/// sample into the film on its own would add the samples in another order and change the
/// images' last bits; the estimate of weight 1 resolves to exactly today's colour. Each worker
/// adds a finished row to a [`SharedFilm`], one lock per row.
pub fn render_rows(
    camera: &Camera,
    world: &World,
    options: &RenderOptions<'_>,
) -> (PartialImage, RenderStats) {
    let (width, height) = (camera.hsize(), camera.vsize());
    let PartialImage { film, mut done } = match options.finished {
        Some(p) if (p.width(), p.height()) == (width, height) => p.clone(),
        _ => PartialImage::new(width, height),
    };
    let film = SharedFilm::from(film);
    let rays = AtomicU64::new(0);
    // The optics model's pixels with no usable sample.
    let ambiguous_pixels = AtomicU64::new(0);
    let index = WorldIndex::build(world);
    let cancelled = || options.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    (0..height)
        .into_par_iter()
        .zip(done.par_iter_mut())
        .for_each_init(
            || {
                let mut tracer = Tracer::new(world, &index);
                tracer.set_bailout(options.bailout);
                tracer
            },
            |tracer, (y, done)| {
                if *done || cancelled() {
                    return;
                }
                let before = tracer.rays_cast();
                let mut row = vec![Color::BLACK; width];
                let mut ambiguous = Vec::new();
                let mut trace = |x: usize| {
                    let seed = (y * width + x) as u64;
                    tracer.reseed(seed);
                    let mut samples = 0;
                    let color = options.sampling.pixel(x, y, seed, |sample| {
                        samples += 1;
                        tracer.color_at(&camera.ray_for_sample(&sample), options.max_depth)
                    });
                    // Ambiguous samples are black: average the others, or leave the pixel to
                    // its neighbours when there are none.
                    match tracer.ambiguous_samples() {
                        0 => color,
                        bad if bad < samples => color * (samples as f64 / (samples - bad) as f64),
                        _ => {
                            ambiguous.push(x);
                            Color::BLACK
                        }
                    }
                };
                match options.subsample {
                    None => {
                        for (x, pixel) in row.iter_mut().enumerate() {
                            *pixel = trace(x);
                        }
                    }
                    Some(threshold) => subsample_row(&mut row, threshold, trace),
                }
                let mut part = Film::new(width, 1);
                for (x, &pixel) in row.iter().enumerate() {
                    let weight = if ambiguous.contains(&x) { 0.0 } else { 1.0 };
                    part.add_pixel(x, 0, pixel, weight);
                }
                part.note_brightest(tracer.brightest());
                // The part is this film's width and one row: adding it cannot be refused.
                *done = film.add(y, &part).is_ok();
                rays.fetch_add(tracer.rays_cast() - before, Ordering::Relaxed);
                ambiguous_pixels.fetch_add(ambiguous.len() as u64, Ordering::Relaxed);
                if let Some(on_row) = options.on_row {
                    on_row(y, &row);
                }
                if let Some(progress) = options.progress {
                    progress(1);
                }
            },
        );
    let image = PartialImage {
        film: film.into_film(),
        done,
    };
    let stats = RenderStats {
        rays: rays.into_inner(),
        ambiguous: ambiguous_pixels.into_inner(),
    };
    (image, stats)
}

/// Traces pixel (`x`, `y`) exactly as the render would (the same samples, seeded the same way)
/// and records every ray each sample casts: what `--trace-pixel` prints. Returns the pixel's
/// colour (before the optics model's exposure) and the record, one line per event.
pub fn trace_pixel(
    camera: &Camera,
    world: &World,
    options: &RenderOptions<'_>,
    x: usize,
    y: usize,
) -> (Color, Vec<String>) {
    let index = WorldIndex::build(world);
    let mut tracer = Tracer::new(world, &index);
    tracer.set_bailout(options.bailout);
    let seed = (y * camera.hsize() + x) as u64;
    tracer.reseed(seed);
    let mut lines = Vec::new();
    let mut samples = 0;
    let color = options.sampling.pixel(x, y, seed, |sample| {
        samples += 1;
        lines.push(format!(
            "sample {samples}: image point ({:.4}, {:.4}), lens ({:.3}, {:.3}), time {:.3}",
            sample.x, sample.y, sample.lens_u, sample.lens_v, sample.time
        ));
        tracer.start_log();
        let color = tracer.color_at(&camera.ray_for_sample(&sample), options.max_depth);
        lines.extend(tracer.take_log().into_iter().map(|l| format!("  {l}")));
        color
    });
    (color, lines)
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
