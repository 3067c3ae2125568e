//! Diffuse transmission (pbrt-v4's `diffusetransmission`): a Lambertian lobe of
//! `reflectance` on the side light arrives from and one of `transmittance` on the other,
//! `f = R/π` for a pair on one side and `T/π` for a pair on opposite sides. Both lobes are
//! symmetric in `wo` and `wi`, so the material is reciprocal, and it is the same seen from
//! either side; it bends nothing, so radiance needs no `1/η²`.
//!
//! Sampling picks reflection with probability `max R / (max R + max T)` (the largest
//! channels, as pbrt-v4 does) and draws a cosine-weighted direction on the chosen side.

use super::BsdfSample;
use crate::color::Color;
use crate::math::{cosine_hemisphere, Vec3};
use std::f64::consts::FRAC_1_PI;

/// The probability of sampling the reflected lobe (`None`: neither lobe scatters anything).
fn reflect_probability(reflectance: Color, transmittance: Color) -> Option<f64> {
    let (r, t) = (
        reflectance.max_channel().max(0.0),
        transmittance.max_channel().max(0.0),
    );
    (r + t > 0.0).then(|| r / (r + t))
}

/// `f |cos θi|`: `R |cos θi| / π` on `wo`'s side, `T |cos θi| / π` on the other.
pub(super) fn eval(reflectance: Color, transmittance: Color, wo: Vec3, wi: Vec3) -> Color {
    if wo.z == 0.0 || wi.z == 0.0 {
        return Color::BLACK;
    }
    let lobe = if wo.z * wi.z > 0.0 {
        reflectance
    } else {
        transmittance
    };
    lobe * (wi.z.abs() * FRAC_1_PI)
}

/// The density of [`sample`]: the chosen side's probability times `|cos θi| / π`.
pub(super) fn pdf(reflectance: Color, transmittance: Color, wo: Vec3, wi: Vec3) -> f64 {
    let Some(pr) = reflect_probability(reflectance, transmittance) else {
        return 0.0;
    };
    if wo.z == 0.0 || wi.z == 0.0 {
        return 0.0;
    }
    let side = if wo.z * wi.z > 0.0 { pr } else { 1.0 - pr };
    side * wi.z.abs() * FRAC_1_PI
}

/// Reflection or transmission by `u_lobe`, then a cosine-weighted direction on that side.
pub(super) fn sample(
    reflectance: Color,
    transmittance: Color,
    wo: Vec3,
    u_lobe: f64,
    u: [f64; 2],
) -> Option<BsdfSample> {
    let pr = reflect_probability(reflectance, transmittance)?;
    let local = cosine_hemisphere(u);
    let reflects = u_lobe < pr;
    let (lobe, chance) = if reflects {
        (reflectance, pr)
    } else {
        (transmittance, 1.0 - pr)
    };
    let same_side = if reflects { 1.0 } else { -1.0 };
    let wi = Vec3::new(local.x, local.y, local.z * wo.z.signum() * same_side);
    let pdf = chance * local.z * FRAC_1_PI;
    (pdf > 0.0).then(|| BsdfSample {
        wi,
        weight: lobe / chance,
        pdf,
        delta: false,
    })
}
