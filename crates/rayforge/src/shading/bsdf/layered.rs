//! pbrt-v4's stochastic layered BSDF (its `LayeredBxDF`, *Physically Based Rendering*, 4th
//! edition, section 14.3): a dielectric coat over a base (Lambertian for `coateddiffuse`, a
//! conductor for `coatedconductor`), with a slab of homogeneous medium of optical thickness
//! `thickness` between them that absorbs, and where its `albedo` is not black scatters by a
//! Henyey–Greenstein phase function of asymmetry `g`.
//!
//! No closed form exists for the light that bounces between the two interfaces and through
//! the medium, so all three functions are Monte Carlo estimates over random walks in the slab,
//! as pbrt-v4 computes them:
//! - `eval` averages `samples` walks, each entering through the coat towards `wo` and joined
//!   to a direction entering towards `wi` by next-event estimation at every vertex, weighted by
//!   the power heuristic against the walk's own continuation: an unbiased estimate of `f cos θi`
//!   (the coat's own reflection added exactly);
//! - `sample` follows one walk from `wo` until it leaves through the coat (at most
//!   `max_depth` events, with Russian roulette after the fourth): its weight `f cos / p` of
//!   that walk is an unbiased estimate of what the material sends along the direction it
//!   leaves by;
//! - `pdf` is not the density `sample` draws from (that has no closed form either) but
//!   pbrt-v4's estimate of its main terms (coat transmission, base, coat transmission), mixed
//!   with 10 % of the uniform density. Multiple importance sampling needs only *a* density
//!   that is the same function of `(wo, wi)` wherever it is asked (the weights of the two
//!   strategies then sum to one), not the exact one; `sample` reports this estimate as its
//!   `pdf` for the same reason, while its `weight` comes from the walk. Being positive
//!   everywhere in the hemisphere it never gives a direction the walk can reach a weight of 0.
//!
//! ## Where the random numbers come from
//! `eval` and `pdf` are given only the two directions, and `sample` only its three numbers, so
//! each seeds its own generator from a hash of its arguments, as pbrt-v4 does (its
//! `RNG(Hash(seed, wo), Hash(wi))`): the estimate is a pure function of the inputs, so a render
//! is the same for any number of threads and any order of pixels, and the integrator's sample
//! stream and dimension layout are untouched. It also makes `pdf` the same for a pair whether
//! next-event estimation or BSDF sampling asks. The price is that two queries with bitwise
//! equal directions get the same estimate (an orthographic camera over a flat coated plane lit
//! by a distant light would see one estimate everywhere); pbrt-v4 pays the same, and
//! `samples` lowers it. `sample` seeds from `(wo, u_lobe, u)`, which the path's own sample
//! stream supplies, so its walks are as independent as the stream's points.
//!
//! ## One deviation from pbrt-v4
//! Where `eval`'s walk reaches `wi` by its own continuation (off the base, or scattered in the
//! medium, then out through a rough coat), pbrt-v4 weighs that strategy against
//! `PDF(−w, wi)`, the density of sampling `wi` from inside, while the strategy it competes
//! with drew `−w` from `wi`; the two weights of one path then do not sum to one. Here the
//! competitor's own density, `pdf(wi, −w)`, is used, so `eval` estimates what `sample`
//! draws: measured at `cos θo = 0.7` on a coat of width 0.3 over a diffuse base, the mean
//! sample weight was 0.396, the integral of `eval` 0.428 with pbrt-v4's weights and 0.398 with
//! these (the tests check the agreement bin by bin).
//!
//! The dispatcher mirrors both directions above the surface first (the coated materials are
//! two-sided, as pbrt-v4's are), so here `wo` always enters through the coat and a walk can
//! only leave through it (the bases transmit nothing): only pbrt-v4's reflection terms are
//! needed. Conventions differ from pbrt-v4 in one place: the coat's rough microfacets use the
//! separable Smith shadowing `G1(wo) G1(wi)` of the rest of this module (pbrt-v4's is height
//! correlated), a difference of at most a few percent at grazing angles on very rough coats.

