//! Metals: a smooth mirror, or GGX microfacets (isotropic or anisotropic), reflecting by the exact conductor Fresnel
//! equations of their complex index `η + iκ`.
//!
//! Directions are in the local frame with `wo` in the upper hemisphere (the dispatcher mirrors
//! two-sided materials there).

use super::microfacet::reflect;
use super::{fresnel, mirror, rough, BsdfSample};
use crate::color::Color;
use crate::math::Vec3;

/// The conductor's parameters, as in [`Bsdf::Conductor`](super::Bsdf::Conductor).
#[derive(Debug, Clone, Copy)]
pub(super) struct Conductor {
    pub eta: Color,
    pub k: Color,
    pub alpha_u: f64,
    pub alpha_v: f64,
    pub tint: Color,
}

impl Conductor {
    /// `f cos θi = tint F(wo·h) D(h) G1(wo) G1(wi) / (4 cos θo)` for the rough conductor; 0 for
    /// the mirror (its reflection is a delta).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        let Some(ggx) = rough(self.alpha_u, self.alpha_v) else {
            return Color::BLACK;
        };
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Color::BLACK;
        }
        let Some(h) = (wo + wi).try_normalize() else {
            return Color::BLACK;
        };
        let g = ggx.g1(wo, h) * ggx.g1(wi, h);
        let scalar = ggx.d(h) * g / (4.0 * wo.z);
        let f = fresnel::conductor(wo.dot(h), self.eta, self.k);
        self.tint.hadamard(f) * scalar
    }

    /// `D_wo(h) / (4 wo·h)`: the visible-normal density carried to reflected directions.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f64 {
        let Some(ggx) = rough(self.alpha_u, self.alpha_v) else {
            return 0.0;
        };
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some(h) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        let cos_oh = wo.dot(h);
        if cos_oh <= 0.0 {
            return 0.0;
        }
        ggx.visible_pdf(wo, h) / (4.0 * cos_oh)
    }

    /// The mirror direction (a delta) or a reflection off a visible microfacet, whose weight
    /// reduces to `tint F(wo·m) G1(wi, m)`.
    pub fn sample(&self, wo: Vec3, u: [f64; 2]) -> Option<BsdfSample> {
        let Some(ggx) = rough(self.alpha_u, self.alpha_v) else {
            let f = fresnel::conductor(wo.z, self.eta, self.k);
            return Some(BsdfSample {
                wi: mirror(wo),
                weight: self.tint.hadamard(f),
                pdf: 1.0,
                delta: true,
            });
        };
        let m = ggx.sample_visible(wo, u)?;
        let wi = reflect(wo, m);
        if wi.z <= 0.0 {
            return None;
        }
        let cos_om = wo.dot(m);
        let pdf = ggx.visible_pdf(wo, m) / (4.0 * cos_om);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = fresnel::conductor(cos_om, self.eta, self.k);
        Some(BsdfSample {
            wi,
            weight: self.tint.hadamard(f) * ggx.g1(wi, m),
            pdf,
            delta: false,
        })
    }
}
