//! Adaptive sampling: a render's samples shared out among its pixels by how noisy each is
//! for what its samples cost, instead of the same number everywhere.
//!
//! A pixel's error after n samples is σ ∕ √n, σ being the spread of its samples, so the
//! image's mean squared error, Σ σᵢ² ∕ nᵢ over the pixels, is least for a given time,
//! Σ cᵢ nᵢ (cᵢ a sample's cost there), when nᵢ grows as σᵢ ∕ √cᵢ: the quiet pixels (a plain
//! wall, the black sky) give samples to the noisy ones (a caustic, the edge of a soft shadow,
//! a glossy highlight).
//!
//! The spreads and costs come from a pilot pass ([`prepare_render`]): the first samples of
//! every pixel (an eighth of the samples per pixel), whose variance and rays are averaged over
//! each pixel's neighbours, leaving the pixel itself out. The pilot's samples are the
//! render's own first samples, kept in the plan and added to the image, so the pilot costs
//! nothing; and as a pixel's count depends on its neighbours' samples, not its own, each
//! pixel's estimate stays unbiased (were its own samples to decide how many it takes, a pixel
//! that drew a rare bright sample would take more and dilute it); its own samples weigh only
//! in the plan's three choices over the whole image, whether to plan, how far to trust the
//! pilot's map and the scale that meets the budget, one part in the number of pixels. The
//! plan is made only where it foresees a gain: planned from one half of the pilot's samples
//! and judged by the other, it must take [`MIN_GAIN`] off the squared error; else every pixel
//! takes the same.
//!
//! A pilot can miss what is rare: a caustic through rough glass is a few bright paths in
//! thousands, and a pixel whose pilot drew none of them looks quiet. Such a map is mostly
//! luck, and the two halves of the pilot show it, each bright where the other drew its
//! spikes; the plan then trusts the map only as far as the halves agree ([`disagreement`],
//! [`defence`]), and shares the rest of the budget evenly ([`defended`]): a pixel that saw
//! nothing still takes that part of the even share. `--sample-allocation by-noise-trusted`
//! turns the defence off.
//!
//! A plan is a pure function of the scene, the seed and the samples per pixel, so the image
//! is still the same for any thread count, and a range of the nominal samples
//! ([`SamplePlan::range`]) maps to a range of each pixel's own: slices of `0..spp` rendered
//! apart still merge into the render of the whole.

use super::moments::Moments;
use super::{learn_roulette, render_path_logged, Aovs, LearnedRoulette, PathJob};
use crate::camera::Camera;
use crate::color::Color;
use crate::film::{Film, SharedFilm};
use crate::math::random::{Jitter, SplitMix64};
use crate::options::{PathOptions, SampleAllocation};
use crate::scene::World;
use std::ops::Range;
use std::sync::atomic::AtomicBool;
use std::sync::OnceLock;

/// Fewer samples per pixel than this are shared out evenly: the pilot's share would be too
/// few samples to judge a pixel by.
pub const MIN_ADAPTIVE_SPP: u64 = 16;

/// The pilot's samples per pixel are the render's divided by this: the fewest any pixel
/// takes.
const PILOT_SHARE: u64 = 8;

/// How far, in pixels, a pixel's variance and cost are averaged over its neighbours (a
/// square of 5 × 5, the pixel itself left out: at 64 samples per pixel, some 190 samples to
/// each estimate).
const SMOOTHING_RADIUS: usize = 2;

/// The most samples a pixel takes, as a multiple of the samples per pixel. The plan's rule
/// (σ ∕ √cost) holds for samples whose error falls as 1 ∕ n; a Sobol sampler's fall faster
/// where a pixel's spread comes from a few dimensions (a pixel across a lamp's edge: a
/// large spread, its stratified samples nearly exact), so such pixels need fewer than their
/// spread asks for, and the cap keeps them from taking the budget. Where the spread is that
/// of rare paths (a small lamp seen in a glossy plate, a sphere lamp's highlights) the rule
/// holds and the cap only starves the pixels that need the samples most. Measured on twelve
/// scenes at 64 samples (the squared error at the same rays against 2048-sample references,
/// seeds 1–8; docs/performance.md, "The path tracer's constants swept"): 6 against 4 takes
/// 31 % off the sphere lamp's error, 19 % off Veach MIS's, 8 % off the Bitterli Cornell
/// box's and 2 % off envmap's, the Cornell box and spheres-materials even (within half a
/// percent), the mirror balls 3 % more; 8 took twice as much off the first two but cost the
/// Cornell box and spheres-materials 1.5 %, 16 and 32 cost the Cornell box 14 % and 24 %, and
/// 2 cost up to 2.3 times as much.
const MAX_SHARE: f64 = 6.0;

