//! What a material means to the path tracer: the [`Bsdf`] it scatters light with.
//!
//! A scene may name a physical material outright ([`Physical`]: a metal, glass, plastic, …),
//! whose colour comes from the material's colour, pattern or texture at the hit. Otherwise the
//! book's parameters are given a physical meaning ([`Scattering::phong`], [`Scattering::cgfs`],
//! [`Scattering::optics`]), so every scene written for the books renders under the path tracer
//! too, as a stack of at most three layers, each a [`Bsdf`] with a share of the light:
//!
//! - a share `transparency` of smooth dielectric with the material's refractive index (relative
//!   to the world's ambient index), Fresnel's reflection included;
//! - of the rest, a share `reflective` of perfect mirror;
//! - the rest is the diffuse base: Lambert with albedo `colour × diffuse`, under a clear coat
//!   (plastic, index 1.5) of strength `specular` and GGX width `√(2 / (shininess + 2))` (the
//!   width whose highlight matches a Blinn–Phong lobe of that exponent) when the material has
//!   a specular highlight.
//!
//! The book's `ambient` term has no physical meaning and is dropped: the path tracer's indirect
//! light is what ambient stood for.
//!
//! A path picks one layer per hit with probability proportional to its share and weighs what
//! it finds by its share over that probability (which is the sum of all the shares), which
//! estimates the shares' weighted sum of the layers without bias (and keeps next-event
//! estimation and multiple importance sampling within the one layer chosen).

use super::bsdf::{Bsdf, Coat, ConductorBase, Layers};
use super::material::Material;
use super::metal_rough::MetalRoughSample;
use crate::color::Color;

/// A material the path tracer understands directly, named in the scene (its colour, pattern or
/// texture gives the colour at each hit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Physical {
    /// Lambertian: the colour is the albedo.
    Diffuse,
    /// A metal of complex index `eta + i k` per channel, GGX widths `alpha_u` along the
    /// surface's tangent and `alpha_v` across it (both 0: polished; equal: isotropic); the
    /// colour tints its reflection (white for the metal itself).
    Conductor {
        /// Real part of the index, per channel.
        eta: Color,
        /// Extinction coefficient, per channel.
        k: Color,
        /// GGX width along the tangent (pbrt-v4's `uroughness` once remapped).
        alpha_u: f64,
        /// GGX width across it (`vroughness`).
        alpha_v: f64,
    },
    /// Glass and other dielectrics: index `eta` inside (relative to the world's ambient index),
    /// GGX widths `alpha_u`, `alpha_v` (both 0: smooth); the colour tints what passes and
    /// reflects.
    Dielectric {
        /// Refractive index inside.
        eta: f64,
        /// GGX width along the tangent.
        alpha_u: f64,
        /// GGX width across it.
        alpha_v: f64,
    },
    /// A thin sheet of dielectric (a window pane, a soap film) that does not bend light.
    ThinDielectric {
        /// The sheet's refractive index.
        eta: f64,
    },
    /// Plastic: a clear coat of index `eta` and GGX width `alpha` over a diffuse base of the
    /// colour.
    Plastic {
        /// The coat's refractive index.
        eta: f64,
        /// The coat's GGX width.
        alpha: f64,
    },
    /// A perfect mirror reflecting the colour's share of the light at every angle.
    Mirror,
    /// pbrt-v4's `coateddiffuse`: a dielectric `coat` over a Lambertian base whose albedo is
    /// the colour, with the medium `layers` between (pbrt-v4's defaults:
    /// `Coat::smooth(1.5)` and [`Layers::PBRT_DEFAULT`]). The coat's index is relative to
    /// the world's ambient index.
    CoatedDiffuse {
        /// The interface on top (pbrt-v4's `eta`, `uroughness`, `vroughness`).
        coat: Coat,
        /// `thickness`, `albedo`, `g`, `maxdepth`, `nsamples`.
        layers: Layers,
    },
    /// pbrt-v4's `coatedconductor`: a dielectric `coat` over a metal `base`, with the medium
    /// `layers` between; the colour tints the metal's reflection (white for the metal itself).
    /// The base's index is given relative to vacuum, as pbrt-v4's `conductor.eta`/`conductor.k`
    /// are, and divided by the coat's index here, as pbrt-v4 divides it.
    CoatedConductor {
        /// The interface on top (pbrt-v4's `interface.eta`, `interface.uroughness`, …).
        coat: Coat,
        /// The metal (`conductor.eta`, `conductor.k`, `conductor.uroughness`, …).
        base: ConductorBase,
        /// `thickness`, `albedo`, `g`, `maxdepth`, `nsamples`.
        layers: Layers,
    },
    /// pbrt-v4's `diffusetransmission`: Lambertian reflection of `reflectance` and Lambertian
    /// transmission of `transmittance` (pbrt-v4's defaults: 0.25 each), both multiplied by the
    /// colour at the hit and each channel held in `[0, 1]`.
    DiffuseTransmission {
        /// The share reflected, per channel.
        reflectance: Color,
        /// The share transmitted, per channel.
        transmittance: Color,
    },
}

