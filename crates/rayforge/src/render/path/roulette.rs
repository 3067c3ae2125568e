//! Efficiency-aware Russian roulette, learned for each scene by a short pilot pass.
//!
//! The classic rule (Mitsuba's, pbrt's) lets a path go on with probability equal to its
//! throughput: what it has left to carry, as if the light still to come were always worth as
//! much as the pixel's. That is far from right where light keeps coming (inside a closed,
//! bright, emitting room a path at its fifth bounce still has a third of its pixel's light to
//! gather, and ending it costs more noise than carrying it on costs time) and can be too
//! generous where little does. Rath et al. ("EARS: Efficiency-Aware Russian Roulette and
//! Splitting", 2022) weigh both: a vertex whose remaining light has second moment `m₂` per
//! unit throughput and costs `c` to gather, in a pixel whose samples have variance `V` and
//! cost `C`, adds `T² m₂ (1/q − 1)` of variance for `(q − 1) c` of cost when it goes on with
//! probability `q`, and the product of the two is least at `q = T √(m₂ C ∕ (c V))`.
//!
//! Their method keeps `m₂` and `c` in a spatial cache learned while rendering. Here they are
//! the scene's averages over a pilot pass, so the rule stays `q = k T` with one scale `k` for
//! the whole scene: a pure function of the scene, its camera and the options (the pilot's
//! pixels, samples and seed are fixed), so the image is still the same for any thread count
//! and sample ranges rendered apart still merge exactly. The pilot traces a grid of pixels at
//! [`PILOT_SAMPLES`] samples each, again and again: the first pass with the classic rule, each
//! next one with the scale the last found (the variance and cost it measures depend on the
//! rule it renders with), until the answer settles; the last answer is used.
//!
//! # What the pilot costs
//!
//! The pilot's paths are never more than [`PILOT_SHARE`], a sixteenth, of the render's own
//! pixels × samples: its grid has at most `pixels × spp ∕ (16 × 8 × 5)` pixels (8 samples
//! each, at most 5 passes), and at most [`PILOT_PIXELS`]. Why a sixteenth: where the pilot
//! learns nothing (the scale stays the classic rule and nothing is predicted: envmap, the open
//! furnace) its paths are pure cost, and a render that takes `1 + s` times its own work is
//! `1 ∕ (1 + s)` as efficient; a sixteenth caps that loss at 6 %, while where the pilot pays
//! (the closed furnace, 19 times the classic rule's efficiency by rays at 64 spp, see
//! docs/performance.md) the same share is a small fraction of the gain. The reference scenes
//! at their own sizes and 64 spp keep the full grid of [`PILOT_PIXELS`] (the closed furnace's
//! 128 × 128 × 64 allows 1,638 pixels), so their images are unchanged there. A render too
//! small for [`MIN_PILOT_PIXELS`] (fewer than 40,960 pixel-samples: a 1-sample preview of up to
//! 200 × 200 pixels, as the live page's quarter-size previews are) runs no pilot and plays the
//! classic rule, which is what the pilot itself answers where it has too little to weigh.
//!
//! The pilot heeds the render's stop flag before every path it traces: a path is the unit of
//! its work (bounded by the render's `max_depth`), so a stop is heeded after at most one path
//! per thread, however slow each path is, and a stopped pilot answers nothing.
//!
//! The averages are trusted only where paths often outlive the roulette depth. Where they
//! seldom do (spheres on an open floor: a path past five bounces is mostly one caught in a
//! glass ball, carrying its caustic), ending them saves little time, and the pilot's few
//! such paths miss the rare bright ones that make the render's noise: its average had the
//! spheres scene end paths more eagerly than the classic rule, and the image's error was a
//! quarter above that of a lenient roulette for the same time. There the roulette is lenient.
//!
//! A pass before those, whose paths no roulette ends, records at each diffuse vertex they
//! leave the light they went on to gather: a [`ContinuationCache`] learns from it
//! where that light is predictable, and there the passes after it and the render end paths
//! into the prediction (see [`continuation`](super::continuation)). The scale is then learned
//! from the other vertices' decisions alone. Options without
//! [`roulette_predictions`](PathOptions::roulette_predictions) skip that pass: the scale is
//! learned alone, and no path ends into a prediction.