/// The least share of the squared error an adaptive plan must foresee taking off, planned
/// from one half of the pilot and judged by the other (else the samples are shared evenly).
const MIN_GAIN: f64 = 0.1;

/// How many samples each pixel takes, for a render of `spp` samples per pixel at the cost of
/// `spp` everywhere, and the pilot's samples, the first of every pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplePlan {
    spp: u64,
    counts: Vec<u64>,
    /// How many samples of each pixel the pilot took (the first).
    pilot: u64,
    /// The pilot's samples as the films summed them, from empty films (the image's size).
    kept: Film,
    /// The same of the albedo, normal, depth and sample-count films, where the pilot had them.
    kept_aovs: Option<[Film; 4]>,
}

impl SamplePlan {
    /// The width and height of the image the plan is for.
    pub fn size(&self) -> (usize, usize) {
        (self.kept.width(), self.kept.height())
    }

    /// The samples per pixel on average.
    pub fn spp(&self) -> u64 {
        self.spp
    }

    /// The samples pixel (`x`, `y`) takes in a render of `spp`.
    pub fn count(&self, x: usize, y: usize) -> u64 {
        self.counts[y * self.kept.width() + x]
    }

    /// The pixel's own sample indices that the nominal range `nominal` (a part of `0..spp`,
    /// as a render's sample slice is given) stands for: the same share of its count. Ranges
    /// that split `0..spp` split every pixel's samples the same way.
    pub fn range(&self, x: usize, y: usize, nominal: &Range<u64>) -> Range<u64> {
        let count = u128::from(self.count(x, y));
        let scale = |s: u64| (u128::from(s) * count / u128::from(self.spp.max(1))) as u64;
        scale(nominal.start)..scale(nominal.end.max(nominal.start))
    }

    /// How many of the first samples of every pixel the plan holds, as the films summed
    /// them (with the AOVs' when `aovs`): a range from 0 past them may start from these.
    pub(super) fn kept_samples(&self, aovs: bool) -> u64 {
        if aovs && self.kept_aovs.is_none() {
            0
        } else {
            self.pilot
        }
    }

    /// The pilot's sums of pixel (`x`, `y`): the image's sum and weight, and the AOVs' sums
    /// (albedo, normal, depth, samples) with the depth's weight, where it had them.
    pub(super) fn kept(&self, x: usize, y: usize) -> (Color, f64, Option<([Color; 4], f64)>) {
        let aovs = self
            .kept_aovs
            .as_ref()
            .map(|films| (films.each_ref().map(|f| f.sum(x, y)), films[2].weight(x, y)));
        (self.kept.sum(x, y), self.kept.weight(x, y), aovs)
    }
}

/// What the pilot records of each pixel: the variance of its samples (the mean over the
/// channels), of the even and the odd ones apart and of all, and a sample's cost in rays.
#[derive(Debug, Clone, Copy)]
pub(super) struct PilotPixel {
    variance: [f64; 3],
    cost: f64,
}

impl PilotPixel {
    /// The record of a pixel whose `samples` samples had the moments `halves` (the even and
    /// the odd) and cast `rays`, shaded `vertices` surfaces and solved `solves` reflections
    /// through a mirror ball.
    pub fn new(halves: &[Moments; 2], samples: u64, rays: u64, vertices: u64, solves: u64) -> Self {
        let [even, odd] = halves;
        // A sample's cost, in rays: its rays, two and a half times its surfaces shaded and
        // ten times its mirror-ball reflections (an iterated root), and a quarter for the
        // camera and the film (weights fitted to the time each pixel's samples took in the
        // reference scenes).
        let work = rays as f64 + 2.5 * vertices as f64 + 10.0 * solves as f64;
        Self {
            variance: [even.variance(), odd.variance(), even.merged(odd).variance()],
            cost: 0.25 + work / samples.max(1) as f64,
        }
    }
}

/// The pilot's record, row by row (each row set once, by the thread that renders it).
pub(super) struct PilotLog {
    pub rows: Vec<OnceLock<Vec<PilotPixel>>>,
}

