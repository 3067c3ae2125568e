//! The path tracer's materials: bidirectional scattering distribution functions (BSDFs) as a
//! closed set, [`Bsdf`], each able to evaluate `f cos θ`, give the density with which it samples
//! directions, and sample one.
//!
//! Written by hand rather than taken from a crate: the books this renderer follows ask us to
//! understand the mathematics of light, and no crate offers physically based BSDFs in `f64` for
//! our colour and vector types. The formulas are the published ones (Walter et al. 2007 for
//! rough refraction, Heitz 2014/2018 and Dupuy & Benyoub 2023 for GGX and its visible normals,
//! the exact Fresnel equations), and the renders are compared with Mitsuba 3 pixel by pixel, so
//! the conventions follow it where there is a choice (separable Smith shadowing, radiance
//! scaling across refraction, the linear plastic model).
//!
//! Every function works in the local shading frame ([`Frame`](crate::math::Frame)): the normal
//! is +Z, all directions are unit vectors pointing away from the surface, `wo` towards the
//! viewer (the previous path vertex) and `wi` towards the light (the next vertex).
//! The frame's first tangent (+X) is the direction of an anisotropic material's `alpha_u`.
//! Opaque materials ([`Bsdf::Diffuse`], [`Bsdf::Conductor`], [`Bsdf::Plastic`] and the coated
//! ones) are two-sided: with `wo` below the surface both directions are mirrored above first,
//! and directions on opposite sides scatter nothing. No function returns NaN or infinity.
//!
//! The coated materials ([`Bsdf::CoatedDiffuse`], [`Bsdf::CoatedConductor`]) are pbrt-v4's
//! stochastic layered model: their `eval` and `pdf` are themselves Monte Carlo estimates (see
//! the `layered` module for what that means and where their random numbers come from).

mod conductor;
mod dielectric;
mod diffuse;
pub mod fresnel;
mod layered;
mod metals;
mod microfacet;
mod plastic;
mod thin;
mod transmission;

#[cfg(test)]
mod chi2;
#[cfg(test)]
mod tests;

pub use layered::{Coat, ConductorBase, Layers};
pub use metals::{conductor_for_reflectance, metal, METAL_NAMES};

use crate::color::Color;
use crate::math::Vec3;

/// GGX widths below this are treated as perfectly smooth: the distribution would be too narrow
/// to evaluate or sample in floating point, and a mirror is what it looks like anyway.
pub const MIN_ALPHA: f64 = 1e-4;

/// A surface's scattering, one variant per kind of material. A closed enum (not a trait object)
/// so that materials are plain `Copy` data the integrator matches on without allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bsdf {
    /// Lambertian reflection: matte surfaces, the same radiance seen from every direction.
    Diffuse {
        /// The fraction of light reflected, per channel.
        albedo: Color,
    },
    /// A metal: complex index `eta + i k` per channel, reflection by the exact conductor
    /// Fresnel equations; `alpha_u`, `alpha_v` are the GGX widths along the frame's two
    /// tangents (both below [`MIN_ALPHA`]: a perfect mirror; equal: isotropic).
    Conductor {
        /// Real part of the complex index of refraction, per channel.
        eta: Color,
        /// Imaginary part (extinction coefficient), per channel.
        k: Color,
        /// GGX width along the first tangent (not squared from a roughness).
        alpha_u: f64,
        /// GGX width along the second tangent.
        alpha_v: f64,
        /// A specular tint multiplying the Fresnel reflectance (white for a physical metal).
        tint: Color,
    },
    /// A boundary between two dielectrics (glass, water), reflecting and refracting.
    Dielectric {
        /// Interior index over exterior index (the interior is below the surface, −Z).
        eta: f64,
        /// GGX width along the first tangent (both below [`MIN_ALPHA`]: a smooth boundary).
        alpha_u: f64,
        /// GGX width along the second tangent.
        alpha_v: f64,
        /// Multiplies both reflection and transmission (white for clear glass).
        tint: Color,
    },
    /// A perfect mirror reflecting the share `tint` of the light whatever the angle: the
    /// book's `reflective` surfaces, which know no Fresnel term. Two-sided.
    Mirror {
        /// The share reflected, per channel.
        tint: Color,
    },
    /// A thin dielectric sheet (a window pane): reflects, or transmits without bending, with
    /// the inter-reflections inside the sheet summed (`R' = R + T²R/(1 − R²)`).
    ThinDielectric {
        /// The sheet's index over the surrounding index.
        eta: f64,
        /// Multiplies both reflection and transmission.
        tint: Color,
    },
    /// Plastic: a smooth or GGX-rough dielectric coat over a Lambertian base, energy-conserving
    /// (see the `plastic` module for the model).
    Plastic {
        /// The base's albedo.
        diffuse: Color,
        /// The coat's index over the outside index.
        eta: f64,
        /// The coat's GGX width (below [`MIN_ALPHA`]: a smooth coat).
        alpha: f64,
        /// Multiplies the coat's reflection (white for a physical coat).
        specular: Color,
    },
    /// pbrt-v4's `coateddiffuse`: a dielectric coat over a Lambertian base, with a
    /// scattering medium of the layers' thickness between them, its light transport
    /// estimated by a random walk (see the `layered` module). Not the same as
    /// [`Bsdf::Plastic`], whose inter-reflections are summed in closed form.
    CoatedDiffuse {
        /// The base's albedo.
        reflectance: Color,
        /// The dielectric interface on top.
        coat: Coat,
        /// The medium between coat and base, and the walk's limits.
        layers: Layers,
    },
    /// pbrt-v4's `coatedconductor`: a dielectric coat over a metal, with a medium between.
    CoatedConductor {
        /// The dielectric interface on top.
        coat: Coat,
        /// The metal under it (its index relative to the coat's inside).
        base: ConductorBase,
        /// Multiplies the metal's Fresnel reflectance (white for a physical metal).
        tint: Color,
        /// The medium between coat and metal, and the walk's limits.
        layers: Layers,
    },
    /// pbrt-v4's `diffusetransmission`: Lambertian reflection of `reflectance` on the side
    /// the light arrives from and Lambertian transmission of `transmittance` to the other
    /// (a lampshade, paper, leaves). Two-sided by nature.
    DiffuseTransmission {
        /// The share reflected, per channel.
        reflectance: Color,
        /// The share transmitted, per channel.
        transmittance: Color,
    },
}

