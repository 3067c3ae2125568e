//! A boundary between two dielectrics (glass, water): smooth, or rough after Walter et al. 2007
//! ("Microfacet Models for Refraction through Rough Surfaces") with GGX microfacets.
//!
//! `eta` is the index below the surface (inside, −Z) over the index above it. Each function
//! first turns the configuration so that `wo` lies above (mirroring z and inverting `eta` when
//! it arrives from inside); below, `eta` always means "index on `wi`'s side of a transmission
//! over index on `wo`'s side".
//!
//! The transport is that of radiance (camera paths): radiance crossing into a medium of
//! relative index η is scaled by `1/η²`, so refracted samples weigh `tint (1 − F)/η² / (1 − F)`
//! = `tint/η²` and the BTDF satisfies `f(wo, wi)/η_o² = f(wi, wo)/η_i²`, with `η_o`, `η_i`
//! the indices on the sides of `wo` and `wi`.

use super::microfacet::{reflect, Ggx};
use super::{fresnel, mirror, rough, BsdfSample};
use crate::color::Color;
use crate::math::Vec3;

/// `wo`, `wi` and `eta` turned so that `wo` is above; `flipped` says whether z was mirrored.
struct Oriented {
    wo: Vec3,
    wi: Vec3,
    eta: f64,
    flipped: bool,
}

/// A rough boundary's microfacet for a pair of directions (see `Dielectric::facet`).
struct Facet {
    o: Oriented,
    ggx: Ggx,
    h: Vec3,
    is_reflection: bool,
    cos_oh: f64,
    cos_ih: f64,
    /// Fresnel reflectance at the microfacet.
    f: f64,
}

impl Facet {
    /// `(wo·h + η wi·h)²`, the refraction Jacobian's denominator, when it is usable.
    fn refraction_denominator(&self) -> Option<f64> {
        let denom = self.cos_oh + self.o.eta * self.cos_ih;
        let denom2 = denom * denom;
        (!denom2.is_nan() && denom2 > 1e-300).then_some(denom2)
    }
}

fn orient(wo: Vec3, wi: Vec3, eta: f64) -> Oriented {
    if wo.z < 0.0 {
        let flip = Vec3::new(1.0, 1.0, -1.0);
        Oriented {
            wo: wo * flip,
            wi: wi * flip,
            eta: 1.0 / eta,
            flipped: true,
        }
    } else {
        Oriented {
            wo,
            wi,
            eta,
            flipped: false,
        }
    }
}

/// The microfacet normal that carries `wo` (above) to `wi` for a rough boundary of relative
/// index `eta`, and whether that is a reflection. `None` for degenerate pairs.
fn half_vector(wo: Vec3, wi: Vec3, eta: f64) -> Option<(Vec3, bool)> {
    if wi.z > 0.0 {
        Some(((wo + wi).try_normalize()?, true))
    } else if wi.z < 0.0 {
        let h = (wo + wi * eta).try_normalize()?;
        Some((if h.z < 0.0 { -h } else { h }, false))
    } else {
        None
    }
}

/// The dielectric's parameters, as in [`Bsdf::Dielectric`](super::Bsdf::Dielectric).
#[derive(Debug, Clone, Copy)]
pub(super) struct Dielectric {
    pub eta: f64,
    pub alpha_u: f64,
    pub alpha_v: f64,
    pub tint: Color,
}