/// Whether a render of `spp` samples per pixel in one pass with `options` plans its samples
/// ([`prepare_render`] makes a pilot and, where it foresees a gain, a plan).
pub fn plans_samples(options: &PathOptions, spp: u64) -> bool {
    matches!(
        options.allocation,
        SampleAllocation::ByNoise | SampleAllocation::ByNoiseTrusted
    ) && spp >= MIN_ADAPTIVE_SPP
}

/// The roulette of a render of `spp` samples per pixel in one pass with `options` (learned
/// once, for the pilot and the render), and its plan where samples are shared out
/// adaptively ([`plan_samples`]; else none). With `aovs`, the pilot keeps their sums too.
/// Once `cancel` is set the pilots stop, and no plan is made (nor a roulette learned: the
/// classic rule's is answered, for a render that will stop at once).
pub fn prepare_render(
    camera: &Camera,
    world: &World,
    options: &PathOptions,
    spp: u64,
    aovs: bool,
    cancel: Option<&AtomicBool>,
) -> (LearnedRoulette, Option<SamplePlan>) {
    let Some(roulette) = learn_roulette(camera, world, options, spp, cancel) else {
        return (LearnedRoulette::fixed(1.0), None);
    };
    let plan = plans_samples(options, spp)
        .then(|| plan_samples(camera, world, options, Some(&roulette), spp, aovs, cancel))
        .flatten();
    (roulette, plan)
}

/// Plans a render of `world` through `camera` at `spp` samples per pixel, from a pilot pass
/// of its first samples with `options` (see the [module](self)): where the pilot foresees no
/// gain, `spp` for every pixel (the pilot's samples still kept). `None` below
/// [`MIN_ADAPTIVE_SPP`], or where `cancel` was set before the pilot was through (or were the
/// pilot refused its film). With `aovs`, the pilot keeps their sums too. The pilot plays
/// `roulette` where given, which should be the one the render plays ([`prepare_render`]
/// learns it once for both); else the one `options` ask for.
pub fn plan_samples(
    camera: &Camera,
    world: &World,
    options: &PathOptions,
    roulette: Option<&LearnedRoulette>,
    spp: u64,
    aovs: bool,
    cancel: Option<&AtomicBool>,
) -> Option<SamplePlan> {
    if spp < MIN_ADAPTIVE_SPP {
        return None;
    }
    let (width, height) = (camera.hsize(), camera.vsize());
    let pilot = spp / PILOT_SHARE;
    let film = SharedFilm::from(Film::with_filter(width, height, options.filter).ok()?);
    let aov_films = aovs.then(|| Aovs::new(width, height));
    let log = PilotLog {
        rows: (0..height).map(|_| OnceLock::new()).collect(),
    };
    let job = PathJob {
        options: *options,
        samples: 0..pilot,
        plan: None,
        progress: None,
        cancel,
        on_row: None,
        roulette,
    };
    let mut done = vec![false; height];
    render_path_logged(
        camera,
        world,
        &job,
        &film,
        aov_films.as_ref(),
        &mut done,
        Some(&log),
    )
    .ok()?;
    let pixels: Vec<PilotPixel> = log
        .rows
        .into_iter()
        .flat_map(|row| row.into_inner().unwrap_or_default())
        .collect();
    if pixels.len() != width * height {
        return None;
    }
    let smooth = |value: &dyn Fn(&PilotPixel) -> f64| {
        let values: Vec<f64> = pixels.iter().map(value).collect();
        neighbours_mean(&values, width, height, SMOOTHING_RADIUS)
    };
    let cost = smooth(&|p| p.cost);
    let [even, odd] = [0, 1].map(|h| smooth(&|p: &PilotPixel| p.variance[h]));
    // How far the halves' maps disagree is how far a map of the pilot's noise is itself
    // noise: the plans lean toward the even share by its square (see [`defence`]).
    let distrust = match options.allocation {
        SampleAllocation::ByNoiseTrusted => 0.0,
        _ => defence(disagreement(&even, &odd)),
    };
    let low = pilot as f64;
    // Planned from one half of the pilot and judged by the other, a plan must foresee a
    // gain: where the spreads are noise, it would not (the halves disagree).
    let n = spp as f64;
    let judged = |plan: &[f64], judge: &[f64]| -> (f64, f64) {
        (plan.iter().zip(judge))
            .map(|(&share, &v)| (usable(v) / share, usable(v) / n))
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y))
    };
    let foreseen = match (
        shares(&even, &cost, spp, low).map(|s| defended(s, distrust, spp)),
        shares(&odd, &cost, spp, low).map(|s| defended(s, distrust, spp)),
    ) {
        (Some(a), Some(b)) => {
            let (planned_a, even_a) = judged(&a, &odd);
            let (planned_b, even_b) = judged(&b, &even);
            planned_a + planned_b < (1.0 - MIN_GAIN) * (even_a + even_b)
        }
        _ => false,
    };
    let variance = smooth(&|p| p.variance[2]);
    let counts = match shares(&variance, &cost, spp, low).map(|s| defended(s, distrust, spp)) {
        Some(shares) if foreseen => {
            let mut dither = SplitMix64::new(options.seed ^ 0x726f_756e_6469_6e67);
            shares
                .iter()
                .map(|&share| ((share + dither.next_offset()).floor() as u64).max(pilot))
                .collect()
        }
        // No gain foreseen: the same number everywhere, the pilot's samples still kept.
        _ => vec![spp; width * height],
    };
    Some(SamplePlan {
        spp,
        counts,
        pilot,
        kept: film.into_film(),
        kept_aovs: aov_films
            .map(|a| [a.albedo, a.normal, a.depth, a.samples].map(SharedFilm::into_film)),
    })
}