impl Physical {
    /// The same material with its GGX width (both widths, the coat's for the coated ones) and
    /// refractive index (the coat's) replaced where given and where it has them (a pattern's
    /// value at a hit).
    pub fn with_parameters(self, alpha: Option<f64>, index: Option<f64>) -> Self {
        let a = |old: f64| alpha.unwrap_or(old);
        let e = |old: f64| index.unwrap_or(old);
        let coat = |c: Coat| Coat {
            eta: e(c.eta),
            alpha_u: a(c.alpha_u),
            alpha_v: a(c.alpha_v),
        };
        match self {
            Physical::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
            } => Physical::Conductor {
                eta,
                k,
                alpha_u: a(alpha_u),
                alpha_v: a(alpha_v),
            },
            Physical::Dielectric {
                eta,
                alpha_u,
                alpha_v,
            } => Physical::Dielectric {
                eta: e(eta),
                alpha_u: a(alpha_u),
                alpha_v: a(alpha_v),
            },
            Physical::CoatedDiffuse { coat: c, layers } => Physical::CoatedDiffuse {
                coat: coat(c),
                layers,
            },
            Physical::CoatedConductor {
                coat: c,
                base,
                layers,
            } => Physical::CoatedConductor {
                coat: coat(c),
                base,
                layers,
            },
            Physical::ThinDielectric { eta } => Physical::ThinDielectric { eta: e(eta) },
            Physical::Plastic { eta, alpha: old } => Physical::Plastic {
                eta: e(eta),
                alpha: a(old),
            },
            other => other,
        }
    }

    /// The same material with the parameters its textures give at a hit replaced where given
    /// (pbrt-v4's textured `roughness`, `eta`, `k`, `reflectance`, `thickness`, …); materials
    /// without a parameter keep their own, and values out of range are held in it.
    pub fn with_textured(self, at: &HitParameters) -> Self {
        let widths = |old: (f64, f64)| at.widths.unwrap_or(old);
        let coat = |c: Coat| {
            let (alpha_u, alpha_v) = widths((c.alpha_u, c.alpha_v));
            Coat {
                alpha_u,
                alpha_v,
                ..c
            }
        };
        let metal = |eta: Color, k: Color| {
            let eta = at.eta.map_or(eta, |e| at_least(e, MIN_INDEX));
            let k = at.k.map_or(k, |k| at_least(k, 0.0));
            (eta, k)
        };
        let layers = |l: Layers| Layers {
            thickness: at
                .thickness
                .map_or(l.thickness, |t| t.max(f64::MIN_POSITIVE)),
            albedo: at.albedo.map_or(l.albedo, clamp_unit),
            g: at.g.map_or(l.g, |g| g.clamp(-MAX_G, MAX_G)),
            ..l
        };
        match self {
            Physical::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
            } => {
                let (alpha_u, alpha_v) = widths((alpha_u, alpha_v));
                let (eta, k) = metal(eta, k);
                Physical::Conductor {
                    eta,
                    k,
                    alpha_u,
                    alpha_v,
                }
            }
            Physical::Dielectric {
                eta,
                alpha_u,
                alpha_v,
            } => {
                let (alpha_u, alpha_v) = widths((alpha_u, alpha_v));
                Physical::Dielectric {
                    eta,
                    alpha_u,
                    alpha_v,
                }
            }
            Physical::CoatedDiffuse { coat: c, layers: l } => Physical::CoatedDiffuse {
                coat: coat(c),
                layers: layers(l),
            },
            Physical::CoatedConductor {
                coat: c,
                base,
                layers: l,
            } => {
                let (alpha_u, alpha_v) = at.base_widths.unwrap_or((base.alpha_u, base.alpha_v));
                let (eta, k) = metal(base.eta, base.k);
                Physical::CoatedConductor {
                    coat: coat(c),
                    base: ConductorBase {
                        eta,
                        k,
                        alpha_u,
                        alpha_v,
                    },
                    layers: layers(l),
                }
            }
            Physical::DiffuseTransmission {
                reflectance,
                transmittance,
            } => Physical::DiffuseTransmission {
                reflectance: at.reflectance.unwrap_or(reflectance),
                transmittance: at.transmittance.unwrap_or(transmittance),
            },
            other => other,
        }
    }

    /// The scattering of this material with `colour` at the hit, where the world's ambient
    /// index is `ambient_index`.
    pub fn bsdf(self, colour: Color, ambient_index: f64) -> Bsdf {
        let relative = |eta: f64| eta / ambient_index.max(1e-6);
        match self {
            Physical::Diffuse => Bsdf::Diffuse {
                albedo: clamp_unit(colour),
            },
            Physical::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
            } => Bsdf::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
                tint: colour,
            },
            Physical::Dielectric {
                eta,
                alpha_u,
                alpha_v,
            } => Bsdf::Dielectric {
                eta: relative(eta),
                alpha_u,
                alpha_v,
                tint: colour,
            },
            Physical::ThinDielectric { eta } => Bsdf::ThinDielectric {
                eta: relative(eta),
                tint: colour,
            },
            Physical::Plastic { eta, alpha } => Bsdf::Plastic {
                diffuse: clamp_unit(colour),
                eta: relative(eta),
                alpha,
                specular: Color::WHITE,
            },
            Physical::Mirror => Bsdf::Mirror { tint: colour },
            Physical::CoatedDiffuse { coat, layers } => Bsdf::CoatedDiffuse {
                reflectance: clamp_unit(colour),
                coat: Coat {
                    eta: relative(coat.eta),
                    ..coat
                },
                layers,
            },
            Physical::CoatedConductor { coat, base, layers } => {
                let inside = coat.eta.max(1e-6);
                Bsdf::CoatedConductor {
                    coat: Coat {
                        eta: relative(coat.eta),
                        ..coat
                    },
                    base: ConductorBase {
                        eta: base.eta / inside,
                        k: base.k / inside,
                        ..base
                    },
                    tint: colour,
                    layers,
                }
            }
            Physical::DiffuseTransmission {
                reflectance,
                transmittance,
            } => Bsdf::DiffuseTransmission {
                reflectance: clamp_unit(colour.hadamard(reflectance)),
                transmittance: clamp_unit(colour.hadamard(transmittance)),
            },
        }
    }
}