use super::continuation::{ContinuationCache, Sighting};
use super::integrator::{DiffuseDeparture, PathLog};
use super::moments::Moments;
use super::{path_context, CameraSampler, SampleStream};
use crate::camera::{Camera, CameraRay};
use crate::color::Color;
use crate::lights::Emitters;
use crate::options::{PathOptions, Roulette};
use crate::scene::{World, WorldIndex};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// The most pixels the pilot traces (a grid over the image).
const PILOT_PIXELS: u64 = 1024;
/// The fewest: a grid of fewer pixels than this is too thin to learn from (a few hundred
/// paths a pass give the scale's average few decisions and the predictions' cells few
/// vertices), and the render plays the classic rule instead.
const MIN_PILOT_PIXELS: u64 = 64;
/// The pilot's paths are at most one in this many of the render's pixels × samples (see the
/// [module](self)).
const PILOT_SHARE: u64 = 16;
/// Samples the pilot takes in each of its pixels (enough for a pixel's variance).
const PILOT_SAMPLES: u64 = 8;
/// The most pilot passes.
const PILOT_ROUNDS: usize = 4;
/// A pass whose scale is within this fraction of the one it rendered with ends the pilot.
const SETTLED: f64 = 0.15;
/// Fewer roulette decisions than this in the pilot (a scene where paths seldom live past
/// the roulette depth) leave the classic rule: too few to weigh, and too few to matter.
const MIN_DECISIONS: u64 = 64;
/// Where the pilot's paths cast less than this share of their rays past the roulette's
/// decisions, ending paths can save little time, and the light those few paths carry is what
/// the pilot sees worst: the scale is then [`RARE_SCALE`] whatever the pilot's averages say.
const RARE_SHARE: f64 = 0.05;
/// The deepest the pass that learns the predictions follows a path (without roulette).
const SIGHTING_DEPTH: u32 = 32;
/// The vertices that pass records: its paths' first eight bounces, each followed for at
/// least 24 more. What a path would gather past its 32nd bounce is left out, so a prediction
/// falls short by up to albedo²⁴ of it (a two-hundredth in a room of albedo 0.8, a twentieth
/// at 0.88): that costs a little of the gain and nothing of the mean. Counting every bounce
/// instead set the closed furnace's predictions 13 % short, and its error rose by a fifth.
const SIGHTED_BOUNCES: u32 = 8;
/// The scale for scenes whose paths seldom outlive the roulette depth: paths end only once
/// their throughput has fallen below an eighth.
const RARE_SCALE: f64 = 8.0;

/// The roulette a render plays: a path survives with probability `scale × throughput`, and
/// where `continuation` predicts what a path still gathers, it ends into the prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct LearnedRoulette {
    /// The scale `k` of `q = k T`.
    pub scale: f64,
    /// The predictions, where the pilot learned any.
    pub continuation: Option<ContinuationCache>,
}

impl LearnedRoulette {
    /// The roulette of the fixed scale `scale`, predicting nothing.
    pub fn fixed(scale: f64) -> Self {
        Self {
            scale,
            continuation: None,
        }
    }
}

