//! The path tracer: a physically based renderer behind the same scene files as the book's
//! ray tracer. Where the books stop (no indirect light, no glossy reflection, no light from
//! emitting surfaces or a sky), it follows light along whole paths ([`PathContext`]) with the
//! materials of [`crate::shading::bsdf`] and the lights of [`crate::lights::Emitters`].
//!
//! Every sample is a pure function of the pixel, its index and the seed ([`SampleStream`]), so
//! the image is the same for any thread count, and any range of sample indices
//! ([`PathJob::samples`]) can be rendered on its own, on another machine even, and the films
//! merged into exactly the film of one render over the union.
//!
//! Each sample belongs to one pixel: it is drawn over the pixel filter's support around the
//! pixel's centre and weighed by the filter there (uniformly over the pixel, at weight 1, for
//! the box filter), and the film divides the weighted sum by the sum of the weights. No sample
//! is shared between pixels, so no two threads ever add to one pixel and rows finish in any
//! order without changing a bit.

mod adaptive;
mod continuation;
mod integrator;
mod moments;
mod roulette;
mod sampler;

pub use adaptive::{plan_samples, plans_samples, prepare_render, SamplePlan, MIN_ADAPTIVE_SPP};
pub use continuation::ContinuationCache;
pub use integrator::{
    DiffuseDeparture, FirstHit, PathContext, PathLog, CAMERA_DIMENSIONS, VERTEX_DIMENSIONS,
};
pub use roulette::{learn_roulette, LearnedRoulette};
pub use sampler::SampleStream;

use super::RowCallback;
use crate::camera::{Camera, CameraRay, CameraSample, Sensor};
use crate::color::Color;
use crate::film::{Film, FilmError, PixelFilter, SharedFilm};
use crate::lights::Emitters;
use crate::options::{PathOptions, Roulette};
use crate::scene::{World, WorldIndex};
use adaptive::{PilotLog, PilotPixel};
use integrator::LENS_DIMENSION;
use moments::Moments;
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// What to render with the path tracer.
#[derive(Clone)]
pub struct PathJob<'p> {
    /// The sampler, filter, depth and seed.
    pub options: PathOptions,
    /// Which samples of every pixel, by index: `0..spp` for a whole render; disjoint ranges
    /// rendered apart merge into the render of their union.
    pub samples: Range<u64>,
    /// How many samples each pixel takes ([`plan_samples`]), `samples` then being a range of
    /// the plan's nominal `0..spp` that each pixel scales to its own count
    /// ([`SamplePlan::range`]); `None`: every pixel takes `samples` as they are.
    pub plan: Option<&'p SamplePlan>,
    /// Called with the number of rows just finished (from any thread).
    pub progress: Option<&'p (dyn Fn(usize) + Sync)>,
    /// Checked before each row is started and every few samples inside a pixel: once set, no
    /// more rows are started and those in progress are left undone.
    pub cancel: Option<&'p AtomicBool>,
    /// Called with each finished row (from any thread): the image's resolved colours, then,
    /// when the albedo and normal are rendered, theirs. A row so saved and added back to the
    /// films as one sample of weight 1 per pixel resolves to the same bits.
    pub on_row: Option<&'p RowCallback<'p>>,
    /// The roulette learned beforehand ([`learn_roulette`]) where the options ask for one
    /// learned: a render in several passes learns it once for all of them, and a pilot sized
    /// for the render's samples needs them told. `None`: learned here, by the largest pilot
    /// (whatever `samples` are, so that ranges rendered apart learn the same), which heeds
    /// `cancel` too. Ignored where the options fix the scale.
    pub roulette: Option<&'p LearnedRoulette>,
}

impl<'p> PathJob<'p> {
    /// The samples `samples` of every pixel as `options` say, and nothing beside: no plan,
    /// no callbacks, no cancel, the roulette learned here. Other jobs start from it
    /// (`PathJob { plan: Some(&plan), ..PathJob::new(options, samples) }`).
    pub fn new(options: PathOptions, samples: Range<u64>) -> Self {
        Self {
            options,
            samples,
            plan: None,
            progress: None,
            cancel: None,
            on_row: None,
            roulette: None,
        }
    }
}

