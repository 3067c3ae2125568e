//! Adaptive sampling: a render's samples shared out among its pixels by how noisy each is,
//! instead of the same number everywhere.
//!
//! A pixel's error after n samples is σ ∕ √n, σ being the spread of its samples, so the
//! image's mean squared error, Σ σᵢ² ∕ nᵢ over the pixels, is least for a given total of
//! samples when nᵢ grows as σᵢ: the quiet pixels (a plain wall, the black sky) give samples
//! to the noisy ones (a caustic, the edge of a soft shadow, a glossy highlight). Where the
//! spread varies across the image, as it does in most scenes, the same total buys a
//! markedly smaller error (on the reference scenes, a third to two thirds of the RMSE).
//!
//! The spreads come from a pilot pass before the render ([`plan_samples`]): a few samples of
//! every pixel on a seed of its own, their variance smoothed over each pixel's neighbours (a
//! few samples of one pixel estimate it poorly, and noise comes in patches). The pilot's
//! samples are not in the image: each pixel's count is then a function of other numbers
//! than those it averages, so every pixel's estimate stays unbiased (taking a pixel's own
//! samples both to decide how many it takes and to average them would bias it: a pixel that
//! drew a rare bright sample would take more samples and dilute it).
//!
//! A plan is a pure function of the scene, the seed and the samples per pixel, so the image
//! is still the same for any thread count, and a range of the nominal samples
//! ([`SamplePlan::range`]) maps to a range of each pixel's own: slices of `0..spp` rendered
//! apart still merge into the render of the whole.

use super::{learn_roulette_scale, path_context, CameraSampler, SampleStream};
use crate::camera::Camera;
use crate::color::Color;
use crate::math::random::SplitMix64;
use crate::options::{PathOptions, Roulette, SampleAllocation};
use crate::scene::{Emitters, World, WorldIndex};
use rayon::prelude::*;
use std::ops::Range;

/// Fewer samples per pixel than this are shared out evenly: a pilot would cost too large a
/// part of them.
pub const MIN_ADAPTIVE_SPP: u64 = 16;

/// The pilot's samples per pixel are the render's divided by this (16: about 6 % of the
/// render's time), within [`PILOT_SPP`].
const PILOT_SHARE: u64 = 16;

/// The fewest and most samples per pixel of the pilot.
const PILOT_SPP: (u64, u64) = (2, 8);

/// How far, in pixels, a pixel's variance is averaged with its neighbours' (a square of
/// 5 × 5: with a 4-sample pilot, a hundred samples to each estimate).
const SMOOTHING_RADIUS: usize = 2;

/// The fewest samples a pixel takes, as a share of the samples per pixel: a pixel whose
/// pilot saw nothing vary may still hide something small and bright.
const MIN_SHARE: f64 = 1.0 / 8.0;

/// The most samples a pixel takes, as a multiple of the samples per pixel.
const MAX_SHARE: f64 = 8.0;

/// The least share of the squared error an adaptive plan must foresee taking off, planned
/// from one half of the pilot and judged by the other (else the samples are shared evenly).
const MIN_GAIN: f64 = 0.1;

/// How many samples each pixel takes, for a render of `spp` samples per pixel on average.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplePlan {
    width: usize,
    height: usize,
    spp: u64,
    counts: Vec<u64>,
}

impl SamplePlan {
    /// The width and height of the image the plan is for.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The samples per pixel on average.
    pub fn spp(&self) -> u64 {
        self.spp
    }

    /// The samples pixel (`x`, `y`) takes in a render of `spp`.
    pub fn count(&self, x: usize, y: usize) -> u64 {
        self.counts[y * self.width + x]
    }

    /// The pixel's own sample indices that the nominal range `nominal` (a part of `0..spp`,
    /// as a render's sample slice is given) stands for: the same share of its count. Ranges
    /// that split `0..spp` split every pixel's samples the same way.
    pub fn range(&self, x: usize, y: usize, nominal: &Range<u64>) -> Range<u64> {
        let count = u128::from(self.count(x, y));
        let scale = |s: u64| (u128::from(s) * count / u128::from(self.spp.max(1))) as u64;
        scale(nominal.start)..scale(nominal.end.max(nominal.start))
    }
}

/// `options` as a render of `spp` samples per pixel in one pass (or in slices of its
/// samples or rows) takes them, and its plan: where samples are shared out adaptively, the
/// roulette is learned here, once for the pilot and the render, and the plan made
/// ([`plan_samples`]); else `options` as they are, and no plan.
pub fn prepare_render(
    camera: &Camera,
    world: &World,
    options: &PathOptions,
    spp: u64,
) -> (PathOptions, Option<SamplePlan>) {
    if options.allocation != SampleAllocation::Adaptive || spp < MIN_ADAPTIVE_SPP {
        return (*options, None);
    }
    let options = match options.roulette {
        Roulette::Learned => PathOptions {
            roulette: Roulette::Scale(learn_roulette_scale(camera, world, options)),
            ..*options
        },
        Roulette::Scale(_) => *options,
    };
    let plan = plan_samples(camera, world, &options, spp);
    (options, plan)
}