/// A material's parameters as its textures give them at one hit; `None` keeps the material's
/// own (see [`Physical::with_textured`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HitParameters {
    /// The GGX widths of the interface on top (a conductor's, a dielectric's, a coat's).
    pub widths: Option<(f64, f64)>,
    /// A coated conductor's metal's widths.
    pub base_widths: Option<(f64, f64)>,
    /// A diffuse transmitter's reflectance.
    pub reflectance: Option<Color>,
    /// A diffuse transmitter's transmittance.
    pub transmittance: Option<Color>,
    /// A metal's index (a conductor's, a coated conductor's base, relative to vacuum).
    pub eta: Option<Color>,
    /// A metal's extinction coefficient.
    pub k: Option<Color>,
    /// A layered material's slab thickness.
    pub thickness: Option<f64>,
    /// Its medium's albedo.
    pub albedo: Option<Color>,
    /// Its medium's asymmetry.
    pub g: Option<f64>,
}

/// The index and extinction coefficient pbrt-v4 gives a conductor of normal-incidence
/// reflectance `r` (its `reflectance` parameter): index 1 and `k = 2√r / √(1 − r)` per
/// channel, `r` held below 1.
pub fn conductor_of_reflectance(r: Color) -> (Color, Color) {
    let k = |r: f64| {
        let r = r.clamp(0.0, 0.9999);
        2.0 * r.sqrt() / (1.0 - r).sqrt()
    };
    (Color::WHITE, Color::new(k(r.red), k(r.green), k(r.blue)))
}

/// Every channel raised to `floor` at least (NaN to it as well).
fn at_least(c: Color, floor: f64) -> Color {
    let f = |v: f64| if v >= floor { v } else { floor };
    Color::new(f(c.red), f(c.green), f(c.blue))
}