/// The images a denoiser wants beside the beauty image: the albedo and the normal of the
/// first surface each camera ray meets, averaged over the pixel's samples.
pub struct Aovs {
    /// Albedo (box filter).
    pub albedo: SharedFilm,
    /// World-space normal facing the camera, each component in [-1, 1] (box filter).
    pub normal: SharedFilm,
    /// Distance from the camera to the first hit, in every channel: the mean over the
    /// pixel's samples that hit something (weighted by their number), 0 where none did.
    pub depth: SharedFilm,
    /// How many samples the pixel took (its finite ones), in every channel, as the sum of a
    /// pixel of weight 1.
    pub samples: SharedFilm,
}

impl Aovs {
    /// Empty AOV films of `width` × `height`.
    pub fn new(width: usize, height: usize) -> Self {
        let film = || SharedFilm::from(Film::new(width, height));
        Self {
            albedo: film(),
            normal: film(),
            depth: film(),
            samples: film(),
        }
    }

    /// Empty AOV films of `width` × `height` that hold only the rows `rows` names, as a
    /// slice's image film does ([`SharedFilm::with_rows`]); refused for a row past the last.
    pub fn with_rows(
        width: usize,
        height: usize,
        rows: impl IntoIterator<Item = usize>,
    ) -> Result<Self, FilmError> {
        let rows: Vec<usize> = rows.into_iter().collect();
        let film = || SharedFilm::with_rows(width, height, PixelFilter::Box, rows.iter().copied());
        Ok(Self {
            albedo: film()?,
            normal: film()?,
            depth: film()?,
            samples: film()?,
        })
    }

    /// The films in the order rows are saved and restored: albedo, normal, depth, samples.
    pub fn films(&self) -> [&SharedFilm; 4] {
        [&self.albedo, &self.normal, &self.depth, &self.samples]
    }
}

/// What a path traced render did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PathStats {
    /// Rays cast: camera rays, bounces and shadow rays.
    pub rays: u64,
    /// Camera samples traced.
    pub samples: u64,
    /// Samples whose radiance was not finite (a NaN or an infinity from a degenerate scene),
    /// left out of their pixel rather than poisoning it.
    pub discarded: u64,
}

/// Where within the filter's support a sample goes, from two numbers in [0, 1): its offset
/// from the pixel's centre and its weight.
#[inline]
fn filter_offset(filter: PixelFilter, [u, v]: [f64; 2]) -> (f64, f64, f64) {
    match filter {
        PixelFilter::Box => (u - 0.5, v - 0.5, 1.0),
        _ => {
            let r = filter.radius();
            let (dx, dy) = ((2.0 * u - 1.0) * r, (2.0 * v - 1.0) * r);
            (dx, dy, filter.weight(dx, dy))
        }
    }
}

/// Where a pixel's samples come from: the camera, the pixel filter, and whether the world
/// stands still before a pinhole that stands still too (then no lens point nor instant is
/// drawn); and what the film records of each sample's radiance (the camera's sensor, `None`
/// for the identity, which then costs nothing).
struct CameraSampler<'c> {
    camera: &'c Camera,
    filter: PixelFilter,
    still: bool,
    sensor: Option<Sensor>,
}

impl<'c> CameraSampler<'c> {
    /// The sampler of `camera` over `world` with `filter`.
    fn new(camera: &'c Camera, world: &World, filter: PixelFilter) -> Self {
        let still = !camera.samples_lens()
            && !camera.moves()
            && world.objects.iter().all(|o| o.motion.is_none());
        let sensor = Some(*camera.sensor()).filter(|s| !s.is_identity());
        Self {
            camera,
            filter,
            still,
            sensor,
        }
    }

    /// What the film records of a sample's `radiance`.
    #[inline]
    fn record(&self, radiance: Color) -> Color {
        match &self.sensor {
            Some(sensor) => sensor.record(radiance),
            None => radiance,
        }
    }

