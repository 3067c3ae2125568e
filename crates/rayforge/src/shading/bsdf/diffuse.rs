//! Lambertian reflection: the same radiance in every direction, `f = ρ/π`.
//!
//! Directions are in the local frame with both in the upper hemisphere (the dispatcher mirrors
//! two-sided materials there).

use super::BsdfSample;
use crate::color::Color;
use crate::math::{cosine_hemisphere, Vec3};
use std::f64::consts::FRAC_1_PI;

/// `f · cos θi = ρ cos θi / π`.
pub(super) fn eval(albedo: Color, wi: Vec3) -> Color {
    albedo * (wi.z.max(0.0) * FRAC_1_PI)
}

/// The cosine-weighted density `cos θi / π` with which [`sample`] draws `wi`.
pub(super) fn pdf(wi: Vec3) -> f64 {
    wi.z.max(0.0) * FRAC_1_PI
}

/// Samples `wi` by [`cosine_hemisphere`]; the weight `f cos / pdf` is the albedo itself.
pub(super) fn sample(albedo: Color, u: [f64; 2]) -> Option<BsdfSample> {
    let wi = cosine_hemisphere(u);
    let pdf = pdf(wi);
    (pdf > 0.0).then_some(BsdfSample {
        wi,
        weight: albedo,
        pdf,
        delta: false,
    })
}
