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
//! and sample ranges rendered apart still merge exactly. The pilot traces a grid of about
//! [`PILOT_PIXELS`] pixels at [`PILOT_SAMPLES`] samples each, twice: the first with the
//! classic rule, the second with the scale the first found (the variance and cost it measures
//! depend on the rule it renders with); the second's answer is used.
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
//! from the other vertices' decisions alone.

use super::continuation::{ContinuationCache, Sighting};
use super::integrator::{DiffuseDeparture, PathLog};
use super::moments::Moments;
use super::{path_context, CameraSampler, SampleStream};
use crate::camera::Camera;
use crate::color::Color;
use crate::lights::Emitters;
use crate::options::{PathOptions, Roulette};
use crate::scene::{World, WorldIndex};
use rayon::prelude::*;

/// About how many pixels the pilot traces (a grid over the image).
const PILOT_PIXELS: usize = 1024;
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
/// scene's averages) and learns where that light is predictable.
pub fn learn_roulette(camera: &Camera, world: &World, options: &PathOptions) -> LearnedRoulette {
    match options.roulette {
        Roulette::Scale(scale) => LearnedRoulette::fixed(scale),
        Roulette::Learned => {
            let index = WorldIndex::build(world);
            let emitters = Emitters::with_sampler(world, options.light_sampler);
            learned(camera, world, &index, &emitters, options)
        }
    }
}

/// The pilot's roulette for `world`, its `index` and `emitters` already built.
pub(super) fn learned(
    camera: &Camera,
    world: &World,
    index: &WorldIndex,
    emitters: &Emitters,
    options: &PathOptions,
) -> LearnedRoulette {
    // First the predictions, from paths that no roulette ends (so that what they record past
    // a vertex is the light there, not the roulette's noise), cut at a depth where what
    // they would still gather is lost in that noise anyway.
    let mut sightings = Vec::new();
    let whole = PathOptions {
        max_depth: options.max_depth.min(SIGHTING_DEPTH),
        roulette_depth: u32::MAX,
        ..*options
    };
    pilot(
        camera,
        world,
        index,
        emitters,
        &whole,
        1.0,
        None,
        Some(&mut sightings),
    );
    let continuation = ContinuationCache::learn(&sightings);
    drop(sightings);
    // The variance and cost a pilot measures depend on the scale it renders with: each pass
    // renders with the last one's answer, until the answer settles.
    let mut k = 1.0;
    for _ in 0..PILOT_ROUNDS {
        let stats = pilot(
            camera,
            world,
            index,
            emitters,
            options,
            k,
            continuation.as_ref(),
            None,
        );
        let Some(next) = stats.scale() else {
            break;
        };
        let settled = (next / k - 1.0).abs() < SETTLED;
        k = next;
        if settled {
            break;
        }
    }
    LearnedRoulette {
        scale: k,
        continuation,
    }
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

/// One pilot pass with the roulette at scale `k` and the predictions `continuation`, adding
/// what its paths saw past diffuse vertices to `sightings` when given (in the pixels'
/// order).
#[allow(clippy::too_many_arguments)]
fn pilot(
    camera: &Camera,
    world: &World,
    index: &WorldIndex,
    emitters: &Emitters,
    options: &PathOptions,
    k: f64,
    continuation: Option<&ContinuationCache>,
    mut sightings: Option<&mut Vec<Sighting>>,
) -> PilotStats {
    let records = sightings.is_some();
    let (width, height) = (camera.hsize(), camera.vsize());
    let stride = ((width * height) as f64 / PILOT_PIXELS as f64)
        .sqrt()
        .ceil()
        .max(1.0) as usize;
    let pixels: Vec<(usize, usize)> = (stride / 2..height)
        .step_by(stride)
        .flat_map(|y| (stride / 2..width).step_by(stride).map(move |x| (x, y)))
        .collect();
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
                    stream.start(s);
                    let (ray, _) = sampler.ray(x, y, &mut stream);
                    let before = context.rays;
                    log.clear();
                    let (radiance, _) = context.radiance_logged(ray, &mut stream, log);
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
}