    /// The camera ray of the sample `stream` is at in pixel (`x`, `y`), drawn over the
    /// filter's support (`None` where a lens system vignettes it: its radiance is zero),
    /// and the sample's filter weight.
    #[inline]
    fn ray(&self, x: usize, y: usize, stream: &mut SampleStream) -> (Option<CameraRay>, f64) {
        // The lens and the instant first, from the camera's second group of four: the image
        // point's group, which holds the first vertex's light point too, is then the one the
        // stream has at hand.
        let ([lens_u, lens_v], time) = if self.still {
            ([0.5, 0.5], 0.5)
        } else {
            stream.seek(LENS_DIMENSION);
            (stream.next_2d(), stream.next_1d())
        };
        stream.seek(0);
        let (dx, dy, weight) = filter_offset(self.filter, stream.next_2d());
        let sample = CameraSample {
            x: x as f64 + 0.5 + dx,
            y: y as f64 + 0.5 + dy,
            lens_u,
            lens_v,
            time,
        };
        (self.camera.path_ray_for_sample(&sample), weight)
    }
}

/// A path tracer's context for `world` (its `index` and `emitters`) as `options` ask, with
/// the roulette at `roulette_scale` ending paths into `continuation`'s predictions.
fn path_context<'w>(
    world: &'w World,
    index: &'w WorldIndex,
    emitters: &'w Emitters,
    options: &PathOptions,
    roulette_scale: f64,
    continuation: Option<&'w ContinuationCache>,
) -> PathContext<'w> {
    let mut context = PathContext::new(
        world,
        index,
        emitters,
        options.max_depth,
        options.roulette_depth.max(1),
    );
    context.roulette_scale = roulette_scale;
    context.continuation = continuation;
    context.techniques = options.techniques;
    context
}

/// Path traces `world` through `camera` into `film` (and the `aovs`, when given), the rows not
/// marked in `done`, marking each as it is finished. The films may hold only those rows
/// ([`SharedFilm::with_rows`]: a slice's). Refused when the films are not the camera's size,
/// `done` is not one entry per row, a row not marked done is not held by every film, or
/// `film`'s filter is not the job's.
pub fn render_path(
    camera: &Camera,
    world: &World,
    job: &PathJob<'_>,
    film: &SharedFilm,
    aovs: Option<&Aovs>,
    done: &mut [bool],
) -> Result<PathStats, FilmError> {
    render_path_logged(camera, world, job, film, aovs, done, None)
}