/// The smallest metal index a texture may give (an index of 0 has no meaning).
const MIN_INDEX: f64 = 1e-4;

/// The largest |g| a texture may give (1 is a delta, which the medium's walk cannot sample).
const MAX_G: f64 = 0.999;

/// Every channel limited to [0, 1]: an albedo above 1 would create light.
fn clamp_unit(c: Color) -> Color {
    Color::new(
        c.red.clamp(0.0, 1.0),
        c.green.clamp(0.0, 1.0),
        c.blue.clamp(0.0, 1.0),
    )
}

/// The most layers a material's scattering has (dielectric, mirror, base).
const MAX_LAYERS: usize = 3;

/// A surface that scatters nothing: a black diffuse one.
const BLACK: Bsdf = Bsdf::Diffuse {
    albedo: Color::BLACK,
};

/// A material's scattering at one hit: up to three [`Bsdf`] layers, each with its share of the
/// light (see the [module](self)). Plain `Copy` data, built per hit without allocating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scattering {
    layers: [(f64, Bsdf); MAX_LAYERS],
    len: usize,
    total: f64,
}

/// One layer chosen from a [`Scattering`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    /// The layer's scattering.
    pub bsdf: Bsdf,
    /// What to multiply its contributions by: its share over the probability of choosing it,
    /// that is the sum of all the shares (1 for a material of one layer).
    pub scale: f64,
}

impl Scattering {
    /// A material of one layer.
    pub fn single(bsdf: Bsdf) -> Self {
        // The unused slots hold the smallest layer there is: built on every hit, the
        // scattering should not copy its one layer three times.
        let unused = (0.0, BLACK);
        Self {
            layers: [(1.0, bsdf), unused, unused],
            len: 1,
            total: 1.0,
        }
    }

    /// Layers with their shares; shares that are not positive and finite are left out. No
    /// layer at all scatters nothing (a black diffuse surface).
    fn layered(parts: &[(f64, Bsdf)]) -> Self {
        let mut out = Self {
            layers: [(0.0, BLACK); MAX_LAYERS],
            len: 0,
            total: 0.0,
        };
        for &(share, bsdf) in parts {
            if share.is_finite() && share > 0.0 && out.len < MAX_LAYERS {
                out.layers[out.len] = (share, bsdf);
                out.len += 1;
                out.total += share;
            }
        }
        if out.len == 0 {
            return Self::single(BLACK);
        }
        out
    }

    /// The Ray Tracer Challenge's material (the Phong model) given a physical meaning: see the
    /// [module](self). `colour` is the surface colour at the hit.
    pub fn phong(material: &Material, colour: Color, ambient_index: f64) -> Self {
        let albedo = clamp_unit(colour * material.diffuse.max(0.0));
        let coat = (material.specular > 0.0 && material.shininess > 0.0)
            .then(|| material.specular.min(1.0));
        Self::book(material, albedo, coat, ambient_index)
    }

    /// Computer Graphics from Scratch's material: the colour is the albedo (the book has no
    /// diffuse weight), a specular exponent (`shininess`, negative for matte) makes a full
    /// clear coat, `reflective` a mirror.
    pub fn cgfs(material: &Material, colour: Color, ambient_index: f64) -> Self {
        let coat = (material.shininess > 0.0).then_some(1.0);
        Self::book(material, clamp_unit(colour), coat, ambient_index)
    }

    /// Fundamentals of Ray Tracing's material: a share `1 − opacity` of dielectric of the
    /// material's index; the opaque share is a matte surface of the colour plus a mirror of the
    /// gloss colour, added as the book adds them.
    pub fn optics(material: &Material, colour: Color, ambient_index: f64) -> Self {
        let opacity = material.opacity.clamp(0.0, 1.0);
        let glass = Physical::Dielectric {
            eta: material.refractive_index.max(1e-3),
            alpha_u: 0.0,
            alpha_v: 0.0,
        }
        .bsdf(Color::WHITE, ambient_index);
        let gloss = material.gloss;
        let gloss_share = opacity * clamp_unit(gloss).max_channel();
        let mirror = Bsdf::Mirror {
            tint: clamp_unit(gloss) * (1.0 / clamp_unit(gloss).max_channel().max(1e-12)),
        };
        Self::layered(&[
            (1.0 - opacity, glass),
            (
                opacity,
                Bsdf::Diffuse {
                    albedo: clamp_unit(colour),
                },
            ),
            (gloss_share, mirror),
        ])
    }