/// `v` where it is a usable variance or cost, else 0.
fn usable(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        v
    } else {
        0.0
    }
}

/// How far two estimates `a` and `b` of the same map of variances disagree, from 0 (the
/// same) to 1 (each bright where the other is dark): Σ |a − b| ∕ Σ (a + b).
///
/// The halves of the pilot are independent estimates of each pixel's variance, so their
/// difference measures the error of the whole pilot's estimate: were a half's relative
/// error ε, the difference's would be √2 ε and the whole's ε ∕ √2, so that this ratio is the
/// whole map's mean relative error (Σ |a − b| is twice Σ of the whole's error, Σ (a + b)
/// twice the whole). Where the noise is rare bright paths (a caustic seen through rough
/// glass, a small lamp found only by chance) each half saw its own few spikes and the ratio
/// nears 1: the map says where the pilot was lucky, not where the noise is, and the pixels
/// it calls quiet may hold paths it never drew.
fn disagreement(a: &[f64], b: &[f64]) -> f64 {
    let (apart, total) = (a.iter().zip(b))
        .map(|(&x, &y)| (usable(x), usable(y)))
        .fold((0.0, 0.0), |(d, t), (x, y)| (d + (x - y).abs(), t + x + y));
    if total > 0.0 {
        (apart / total).min(1.0)
    } else {
        0.0
    }
}

/// The share of the budget to spread evenly for a pilot whose halves disagree by
/// `disagreement`: its square. A map of relative error ε misplaces the samples by about ε ∕ 2
/// (they follow σ, the square root of the variance), and a plan's excess error over the best
/// one grows as the square of the misplacement: the noise of an ordinary pilot (its halves
/// apart by a tenth to a quarter on the reference scenes, the Bitterli Cornell box and the
/// bench's lamps) costs a plan little, and is met with 1–6 % of the budget; a pilot that
/// drew rare paths (0.66–0.96 on the glass gem's caustics) keeps a half or more of it
/// even. Measured against the disagreement itself as the share on twelve scenes, eight
/// seeds each (docs/performance.md, "The by-noise plan's defence"): the square took the
/// glass gem's loss back as well, and cost the well-sampled scenes a third to a half as
/// much.
fn defence(disagreement: f64) -> f64 {
    disagreement * disagreement
}

/// The planned `shares` of a render of `spp` samples per pixel mixed with the even share by
/// `distrust` (0: as planned, 1: `spp` everywhere): the part of the budget the pilot's map
/// cannot be trusted with is spread evenly, as defensive importance sampling mixes an even
/// density into a learned one. This is the plan's floor where the pilot may have missed
/// rare paths: every pixel takes at least `distrust` × `spp`, and where the halves agree
/// the plan stays nearly the one the map asks for.
/// The mixture costs what the two parts cost, each the budget, and stays within the bounds
/// both keep.
fn defended(shares: Vec<f64>, distrust: f64, spp: u64) -> Vec<f64> {
    let even = spp as f64;
    (shares.into_iter())
        .map(|share| (1.0 - distrust) * share + distrust * even)
        .collect()
}