/// [`render_path`], recording each pixel's samples in `log` when given (an adaptive plan's
/// pilot).
fn render_path_logged(
    camera: &Camera,
    world: &World,
    job: &PathJob<'_>,
    film: &SharedFilm,
    aovs: Option<&Aovs>,
    done: &mut [bool],
    log: Option<&PilotLog>,
) -> Result<PathStats, FilmError> {
    let (width, height) = (camera.hsize(), camera.vsize());
    let mismatch = |w: usize, h: usize| (w, h) != (width, height);
    if mismatch(film.width(), film.height())
        || done.len() != height
        || aovs.is_some_and(|a| {
            mismatch(a.albedo.width(), a.albedo.height())
                || mismatch(a.normal.width(), a.normal.height())
        })
    {
        return Err(FilmError::SizeMismatch(
            film.width(),
            done.len(),
            width,
            height,
        ));
    }
    if let Some(plan) = job.plan {
        let (w, h) = plan.size();
        if mismatch(w, h) {
            return Err(FilmError::SizeMismatch(w, h, width, height));
        }
    }
    film.check_holds_undone(done)?;
    for layer in aovs.iter().flat_map(|a| a.films()) {
        layer.check_holds_undone(done)?;
    }
    let filter = job.options.filter.checked()?;
    if film.filter() != filter {
        return Err(FilmError::FilterMismatch(filter, film.filter()));
    }
    // A stop during the index's build renders nothing (as a stop during the pilot below).
    let Some(index) = WorldIndex::build_until(world, job.cancel) else {
        return Ok(PathStats::default());
    };
    let emitters = Emitters::for_options(world, &job.options);
    let rays = AtomicU64::new(0);
    let discarded = AtomicU64::new(0);
    let samples = AtomicU64::new(0);
    let cancelled = || job.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let options = job.options;
    let sampler = CameraSampler::new(camera, world, filter);
    let learned_here;
    let roulette = match (options.roulette, job.roulette) {
        // Without the roulette there is nothing to learn.
        _ if !options.techniques.roulette => {
            learned_here = LearnedRoulette::fixed(1.0);
            &learned_here
        }
        (Roulette::Learned, Some(learned)) => learned,
        (Roulette::Learned, None) => {
            // The pilot's size may not follow this job's samples: sample ranges rendered
            // apart must learn one roulette to merge exactly. It is the largest, whatever the
            // samples; a caller that wants its share of the render learns it beforehand.
            let learned = roulette::learned(
                camera,
                world,
                &index,
                &emitters,
                &options,
                u64::MAX,
                job.cancel,
            );
            let Some(learned) = learned else {
                return Ok(PathStats::default());
            };
            learned_here = learned;
            &learned_here
        }
        (Roulette::Scale(scale), _) => {
            learned_here = LearnedRoulette::fixed(scale);
            &learned_here
        }
    };
    // A row at a time for each thread to take: rayon otherwise runs a quarter of the rows per
    // thread as one unsplittable piece, and with rows of unequal cost (adaptive sampling puts
    // four times the samples on some) one thread was left with a long tail while the other
    // idled, a seventh of a short two-thread render.
    (0..height)
        .into_par_iter()
        .zip(done.par_iter_mut())
        .with_max_len(1)
        .try_for_each_init(
            || {
                let (scale, continuation) = (roulette.scale, roulette.continuation.as_ref());
                let mut context =
                    path_context(world, &index, &emitters, &options, scale, continuation);
                context.first_hit_shading = aovs.is_some();
                context
            },
            |context, (y, done)| -> Result<(), FilmError> {
                if *done || cancelled() {
                    return Ok(());
                }
                let before = context.rays;
                // The row as the film holds it: this pass's samples go on from its sums, so a
                // pixel's samples are summed in one order however many passes bring them.
                let mut beauty = film.row(y)?;
                let mut layers = match aovs {
                    Some(aovs) => Some([
                        aovs.albedo.row(y)?,
                        aovs.normal.row(y)?,
                        aovs.depth.row(y)?,
                        aovs.samples.row(y)?,
                    ]),
                    None => None,
                };
                let (mut row_discarded, mut row_samples) = (0, 0);
                let mut row_pilot = Vec::with_capacity(if log.is_some() { width } else { 0 });
                for x in 0..width {
                    let range = match job.plan {
                        Some(plan) => plan.range(x, y, &job.samples),
                        None => job.samples.clone(),
                    };
                    let taken = range.end.saturating_sub(range.start);
                    row_samples += taken;
                    let mut sum = beauty.sum(x, 0);
                    let mut weights = beauty.weight(x, 0);
                    let [mut albedo_sum, mut normal_sum, mut depth_sum, mut count] = match &layers {
                        Some(films) => films.each_ref().map(|f| f.sum(x, 0)),
                        None => [Color::BLACK; 4],
                    };
                    let mut hits = layers
                        .as_ref()
                        .map_or(0.0, |[_, _, depth, _]| depth.weight(x, 0));
                    // A planned pixel's first samples are the pilot's, summed in the plan as
                    // these films would have summed them.
                    let mut first_sample = range.start;
                    if let Some(plan) = job.plan {
                        let kept = plan.kept_samples(layers.is_some());
                        if range.start == 0 && kept > 0 && range.end >= kept {
                            let (kept_sum, kept_weight, kept_aovs) = plan.kept(x, y);
                            sum += kept_sum;
                            weights += kept_weight;
                            if let (Some(([a, n, d, c], h)), Some(_)) = (kept_aovs, &layers) {
                                albedo_sum += a;
                                normal_sum += n;
                                depth_sum += d;
                                count += c;
                                hits += h;
                            }
                            first_sample = kept;
                        }
                    }
                    let mut halves = [Moments::default(); 2];
                    let (rays_before, vertices_before, solves_before) =
                        (context.rays, context.vertices, context.solves);
                    let mut stream = SampleStream::new(
                        options.sampler,
                        options.seed,
                        x as u32,
                        y as u32,
                        first_sample,
                    );
                    for s in first_sample..range.end {
                        // A pixel may take millions of samples, and one path through a scene
                        // of thousands of overlapping objects a second: a stop is heeded
                        // before every sample (a load of a flag, nothing beside a path), and
                        // the row, unfinished, is left undone.
                        if cancelled() {
                            return Ok(());
                        }
                        stream.start(s);
                        let (ray, weight) = sampler.ray(x, y, &mut stream);
                        let (radiance, first) = match ray {
                            Some(CameraRay { ray, weight }) => {
                                let (radiance, first) = context.radiance(ray, &mut stream);
                                (radiance * weight, first)
                            }
                            // Vignetted: no light, and nothing seen (depth infinite).
                            None => (
                                Color::BLACK,
                                FirstHit {
                                    depth: f64::INFINITY,
                                    ..FirstHit::default()
                                },
                            ),
                        };
                        let radiance = sampler.record(radiance);
                        let finite = radiance.red.is_finite()
                            && radiance.green.is_finite()
                            && radiance.blue.is_finite();
                        if finite {
                            sum += radiance * weight;
                            weights += weight;
                            count += Color::WHITE;
                            if log.is_some() {
                                halves[(s % 2) as usize].add(radiance);
                            }
                        } else {
                            row_discarded += 1;
                        }
                        albedo_sum += first.albedo;
                        normal_sum += Color::new(first.normal.x, first.normal.y, first.normal.z);
                        if first.depth.is_finite() {
                            depth_sum += Color::WHITE * first.depth;
                            hits += 1.0;
                        }
                    }
                    beauty.set_pixel_sum(x, 0, sum, weights);
                    if let Some([albedo, normal, depth, samples]) = &mut layers {
                        let weight = albedo.weight(x, 0) + taken as f64;
                        albedo.set_pixel_sum(x, 0, albedo_sum, weight);
                        normal.set_pixel_sum(x, 0, normal_sum, weight);
                        depth.set_pixel_sum(x, 0, depth_sum, hits);
                        samples.set_pixel_sum(x, 0, count, 1.0);
                    }
                    if log.is_some() {
                        row_pilot.push(PilotPixel::new(
                            &halves,
                            taken,
                            context.rays - rays_before,
                            context.vertices - vertices_before,
                            context.solves - solves_before,
                        ));
                    }
                }
                if let Some(log) = log {
                    // Each row is rendered once: the first record is the only one.
                    let _ = log.rows[y].set(row_pilot);
                }
                film.set_row(y, &beauty)?;
                if let (Some(aovs), Some(rows)) = (aovs, &layers) {
                    for (target, row) in aovs.films().into_iter().zip(rows) {
                        target.set_row(y, row)?;
                    }
                }
                *done = true;
                if let Some(on_row) = job.on_row {
                    let mut values = beauty.resolve().pixels().to_vec();
                    for row in layers.iter().flatten() {
                        values.extend_from_slice(row.resolve().pixels());
                    }
                    on_row(y, &values);
                }
                rays.fetch_add(context.rays - before, Ordering::Relaxed);
                samples.fetch_add(row_samples, Ordering::Relaxed);
                discarded.fetch_add(row_discarded, Ordering::Relaxed);
                if let Some(progress) = job.progress {
                    progress(1);
                }
                Ok(())
            },
        )?;
    Ok(PathStats {
        rays: rays.into_inner(),
        samples: samples.into_inner(),
        discarded: discarded.into_inner(),
    })
}
