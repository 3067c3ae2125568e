//! A chi-square goodness-of-fit test of [`Bsdf::sample`] against [`Bsdf::pdf`], as renderers
//! test their BSDFs: sampled directions are binned over the sphere in (cos θ, φ), each bin's
//! expected count is the pdf integrated over it numerically, bins expecting fewer than five
//! samples are pooled, and the statistic's p-value comes from the chi-square distribution
//! (`math::stats`'s incomplete gamma function). Delta samples and failed
//! samples get a bin each, expected from their discrete probability and the pdf's deficit.

use super::Bsdf;
use crate::color::Color;
use crate::math::random::{Jitter, SplitMix64};
use crate::math::stats::chi_square_tail;
use crate::math::Vec3;
use std::f64::consts::TAU;

const COS_BINS: usize = 10;
const PHI_BINS: usize = 20;
/// Midpoint-rule sub-cells per bin and axis when integrating the pdf.
const SUB: usize = 40;

fn direction(cos_theta: f64, phi: f64) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

fn bin_of(w: Vec3) -> usize {
    let c = (((w.z + 1.0) * 0.5 * COS_BINS as f64) as usize).min(COS_BINS - 1);
    let mut phi = w.y.atan2(w.x);
    if phi < 0.0 {
        phi += TAU;
    }
    let p = ((phi / TAU * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
    c * PHI_BINS + p
}

/// Relative closeness of two colours, for comparing weights.
fn close(a: Color, b: Color, tolerance: f64) -> bool {
    let scale = a.max_channel().abs().max(b.max_channel().abs()).max(1e-12);
    (a - b)
        .to_array()
        .iter()
        .all(|d| d.abs() <= tolerance * scale)
}

/// Draws `samples` directions for `wo`, checks every non-delta sample's pdf and weight against
/// [`Bsdf::pdf`] and [`Bsdf::eval`], and returns the chi-square test's p-value (or a message
/// when a sample is inconsistent).
pub(super) fn p_value(bsdf: &Bsdf, wo: Vec3, samples: usize, seed: u64) -> Result<f64, String> {
    p_value_against(bsdf, bsdf, wo, samples, seed)
}

/// The test proper: directions drawn by `sampler`, expected counts from `density`'s pdf (the
/// same material but for the test of the test, which must see a wrong density rejected).
fn p_value_against(
    sampler: &Bsdf,
    density: &Bsdf,
    wo: Vec3,
    samples: usize,
    seed: u64,
) -> Result<f64, String> {
    let bsdf = sampler;
    let same = sampler == density;
    let cells = COS_BINS * PHI_BINS;
    let mut observed = vec![0.0; cells];
    let mut delta_count = 0.0;
    let mut delta_probability: Option<f64> = None;
    let mut failed = 0.0;
    let mut rng = SplitMix64::new(seed);
    for _ in 0..samples {
        let u_lobe = rng.next_offset();
        let u = [rng.next_offset(), rng.next_offset()];
        let Some(s) = bsdf.sample(wo, u_lobe, u) else {
            failed += 1.0;
            continue;
        };
        if s.delta {
            delta_count += 1.0;
            match delta_probability {
                None => delta_probability = Some(s.pdf),
                Some(p) if (p - s.pdf).abs() > 1e-12 => {
                    return Err(format!("delta probability changed: {p} vs {}", s.pdf))
                }
                Some(_) => {}
            }
            continue;
        }
        if !same {
            observed[bin_of(s.wi)] += 1.0;
            continue;
        }
        let pdf = bsdf.pdf(wo, s.wi);
        if (pdf - s.pdf).abs() > 1e-7 * pdf.max(s.pdf) {
            return Err(format!("sample pdf {} but pdf() {pdf} at {}", s.pdf, s.wi));
        }
        let expected = bsdf.eval(wo, s.wi) / s.pdf;
        if !close(s.weight, expected, 1e-7) {
            return Err(format!(
                "weight {:?} but eval/pdf {expected:?} at {}",
                s.weight, s.wi
            ));
        }
        observed[bin_of(s.wi)] += 1.0;
    }
    let n = samples as f64;
    let dz = 2.0 / COS_BINS as f64;
    let dphi = TAU / PHI_BINS as f64;
    let mut expected = vec![0.0; cells];
    for (cell, e) in expected.iter_mut().enumerate() {
        let (c, p) = (cell / PHI_BINS, cell % PHI_BINS);
        let mut sum = 0.0;
        for i in 0..SUB {
            let z = -1.0 + dz * (c as f64 + (i as f64 + 0.5) / SUB as f64);
            for j in 0..SUB {
                let phi = dphi * (p as f64 + (j as f64 + 0.5) / SUB as f64);
                sum += density.pdf(wo, direction(z, phi));
            }
        }
        *e = n * sum * dz * dphi / (SUB * SUB) as f64;
    }
    let integral: f64 = expected.iter().sum::<f64>() / n;
    let p_delta = delta_probability.unwrap_or(0.0);
    let mut table: Vec<(f64, f64)> = expected.into_iter().zip(observed).collect();
    table.push((n * p_delta, delta_count));
    table.push(((n * (1.0 - integral - p_delta)).max(0.0), failed));
    table.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut pooled: Vec<(f64, f64)> = Vec::new();
    let (mut pool_e, mut pool_o) = (0.0, 0.0);
    for (e, o) in table {
        if e >= 5.0 && pool_e == 0.0 && pool_o == 0.0 {
            pooled.push((e, o));
        } else {
            pool_e += e;
            pool_o += o;
            if pool_e >= 5.0 {
                pooled.push((pool_e, pool_o));
                pool_e = 0.0;
                pool_o = 0.0;
            }
        }
    }
    if pool_e > 0.0 || pool_o > 0.0 {
        match pooled.last_mut() {
            Some(last) => {
                last.0 += pool_e;
                last.1 += pool_o;
            }
            None => pooled.push((pool_e, pool_o)),
        }
    }
    if pooled.len() < 2 {
        return Ok(1.0);
    }
    let chi2: f64 = pooled.iter().map(|(e, o)| (o - e) * (o - e) / e).sum();
    Ok(chi_square_tail(chi2, pooled.len() - 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_density_that_does_not_match_the_sampler_is_rejected() {
        let rough = |alpha| Bsdf::Conductor {
            eta: Color::new(0.2, 0.9, 1.1),
            k: Color::new(3.9, 2.5, 2.1),
            alpha_u: alpha,
            alpha_v: alpha,
            tint: Color::WHITE,
        };
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let right = p_value_against(&rough(0.3), &rough(0.3), wo, 20_000, 5).expect("runs");
        let wrong = p_value_against(&rough(0.3), &rough(0.36), wo, 20_000, 5).expect("runs");
        assert!(right > 1e-3, "{right}");
        assert!(wrong < 1e-6, "{wrong}");
    }
}