/// `values` (a `width` × `height` image, row by row) averaged over the square of `radius`
/// around each pixel (the part of it inside the image), the pixel itself left out.
fn neighbours_mean(values: &[f64], width: usize, height: usize, radius: usize) -> Vec<f64> {
    let window = |i: usize, n: usize| i.saturating_sub(radius)..(i + radius + 1).min(n);
    let mut rows = vec![0.0; values.len()];
    for y in 0..height {
        let row = &values[y * width..(y + 1) * width];
        for x in 0..width {
            rows[y * width + x] = row[window(x, width)].iter().sum::<f64>();
        }
    }
    let mut out = vec![0.0; values.len()];
    for y in 0..height {
        let w = window(y, height);
        for x in 0..width {
            let cells = w.len() * window(x, width).len();
            let sum = w.clone().map(|yy| rows[yy * width + x]).sum::<f64>();
            let own = values[y * width + x];
            out[y * width + x] = if cells > 1 {
                (sum - own) / (cells - 1) as f64
            } else {
                own
            };
        }
    }
    out
}

/// Each pixel's share of samples for the pixels' `variance` and `cost` per sample: as many
/// as σ ∕ √cost (σ² being the variance), which makes the image's squared error least for the
/// time (the error is Σ σ² ∕ n, the time Σ cost × n), between `low` and [`MAX_SHARE`] ×
/// `spp`, costing in all what `spp` samples of every pixel would. The scale is found by
/// bisection (the clamped cost grows with it). `None` where nothing varies.
fn shares(variance: &[f64], cost: &[f64], spp: u64, low: f64) -> Option<Vec<f64>> {
    let n = spp as f64;
    let (low, high) = (low.max(1.0), n * MAX_SHARE);
    let cost: Vec<f64> = cost.iter().map(|&c| usable(c).max(1.0)).collect();
    let weight: Vec<f64> = (variance.iter().zip(&cost))
        .map(|(&v, &c)| (usable(v) / c).sqrt())
        .collect();
    let mean = weight.iter().sum::<f64>() / weight.len().max(1) as f64;
    if !(mean > 0.0 && mean.is_finite()) {
        return None;
    }
    let share = |scale: f64, w: f64| (scale * w).clamp(low, high);
    let spent = |scale: f64| {
        (weight.iter().zip(&cost))
            .map(|(&w, &c)| c * share(scale, w))
            .sum::<f64>()
    };
    // The cost runs from that of `low` samples each (scale 0) to that of `high` each, and
    // the budget lies between. Past the scale that holds the faintest noisy pixel at `high`
    // nothing changes (and where most pixels are silent, as around a furnace's ball, the
    // budget is never reached: the search stops there instead of doubling to overflow).
    let budget = n * cost.iter().sum::<f64>();
    let faintest = weight
        .iter()
        .copied()
        .filter(|&w| w > 0.0)
        .fold(f64::INFINITY, f64::min);
    let saturated = high / faintest;
    let (mut lo, mut hi) = (0.0, (n / mean).min(saturated));
    while spent(hi) < budget && hi < saturated {
        hi = (hi * 2.0).min(saturated);
    }
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if spent(mid) < budget {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(weight.iter().map(|&w| share(hi, w)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_follow_the_spread_for_the_cost_within_the_budget_and_the_bounds() {
        // Ten quiet pixels, a noisy one, a very noisy one and a silent one; the noisy one
        // costs twice as much a sample.
        let mut variance = vec![1.0; 10];
        variance.extend([64.0, 1e8, 0.0]);
        let mut cost = vec![1.0; 10];
        cost.extend([2.0, 1.0, 1.0]);
        let counts = shares(&variance, &cost, 64, 8.0).expect("uneven");
        // The very noisy one is held to 6 × 64, the silent one given 64 ∕ 8.
        assert_eq!(counts[11], 384.0);
        assert_eq!(counts[12], 8.0);
        // The noisy one takes σ ∕ √cost = 8 ∕ √2 times a quiet one's share.
        let ratio = counts[10] / counts[0];
        assert!((ratio - 8.0 / 2f64.sqrt()).abs() < 1e-9, "{counts:?}");
        // And the whole costs what 64 samples of each would.
        let spent: f64 = counts.iter().zip(&cost).map(|(&n, c)| n * c).sum();
        let budget = 64.0 * cost.iter().sum::<f64>();
        assert!(
            (spent - budget).abs() <= 1e-6 * budget,
            "{spent} against {budget}"
        );
    }

    #[test]
    fn a_budget_the_noisy_few_cannot_spend_holds_them_at_the_most() {
        // A furnace's ball in a silent sky: even at six times the samples the two noisy
        // pixels spend less than the budget, so they take the most and the rest the least.
        let mut variance = vec![0.0; 1000];
        variance.extend([1.0, 4.0]);
        let counts = shares(&variance, &[1.0; 1002], 64, 8.0).expect("uneven");
        assert!(counts[..1000].iter().all(|&n| n == 8.0));
        assert_eq!(&counts[1000..], &[384.0, 384.0]);
    }

    #[test]
    fn even_noise_shares_evenly_and_none_at_all_asks_for_no_plan() {
        assert_eq!(shares(&[2.0; 9], &[3.0; 9], 64, 8.0), Some(vec![64.0; 9]));
        assert_eq!(shares(&[0.0; 9], &[1.0; 9], 64, 8.0), None);
        assert_eq!(shares(&[f64::NAN; 9], &[1.0; 9], 64, 8.0), None);
    }

    #[test]
    fn halves_that_agree_are_trusted_and_halves_that_saw_different_spikes_are_not() {
        let map = [1.0, 4.0, 9.0, 0.0];
        let planned = vec![8.0, 16.0, 40.0, 0.0];
        assert_eq!(disagreement(&map, &map), 0.0);
        assert_eq!(defended(planned.clone(), 0.0, 16), planned);
        // Each half bright where the other is dark: nothing of the map is to be trusted,
        // and every pixel takes the even share.
        assert_eq!(disagreement(&[2.0, 0.0], &[0.0, 2.0]), 1.0);
        assert_eq!(defended(planned.clone(), 1.0, 16), vec![16.0; 4]);
        // Halves off by a tenth of their level: a tenth of the budget is shared evenly,
        // and the whole still costs the budget.
        let d = disagreement(&[1.1, 2.2], &[0.9, 1.8]);
        assert!((d - 0.1).abs() < 1e-12, "{d}");
        let s = defended(planned, d, 16);
        let expected = [8.8, 16.0, 37.6, 1.6];
        assert!(
            s.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12),
            "{s:?}"
        );
        assert!((s.iter().sum::<f64>() - 64.0).abs() < 1e-12);
        // Nothing measured (or nothing usable) is no evidence against the map.
        assert_eq!(disagreement(&[0.0, f64::NAN], &[0.0, 0.0]), 0.0);
    }

    #[test]
    fn slices_of_the_nominal_samples_split_each_pixels_own() {
        let plan = SamplePlan {
            spp: 10,
            counts: vec![1, 7, 80],
            pilot: 1,
            kept: Film::new(3, 1),
            kept_aovs: None,
        };
        for x in 0..3 {
            let cuts = [0, 3, 3, 7, 10];
            let mut next = 0;
            for pair in cuts.windows(2) {
                let range = plan.range(x, 0, &(pair[0]..pair[1]));
                assert_eq!(range.start, next, "slices follow one another");
                next = range.end;
            }
            assert_eq!(next, plan.count(x, 0), "and cover the pixel's samples");
        }
        // The whole render at twice the nominal range takes each pixel's count twice over.
        assert_eq!(plan.range(1, 0, &(0..20)), 0..14);
    }

    #[test]
    fn each_pixel_takes_its_neighbours_mean_leaving_itself_out() {
        let mut values = vec![0.0; 81];
        values[4 * 9 + 4] = 24.0;
        let out = neighbours_mean(&values, 9, 9, 2);
        // The spike is not its own estimate; its neighbours within two pixels share it.
        assert_eq!(out[4 * 9 + 4], 0.0);
        assert_eq!(out[2 * 9 + 2], 1.0);
        assert_eq!(out[0], 0.0);
        // A constant stays itself, at the edges too.
        assert!(neighbours_mean(&[4.0; 12], 4, 3, 2)
            .iter()
            .all(|&v| (v - 4.0).abs() < 1e-12));
    }
}