/// One direction drawn by [`Bsdf::sample`], with what the path tracer needs to continue.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// The sampled direction towards the next vertex, unit, in the local frame.
    pub wi: Vec3,
    /// `f(wo, wi) · |cos θi| / pdf`: what multiplies the path's throughput.
    pub weight: Color,
    /// Solid-angle density of `wi`; for a delta lobe, the discrete probability of choosing it
    /// (and `delta` is true).
    pub pdf: f64,
    /// Whether `wi` came from a delta (perfectly specular) lobe: light sampling can never find
    /// such a direction, so multiple importance sampling must skip it.
    pub delta: bool,
}

/// Whether a GGX width means "perfectly smooth" (also for NaN or negative widths).
#[inline]
pub(crate) fn is_smooth(alpha: f64) -> bool {
    alpha.is_nan() || alpha < MIN_ALPHA
}

/// The GGX distribution of widths `alpha_u`, `alpha_v`, or `None` where both mean smooth. A
/// width below [`MIN_ALPHA`] beside a rough one is raised to it, as pbrt-v4 does, so that a
/// surface rough along one tangent only has a distribution that can be evaluated.
#[inline]
pub(crate) fn rough(alpha_u: f64, alpha_v: f64) -> Option<microfacet::Ggx> {
    if is_smooth(alpha_u) && is_smooth(alpha_v) {
        return None;
    }
    Some(microfacet::Ggx {
        alpha_x: alpha_u.max(MIN_ALPHA),
        alpha_y: alpha_v.max(MIN_ALPHA),
    })
}