use super::microfacet::{reflect, Ggx};
use super::{conductor, fresnel, rough, Bsdf, BsdfSample};
use crate::color::Color;
use crate::math::random::{Jitter, SplitMix64};
use crate::math::{cosine_hemisphere, sin_cos_turns, Frame, Vec3};
use std::f64::consts::{FRAC_1_PI, PI};

/// The dielectric coat of a layered material: its index and GGX widths.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coat {
    /// The coat's index over the index outside (pbrt-v4's `eta`, 1.5 by default there).
    pub eta: f64,
    /// GGX width along the frame's first tangent (both below `MIN_ALPHA`: a smooth coat).
    pub alpha_u: f64,
    /// GGX width along the second tangent.
    pub alpha_v: f64,
}

impl Coat {
    /// A smooth coat of index `eta`.
    pub const fn smooth(eta: f64) -> Self {
        Self {
            eta,
            alpha_u: 0.0,
            alpha_v: 0.0,
        }
    }
}

/// The metal under a coated conductor's coat: its complex index relative to the coat (pbrt-v4's
/// `conductor.eta` and `conductor.k`; [`conductor_for_reflectance`](super::conductor_for_reflectance)
/// turns a `reflectance` into them) and its GGX widths.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConductorBase {
    /// Real part of the index, per channel.
    pub eta: Color,
    /// Extinction coefficient, per channel.
    pub k: Color,
    /// GGX width along the frame's first tangent (both below `MIN_ALPHA`: polished).
    pub alpha_u: f64,
    /// GGX width along the second tangent.
    pub alpha_v: f64,
}

/// The medium between a layered material's coat and base, and the limits of the random walks
/// that estimate its light transport.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layers {
    /// Optical thickness of the slab (its extinction coefficient is 1): light crossing it at
    /// `cos θ` keeps `exp(−thickness / |cos θ|)`. Raised to the smallest positive number.
    pub thickness: f64,
    /// The medium's single-scattering albedo, per channel in `[0, 1]` (black: it only absorbs).
    pub albedo: Color,
    /// The Henyey–Greenstein asymmetry of its scattering, in `(−1, 1)` (0: isotropic).
    pub g: f64,
    /// The most scattering events of one walk.
    pub max_depth: u32,
    /// Walks averaged by each evaluation and density estimate (at least one).
    pub samples: u32,
}

impl Layers {
    /// pbrt-v4's defaults: thickness 0.01, albedo 0, g 0, maxdepth 10, nsamples 1.
    pub const PBRT_DEFAULT: Self = Self {
        thickness: 0.01,
        albedo: Color::BLACK,
        g: 0.0,
        max_depth: 10,
        samples: 1,
    };

    /// Whether the medium scatters (its albedo is not black).
    pub fn scatters(&self) -> bool {
        self.albedo.max_channel() > 0.0
    }
}

/// How a direction's value is meant, for the coat's transmission (pbrt-v4's `TransportMode`):
/// radiance is scaled by `1/η²` crossing into a denser medium, importance is not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Radiance,
    Importance,
}

/// Which lobes a sampling or density query may use (pbrt-v4's `BxDFReflTransFlags`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Lobes {
    All,
    Reflection,
    Transmission,
}

impl Lobes {
    /// The probabilities of reflecting and transmitting for reflectance `r`, restricted to the
    /// allowed lobes and normalised (`None`: nothing allowed scatters).
    fn shares(self, r: f64) -> Option<(f64, f64)> {
        let pr = if self == Lobes::Transmission { 0.0 } else { r };
        let pt = if self == Lobes::Reflection {
            0.0
        } else {
            1.0 - r
        };
        let sum = pr + pt;
        (sum > 0.0).then(|| (pr / sum, pt / sum))
    }
}