/// The roulette `options` ask for: their scale (and no predictions), or one learned for
/// `world` seen through `camera` by a pilot pass that weighs the light paths still have to
/// gather against the rays it costs (efficiency-aware roulette, Rath et al. 2022, with the
/// scene's averages) and learns where that light is predictable. The pilot's size follows
/// from the render's `spp` samples per pixel (a sixteenth of its paths at most; see the
/// [module](self)); the predictions are learned only where the options'
/// [`roulette_predictions`](PathOptions::roulette_predictions) ask for them. `None` where
/// `cancel` was set before the pilot was through.
pub fn learn_roulette(
    camera: &Camera,
    world: &World,
    options: &PathOptions,
    spp: u64,
    cancel: Option<&AtomicBool>,
) -> Option<LearnedRoulette> {
    match options.roulette {
        // Without the roulette (`Techniques::roulette`) there is nothing to learn.
        _ if !options.techniques.roulette => Some(LearnedRoulette::fixed(1.0)),
        Roulette::Scale(scale) => Some(LearnedRoulette::fixed(scale)),
        Roulette::Learned => {
            let index = WorldIndex::build_until(world, cancel)?;
            let emitters = Emitters::for_options(world, options);
            learned(camera, world, &index, &emitters, options, spp, cancel)
        }
    }
}

/// The pilot's roulette for `world`, its `index` and `emitters` already built, for a render
/// of `spp` samples per pixel; `None` once `cancel` is set.
pub(super) fn learned(
    camera: &Camera,
    world: &World,
    index: &WorldIndex,
    emitters: &Emitters,
    options: &PathOptions,
    spp: u64,
    cancel: Option<&AtomicBool>,
) -> Option<LearnedRoulette> {
    learn(camera, world, index, emitters, options, spp, cancel).map(|(roulette, _)| roulette)
}

/// [`learned`], and how many paths its pilot traced.
fn learn(
    camera: &Camera,
    world: &World,
    index: &WorldIndex,
    emitters: &Emitters,
    options: &PathOptions,
    spp: u64,
    cancel: Option<&AtomicBool>,
) -> Option<(LearnedRoulette, u64)> {
    let pixels = pilot_pixels(camera.hsize(), camera.vsize(), spp);
    if pixels.is_empty() {
        return Some((LearnedRoulette::fixed(1.0), 0));
    }
    let pass = |options: &PathOptions,
                k: f64,
                continuation: Option<&ContinuationCache>,
                sightings: Option<&mut Vec<Sighting>>| {
        let stats = pilot(
            camera,
            world,
            index,
            emitters,
            options,
            &pixels,
            cancel,
            k,
            continuation,
            sightings,
        );
        (!stats.cancelled).then_some(stats)
    };
    // First the predictions (unless the options turn them off), from paths that no roulette
    // ends (so that what they record past a vertex is the light there, not the roulette's
    // noise), cut at a depth where what they would still gather is lost in that noise anyway.
    let (mut traced, mut continuation) = (0, None);
    if options.roulette_predictions {
        let mut sightings = Vec::new();
        let whole = PathOptions {
            max_depth: options.max_depth.min(SIGHTING_DEPTH),
            roulette_depth: u32::MAX,
            ..*options
        };
        traced += pass(&whole, 1.0, None, Some(&mut sightings))?.traced;
        continuation = ContinuationCache::learn(&sightings);
    }
    // The variance and cost a pilot measures depend on the scale it renders with: each pass
    // renders with the last one's answer, until the answer settles.
    let mut k = 1.0;
    for _ in 0..PILOT_ROUNDS {
        let stats = pass(options, k, continuation.as_ref(), None)?;
        traced += stats.traced;
        let Some(next) = stats.scale() else {
            break;
        };
        let settled = (next / k - 1.0).abs() < SETTLED;
        k = next;
        if settled {
            break;
        }
    }
    let roulette = LearnedRoulette {
        scale: k,
        continuation,
    };
    Some((roulette, traced))
}

