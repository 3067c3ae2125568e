//! The parallel render loop: rows of the image traced on every core into a [`Film`].
//!
//! Each pixel is a pure function of the scene, so the image is identical for any thread count
//! and any order in which rows finish. That also makes renders resumable: a render can be
//! cancelled between rows ([`RenderOptions::cancel`]) and continued later from the rows it
//! finished ([`RenderOptions::finished`]), giving exactly the image of an uninterrupted run.
//! The film is developed into the image ([`develop`]) once the render is complete.
//!
//! What colour a camera ray brings back is the business of the [`integrator`] chosen from the
//! world's lighting model, once per render; what happens on the way can be watched through an
//! [`observer`] (what [`trace_pixel`] does).

pub mod integrator;
pub mod observer;
pub mod path;
mod sampler;

pub use integrator::{Integrator, Stopped, TraceState, DEFAULT_MAX_RAYS_PER_SAMPLE};
pub use observer::{NoTrace, TraceLog, TraceObserver};
pub use sampler::Sampling;

use crate::camera::{Camera, CameraRay};
use crate::canvas::Canvas;
use crate::color::Color;
use crate::film::{develop, Exposure, Film, FilmError, SharedFilm};
use crate::math::Ray;
use crate::scene::{World, WorldIndex};
use integrator::{dispatch, IntegratorJob};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The recursion limit the book's tests use (and a sensible default for renders).
pub const DEFAULT_MAX_DEPTH: u32 = 5;

/// Called with a finished row's index and pixels.
pub type RowCallback<'a> = dyn Fn(usize, &[Color]) + Sync + 'a;

/// How to render: recursion depth, anti-aliasing, and optional progress, cancellation and
/// resumption.
pub struct RenderOptions<'p> {
    /// How many reflection/refraction bounces to follow.
    pub max_depth: u32,
    /// Adaptive depth control: secondary rays weighing less than this are not traced (see
    /// [`TraceState::set_bailout`]); 0 follows every bounce.
    pub bailout: f64,
    /// Where in each pixel the camera rays go.
    pub sampling: Sampling,
    /// Called with the number of rows just finished (from any thread).
    pub progress: Option<&'p (dyn Fn(usize) + Sync)>,
    /// Computer Graphics from Scratch's subsampling: trace only every other pixel of a row and
    /// fill each pixel between two traced ones with their average when no channel of the two
    /// differs by more than this threshold (trace it otherwise). `None` traces every pixel.
    pub subsample: Option<f64>,
    /// Checked before each row is started and before every ray inside a pixel's work:
    /// once it is set, no more rows are started, the rows in progress are abandoned, and the
    /// render returns at once ([`render_rows`] says which rows are done).
    pub cancel: Option<&'p AtomicBool>,
    /// The most rays one camera ray may lead to (see [`TraceState::set_ray_budget`]); a
    /// sample past it stops the render, and [`RenderStats::over_budget`] names its pixel.
    pub max_rays_per_sample: u64,
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
            max_rays_per_sample: DEFAULT_MAX_RAYS_PER_SAMPLE,
            finished: None,
            on_row: None,
        }
    }
}

/// What a render produced besides the image.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Every ray cast: camera, reflected, refracted and shadow rays.
    pub rays: u64,
    /// Pixels none of whose samples could be traced (the optics model's ties between two
    /// surfaces), repaired from their neighbours.
    pub ambiguous: u64,
    /// A pixel (x, y) one of whose camera rays led to more than
    /// [`RenderOptions::max_rays_per_sample`] rays: the render stopped there, unfinished.
    pub over_budget: Option<(usize, usize)>,
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