/// The pilot's samples per pixel for a render of `spp`.
fn pilot_spp(spp: u64) -> u64 {
    (spp / PILOT_SHARE).clamp(PILOT_SPP.0, PILOT_SPP.1)
}

/// Plans a render of `world` through `camera` at `spp` samples per pixel on average, from a
/// pilot pass with `options` (see the [module](self)); `None` below [`MIN_ADAPTIVE_SPP`],
/// where samples are best shared out evenly. The roulette of `options` should be the one the
/// render uses (a scale, not one to learn: learning it is the caller's, once for both).
pub fn plan_samples(
    camera: &Camera,
    world: &World,
    options: &PathOptions,
    spp: u64,
) -> Option<SamplePlan> {
    if spp < MIN_ADAPTIVE_SPP {
        return None;
    }
    let (width, height) = (camera.hsize(), camera.vsize());
    let index = WorldIndex::build(world);
    let emitters = Emitters::new(world);
    let roulette_scale = match options.roulette {
        Roulette::Scale(k) => k,
        Roulette::Learned => 1.0,
    };
    let sampler = CameraSampler::new(camera, world, options.filter);
    // Its own seed: the plan is independent of the numbers the render averages.
    let seed = options.seed ^ 0x6164_6170_7469_7665;
    let samples = pilot_spp(spp);
    // Each pixel's variance per sample, from all its pilot samples and from each half of
    // them (the even and the odd), and its cost per sample.
    let pilot: Vec<PilotPixel> = (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let mut context = path_context(world, &index, &emitters, options, roulette_scale);
            let sampler = &sampler;
            (0..width)
                .map(move |x| {
                    let mut stream =
                        SampleStream::new(options.sampler, seed, x as u32, y as u32, 0);
                    let mut halves = [Moments::default(); 2];
                    let (rays, vertices) = (context.rays, context.vertices);
                    for s in 0..samples {
                        stream.start(s);
                        let (ray, _) = sampler.ray(x, y, &mut stream);
                        let (radiance, _) = context.radiance(ray, &mut stream);
                        halves[(s % 2) as usize].add(radiance);
                    }
                    // A sample costs its rays, twice its surfaces (shading one costs about
                    // two rays) and the camera's and film's share, about a ray's.
                    let work = (context.rays - rays) + 2 * (context.vertices - vertices);
                    PilotPixel {
                        variance: halves[0].merged(&halves[1]).variance(),
                        halves: halves.map(|h| h.variance()),
                        cost: 1.0 + work as f64 / samples as f64,
                    }
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let smooth = |value: &dyn Fn(&PilotPixel) -> f64| {
        let values: Vec<f64> = pilot.iter().map(value).collect();
        smoothed(&values, width, height, SMOOTHING_RADIUS)
    };
    let cost = smooth(&|p| p.cost);
    let [even, odd] = [0, 1].map(|h| smooth(&|p: &PilotPixel| p.halves[h]));
    // Planned from one half of the pilot and judged by the other, a plan must foresee a
    // gain: where the spreads are noise, it would not (the halves disagree).
    let n = spp as f64;
    let judged = |plan: &[f64], judge: &[f64]| -> (f64, f64) {
        (plan.iter().zip(judge))
            .map(|(&share, &v)| (usable(v) / share, usable(v) / n))
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y))
    };
    let (a, b) = (shares(&even, &cost, spp)?, shares(&odd, &cost, spp)?);
    let (planned_a, even_a) = judged(&a, &odd);
    let (planned_b, even_b) = judged(&b, &even);
    let foreseen = planned_a + planned_b < (1.0 - MIN_GAIN) * (even_a + even_b);
    if !foreseen {
        return None;
    }
    let shares = shares(&smooth(&|p| p.variance), &cost, spp)?;
    let mut dither = SplitMix64::new(options.seed ^ 0x726f_756e_6469_6e67);
    let counts = shares
        .iter()
        .map(|&share| {
            let u = (dither.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
            ((share + u).floor() as u64).max(1)
        })
        .collect();
    Some(SamplePlan {
        width,
        height,
        spp,
        counts,
    })
}

/// What the pilot finds of one pixel: its variance per sample (the mean over the channels),
/// that of each half of its samples, and its cost per sample.
struct PilotPixel {
    variance: f64,
    halves: [f64; 2],
    cost: f64,
}

/// The count, sum and sum of squares of a pixel's finite samples.
#[derive(Debug, Clone, Copy, Default)]
struct Moments {
    n: f64,
    sum: Color,
    squares: Color,
}

impl Moments {
    fn add(&mut self, radiance: Color) {
        if radiance.red.is_finite() && radiance.green.is_finite() && radiance.blue.is_finite() {
            self.n += 1.0;
            self.sum += radiance;
            self.squares += radiance.hadamard(radiance);
        }
    }

    fn merged(&self, other: &Self) -> Self {
        Self {
            n: self.n + other.n,
            sum: self.sum + other.sum,
            squares: self.squares + other.squares,
        }
    }

    /// The unbiased variance, the mean over the channels (0 from fewer than two samples).
    fn variance(&self) -> f64 {
        if self.n < 2.0 {
            return 0.0;
        }
        let mean = self.sum * (1.0 / self.n);
        let spread = (self.squares - mean.hadamard(self.sum)) * (1.0 / (self.n - 1.0));
        ((spread.red + spread.green + spread.blue) / 3.0).max(0.0)
    }
}

/// `v` where it is a usable variance or cost, else 0.
fn usable(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        v
    } else {
        0.0
    }
}

/// `values` (a `width` × `height` image, row by row) averaged over the square of `radius`
/// around each pixel (the part of it inside the image).
fn smoothed(values: &[f64], width: usize, height: usize, radius: usize) -> Vec<f64> {
    let window = |i: usize, n: usize| i.saturating_sub(radius)..(i + radius + 1).min(n);
    let mut rows = vec![0.0; values.len()];
    for y in 0..height {
        let row = &values[y * width..(y + 1) * width];
        for x in 0..width {
            let w = window(x, width);
            rows[y * width + x] = row[w.clone()].iter().sum::<f64>() / w.len() as f64;
        }
    }
    let mut out = vec![0.0; values.len()];
    for y in 0..height {
        let w = window(y, height);
        for x in 0..width {
            out[y * width + x] =
                w.clone().map(|yy| rows[yy * width + x]).sum::<f64>() / w.len() as f64;
        }
    }
    out
}

/// Each pixel's share of samples for the pixels' `variance` and `cost` per sample: as many
/// as σ ∕ √cost (σ² being the variance), which makes the image's squared error least for the
/// time (the error is Σ σ² ∕ n, the time Σ cost × n), between [`MIN_SHARE`] and
/// [`MAX_SHARE`] of `spp`, costing in all what `spp` samples of every pixel would. The scale
/// is found by bisection (the clamped cost grows with it). `None` where nothing varies.
fn shares(variance: &[f64], cost: &[f64], spp: u64) -> Option<Vec<f64>> {
    let n = spp as f64;
    let (low, high) = ((n * MIN_SHARE).max(1.0), n * MAX_SHARE);
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
    // the budget lies between.
    let budget = n * cost.iter().sum::<f64>();
    let (mut lo, mut hi) = (0.0, n / mean);
    while spent(hi) < budget && hi < f64::MAX / 4.0 {
        hi *= 2.0;
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
        let counts = shares(&variance, &cost, 64).expect("uneven");
        // The very noisy one is held to 8 × 64, the silent one given 64 ∕ 8.
        assert_eq!(counts[11], 512.0);
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
    fn even_noise_shares_evenly_and_none_at_all_asks_for_no_plan() {
        assert_eq!(shares(&[2.0; 9], &[3.0; 9], 64), Some(vec![64.0; 9]));
        assert_eq!(shares(&[0.0; 9], &[1.0; 9], 64), None);
        assert_eq!(shares(&[f64::NAN; 9], &[1.0; 9], 64), None);
    }

    #[test]
    fn slices_of_the_nominal_samples_split_each_pixels_own() {
        let plan = SamplePlan {
            width: 3,
            height: 1,
            spp: 10,
            counts: vec![1, 7, 80],
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
    fn smoothing_averages_each_pixel_with_its_neighbours_inside_the_image() {
        let mut values = vec![0.0; 81];
        values[4 * 9 + 4] = 25.0;
        let out = smoothed(&values, 9, 9, 2);
        // The 5 × 5 squares around the spike share it; the corners' lie apart from it.
        assert_eq!(out[4 * 9 + 4], 1.0);
        assert_eq!(out[2 * 9 + 2], 1.0);
        assert_eq!(out[0], 0.0);
        // A constant stays itself, at the edges too.
        assert!(smoothed(&[4.0; 12], 4, 3, 2).iter().all(|&v| v == 4.0));
    }
}