/// The pixels the pilot traces for an image of `width` × `height` rendered at `spp` samples
/// per pixel: a grid, its step the same across and down, of at most [`PILOT_PIXELS`] and at
/// most what [`PILOT_SHARE`] allows for all its passes; none where that is fewer than
/// [`MIN_PILOT_PIXELS`].
fn pilot_pixels(width: usize, height: usize, spp: u64) -> Vec<(usize, usize)> {
    let image = (width as u64).saturating_mul(height as u64);
    let passes = 1 + PILOT_ROUNDS as u64;
    let allowed = image.saturating_mul(spp) / (PILOT_SHARE * PILOT_SAMPLES * passes);
    let target = allowed.min(PILOT_PIXELS);
    if target < MIN_PILOT_PIXELS {
        return Vec::new();
    }
    let mut stride = ((image as f64 / target as f64).sqrt().ceil() as usize).max(1);
    let along = |side: usize, stride: usize| (stride / 2..side).step_by(stride).len() as u64;
    // The step that the image's area suggests may leave a few pixels too many at the edges.
    while along(width, stride) * along(height, stride) > target {
        stride += 1;
    }
    (stride / 2..height)
        .step_by(stride)
        .flat_map(|y| (stride / 2..width).step_by(stride).map(move |x| (x, y)))
        .collect()
}

/// What a pilot pass measured (sums over its pixels, in the pixels' order).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct PilotStats {
    /// Roulette decisions taken.
    decisions: u64,
    /// The second moment of the light a path gathered after a decision, per unit of its
    /// throughput there, summed over the survivors each weighed by one over its chance.
    moment: f64,
    /// The rays a path cast after a decision, summed the same way.
    cost: f64,
    /// Paths traced.
    paths: u64,
    /// Rays cast by them.
    rays: u64,
    /// The sum over pixels of the variance of their samples (the mean over channels).
    variance: f64,
    /// Pixels whose variance is in `variance`.
    pixels: u64,
    /// Paths started, finite or not.
    traced: u64,
    /// Whether a stop cut the pass short.
    cancelled: bool,
}

impl PilotStats {
    /// Adds `other` to these.
    fn add(mut self, other: &Self) -> Self {
        self.decisions += other.decisions;
        self.moment += other.moment;
        self.cost += other.cost;
        self.paths += other.paths;
        self.rays += other.rays;
        self.variance += other.variance;
        self.pixels += other.pixels;
        self.traced += other.traced;
        self.cancelled |= other.cancelled;
        self
    }

    /// The scale `k` of `q = k T` that these measure, `√(m₂ C ∕ (c V))`, within
    /// [`Roulette::MIN_SCALE`] and [`Roulette::MAX_SCALE`]; [`RARE_SCALE`] where the paths
    /// past the roulette cast few of the rays; `None` where there is too little to tell (few
    /// decisions, no variance).
    fn scale(&self) -> Option<f64> {
        if self.decisions < MIN_DECISIONS || self.paths == 0 || self.pixels == 0 {
            return None;
        }
        if self.cost < RARE_SHARE * self.rays as f64 {
            return Some(RARE_SCALE);
        }
        let n = self.decisions as f64;
        let (moment, cost) = (self.moment / n, self.cost / n);
        let pixel_cost = self.rays as f64 / self.paths as f64;
        let pixel_variance = self.variance / self.pixels as f64;
        let k = (moment * pixel_cost / (cost * pixel_variance)).sqrt();
        k.is_finite()
            .then(|| k.clamp(Roulette::MIN_SCALE, Roulette::MAX_SCALE))
    }
}

/// One survived roulette decision, as the path went on from it.
#[derive(Debug, Clone, Copy)]
struct Decision {
    weight: f64,
    throughput: f64,
    gathered: Color,
    rays: u64,
    /// The radiance gathered when its branch of the path ended (a path split at glass goes on
    /// with its other half, whose light this decision did not lead to).
    end: Color,
}

/// A diffuse vertex the path being traced went on from, and the radiance gathered when its
/// branch ended.
#[derive(Debug, Clone, Copy)]
struct Departure {
    from: DiffuseDeparture,
    end: Color,
}

/// The decisions of the path being traced.
#[derive(Debug, Default)]
struct Decisions {
    ended: u64,
    survived: Vec<Decision>,
    /// How many of `survived` belong to branches that have ended.
    closed: usize,
    /// Whether diffuse vertices are recorded.
    records: bool,
    departures: Vec<Departure>,
    /// How many of `departures` belong to branches that have ended.
    departed: usize,
}