impl Dielectric {
    /// `f cos θi` of the rough boundary (Walter et al.): reflection
    /// `F D G / (4 cos θo)`, transmission `|wi·h| |wo·h| (1 − F) D G / (cos θo (wo·h + η wi·h)²)`;
    /// 0 for a smooth boundary (all its scattering is delta).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        self.tint * self.eval_scalar(wo, wi)
    }

    fn eval_scalar(&self, wo: Vec3, wi: Vec3) -> f64 {
        let Some(m) = self.facet(wo, wi) else {
            return 0.0;
        };
        let g = m.ggx.g1(m.o.wo, m.h) * m.ggx.g1(m.o.wi, m.h);
        if g <= 0.0 {
            return 0.0;
        }
        let d = m.ggx.d(m.h);
        if m.is_reflection {
            m.f * d * g / (4.0 * m.o.wo.z)
        } else if let Some(denom2) = m.refraction_denominator() {
            (m.cos_ih * m.cos_oh).abs() * (1.0 - m.f) * d * g / (m.o.wo.z * denom2)
        } else {
            0.0
        }
    }

    /// What evaluating and the density of a rough boundary share for the pair `wo`, `wi`: the
    /// pair turned to the outside, the microfacet normal joining them, and its Fresnel
    /// reflectance; `None` for a smooth boundary or no such normal.
    fn facet(&self, wo: Vec3, wi: Vec3) -> Option<Facet> {
        let ggx = rough(self.alpha_u, self.alpha_v)?;
        if wo.z == 0.0 {
            return None;
        }
        let o = orient(wo, wi, self.eta);
        let (h, is_reflection) = half_vector(o.wo, o.wi, o.eta)?;
        let (cos_oh, cos_ih) = (o.wo.dot(h), o.wi.dot(h));
        Some(Facet {
            ggx,
            h,
            is_reflection,
            cos_oh,
            cos_ih,
            f: fresnel::dielectric(cos_oh, o.eta).reflectance,
            o,
        })
    }

    /// The density of [`sample`](Self::sample)'s `wi`: the visible-normal density, times the
    /// probability `F` or `1 − F` of choosing reflection or transmission at that normal, times
    /// the Jacobian from normals to directions (`1/(4 wo·h)` or `η² |wi·h| / (wo·h + η wi·h)²`).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f64 {
        let Some(m) = self.facet(wo, wi) else {
            return 0.0;
        };
        let (cos_oh, cos_ih) = (m.cos_oh, m.cos_ih);
        if cos_oh <= 0.0
            || (m.is_reflection && cos_ih <= 0.0)
            || (!m.is_reflection && cos_ih >= 0.0)
        {
            return 0.0;
        }
        let visible = m.ggx.visible_pdf(m.o.wo, m.h);
        if m.is_reflection {
            m.f * visible / (4.0 * cos_oh)
        } else if let Some(denom2) = m.refraction_denominator() {
            (1.0 - m.f) * visible * m.o.eta * m.o.eta * cos_ih.abs() / denom2
        } else {
            0.0
        }
    }

    /// Reflection with probability `F`, refraction otherwise, off the smooth boundary or a
    /// visible microfacet. Weights: `tint` for reflection (times `G1(wi)` when rough) and
    /// `tint/η²` for refraction (times `G1(wi)` when rough).
    pub fn sample(&self, wo: Vec3, u_lobe: f64, u: [f64; 2]) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let o = orient(wo, Vec3::ZERO, self.eta);
        let unflip = |v: Vec3| {
            if o.flipped {
                Vec3::new(v.x, v.y, -v.z)
            } else {
                v
            }
        };
        let Some(ggx) = rough(self.alpha_u, self.alpha_v) else {
            let fr = fresnel::dielectric(o.wo.z, o.eta);
            let f = fr.reflectance;
            if u_lobe < f {
                return Some(BsdfSample {
                    wi: unflip(mirror(o.wo)),
                    weight: self.tint,
                    pdf: f,
                    delta: true,
                });
            }
            let wi = Vec3::new(-o.wo.x / o.eta, -o.wo.y / o.eta, fr.cos_t);
            return Some(BsdfSample {
                wi: unflip(wi),
                weight: self.tint / (o.eta * o.eta),
                pdf: 1.0 - f,
                delta: true,
            });
        };
        let m = ggx.sample_visible(o.wo, u)?;
        let cos_om = o.wo.dot(m);
        let fr = fresnel::dielectric(cos_om, o.eta);
        let f = fr.reflectance;
        let visible = ggx.visible_pdf(o.wo, m);
        let (wi, pdf, weight) = if u_lobe < f {
            let wi = reflect(o.wo, m);
            if wi.z <= 0.0 {
                return None;
            }
            (wi, f * visible / (4.0 * cos_om), ggx.g1(wi, m))
        } else {
            let wi = m * (cos_om / o.eta + fr.cos_t) - o.wo / o.eta;
            if wi.z >= 0.0 {
                return None;
            }
            let cos_im = wi.dot(m);
            let denom = cos_om + o.eta * cos_im;
            let pdf = (1.0 - f) * visible * o.eta * o.eta * cos_im.abs() / (denom * denom);
            (wi, pdf, ggx.g1(wi, m) / (o.eta * o.eta))
        };
        if pdf.is_nan() || pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi: unflip(wi),
            weight: self.tint * weight,
            pdf,
            delta: false,
        })
    }
}
