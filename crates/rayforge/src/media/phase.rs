//! Phase functions: how a medium scatters light at a point, by the angle between the
//! direction light travelled and the direction it leaves in. Henyey–Greenstein (one
//! parameter `g`, the mean cosine: 0 isotropic, towards 1 forward, towards −1 backward), the
//! phase function of pbrt-v4, Mitsuba 3 and Cycles, sampled exactly (its inverse CDF in
//! closed form), so `sample`'s density is `pdf` and its weight 1.

use crate::math::{Frame, Vec3};
use std::f64::consts::PI;

/// The most |g| a phase function may take: at ±1 Henyey–Greenstein is a delta, whose
/// density no finite number holds.
pub const MAX_ASYMMETRY: f64 = 0.99;

/// A Henyey–Greenstein phase function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HenyeyGreenstein {
    /// The mean cosine of the scattering angle, in [−0.99, 0.99].
    pub g: f64,
}

/// A direction drawn from a phase function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseSample {
    /// The unit direction the light leaves in.
    pub wi: Vec3,
    /// The phase function's value there (equal to `pdf`: the sampling is exact).
    pub p: f64,
    /// The density (per steradian) of the draw.
    pub pdf: f64,
}

impl HenyeyGreenstein {
    /// Isotropic scattering.
    pub const ISOTROPIC: Self = Self { g: 0.0 };

    /// The phase function of mean cosine `g`, held to ±[`MAX_ASYMMETRY`].
    pub fn new(g: f64) -> Self {
        Self {
            g: g.clamp(-MAX_ASYMMETRY, MAX_ASYMMETRY),
        }
    }

    /// The density for light travelling along unit `travel` scattered into unit `wi`
    /// (per steradian; it integrates to 1 over the sphere).
    #[inline]
    pub fn eval(&self, travel: Vec3, wi: Vec3) -> f64 {
        hg(travel.dot(wi), self.g)
    }

    /// The density with which [`sample`](Self::sample) draws `wi` (the value itself).
    #[inline]
    pub fn pdf(&self, travel: Vec3, wi: Vec3) -> f64 {
        self.eval(travel, wi)
    }

    /// A direction for light travelling along unit `travel`, from two numbers in [0, 1):
    /// the cosine from the inverse of the distribution's CDF, the angle about `travel`
    /// uniform.
    pub fn sample(&self, travel: Vec3, [u0, u1]: [f64; 2]) -> PhaseSample {
        let g = self.g;
        let cos = if g.abs() < 1e-3 {
            1.0 - 2.0 * u0
        } else {
            let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u0);
            (1.0 + g * g - s * s) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u1;
        let local = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
        let wi = Frame::from_normal(travel).to_world(local).normalize();
        let p = hg(cos, g);
        PhaseSample { wi, p, pdf: p }
    }
}

/// Henyey–Greenstein's density at the cosine `cos` between the travel and the new direction.
#[inline]
fn hg(cos: f64, g: f64) -> f64 {
    let denom = 1.0 + g * g - 2.0 * g * cos;
    (1.0 - g * g) / (4.0 * PI * denom * denom.max(1e-300).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::stats::chi_square_tail;

    const COS_BINS: usize = 20;
    const PHI_BINS: usize = 10;

    /// The chi-square p-value of `draw`'s directions (in the frame of +Z, the travel)
    /// against the density `density`, integrated over bins in (cos θ, φ).
    fn p_value(
        draw: impl Fn([f64; 2]) -> Vec3,
        density: impl Fn(Vec3) -> f64,
        samples: usize,
        seed: u64,
    ) -> f64 {
        let mut observed = vec![0.0; COS_BINS * PHI_BINS];
        let mut rng = SplitMix64::new(seed);
        let bin = |w: Vec3| {
            let c = (((w.z + 1.0) * 0.5 * COS_BINS as f64) as usize).min(COS_BINS - 1);
            let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI);
            let p = ((phi / (2.0 * PI) * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
            c * PHI_BINS + p
        };
        for _ in 0..samples {
            let w = draw([rng.next_offset(), rng.next_offset()]);
            observed[bin(w)] += 1.0;
        }
        const SUB: usize = 32;
        let (dz, dphi) = (2.0 / COS_BINS as f64, 2.0 * PI / PHI_BINS as f64);
        let mut chi2 = 0.0;
        let mut total = 0.0;
        for (cell, o) in observed.iter().enumerate() {
            let (c, p) = (cell / PHI_BINS, cell % PHI_BINS);
            let mut sum = 0.0;
            for i in 0..SUB {
                let z = -1.0 + dz * (c as f64 + (i as f64 + 0.5) / SUB as f64);
                for j in 0..SUB {
                    let phi = dphi * (p as f64 + (j as f64 + 0.5) / SUB as f64);
                    let s = (1.0 - z * z).sqrt();
                    sum += density(Vec3::new(s * phi.cos(), s * phi.sin(), z));
                }
            }
            let e = samples as f64 * sum * dz * dphi / (SUB * SUB) as f64;
            total += e;
            chi2 += (o - e) * (o - e) / e;
        }
        assert!(
            (total / samples as f64 - 1.0).abs() < 1e-3,
            "density integrates to {total}"
        );
        chi_square_tail(chi2, COS_BINS * PHI_BINS - 1)
    }

    #[test]
    fn samples_follow_the_density_for_every_asymmetry() {
        for (k, g) in [0.0, 0.3, -0.5, 0.7, -0.7].into_iter().enumerate() {
            let phase = HenyeyGreenstein::new(g);
            let p = p_value(
                |u| phase.sample(Vec3::Z, u).wi,
                |w| phase.pdf(Vec3::Z, w),
                40_000,
                k as u64 + 1,
            );
            assert!(p > 1e-3, "g = {g}: p-value {p}");
        }
    }

    #[test]
    fn a_density_that_does_not_match_the_sampler_is_rejected() {
        let (drawn, claimed) = (HenyeyGreenstein::new(0.5), HenyeyGreenstein::new(0.55));
        let p = p_value(
            |u| drawn.sample(Vec3::Z, u).wi,
            |w| claimed.pdf(Vec3::Z, w),
            40_000,
            9,
        );
        assert!(p < 1e-6, "{p}");
    }

    #[test]
    fn a_sample_carries_its_density_and_the_mean_cosine_is_g() {
        let phase = HenyeyGreenstein::new(0.6);
        let travel = Vec3::new(0.0, 0.6, 0.8);
        let mut rng = SplitMix64::new(3);
        let n = 200_000;
        let mut mean = 0.0;
        for _ in 0..n {
            let s = phase.sample(travel, [rng.next_offset(), rng.next_offset()]);
            assert!((s.pdf - phase.pdf(travel, s.wi)).abs() <= 1e-9 * s.pdf);
            assert!((s.wi.length() - 1.0).abs() < 1e-12);
            mean += s.wi.dot(travel);
        }
        mean /= n as f64;
        // The cosine's spread is below 1: 5 standard errors of the mean.
        assert!((mean - 0.6).abs() < 5.0 / (n as f64).sqrt(), "{mean}");
    }
}