    /// glTF's metallic-roughness material at one point (see
    /// [`MetalRough`](super::MetalRough)): a share `metallic` of GGX conductor reflecting the
    /// base colour (Fresnel 1), of the rest a share `transmission` of rough glass of index
    /// `ior` tinted by the base colour, and the remainder a rough coat of index `ior` over a
    /// Lambertian base of the base colour; every layer of GGX width `roughness²`.
    pub fn metal_rough(point: &MetalRoughSample, ior: f64, ambient_index: f64) -> Self {
        let alpha = point.roughness * point.roughness;
        let eta = ior.max(1.0 + 1e-6) / ambient_index.max(1e-6);
        let metal = Bsdf::Conductor {
            eta: Color::BLACK,
            k: Color::WHITE,
            alpha_u: alpha,
            alpha_v: alpha,
            tint: point.base,
        };
        let glass = Bsdf::Dielectric {
            eta,
            alpha_u: alpha,
            alpha_v: alpha,
            tint: point.base,
        };
        let base = Bsdf::Plastic {
            diffuse: point.base,
            eta,
            alpha,
            specular: Color::WHITE,
        };
        let dielectric = 1.0 - point.metallic;
        Self::layered(&[
            (point.metallic, metal),
            (dielectric * point.transmission, glass),
            (dielectric * (1.0 - point.transmission), base),
        ])
    }

    /// The stack of the Phong and CGFS models: dielectric, mirror, then the base (plastic with
    /// a coat of strength `coat`, or Lambert).
    fn book(material: &Material, albedo: Color, coat: Option<f64>, ambient_index: f64) -> Self {
        let t = material.transparency.clamp(0.0, 1.0);
        let r = material.reflective.clamp(0.0, 1.0);
        let base = match coat {
            Some(strength) => Bsdf::Plastic {
                diffuse: albedo,
                eta: 1.5,
                alpha: (2.0 / (material.shininess + 2.0)).sqrt(),
                specular: Color::WHITE * strength,
            },
            None => Bsdf::Diffuse { albedo },
        };
        let glass = Physical::Dielectric {
            eta: material.refractive_index.max(1e-3),
            alpha_u: 0.0,
            alpha_v: 0.0,
        }
        .bsdf(Color::WHITE, ambient_index);
        Self::layered(&[
            (t, glass),
            (r * (1.0 - t), Bsdf::Mirror { tint: Color::WHITE }),
            ((1.0 - t) * (1.0 - r), base),
        ])
    }

    /// The layer a path follows, chosen by `u` in [0, 1), and `u` rescaled to [0, 1) within
    /// that layer's range (so the caller can reuse it for the layer's own lobe choice).
    #[inline]
    pub fn pick(&self, u: f64) -> (Layer, f64) {
        if self.len == 1 {
            return (
                Layer {
                    bsdf: self.layers[0].1,
                    scale: self.total,
                },
                u,
            );
        }
        let target = u * self.total;
        let mut start = 0.0;
        for (i, &(share, bsdf)) in self.layers[..self.len].iter().enumerate() {
            let end = start + share;
            if target < end || i + 1 == self.len {
                let rescaled = ((target - start) / share).clamp(0.0, 1.0 - f64::EPSILON);
                return (
                    Layer {
                        bsdf,
                        scale: self.total,
                    },
                    rescaled,
                );
            }
            start = end;
        }
        unreachable!("a scattering has at least one layer")
    }

    /// What a denoiser's albedo image shows: the layers' albedos weighed by their shares.
    pub fn albedo(&self) -> Color {
        self.layers[..self.len]
            .iter()
            .fold(Color::BLACK, |sum, &(share, bsdf)| {
                sum + bsdf.albedo() * share
            })
    }

    /// Whether [`pick`](Self::pick)'s number is used: to choose a layer, or a lobe of the one
    /// layer (see [`Bsdf::chooses_lobe`]).
    pub fn chooses(&self) -> bool {
        self.len > 1 || self.layers[0].1.chooses_lobe()
    }