impl Decisions {
    /// Ready for the next path.
    fn clear(&mut self) {
        self.ended = 0;
        self.survived.clear();
        self.closed = 0;
        self.departures.clear();
        self.departed = 0;
    }
}

impl PathLog for Decisions {
    fn ended(&mut self) {
        self.ended += 1;
    }

    fn survived(&mut self, survive: f64, throughput: f64, gathered: Color, rays: u64) {
        self.survived.push(Decision {
            weight: 1.0 / survive,
            throughput,
            gathered,
            rays,
            end: gathered,
        });
    }

    fn branch_ended(&mut self, gathered: Color) {
        for d in &mut self.survived[self.closed..] {
            d.end = gathered;
        }
        self.closed = self.survived.len();
        for d in &mut self.departures[self.departed..] {
            d.end = gathered;
        }
        self.departed = self.departures.len();
    }

    fn left_diffuse(&mut self, bounce: u32, from: DiffuseDeparture) {
        if self.records && bounce <= SIGHTED_BOUNCES {
            self.departures.push(Departure {
                from,
                end: from.gathered,
            });
        }
    }
}

/// What `departure` saw: the light gathered past it per unit of its throughput, channel by
/// channel; `None` where a channel carried nothing (what would come there is unknown).
fn sighting(departure: &Departure) -> Option<Sighting> {
    let Departure { from, end } = departure;
    let t = from.throughput;
    if !(t.red > 0.0 && t.green > 0.0 && t.blue > 0.0) {
        return None;
    }
    let future = *end - from.gathered;
    let light = Color::new(
        future.red / t.red,
        future.green / t.green,
        future.blue / t.blue,
    );
    let finite = light.red.is_finite() && light.green.is_finite() && light.blue.is_finite();
    finite.then_some(Sighting {
        point: from.point,
        facing: from.facing,
        light,
    })
}

/// The mean over channels of `c`'s squares.
fn mean_square(c: Color) -> f64 {
    (c.red * c.red + c.green * c.green + c.blue * c.blue) / 3.0
}

