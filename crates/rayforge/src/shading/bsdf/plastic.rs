//! Plastic: a dielectric coat of index `eta` (smooth, or GGX-rough) over a Lambertian base.
//!
//! The coat reflects specularly (`specular` tints it); what it transmits reaches the base, is
//! scattered diffusely and bounces between base and coat until it leaves. The base term is
//!
//! `f_base(wo, wi) = ρ / (π η² (1 − F̄ᵢₙ)) · (1 − F(cos θo)) (1 − F(cos θi))`
//!
//! with `F` the coat's Fresnel reflectance at the macro normal and `F̄ᵢₙ` its diffuse
//! reflectance seen from inside (light leaving the base uniformly). The `1/η²` and `1 − F̄ᵢₙ`
//! cancel exactly against the escaping fraction (`∫ (1 − F) cos/π dω / η² = 1 − F̄ᵢₙ`), so the
//! base contributes `(1 − F(cos θo)) ρ` to the albedo: with the smooth coat's `F(cos θo)`, the
//! total is `F(cos θo) s + (1 − F(cos θo)) ρ ≤ 1`. This is the linear model of Mitsuba's
//! `plastic` (its `nonlinear = false`), chosen because the renders are compared with Mitsuba.
//! The rough coat keeps the same base term: its microfacet reflectance stays below the smooth
//! coat's `F(cos θo)` (shadowing and the Fresnel average over visible normals only lower it),
//! which the tests check numerically, so the albedo stays ≤ 1 there too.
//!
//! Directions are in the local frame with both in the upper hemisphere (the dispatcher mirrors
//! two-sided materials there).

use super::microfacet::{reflect, Ggx};
use super::{diffuse, fresnel, is_smooth, mirror, BsdfSample};
use crate::color::Color;
use crate::math::{cosine_hemisphere, Vec3};
use std::f64::consts::FRAC_1_PI;

/// The plastic's parameters, as in [`Bsdf::Plastic`](super::Bsdf::Plastic).
#[derive(Debug, Clone, Copy)]
pub(super) struct Plastic {
    pub diffuse: Color,
    pub eta: f64,
    pub alpha: f64,
    pub specular: Color,
}

fn mean(c: Color) -> f64 {
    (c.red.max(0.0) + c.green.max(0.0) + c.blue.max(0.0)) / 3.0
}

impl Plastic {
    fn coat_reflectance(&self, cos: f64) -> f64 {
        fresnel::dielectric(cos, self.eta).reflectance
    }

    /// The probability of sampling the coat's reflection for `wo`: its share of the expected
    /// reflected energy, `F s̄ / (F s̄ + (1 − F) ρ̄)`.
    pub fn specular_probability(&self, wo: Vec3) -> f64 {
        let f = self.coat_reflectance(wo.z);
        let ws = f * mean(self.specular);
        let wd = (1.0 - f) * mean(self.diffuse);
        if ws + wd > 0.0 {
            ws / (ws + wd)
        } else {
            0.5
        }
    }

    fn base(&self, wo: Vec3, wi: Vec3) -> Color {
        let inside = fresnel::diffuse_reflectance(1.0 / self.eta);
        let t = (1.0 - self.coat_reflectance(wo.z)) * (1.0 - self.coat_reflectance(wi.z));
        let scale = t * FRAC_1_PI * wi.z / (self.eta * self.eta * (1.0 - inside).max(1e-12));
        self.diffuse * scale
    }

    fn coat(&self, ggx: Ggx, wo: Vec3, wi: Vec3) -> Color {
        let Some(h) = (wo + wi).try_normalize() else {
            return Color::BLACK;
        };
        let g = ggx.g1(wo, h) * ggx.g1(wi, h);
        let f = self.coat_reflectance(wo.dot(h));
        self.specular * (f * ggx.d(h) * g / (4.0 * wo.z))
    }

    fn coat_pdf(ggx: Ggx, wo: Vec3, wi: Vec3) -> f64 {
        let Some(h) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        let cos_oh = wo.dot(h);
        if cos_oh <= 0.0 {
            return 0.0;
        }
        ggx.visible_pdf(wo, h) / (4.0 * cos_oh)
    }

    /// `f cos θi`: the base term, plus the rough coat's microfacet reflection (a smooth coat's
    /// reflection is a delta and left out).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Color::BLACK;
        }
        let base = self.base(wo, wi);
        if is_smooth(self.alpha) {
            base
        } else {
            base + self.coat(Ggx::isotropic(self.alpha), wo, wi)
        }
    }

    /// The mixture of the coat's density (with its probability) and the cosine density.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f64 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let p = self.specular_probability(wo);
        let diffuse = (1.0 - p) * diffuse::pdf(wi);
        if is_smooth(self.alpha) {
            diffuse
        } else {
            diffuse + p * Self::coat_pdf(Ggx::isotropic(self.alpha), wo, wi)
        }
    }

    /// Chooses the coat with [`specular_probability`](Self::specular_probability), else the
    /// base by the cosine density. A smooth coat's mirror direction is a delta sample; every
    /// other sample weighs `eval / pdf` of the whole mixture.
    pub fn sample(&self, wo: Vec3, u_lobe: f64, u: [f64; 2]) -> Option<BsdfSample> {
        let p = self.specular_probability(wo);
        let smooth = is_smooth(self.alpha);
        let wi = if u_lobe < p {
            if smooth {
                let f = self.coat_reflectance(wo.z);
                return Some(BsdfSample {
                    wi: mirror(wo),
                    weight: self.specular * (f / p),
                    pdf: p,
                    delta: true,
                });
            }
            let m = Ggx::isotropic(self.alpha).sample_visible(wo, u)?;
            reflect(wo, m)
        } else {
            cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) / pdf,
            pdf,
            delta: false,
        })
    }
}