    /// Whether every layer is a mirror or smooth glass (nothing for light sampling to find).
    pub fn is_delta(&self) -> bool {
        self.layers[..self.len].iter().all(|(_, b)| b.is_delta())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_book_material_is_a_stack_whose_shares_sum_to_one() {
        let m = Material {
            transparency: 0.5,
            reflective: 0.5,
            ..Material::DEFAULT
        };
        let s = Scattering::phong(&m, Color::WHITE, 1.0);
        assert_eq!(s.len, 3);
        assert!((s.total - 1.0).abs() < 1e-12);
        // Glass takes the first half of u, the mirror the next quarter, the base the rest.
        let (glass, u) = Scattering::pick(&s, 0.25);
        assert!(matches!(glass.bsdf, Bsdf::Dielectric { .. }));
        assert!((glass.scale - 1.0).abs() < 1e-12 && (u - 0.5).abs() < 1e-12);
        assert!(matches!(s.pick(0.6).0.bsdf, Bsdf::Mirror { .. }));
        assert!(matches!(s.pick(0.9).0.bsdf, Bsdf::Plastic { .. }));
    }

    #[test]
    fn a_matte_book_material_is_lambert_with_colour_times_diffuse() {
        let m = Material {
            specular: 0.0,
            diffuse: 0.5,
            ..Material::DEFAULT
        };
        let s = Scattering::phong(&m, Color::new(1.0, 0.5, 0.2), 1.0);
        let (layer, _) = s.pick(0.7);
        assert_eq!(
            layer.bsdf,
            Bsdf::Diffuse {
                albedo: Color::new(0.5, 0.25, 0.1)
            }
        );
        assert_eq!(layer.scale, 1.0);
        assert_eq!(s.albedo(), Color::new(0.5, 0.25, 0.1));
    }

    #[test]
    fn the_picked_layers_estimate_the_sum_of_the_layers() {
        // Picking layer i with probability share/total and scaling by total gives back each
        // share on average: the material is the shares' weighted sum of its layers.
        let m = Material {
            transparency: 0.3,
            reflective: 0.6,
            ..Material::DEFAULT
        };
        let s = Scattering::phong(&m, Color::WHITE, 1.0);
        let n = 10_000;
        let mut glass = 0.0;
        for i in 0..n {
            let (layer, u) = s.pick((i as f64 + 0.5) / n as f64);
            assert!((0.0..1.0).contains(&u));
            if matches!(layer.bsdf, Bsdf::Dielectric { .. }) {
                glass += layer.scale / n as f64;
            }
        }
        assert!((glass - 0.3).abs() < 1e-3, "{glass}");
    }

    #[test]
    fn a_gltf_material_splits_into_metal_glass_and_coated_base_by_its_factors() {
        let point = MetalRoughSample {
            base: Color::new(0.8, 0.4, 0.2),
            metallic: 0.25,
            roughness: 0.5,
            transmission: 0.5,
        };
        let s = Scattering::metal_rough(&point, 1.5, 1.0);
        assert_eq!(s.len, 3);
        assert!((s.total - 1.0).abs() < 1e-12);
        // A quarter metal, then 0.375 glass, then 0.375 plastic; all of GGX width 0.25.
        let (metal, _) = s.pick(0.2);
        assert!(
            matches!(metal.bsdf, Bsdf::Conductor { alpha_u, alpha_v, tint, .. } if alpha_u == 0.25 && alpha_v == 0.25 && tint == point.base)
        );
        assert!(matches!(s.pick(0.5).0.bsdf, Bsdf::Dielectric { eta, .. } if eta == 1.5));
        assert!(
            matches!(s.pick(0.9).0.bsdf, Bsdf::Plastic { diffuse, .. } if diffuse == point.base)
        );
        // Fully metallic: one layer, and its Fresnel is 1 at every angle (eta 0, k 1).
        let metal = Scattering::metal_rough(
            &MetalRoughSample {
                metallic: 1.0,
                ..point
            },
            1.5,
            1.0,
        );
        assert_eq!(metal.len, 1);
        let f = super::super::bsdf::fresnel::conductor(0.3, Color::BLACK, Color::WHITE);
        assert!((f.red - 1.0).abs() < 1e-12, "{f:?}");
    }

    #[test]
    fn a_named_metal_keeps_its_index_and_is_tinted_by_the_colour() {
        let (eta, k) = super::super::bsdf::metal("aluminium").unwrap();
        let b = Physical::Conductor {
            eta,
            k,
            alpha_u: 0.2,
            alpha_v: 0.2,
        }
        .bsdf(Color::WHITE, 1.0);
        assert_eq!(
            b,
            Bsdf::Conductor {
                eta,
                k,
                alpha_u: 0.2,
                alpha_v: 0.2,
                tint: Color::WHITE
            }
        );
    }
}