/// A direction one interface scattered into: the BSDF value `f` (no cosine), the density, and
/// whether it is a delta.
#[derive(Debug, Clone, Copy)]
struct Scattered {
    f: Color,
    wi: Vec3,
    pdf: f64,
    specular: bool,
}

impl Scattered {
    fn usable(self) -> Option<Self> {
        let ok = self.f.max_channel() > 0.0
            && self.pdf > 0.0
            && self.pdf.is_finite()
            && self.wi.z != 0.0
            && self.wi.is_finite();
        ok.then_some(self)
    }
}

/// The coat: a dielectric boundary seen from either side (pbrt-v4's `DielectricBxDF`).
#[derive(Debug, Clone, Copy)]
struct Interface {
    eta: f64,
    ggx: Option<Ggx>,
}

/// `w` refracted through the microfacet `m` (either side) of a boundary of index `eta`, and the
/// index ratio it crossed (transmitted side over incident side); `None` under total internal
/// reflection.
fn refract(w: Vec3, m: Vec3, eta: f64) -> Option<(Vec3, f64)> {
    let cos = w.dot(m);
    let (n, cos_i, eta_ti) = if cos < 0.0 {
        (-m, -cos, 1.0 / eta)
    } else {
        (m, cos, eta)
    };
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta_ti * eta_ti);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-w / eta_ti + n * (cos_i / eta_ti - cos_t), eta_ti))
}

impl Interface {
    fn specular(&self) -> bool {
        self.ggx.is_none()
    }

