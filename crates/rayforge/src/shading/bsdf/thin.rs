//! A thin dielectric sheet (a window pane): light is reflected or passes straight through,
//! never bent, because the two parallel faces undo each other's refraction. The light bouncing
//! inside the sheet is summed as a geometric series: with `R` the reflectance of one face and
//! `T = 1 − R`, the sheet reflects `R' = R + T²R/(1 − R²) = 2R/(1 + R)` and transmits `1 − R'`.

use super::{fresnel, mirror, BsdfSample};
use crate::color::Color;
use crate::math::Vec3;

/// The sheet's total reflectance `R'` for a direction at `cos_theta` from the normal.
pub(super) fn sheet_reflectance(cos_theta: f64, eta: f64) -> f64 {
    let r = fresnel::dielectric(cos_theta.abs(), eta).reflectance;
    if r >= 1.0 {
        1.0
    } else {
        2.0 * r / (1.0 + r)
    }
}

/// Reflection (with probability `R'`) or straight transmission, both deltas weighted by `tint`.
pub(super) fn sample(eta: f64, tint: Color, wo: Vec3, u_lobe: f64) -> Option<BsdfSample> {
    if wo.z == 0.0 {
        return None;
    }
    let r = sheet_reflectance(wo.z, eta);
    let (wi, pdf) = if u_lobe < r {
        (mirror(wo), r)
    } else {
        (-wo, 1.0 - r)
    };
    (pdf > 0.0).then_some(BsdfSample {
        wi,
        weight: tint,
        pdf,
        delta: true,
    })
}