/// How `world`'s films are developed: an integrator with automatic exposure (the optics
/// model's) has its film exposed by the brightest sample, and the pixels its ties left without
/// a sample repaired; the book's other models keep their colours.
pub fn exposure(world: &World) -> Exposure {
    /// Asks the world's integrator whether its images are exposed automatically.
    struct AutoExposure;
    impl IntegratorJob for AutoExposure {
        type Output = bool;
        fn run<I: Integrator>(self, _: I) -> bool {
            I::AUTO_EXPOSURE
        }
    }
    if dispatch(world.lighting, AutoExposure) {
        Exposure::Automatic
    } else {
        Exposure::Fixed
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
    // The film and the rows are the camera's size: the render cannot refuse them.
    let stats = render_rows_into(camera, world, options, &film, &mut done).unwrap_or_default();
    let image = PartialImage {
        film: film.into_film(),
        done,
    };
    (image, stats)
}

/// [`render_rows`] into a film the caller holds, so that it can look at the image while the
/// render runs: another thread may take [`SharedFilm::snapshot`]s at any moment (a live
/// preview, a progress image). Rows marked in `done` are left alone; each row finished is added
/// to `film` and then marked. [`RenderOptions::finished`] is not read here: the film and `done`
/// are the starting point. The film may hold only the rows to render ([`SharedFilm::with_rows`]:
/// a slice's). Refused when `film` is not the camera's size, `done` not one entry per row, or a
/// row not marked done is not held by the film.
pub fn render_rows_into(
    camera: &Camera,
    world: &World,
    options: &RenderOptions<'_>,
    film: &SharedFilm,
    done: &mut [bool],
) -> Result<RenderStats, FilmError> {
    let (width, height) = (camera.hsize(), camera.vsize());
    if (film.width(), film.height()) != (width, height) || done.len() != height {
        return Err(FilmError::SizeMismatch(
            film.width(),
            done.len(),
            width,
            height,
        ));
    }
    film.check_holds_undone(done)?;
    Ok(dispatch(
        world.lighting,
        RenderRows {
            camera,
            world,
            options,
            film,
            done,
        },
    ))
}

/// [`render_rows_into`] as a job for [`dispatch`]: the loop compiled for each integrator.
struct RenderRows<'a, 'p> {
    camera: &'a Camera,
    world: &'a World,
    options: &'a RenderOptions<'p>,
    film: &'a SharedFilm,
    done: &'a mut [bool],
}

impl IntegratorJob for RenderRows<'_, '_> {
    type Output = RenderStats;

    fn run<I: Integrator>(self, integrator: I) -> Self::Output {
        let RenderRows {
            camera,
            world,
            options,
            film,
            done,
        } = self;
        render_rows_with(integrator, camera, world, options, film, done)
    }
}

/// [`render_rows_into`] with `integrator`.
fn render_rows_with<I: Integrator>(
    integrator: I,
    camera: &Camera,
    world: &World,
    options: &RenderOptions<'_>,
    film: &SharedFilm,
    done: &mut [bool],
) -> RenderStats {
    let (width, height) = (camera.hsize(), camera.vsize());
    let rays = AtomicU64::new(0);
    // The pixels with no usable sample (the optics model's ties).
    let ambiguous_pixels = AtomicU64::new(0);
    // Stopped while the index was built: no row is rendered (`done` is left as it was).
    let Some(index) = WorldIndex::build_until(world, options.cancel) else {
        return RenderStats::default();
    };
    // Set by the first thread whose sample goes over the ray budget: every thread stops.
    let failed = AtomicBool::new(false);
    // The index of the lowest pixel found over the budget (u64::MAX: none).
    let over_budget = AtomicU64::new(u64::MAX);
    let cancelled = || {
        failed.load(Ordering::Relaxed) || options.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    };
    (0..height)
        .into_par_iter()
        .zip(done.par_iter_mut())
        .for_each_init(
            || {
                let mut state = TraceState::new(world, &index);
                state.set_bailout(options.bailout);
                state.set_ray_budget(options.max_rays_per_sample);
                state.set_stop_flags([options.cancel, Some(&failed)]);
                // The brightest channel of every sample this thread has traced.
                (state, 0.0f64)
            },
            |(state, thread_brightest), (y, done)| {
                if *done || cancelled() || state.stopped().is_some() {
                    return;
                }
                let before = state.rays_cast();
                let mut row = vec![Color::BLACK; width];
                // Each pixel's weight in the film: 0 for one left to its neighbours.
                let mut weights = vec![1.0; width];
                let mut trace = |x: usize| {
                    let seed = (y * width + x) as u64;
                    state.reseed(seed);
                    let (mut samples, mut bad) = (0, 0);
                    let color = options.sampling.pixel(x, y, seed, |sample| {
                        samples += 1;
                        // A sample the lens system vignettes sees nothing: black, and counted.
                        let Some(CameraRay { ray, weight }) = camera.ray_for_sample(&sample) else {
                            return Color::BLACK;
                        };
                        state.begin_sample();
                        let radiance = integrator
                            .radiance(state, &ray, options.max_depth, &mut NoTrace)
                            .map(|c| c * weight);
                        if state.stopped() == Some(Stopped::OverBudget) {
                            over_budget.fetch_min((y * width + x) as u64, Ordering::Relaxed);
                            failed.store(true, Ordering::Relaxed);
                        }
                        match radiance {
                            Some(c) => {
                                let c = camera.record(c);
                                if I::AUTO_EXPOSURE {
                                    *thread_brightest =
                                        thread_brightest.max(c.red).max(c.green).max(c.blue);
                                }
                                c
                            }
                            None => {
                                bad += 1;
                                Color::BLACK
                            }
                        }
                    });
                    // Samples with no colour are black: average the others, or leave the
                    // pixel to its neighbours when there are none.
                    match bad {
                        0 => color,
                        bad if bad < samples => color * (samples as f64 / (samples - bad) as f64),
                        _ => {
                            weights[x] = 0.0;
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
                if state.stopped().is_some() {
                    // Stopped inside the row: its pixels are not all whole; it is left undone.
                    rays.fetch_add(state.rays_cast() - before, Ordering::Relaxed);
                    return;
                }
                let mut part = Film::new(width, 1);
                for (x, (&pixel, &weight)) in row.iter().zip(&weights).enumerate() {
                    part.add_pixel(x, 0, pixel, weight);
                }
                part.note_brightest(*thread_brightest);
                // The part is this film's width and one row: adding it cannot be refused.
                *done = film.add(y, &part).is_ok();
                rays.fetch_add(state.rays_cast() - before, Ordering::Relaxed);
                let left_out = weights.iter().filter(|&&w| w == 0.0).count();
                ambiguous_pixels.fetch_add(left_out as u64, Ordering::Relaxed);
                if let Some(on_row) = options.on_row {
                    on_row(y, &row);
                }
                if let Some(progress) = options.progress {
                    progress(1);
                }
            },
        );
    let over_budget = over_budget.into_inner();
    RenderStats {
        rays: rays.into_inner(),
        ambiguous: ambiguous_pixels.into_inner(),
        over_budget: (over_budget != u64::MAX).then(|| {
            (
                (over_budget % width as u64) as usize,
                (over_budget / width as u64) as usize,
            )
        }),
    }
}

/// How many lines [`trace_pixel`]'s record of one pixel keeps at most (about 10 MB of text).
pub const MAX_TRACE_LINES: usize = 100_000;

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
    dispatch(
        world.lighting,
        TracePixel {
            camera,
            world,
            options,
            x,
            y,
        },
    )
}

/// [`trace_pixel`] as a job for [`dispatch`].
struct TracePixel<'a, 'p> {
    camera: &'a Camera,
    world: &'a World,
    options: &'a RenderOptions<'p>,
    x: usize,
    y: usize,
}

impl IntegratorJob for TracePixel<'_, '_> {
    type Output = (Color, Vec<String>);

    fn run<I: Integrator>(self, integrator: I) -> Self::Output {
        let TracePixel {
            camera,
            world,
            options,
            x,
            y,
        } = self;
        let index = WorldIndex::build(world);
        let mut state = TraceState::new(world, &index);
        state.set_bailout(options.bailout);
        state.set_ray_budget(options.max_rays_per_sample);
        state.set_stop_flags([options.cancel, None]);
        let seed = (y * camera.hsize() + x) as u64;
        state.reseed(seed);
        let mut lines = Vec::new();
        let mut samples = 0;
        let color = options.sampling.pixel(x, y, seed, |sample| {
            samples += 1;
            lines.push(format!(
                "sample {samples}: image point ({:.4}, {:.4}), lens ({:.3}, {:.3}), time {:.3}",
                sample.x, sample.y, sample.lens_u, sample.lens_v, sample.time
            ));
            let mut log = TraceLog::new(world, MAX_TRACE_LINES.saturating_sub(lines.len()));
            let Some(CameraRay { ray, weight }) = camera.ray_for_sample(&sample) else {
                lines.push("  vignetted: the lens system passes no ray here (black)".into());
                return Color::BLACK;
            };
            if weight != 1.0 {
                lines.push(format!("  the camera ray's weight: {weight:.6}"));
            }
            state.begin_sample();
            let color = integrator
                .radiance(&mut state, &ray, options.max_depth, &mut log)
                .map_or(Color::BLACK, |c| camera.record(c * weight));
            lines.extend(log.into_lines().into_iter().map(|l| format!("  {l}")));
            match state.stopped() {
                Some(Stopped::OverBudget) => lines.push(format!(
                    "  stopped: this camera ray led to more than {} rays (--max-rays-per-sample)",
                    options.max_rays_per_sample
                )),
                Some(Stopped::Cancelled) => lines.push("  stopped: interrupted".to_string()),
                None => {}
            }
            // Each sample has its own budget; an interrupt stops them all.
            if state.stopped() == Some(Stopped::OverBudget) {
                state.resume();
            }
            color
        });
        (color, lines)
    }
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

/// The colour of one pixel (for tests and tools that need a single sample): the camera ray
/// through its centre, `max_depth` bounces deep (black for a sample with no colour).
pub fn render_pixel(camera: &Camera, world: &World, x: usize, y: usize, max_depth: u32) -> Color {
    let index = WorldIndex::build(world);
    let mut state = TraceState::new(world, &index);
    let ray = camera.ray_for_pixel(x, y);
    render_one_ray(&mut state, &ray, max_depth)
}

/// One camera ray traced on `state` with its world's integrator, `max_depth` bounces deep
/// (black for a sample with no colour): for tests and tools that drive a state themselves.
pub fn render_one_ray(state: &mut TraceState<'_>, ray: &Ray, max_depth: u32) -> Color {
    let lighting = state.world().lighting;
    dispatch(lighting, OneRay(state, ray, max_depth)).unwrap_or(Color::BLACK)
}

/// One camera ray traced with the world's integrator, unobserved: a job for [`dispatch`].
pub struct OneRay<'a, 'w>(pub &'a mut TraceState<'w>, pub &'a Ray, pub u32);

impl IntegratorJob for OneRay<'_, '_> {
    type Output = Option<Color>;

    fn run<I: Integrator>(self, integrator: I) -> Self::Output {
        let OneRay(state, ray, max_depth) = self;
        integrator.radiance(state, ray, max_depth, &mut NoTrace)
    }
}