/// The mirror direction of `w` about the normal +Z.
#[inline]
pub(crate) fn mirror(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

#[inline]
fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// For two-sided opaque materials: the pair mirrored so that `wo` is above, or `None` when the
/// directions lie on opposite sides (or in the surface plane).
fn upper_pair(wo: Vec3, wi: Vec3) -> Option<(Vec3, Vec3)> {
    if wo.z > 0.0 && wi.z > 0.0 {
        Some((wo, wi))
    } else if wo.z < 0.0 && wi.z < 0.0 {
        Some((flip_z(wo), flip_z(wi)))
    } else {
        None
    }
}

fn finite_color(c: Color) -> Color {
    if c.red.is_finite() && c.green.is_finite() && c.blue.is_finite() {
        c
    } else {
        Color::BLACK
    }
}

fn finite_or_zero(x: f64) -> f64 {
    if x.is_finite() && x > 0.0 {
        x
    } else {
        0.0
    }
}

/// For Lambert: `|cos θi|` where `wo` and `wi` are finite and on one side of the surface
/// (strictly), else `None`. What the general checks of [`Bsdf::eval`] and [`Bsdf::pdf`] come
/// to for a lobe that reads only the cosines, at a fraction of their cost on the commonest
/// surface (both directions being off the plane, neither is zero).
#[inline]
fn lambert_cos(wo: Vec3, wi: Vec3) -> Option<f64> {
    let cos = if wo.z > 0.0 && wi.z > 0.0 {
        wi.z
    } else if wo.z < 0.0 && wi.z < 0.0 {
        -wi.z
    } else {
        return None;
    };
    (wo.is_finite() && wi.is_finite()).then_some(cos)
}

fn valid_direction(w: Vec3) -> bool {
    w.is_finite() && w.length_squared() > 0.0
}

impl Bsdf {
    /// `f(wo, wi) · |cos θi|` for the non-delta parts (black for purely specular materials):
    /// what light sampling multiplies a light's radiance by.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        let value = match *self {
            // The commonest surface reads only the cosines (see `lambert_cos`).
            Self::Diffuse { albedo } => {
                return lambert_cos(wo, wi).map_or(Color::BLACK, |cos| {
                    finite_color(diffuse::eval(albedo, Vec3::new(0.0, 0.0, cos)))
                })
            }
            _ if !valid_direction(wo) || !valid_direction(wi) => return Color::BLACK,
            Self::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
                tint,
            } => match upper_pair(wo, wi) {
                Some((wo, wi)) => conductor::Conductor {
                    eta,
                    k,
                    alpha_u,
                    alpha_v,
                    tint,
                }
                .eval(wo, wi),
                None => Color::BLACK,
            },
            Self::Dielectric {
                eta,
                alpha_u,
                alpha_v,
                tint,
            } => dielectric::Dielectric {
                eta,
                alpha_u,
                alpha_v,
                tint,
            }
            .eval(wo, wi),
            Self::CoatedDiffuse { .. } | Self::CoatedConductor { .. } => {
                match (upper_pair(wo, wi), layered::Layered::of(self)) {
                    (Some((wo, wi)), Some(l)) => l.eval(wo, wi),
                    _ => Color::BLACK,
                }
            }
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
            } => transmission::eval(reflectance, transmittance, wo, wi),
            Self::ThinDielectric { .. } | Self::Mirror { .. } => Color::BLACK,
            Self::Plastic {
                diffuse,
                eta,
                alpha,
                specular,
            } => match upper_pair(wo, wi) {
                Some((wo, wi)) => plastic::Plastic {
                    diffuse,
                    eta,
                    alpha,
                    specular,
                }
                .eval(wo, wi),
                None => Color::BLACK,
            },
        };
        finite_color(value)
    }

    /// The solid-angle density with which [`sample`](Self::sample) chooses `wi` among its
    /// non-delta parts, including the probability of picking that part: what multiple
    /// importance sampling weighs light samples against.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f64 {
        let pdf = match *self {
            Self::Diffuse { .. } => {
                return lambert_cos(wo, wi).map_or(0.0, |cos| {
                    finite_or_zero(diffuse::pdf(Vec3::new(0.0, 0.0, cos)))
                })
            }
            _ if !valid_direction(wo) || !valid_direction(wi) => return 0.0,
            Self::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
                tint,
            } => upper_pair(wo, wi).map_or(0.0, |(wo, wi)| {
                conductor::Conductor {
                    eta,
                    k,
                    alpha_u,
                    alpha_v,
                    tint,
                }
                .pdf(wo, wi)
            }),
            Self::Dielectric {
                eta,
                alpha_u,
                alpha_v,
                tint,
            } => dielectric::Dielectric {
                eta,
                alpha_u,
                alpha_v,
                tint,
            }
            .pdf(wo, wi),
            Self::CoatedDiffuse { .. } | Self::CoatedConductor { .. } => {
                match (upper_pair(wo, wi), layered::Layered::of(self)) {
                    (Some((wo, wi)), Some(l)) => l.pdf(wo, wi),
                    _ => 0.0,
                }
            }
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
            } => transmission::pdf(reflectance, transmittance, wo, wi),
            Self::ThinDielectric { .. } | Self::Mirror { .. } => 0.0,
            Self::Plastic {
                diffuse,
                eta,
                alpha,
                specular,
            } => upper_pair(wo, wi).map_or(0.0, |(wo, wi)| {
                plastic::Plastic {
                    diffuse,
                    eta,
                    alpha,
                    specular,
                }
                .pdf(wo, wi)
            }),
        };
        finite_or_zero(pdf)
    }

    /// Samples `wi` for `wo`, choosing a lobe with `u_lobe` in `[0, 1)` and the direction with
    /// `u` in `[0, 1)²`. `None` when sampling fails (a reflection that would go below an opaque
    /// surface, a degenerate `wo`): the path ends there.
    pub fn sample(&self, wo: Vec3, u_lobe: f64, u: [f64; 2]) -> Option<BsdfSample> {
        if !valid_direction(wo) || wo.z == 0.0 {
            return None;
        }
        let below = wo.z < 0.0;
        let up = if below { flip_z(wo) } else { wo };
        let opaque = |s: Option<BsdfSample>| {
            s.map(|s| BsdfSample {
                wi: if below { flip_z(s.wi) } else { s.wi },
                ..s
            })
        };
        let sample = match *self {
            Self::Diffuse { albedo } => {
                // The commonest surface, spared the general checks below: a cosine sample is
                // a unit vector off the surface, its weight the albedo, so only their
                // finiteness is left to check.
                let sample = opaque(diffuse::sample(albedo, u))?;
                let finite = sample.wi.is_finite()
                    && sample.pdf.is_finite()
                    && albedo.red.is_finite()
                    && albedo.green.is_finite()
                    && albedo.blue.is_finite();
                return finite.then_some(sample);
            }
            Self::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
                tint,
            } => opaque(
                conductor::Conductor {
                    eta,
                    k,
                    alpha_u,
                    alpha_v,
                    tint,
                }
                .sample(up, u),
            ),
            Self::Dielectric {
                eta,
                alpha_u,
                alpha_v,
                tint,
            } => dielectric::Dielectric {
                eta,
                alpha_u,
                alpha_v,
                tint,
            }
            .sample(wo, u_lobe, u),
            Self::CoatedDiffuse { .. } | Self::CoatedConductor { .. } => {
                opaque(layered::Layered::of(self).and_then(|l| l.sample(up, u_lobe, u)))
            }
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
            } => transmission::sample(reflectance, transmittance, wo, u_lobe, u),
            Self::ThinDielectric { eta, tint } => thin::sample(eta, tint, wo, u_lobe),
            Self::Mirror { tint } => opaque(Some(BsdfSample {
                wi: mirror(up),
                weight: tint,
                pdf: 1.0,
                delta: true,
            })),
            Self::Plastic {
                diffuse,
                eta,
                alpha,
                specular,
            } => opaque(
                plastic::Plastic {
                    diffuse,
                    eta,
                    alpha,
                    specular,
                }
                .sample(up, u_lobe, u),
            ),
        }?;
        let ok = valid_direction(sample.wi)
            && sample.pdf.is_finite()
            && sample.pdf > 0.0
            && sample.weight.red.is_finite()
            && sample.weight.green.is_finite()
            && sample.weight.blue.is_finite();
        ok.then_some(sample)
    }

    /// Whether [`sample`](Self::sample) uses its number `u_lobe`: to choose between reflection
    /// and transmission (glass, a thin sheet, diffuse transmission) or between a coat and what
    /// lies under it (plastic, the coated materials). Where it does not, a path tracer need not
    /// draw the number at all.
    pub fn chooses_lobe(&self) -> bool {
        match *self {
            Self::Dielectric { .. }
            | Self::ThinDielectric { .. }
            | Self::Plastic { .. }
            | Self::CoatedDiffuse { .. }
            | Self::CoatedConductor { .. }
            | Self::DiffuseTransmission { .. } => true,
            Self::Diffuse { .. } | Self::Conductor { .. } | Self::Mirror { .. } => false,
        }
    }

    /// Whether every lobe is a delta: the integrator then skips light sampling, which could
    /// never hit a direction the material scatters into. A coated metal is one where coat
    /// and metal are smooth and the medium between them scatters nothing (every walk then
    /// leaves in the mirror direction).
    pub fn is_delta(&self) -> bool {
        match *self {
            Self::Diffuse { .. }
            | Self::Plastic { .. }
            | Self::CoatedDiffuse { .. }
            | Self::DiffuseTransmission { .. } => false,
            Self::Conductor {
                alpha_u, alpha_v, ..
            }
            | Self::Dielectric {
                alpha_u, alpha_v, ..
            } => rough(alpha_u, alpha_v).is_none(),
            Self::CoatedConductor {
                coat, base, layers, ..
            } => {
                rough(coat.alpha_u, coat.alpha_v).is_none()
                    && rough(base.alpha_u, base.alpha_v).is_none()
                    && !layers.scatters()
            }
            Self::ThinDielectric { .. } | Self::Mirror { .. } => true,
        }
    }

    /// Whether the material's scattering depends on the direction of the frame's tangents
    /// (an anisotropic GGX width anywhere in it): only then must the integrator align the
    /// frame's first tangent with the surface's.
    pub fn is_anisotropic(&self) -> bool {
        let aniso = |u: f64, v: f64| rough(u, v).is_some_and(|g| g.alpha_x != g.alpha_y);
        match *self {
            Self::Conductor {
                alpha_u, alpha_v, ..
            }
            | Self::Dielectric {
                alpha_u, alpha_v, ..
            } => aniso(alpha_u, alpha_v),
            Self::CoatedDiffuse { coat, .. } => aniso(coat.alpha_u, coat.alpha_v),
            Self::CoatedConductor { coat, base, .. } => {
                aniso(coat.alpha_u, coat.alpha_v) || aniso(base.alpha_u, base.alpha_v)
            }
            _ => false,
        }
    }

    /// Both lobes of a perfectly smooth boundary that reflects and transmits (smooth glass, a
    /// thin sheet), so that a path can follow both at once: where a camera sees glass,
    /// choosing one lobe by chance makes the few samples that reflect a light carry it all
    /// (speckle on the glass that only many samples smooth out). Each comes with the chance
    /// [`sample`](Self::sample) would have chosen it with, by which its weight is already
    /// multiplied (its `pdf` is 1: it is followed for certain). `None` for other materials,
    /// and where one lobe takes all the light (total internal reflection).
    pub fn split(&self, wo: Vec3) -> Option<[(BsdfSample, f64); 2]> {
        let splits = match *self {
            Self::Dielectric {
                alpha_u, alpha_v, ..
            } => rough(alpha_u, alpha_v).is_none(),
            Self::ThinDielectric { .. } => true,
            _ => false,
        };
        if !splits {
            return None;
        }
        // The lobe is chosen by `u_lobe` against the reflectance: 0 reflects wherever anything
        // does, the number just below 1 transmits wherever anything does.
        let reflected = self.sample(wo, 0.0, [0.5; 2])?;
        let transmitted = self.sample(wo, 1.0 - f64::EPSILON / 2.0, [0.5; 2])?;
        if reflected.wi.z * wo.z <= 0.0 || transmitted.wi.z * wo.z >= 0.0 {
            return None;
        }
        let whole = |s: BsdfSample| {
            let certain = BsdfSample {
                weight: s.weight * s.pdf,
                pdf: 1.0,
                ..s
            };
            (certain, s.pdf)
        };
        Some([whole(reflected), whole(transmitted)])
    }

    /// Whether the material has any non-delta lobe, i.e. whether next-event estimation (light
    /// sampling) can contribute at all. Smooth plastic has one (its base) besides its delta coat.
    pub fn has_non_delta_lobe(&self) -> bool {
        !self.is_delta()
    }

    /// The colour a denoiser's albedo image shows: the diffuse albedo, a metal's reflectance at
    /// normal incidence times its tint, a dielectric's tint, plastic's reflectance head-on
    /// (`F₀ s + (1 − F₀) ρ`), and as much for the coated materials (their base's head-on
    /// reflectance in place of `ρ`, the medium left out), diffuse transmission's two shares.
    pub fn albedo(&self) -> Color {
        match *self {
            Self::Diffuse { albedo } => albedo,
            Self::Conductor { eta, k, tint, .. } => {
                tint.hadamard(fresnel::conductor_normal(eta, k))
            }
            Self::Dielectric { tint, .. }
            | Self::ThinDielectric { tint, .. }
            | Self::Mirror { tint } => tint,
            Self::Plastic {
                diffuse,
                eta,
                specular,
                ..
            } => {
                let f0 = fresnel::dielectric(1.0, eta).reflectance;
                specular * f0 + diffuse * (1.0 - f0)
            }
            Self::CoatedDiffuse {
                reflectance, coat, ..
            } => {
                let f0 = fresnel::dielectric(1.0, coat.eta).reflectance;
                Color::WHITE * f0 + reflectance * (1.0 - f0)
            }
            Self::CoatedConductor {
                coat, base, tint, ..
            } => {
                let f0 = fresnel::dielectric(1.0, coat.eta).reflectance;
                let metal = tint.hadamard(fresnel::conductor_normal(base.eta, base.k));
                Color::WHITE * f0 + metal * (1.0 - f0)
            }
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
            } => reflectance + transmittance,
        }
    }
}