    /// The microfacet normal joining `wo` and `wi` (pbrt-v4's generalised half vector), the
    /// index ratio of a transmission (1 for a reflection), and whether it is a reflection.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f64, bool)> {
        let (co, ci) = (wo.z, wi.z);
        if co == 0.0 || ci == 0.0 {
            return None;
        }
        let reflection = co * ci > 0.0;
        let etap = match (reflection, co > 0.0) {
            (true, _) => 1.0,
            (false, true) => self.eta,
            (false, false) => 1.0 / self.eta,
        };
        let wm = (wi * etap + wo).try_normalize()?;
        let wm = if wm.z < 0.0 { -wm } else { wm };
        // Microfacets seen from behind by either direction scatter nothing.
        if wm.dot(wi) * ci <= 0.0 || wm.dot(wo) * co <= 0.0 {
            return None;
        }
        Some((wm, etap, reflection))
    }

    /// The BSDF value (no cosine); a smooth coat's is all delta, 0 here.
    fn f(&self, wo: Vec3, wi: Vec3, mode: Mode) -> f64 {
        let Some(ggx) = self.ggx else {
            return 0.0;
        };
        let Some((wm, etap, reflection)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let d = ggx.d(wm);
        let g = ggx.g1(wo, wm) * ggx.g1(wi, wm);
        let r = fresnel::dielectric(wo.dot(wm), self.eta).reflectance;
        let value = if reflection {
            d * g * r / (4.0 * wi.z * wo.z).abs()
        } else {
            let (cos_im, cos_om) = (wi.dot(wm), wo.dot(wm));
            let denom = (cos_im + cos_om / etap).powi(2) * wi.z * wo.z;
            let t = d * (1.0 - r) * g * (cos_im * cos_om / denom).abs();
            match mode {
                Mode::Radiance => t / (etap * etap),
                Mode::Importance => t,
            }
        };
        if value.is_finite() {
            value
        } else {
            0.0
        }
    }

    /// The density of [`sample`](Self::sample) restricted to `lobes`.
    fn pdf(&self, wo: Vec3, wi: Vec3, lobes: Lobes) -> f64 {
        let Some(ggx) = self.ggx else {
            return 0.0;
        };
        let Some((wm, etap, reflection)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let r = fresnel::dielectric(wo.dot(wm), self.eta).reflectance;
        let Some((pr, pt)) = lobes.shares(r) else {
            return 0.0;
        };
        let seen_from = if wo.z < 0.0 { -wo } else { wo };
        let visible = ggx.visible_pdf(seen_from, wm);
        let pdf = if reflection {
            pr * visible / (4.0 * wo.dot(wm).abs())
        } else {
            let cos_im = wi.dot(wm);
            let denom = (cos_im + wo.dot(wm) / etap).powi(2);
            pt * visible * cos_im.abs() / denom
        };
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// Reflection or transmission (by `uc` against the Fresnel shares of the allowed lobes) off
    /// the smooth coat or a visible microfacet.
    fn sample(
        &self,
        wo: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Mode,
        lobes: Lobes,
    ) -> Option<Scattered> {
        let scale = |etap: f64| match mode {
            Mode::Radiance => 1.0 / (etap * etap),
            Mode::Importance => 1.0,
        };
        let Some(ggx) = self.ggx else {
            let fr = fresnel::dielectric(wo.z, self.eta);
            let r = fr.reflectance;
            let (pr, pt) = lobes.shares(r)?;
            if uc < pr {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                return Scattered {
                    f: Color::WHITE * (r / wi.z.abs()),
                    wi,
                    pdf: pr,
                    specular: true,
                }
                .usable();
            }
            if fr.cos_t == 0.0 {
                return None;
            }
            let wi = Vec3::new(-wo.x / fr.eta_ti, -wo.y / fr.eta_ti, fr.cos_t);
            return Scattered {
                f: Color::WHITE * ((1.0 - r) / wi.z.abs() * scale(fr.eta_ti)),
                wi,
                pdf: pt,
                specular: true,
            }
            .usable();
        };
        let seen_from = if wo.z < 0.0 { -wo } else { wo };
        let wm = ggx.sample_visible(seen_from, u)?;
        let cos_om = wo.dot(wm);
        let r = fresnel::dielectric(cos_om, self.eta).reflectance;
        let (pr, pt) = lobes.shares(r)?;
        let visible = ggx.visible_pdf(seen_from, wm);
        let d = ggx.d(wm);
        let scattered = if uc < pr {
            let wi = reflect(wo, wm);
            if wi.z * wo.z <= 0.0 {
                return None;
            }
            let g = ggx.g1(wo, wm) * ggx.g1(wi, wm);
            Scattered {
                f: Color::WHITE * (d * g * r / (4.0 * wi.z * wo.z).abs()),
                wi,
                pdf: pr * visible / (4.0 * cos_om.abs()),
                specular: false,
            }
        } else {
            let (wi, etap) = refract(wo, wm, self.eta)?;
            if wi.z * wo.z >= 0.0 {
                return None;
            }
            let cos_im = wi.dot(wm);
            let denom = (cos_im + cos_om / etap).powi(2);
            let g = ggx.g1(wo, wm) * ggx.g1(wi, wm);
            let t = d * (1.0 - r) * g * (cos_im * cos_om / (denom * wi.z * wo.z)).abs();
            Scattered {
                f: Color::WHITE * (t * scale(etap)),
                wi,
                pdf: pt * visible * cos_im.abs() / denom,
                specular: false,
            }
        };
        scattered.usable()
    }
}

/// What lies under the coat: it reflects only (pbrt-v4's `DiffuseBxDF` or `ConductorBxDF`).
#[derive(Debug, Clone, Copy)]
enum Base {
    Diffuse(Color),
    Conductor(conductor::Conductor),
}

/// `wo` and `wi` turned so that `wo` is above (the bases are the same from either side).
fn upper(wo: Vec3, wi: Vec3) -> (Vec3, Vec3, bool) {
    if wo.z < 0.0 {
        (
            Vec3::new(wo.x, wo.y, -wo.z),
            Vec3::new(wi.x, wi.y, -wi.z),
            true,
        )
    } else {
        (wo, wi, false)
    }
}

impl Base {
    fn specular(&self) -> bool {
        match self {
            Base::Diffuse(_) => false,
            Base::Conductor(c) => rough(c.alpha_u, c.alpha_v).is_none(),
        }
    }

    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        if wo.z * wi.z <= 0.0 {
            return Color::BLACK;
        }
        match self {
            Base::Diffuse(r) => *r * FRAC_1_PI,
            Base::Conductor(c) => {
                let (wo, wi, _) = upper(wo, wi);
                c.eval(wo, wi) / wi.z
            }
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, lobes: Lobes) -> f64 {
        if lobes == Lobes::Transmission || wo.z * wi.z <= 0.0 {
            return 0.0;
        }
        match self {
            Base::Diffuse(_) => wi.z.abs() * FRAC_1_PI,
            Base::Conductor(c) => {
                let (wo, wi, _) = upper(wo, wi);
                c.pdf(wo, wi)
            }
        }
    }

    fn sample(&self, wo: Vec3, u: [f64; 2], lobes: Lobes) -> Option<Scattered> {
        if lobes == Lobes::Transmission || wo.z == 0.0 {
            return None;
        }
        let (up, _, flipped) = upper(wo, Vec3::ZERO);
        let (wi, f, pdf, specular) = match self {
            Base::Diffuse(r) => {
                let wi = cosine_hemisphere(u);
                (wi, *r * FRAC_1_PI, wi.z * FRAC_1_PI, false)
            }
            Base::Conductor(c) => {
                let s = c.sample(up, u)?;
                let cos = s.wi.z.abs();
                let f = if s.delta {
                    s.weight / cos
                } else {
                    s.weight * (s.pdf / cos)
                };
                (s.wi, f, s.pdf, s.delta)
            }
        };
        let wi = if flipped {
            Vec3::new(wi.x, wi.y, -wi.z)
        } else {
            wi
        };
        Scattered {
            f,
            wi,
            pdf,
            specular,
        }
        .usable()
    }
}

/// The Henyey–Greenstein phase function in pbrt-v4's convention: both directions point away
/// from the scattering point, so forward scattering (`g > 0`) favours `wi ≈ −wo`.
#[derive(Debug, Clone, Copy)]
struct Phase {
    g: f64,
}

impl Phase {
    fn hg(&self, cos: f64) -> f64 {
        let g = self.g;
        let denom = 1.0 + g * g + 2.0 * g * cos;
        (1.0 - g * g) / (4.0 * PI * denom * denom.max(0.0).sqrt())
    }

    fn p(&self, wo: Vec3, wi: Vec3) -> f64 {
        self.hg(wo.dot(wi))
    }

    /// A direction drawn exactly from `p(wo, ·)`, and its density (the phase function itself).
    fn sample(&self, wo: Vec3, u: [f64; 2]) -> Option<(Vec3, f64)> {
        let g = self.g;
        // The cosine from the forward direction −wo, by inverting HG's distribution.
        let cos = if g.abs() < 1e-3 {
            1.0 - 2.0 * u[0]
        } else {
            let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u[0]);
            (1.0 + g * g - s * s) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (sin_phi, cos_phi) = sin_cos_turns(u[1]);
        let wi = Frame::from_normal(-wo).to_world(Vec3::new(sin * cos_phi, sin * sin_phi, cos));
        let pdf = self.p(wo, wi);
        (pdf > 0.0 && pdf.is_finite() && wi.is_finite()).then_some((wi, pdf))
    }
}

/// The power heuristic (exponent 2) of density `a` against `b`.
fn power(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && (a2 + b2).is_finite() {
        a2 / (a2 + b2)
    } else if a.is_infinite() {
        1.0
    } else {
        0.0
    }
}

/// The share of light that crosses `dz` of the slab along `w`: `exp(−|dz / cos θ|)`.
fn transmittance(dz: f64, w: Vec3) -> f64 {
    if dz.abs() <= f64::MIN_POSITIVE {
        1.0
    } else {
        (-(dz / w.z).abs()).exp()
    }
}

/// A generator seeded from the bits of `parts` and a salt naming the query (so that `eval`,
/// `pdf` and `sample` with equal numbers do not draw the same walks).
fn generator(salt: u64, parts: &[f64]) -> SplitMix64 {
    let mut h = SplitMix64::new(salt).next_u64();
    for x in parts {
        // Zero's two signs hash alike.
        let bits = if *x == 0.0 { 0 } else { x.to_bits() };
        h = SplitMix64::new(h ^ bits).next_u64();
    }
    SplitMix64::new(h)
}

const EVAL_SALT: u64 = 0x6576_616c;
const PDF_SALT: u64 = 0x0070_6466;
const SAMPLE_SALT: u64 = 0x7361_6d70;

/// Numbers in `[0, 1)` from `rng`.
fn draw(rng: &mut SplitMix64) -> f64 {
    rng.next_offset()
}

fn draw2(rng: &mut SplitMix64) -> [f64; 2] {
    [rng.next_offset(), rng.next_offset()]
}

/// A coated material ready to evaluate: coat, base and slab, with its parameters made safe.
#[derive(Debug, Clone, Copy)]
pub(super) struct Layered {
    top: Interface,
    bottom: Base,
    thickness: f64,
    albedo: Color,
    phase: Phase,
    max_depth: u32,
    samples: u32,
}

impl Layered {
    /// The layered model of a coated [`Bsdf`] (`None` for other materials).
    pub fn of(bsdf: &Bsdf) -> Option<Self> {
        let (coat, bottom, layers) = match *bsdf {
            Bsdf::CoatedDiffuse {
                reflectance,
                coat,
                layers,
            } => (coat, Base::Diffuse(reflectance), layers),
            Bsdf::CoatedConductor {
                coat,
                base,
                tint,
                layers,
            } => (
                coat,
                Base::Conductor(conductor::Conductor {
                    eta: base.eta,
                    k: base.k,
                    alpha_u: base.alpha_u,
                    alpha_v: base.alpha_v,
                    tint,
                }),
                layers,
            ),
            _ => return None,
        };
        let unit = |x: f64| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        let albedo = layers.albedo;
        Some(Self {
            top: Interface {
                eta: coat.eta,
                ggx: rough(coat.alpha_u, coat.alpha_v),
            },
            bottom,
            thickness: if layers.thickness.is_nan() {
                f64::MIN_POSITIVE
            } else {
                layers.thickness.max(f64::MIN_POSITIVE)
            },
            albedo: Color::new(unit(albedo.red), unit(albedo.green), unit(albedo.blue)),
            phase: Phase {
                g: if layers.g.is_nan() {
                    0.0
                } else {
                    layers.g.clamp(-0.999, 0.999)
                },
            },
            max_depth: layers.max_depth,
            samples: layers.samples.max(1),
        })
    }

    fn scatters(&self) -> bool {
        self.albedo.max_channel() > 0.0
    }

    /// The estimate of `f(wo, wi) cos θi`, both directions above.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Color::BLACK;
        }
        let (top, bottom, thickness) = (&self.top, &self.bottom, self.thickness);
        let n = f64::from(self.samples);
        let mut f = Color::WHITE * (n * top.f(wo, wi, Mode::Radiance));
        let mut rng = generator(EVAL_SALT, &[wo.x, wo.y, wo.z, wi.x, wi.y, wi.z]);
        let rng = &mut rng;
        let exit_z = thickness;
        for _ in 0..self.samples {
            let entering = top.sample(
                wo,
                draw(rng),
                draw2(rng),
                Mode::Radiance,
                Lobes::Transmission,
            );
            let Some(wos) = entering else { continue };
            let leaving = top.sample(
                wi,
                draw(rng),
                draw2(rng),
                Mode::Importance,
                Lobes::Transmission,
            );
            let Some(wis) = leaving else { continue };
            let mut beta = wos.f * (wos.wi.z.abs() / wos.pdf);
            let mut z = thickness;
            let mut w = wos.wi;
            for depth in 0..self.max_depth {
                if depth > 3 && beta.max_channel() < 0.25 {
                    let q = (1.0 - beta.max_channel()).max(0.0);
                    if draw(rng) < q {
                        break;
                    }
                    beta = beta / (1.0 - q);
                }
                if !self.scatters() {
                    z = if z == thickness { 0.0 } else { thickness };
                    beta = beta * transmittance(thickness, w);
                } else {
                    let dz = -(1.0 - draw(rng)).ln() * w.z.abs();
                    let zp = if w.z > 0.0 { z + dz } else { z - dz };
                    if zp == z {
                        continue;
                    }
                    if 0.0 < zp && zp < thickness {
                        // Scattered in the medium: joined to `wi` through the coat along the
                        // direction drawn for it, then the phase function's own direction.
                        let weight = if top.specular() {
                            1.0
                        } else {
                            power(wis.pdf, self.phase.p(-w, -wis.wi))
                        };
                        f += beta.hadamard(self.albedo).hadamard(wis.f)
                            * (self.phase.p(-w, -wis.wi)
                                * weight
                                * transmittance(zp - exit_z, wis.wi)
                                / wis.pdf);
                        let Some((next, p)) = self.phase.sample(-w, draw2(rng)) else {
                            continue;
                        };
                        if next.z == 0.0 {
                            continue;
                        }
                        // The phase function is sampled exactly: p / pdf is 1.
                        beta = beta.hadamard(self.albedo);
                        w = next;
                        z = zp;
                        if z < exit_z && w.z > 0.0 && !top.specular() {
                            let exit = top.f(-w, wi, Mode::Radiance);
                            if exit > 0.0 {
                                let exit_pdf = top.pdf(wi, -w, Lobes::Transmission);
                                let weight = power(p, exit_pdf);
                                f += beta * (transmittance(zp - exit_z, next) * exit * weight);
                            }
                        }
                        continue;
                    }
                    z = zp.clamp(0.0, thickness);
                }
                if z == exit_z {
                    // Back down off the underside of the coat.
                    let Some(bs) =
                        top.sample(-w, draw(rng), draw2(rng), Mode::Radiance, Lobes::Reflection)
                    else {
                        break;
                    };
                    beta = beta.hadamard(bs.f) * (bs.wi.z.abs() / bs.pdf);
                    w = bs.wi;
                } else {
                    // At the base: joined to `wi` along the direction drawn for it, then the
                    // base's own direction joined to `wi` through the coat.
                    if !bottom.specular() {
                        let weight = if top.specular() {
                            1.0
                        } else {
                            power(wis.pdf, bottom.pdf(-w, -wis.wi, Lobes::All))
                        };
                        f += beta.hadamard(bottom.f(-w, -wis.wi)).hadamard(wis.f)
                            * (wis.wi.z.abs() * weight * transmittance(thickness, wis.wi)
                                / wis.pdf);
                    }
                    let Some(bs) = bottom.sample(-w, draw2(rng), Lobes::Reflection) else {
                        break;
                    };
                    beta = beta.hadamard(bs.f) * (bs.wi.z.abs() / bs.pdf);
                    w = bs.wi;
                    if !top.specular() {
                        let exit = top.f(-w, wi, Mode::Radiance);
                        if exit > 0.0 {
                            let weight = if bottom.specular() {
                                1.0
                            } else {
                                power(bs.pdf, top.pdf(wi, -w, Lobes::Transmission))
                            };
                            f += beta * (transmittance(thickness, bs.wi) * exit * weight);
                        }
                    }
                }
            }
        }
        f * (wi.z / n)
    }

    /// pbrt-v4's estimate of the sampling density (see the [module](self)), both above.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f64 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let (top, bottom) = (&self.top, &self.bottom);
        let n = f64::from(self.samples);
        let mut rng = generator(PDF_SALT, &[wi.x, wi.y, wi.z, wo.x, wo.y, wo.z]);
        let rng = &mut rng;
        let mut sum = n * top.pdf(wo, wi, Lobes::Reflection);
        for _ in 0..self.samples {
            let wos = top.sample(
                wo,
                draw(rng),
                draw2(rng),
                Mode::Radiance,
                Lobes::Transmission,
            );
            let wis = top.sample(
                wi,
                draw(rng),
                draw2(rng),
                Mode::Importance,
                Lobes::Transmission,
            );
            let (Some(wos), Some(wis)) = (wos, wis) else {
                continue;
            };
            if top.specular() {
                sum += bottom.pdf(-wos.wi, -wis.wi, Lobes::All);
                continue;
            }
            let Some(rs) = bottom.sample(-wos.wi, draw2(rng), Lobes::All) else {
                continue;
            };
            if bottom.specular() {
                sum += top.pdf(-rs.wi, wi, Lobes::All);
            } else {
                let r_pdf = bottom.pdf(-wos.wi, -wis.wi, Lobes::All);
                sum += power(wis.pdf, r_pdf) * r_pdf;
                let t_pdf = top.pdf(-rs.wi, wi, Lobes::All);
                sum += power(rs.pdf, t_pdf) * t_pdf;
            }
        }
        let pdf = 0.1 / (4.0 * PI) + 0.9 * sum / n;
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// One walk from `wo` (above) until it leaves through the coat.
    pub fn sample(&self, wo: Vec3, u_lobe: f64, u: [f64; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (top, bottom, thickness) = (&self.top, &self.bottom, self.thickness);
        let first = top.sample(wo, u_lobe, u, Mode::Radiance, Lobes::All)?;
        if first.wi.z > 0.0 {
            // The coat's own reflection.
            let weight = first.f * (first.wi.z / first.pdf);
            let pdf = if first.specular {
                first.pdf
            } else {
                self.pdf(wo, first.wi)
            };
            return Some(BsdfSample {
                wi: first.wi,
                weight,
                pdf,
                delta: first.specular,
            });
        }
        let mut rng = generator(SAMPLE_SALT, &[wo.x, wo.y, wo.z, u_lobe, u[0], u[1]]);
        let rng = &mut rng;
        let mut specular_path = first.specular;
        let mut f = first.f * first.wi.z.abs();
        let mut pdf = first.pdf;
        let mut z = thickness;
        let mut w = first.wi;
        for depth in 0..self.max_depth {
            let rr_beta = f.max_channel() / pdf;
            if depth > 3 && rr_beta < 0.25 {
                let q = (1.0 - rr_beta).max(0.0);
                if draw(rng) < q {
                    return None;
                }
                pdf *= 1.0 - q;
            }
            if w.z == 0.0 {
                return None;
            }
            if self.scatters() {
                let dz = -(1.0 - draw(rng)).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    return None;
                }
                if 0.0 < zp && zp < thickness {
                    let (next, p) = self.phase.sample(-w, draw2(rng))?;
                    if next.z == 0.0 {
                        return None;
                    }
                    f = f.hadamard(self.albedo) * p;
                    pdf *= p;
                    specular_path = false;
                    w = next;
                    z = zp;
                    continue;
                }
                z = zp.clamp(0.0, thickness);
            } else {
                z = if z == thickness { 0.0 } else { thickness };
                f = f * transmittance(thickness, w);
            }
            let bs = if z == 0.0 {
                bottom.sample(-w, draw2(rng), Lobes::All)?
            } else {
                top.sample(-w, draw(rng), draw2(rng), Mode::Radiance, Lobes::All)?
            };
            f = f.hadamard(bs.f);
            pdf *= bs.pdf;
            specular_path &= bs.specular;
            w = bs.wi;
            if z != 0.0 && bs.wi.z > 0.0 {
                // Out through the coat.
                let weight = f * (w.z / pdf);
                let reported = if specular_path {
                    first.pdf
                } else {
                    self.pdf(wo, w)
                };
                return Some(BsdfSample {
                    wi: w,
                    weight,
                    pdf: reported,
                    delta: specular_path,
                });
            }
            f = f * bs.wi.z.abs();
        }
        None
    }
}