/// One pilot pass over `pixels` with the roulette at scale `k` and the predictions
/// `continuation`, adding what its paths saw past diffuse vertices to `sightings` when given
/// (in the pixels' order). Once `cancel` is set no more paths are started, and the pass is
/// marked cancelled.
#[allow(clippy::too_many_arguments)]
fn pilot(
    camera: &Camera,
    world: &World,
    index: &WorldIndex,
    emitters: &Emitters,
    options: &PathOptions,
    pixels: &[(usize, usize)],
    cancel: Option<&AtomicBool>,
    k: f64,
    continuation: Option<&ContinuationCache>,
    mut sightings: Option<&mut Vec<Sighting>>,
) -> PilotStats {
    let records = sightings.is_some();
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let sampler = CameraSampler::new(camera, world, options.filter);
    // Its own seed: the scale it finds is independent of the render's numbers.
    let seed = options.seed ^ 0x7069_6C6F_745F_7272;
    // In small pieces, as the render's rows (see `render_path_logged`): pixels differ in cost.
    let per_pixel: Vec<(PilotStats, Vec<Sighting>)> = pixels
        .par_iter()
        .with_max_len(16)
        .map_init(
            || {
                let context = path_context(world, index, emitters, options, k, continuation);
                let log = Decisions {
                    records,
                    ..Decisions::default()
                };
                (context, log)
            },
            |(context, log), &(x, y)| {
                let mut stats = PilotStats::default();
                let mut seen = Vec::new();
                let mut stream = SampleStream::new(options.sampler, seed, x as u32, y as u32, 0);
                let mut moments = Moments::default();
                for s in 0..PILOT_SAMPLES {
                    if cancelled() {
                        stats.cancelled = true;
                        break;
                    }
                    stats.traced += 1;
                    stream.start(s);
                    let (ray, _) = sampler.ray(x, y, &mut stream);
                    // A vignetted sample has no path to learn from.
                    let Some(CameraRay { ray, weight }) = ray else {
                        continue;
                    };
                    let before = context.rays;
                    log.clear();
                    let (radiance, _) = context.radiance_logged(ray, &mut stream, log);
                    let radiance = radiance * weight;
                    if !(radiance.red.is_finite()
                        && radiance.green.is_finite()
                        && radiance.blue.is_finite())
                    {
                        continue;
                    }
                    stats.paths += 1;
                    stats.rays += context.rays - before;
                    stats.decisions += log.ended + log.survived.len() as u64;
                    for d in &log.survived {
                        let future = (d.end - d.gathered) * (1.0 / d.throughput);
                        stats.moment += d.weight * mean_square(future);
                        stats.cost += d.weight * (context.rays - d.rays) as f64;
                    }
                    seen.extend(log.departures.iter().filter_map(sighting));
                    moments.add(radiance);
                }
                if stats.paths > 1 {
                    stats.variance = moments.variance();
                    stats.pixels = 1;
                }
                (stats, seen)
            },
        )
        .collect();
    let mut total = PilotStats::default();
    for (stats, seen) in per_pixel {
        total = total.add(&stats);
        if let Some(all) = sightings.as_deref_mut() {
            all.extend(seen);
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_balances_the_light_to_come_against_its_cost() {
        // m₂ = 2, c = 4, C = 8, V = 0.25: k = √(2 · 8 ∕ (4 · 0.25)) = 4.
        let stats = PilotStats {
            decisions: 100,
            moment: 200.0,
            cost: 400.0,
            paths: 10,
            rays: 80,
            variance: 2.5,
            pixels: 10,
            ..PilotStats::default()
        };
        assert!((stats.scale().unwrap() - 4.0).abs() < 1e-12);
        // Noisier pixels leave less to gain from long paths.
        let noisy = PilotStats {
            variance: 2500.0,
            ..stats
        };
        assert_eq!(noisy.scale(), Some(Roulette::MIN_SCALE));
        // Paths that seldom outlive the roulette depth (a twentieth of the rays past it):
        // the averages of the few that do are not trusted, and the roulette stays lenient.
        let rare = PilotStats { cost: 3.9, ..stats };
        assert_eq!(rare.scale(), Some(RARE_SCALE));
        let few = PilotStats {
            decisions: MIN_DECISIONS - 1,
            ..stats
        };
        assert_eq!(few.scale(), None);
        let still = PilotStats {
            variance: 0.0,
            ..stats
        };
        assert_eq!(still.scale(), None);
    }

    /// A closed sphere of albedo 0.8 that emits 0.2 inwards, seen from its centre by a camera
    /// of `width` × `height`: paths there live long, and the pilot predicts.
    fn closed_room(width: usize, height: usize) -> (World, Camera) {
        let world = super::super::continuation::tests::closed_room();
        (world, Camera::new(width, height, 1.0))
    }

    /// How many paths the pilot traces for a render of `spp` samples per pixel of `world`
    /// through `camera`; `None` when `cancel` stopped it.
    fn pilot_paths(
        world: &World,
        camera: &Camera,
        spp: u64,
        cancel: Option<&AtomicBool>,
    ) -> Option<u64> {
        let (index, emitters) = (WorldIndex::build(world), Emitters::new(world));
        let options = PathOptions::default();
        learn(camera, world, &index, &emitters, &options, spp, cancel).map(|(_, paths)| paths)
    }

    #[test]
    fn the_pilot_traces_at_most_a_sixteenth_of_the_renders_paths() {
        for (width, height, spp) in [(40, 30, 64), (24, 24, 160), (12, 10, 2048), (64, 48, 16)] {
            let (world, camera) = closed_room(width, height);
            let render = (width * height) as u64 * spp;
            let paths = pilot_paths(&world, &camera, spp, None).unwrap();
            assert!(
                paths > 0 && paths * PILOT_SHARE <= render,
                "{width} × {height} at {spp} spp: {paths} pilot paths for {render}"
            );
        }
        // However many samples, the pilot is at most its full grid's five passes.
        let (world, camera) = closed_room(64, 64);
        let paths = pilot_paths(&world, &camera, u64::MAX, None).unwrap();
        let most = PILOT_PIXELS * PILOT_SAMPLES * (1 + PILOT_ROUNDS as u64);
        assert!(paths > 0 && paths <= most, "{paths} pilot paths");
        // A 1-sample preview of 64 × 48 (a quarter of 256 × 192) runs none.
        let (world, camera) = closed_room(64, 48);
        assert_eq!(pilot_paths(&world, &camera, 1, None), Some(0));
    }

    #[test]
    fn the_pilots_grid_keeps_to_its_share_at_any_shape() {
        for (width, height) in [(1000, 1), (1, 700), (33, 17), (320, 240), (256, 256)] {
            for spp in [1, 7, 64, 1000] {
                let allowed = (width * height) as u64 * spp
                    / (PILOT_SHARE * PILOT_SAMPLES * (1 + PILOT_ROUNDS as u64));
                let n = pilot_pixels(width, height, spp).len() as u64;
                assert!(
                    n <= allowed.min(PILOT_PIXELS),
                    "{width} × {height}, {spp}: {n}"
                );
                assert!(
                    n == 0 || n >= MIN_PILOT_PIXELS / 2,
                    "{width} × {height}: {n}"
                );
            }
        }
        // The reference scenes' 128 × 128 and 256 × 256 at 64 spp keep the full grid.
        assert_eq!(pilot_pixels(128, 128, 64).len(), 1024);
        assert_eq!(pilot_pixels(256, 256, 64).len(), 1024);
    }

    #[test]
    fn without_predictions_the_pilot_learns_the_scale_alone() {
        let (world, camera) = closed_room(40, 30);
        let (index, emitters) = (WorldIndex::build(&world), Emitters::new(&world));
        let on = PathOptions::default();
        let off = PathOptions {
            roulette_predictions: false,
            ..on
        };
        let learn_with = |options: &PathOptions| {
            learn(&camera, &world, &index, &emitters, options, 64, None).expect("not stopped")
        };
        let ((predicting, _), (alone, _)) = (learn_with(&on), learn_with(&off));
        // Every wall of the closed room predicts, unless the predictions are off.
        assert!(predicting.continuation.is_some());
        assert_eq!(alone.continuation, None);
        // The scale is still learned: paths in a bright closed room live longer than the
        // classic rule lets them.
        assert!(alone.scale > 1.0, "scale {}", alone.scale);
    }

    #[test]
    fn a_stop_ends_the_pilot_before_its_next_path() {
        let (world, camera) = closed_room(40, 30);
        let stop = AtomicBool::new(true);
        assert_eq!(pilot_paths(&world, &camera, 64, Some(&stop)), None);
        // A pass stopped before its first path traces none and says it was stopped.
        let (index, emitters) = (WorldIndex::build(&world), Emitters::new(&world));
        let options = PathOptions::default();
        let pixels = pilot_pixels(40, 30, 64);
        assert!(!pixels.is_empty());
        let pass = |stop: &AtomicBool| {
            pilot(
                &camera,
                &world,
                &index,
                &emitters,
                &options,
                &pixels,
                Some(stop),
                1.0,
                None,
                None,
            )
        };
        let stats = pass(&stop);
        assert!(stats.cancelled);
        assert_eq!(stats.traced, 0);
        // Unset, the same pass traces every pixel's samples.
        stop.store(false, Ordering::Relaxed);
        let stats = pass(&stop);
        assert!(!stats.cancelled);
        assert_eq!(stats.traced, pixels.len() as u64 * PILOT_SAMPLES);
    }
}
