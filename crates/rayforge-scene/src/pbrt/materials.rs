//! pbrt-v4's materials as rayforge's path-tracer materials ([`Physical`]).
//!
//! - `diffuse` (`reflectance`, default 0.5): Lambertian.
//! - `conductor`: `eta` and `k` (rgb or pbrt's named metal spectra; copper by default), or
//!   `reflectance` instead, read as pbrt-v4 reads it: index 1 and `k = 2√r / √(1 − r)`, whose
//!   reflectance at normal incidence is `r`.
//! - `dielectric` (`eta`, default 1.5; a named glass is its index at 550 nm) and
//!   `thindielectric`.
//! - `interface` and `none`: no surface, light passes straight through (a dielectric of index 1,
//!   which bends and reflects nothing).
//! - `coateddiffuse` (`reflectance` 0.5, the coat's `eta` 1.5 and roughness, `thickness` 0.01,
//!   the medium's `albedo` 0 and `g` 0, `maxdepth` 10, `nsamples` 1) and `coatedconductor`
//!   (the coat's `interface.eta`, `interface.roughness`; the metal's `conductor.eta`,
//!   `conductor.k` or `reflectance`, `conductor.roughness`; the same medium parameters):
//!   pbrt-v4's stochastic layered materials ([`Physical::CoatedDiffuse`],
//!   [`Physical::CoatedConductor`]).
//! - `diffusetransmission` (`reflectance` and `transmittance`, 0.25 each, times `scale`).
//!
//! Roughness (`roughness`, or `uroughness` and `vroughness`, which take its place where given)
//! becomes the GGX widths along the surface's two tangents as pbrt-v4's
//! `TrowbridgeReitzDistribution::RoughnessToAlpha` makes them, `α = √roughness`, unless
//! `remaproughness` is false (then the roughness is the width).
//!
//! Textures ([`super::textures`]) are read where pbrt-v4 takes them and rayforge's materials
//! can vary per hit: `reflectance` (diffuse, coateddiffuse, diffusetransmission's two shares),
//! `roughness`, `uroughness`, `vroughness` (conductor, dielectric, coateddiffuse, and
//! coatedconductor's `interface.` and `conductor.` ones), a conductor's `eta`, `k` or
//! `reflectance` (coatedconductor's `conductor.eta`, `conductor.k`, `reflectance`), and a
//! layer's `thickness`, `albedo` and `g`. A dielectric's or coat's `eta` is a number or a
//! spectrum in pbrt-v4 too (a texture there is refused at the parameter), and the materials
//! rayforge does not read are refused at their type.

use super::params::{ParamType, Values};
use super::reader::{Description, Entity};
use super::spectra::{self, SpectrumUse};
use super::textures::SceneTextures;
use crate::error::SceneError;
use rayforge::shading::bsdf::{Coat, ConductorBase, Layers};
use rayforge::shading::texture_graph::{
    FloatInput, LayerTextures, MetalTextures, NodeId, SurfaceTextures, TexturedWidths,
};
use rayforge::shading::{conductor_of_reflectance, MaterialMix, Physical};
use rayforge::{Color, Material};
use std::sync::Arc;

/// The material described by `entity` (a `Material`, whose name is its type, or a
/// `MakeNamedMaterial`, whose `"string type"` is), with the scene's `textures` (made by
/// `desc`) to look names up in.
pub fn material(
    entity: &Entity,
    textures: &SceneTextures,
    desc: &Description,
    warnings: &mut Vec<SceneError>,
) -> Result<Material, SceneError> {
    material_within(entity, textures, desc, warnings, 0)
}

/// How deep `mix` materials may name mixes (a mix that names itself, directly or not, would
/// go on for ever).
pub const MAX_MIX_DEPTH: usize = 16;

/// [`material`] at `depth` mixes down.
fn material_within(
    entity: &Entity,
    textures: &SceneTextures,
    desc: &Description,
    warnings: &mut Vec<SceneError>,
    depth: usize,
) -> Result<Material, SceneError> {
    if kind_of(entity)? == "mix" {
        return mix(entity, textures, desc, warnings, depth);
    }
    let t = Textured { textures, desc };
    let mut surface = SurfaceTextures::new(textures.graph.clone());
    let params = &entity.params;
    let kind = kind_of(entity)?;
    let physical = |physical: Physical, color: Color| Material {
        color,
        physical: Some(physical),
        ..Material::DEFAULT
    };
    let mut material = match kind.as_str() {
        "diffuse" => physical(
            Physical::Diffuse,
            t.reflectance(entity, "reflectance", 0.5, &mut surface.color)?,
        ),
        "conductor" => {
            let (alpha_u, alpha_v) = t.widths(entity, "", &mut surface.widths, warnings)?;
            let (eta, k) = t.metal(entity, "", &mut surface.metal)?;
            physical(
                Physical::Conductor {
                    eta,
                    k,
                    alpha_u,
                    alpha_v,
                },
                Color::WHITE,
            )
        }
        "dielectric" | "thindielectric" => {
            let eta = dielectric_index(entity)?;
            if kind == "dielectric" {
                let (alpha_u, alpha_v) = t.widths(entity, "", &mut surface.widths, warnings)?;
                physical(
                    Physical::Dielectric {
                        eta,
                        alpha_u,
                        alpha_v,
                    },
                    Color::WHITE,
                )
            } else {
                physical(Physical::ThinDielectric { eta }, Color::WHITE)
            }
        }
        "interface" | "none" | "" => physical(
            Physical::Dielectric {
                eta: 1.0,
                alpha_u: 0.0,
                alpha_v: 0.0,
            },
            Color::WHITE,
        ),
        "coateddiffuse" => {
            let (alpha_u, alpha_v) = t.widths(entity, "", &mut surface.widths, warnings)?;
            let coat = Coat {
                eta: coat_index(entity, "eta")?,
                alpha_u,
                alpha_v,
            };
            physical(
                Physical::CoatedDiffuse {
                    coat,
                    layers: t.layers(entity, &mut surface.layers)?,
                },
                t.reflectance(entity, "reflectance", 0.5, &mut surface.color)?,
            )
        }
        "coatedconductor" => {
            let (alpha_u, alpha_v) =
                t.widths(entity, "interface.", &mut surface.widths, warnings)?;
            let coat = Coat {
                eta: coat_index(entity, "interface.eta")?,
                alpha_u,
                alpha_v,
            };
            let (eta, k) = t.metal(entity, "conductor.", &mut surface.metal)?;
            let (alpha_u, alpha_v) =
                t.widths(entity, "conductor.", &mut surface.base_widths, warnings)?;
            let base = ConductorBase {
                eta,
                k,
                alpha_u,
                alpha_v,
            };
            physical(
                Physical::CoatedConductor {
                    coat,
                    base,
                    layers: t.layers(entity, &mut surface.layers)?,
                },
                Color::WHITE,
            )
        }
        "diffusetransmission" => {
            let scale = params.float_or("scale", 1.0)?;
            if scale.is_nan() || scale < 0.0 {
                return Err(entity.error(format!("a scale is not negative, found {scale}")));
            }
            // The scale multiplies both shares: it is the material's colour, which the
            // path tracer multiplies them by, so a textured share is scaled too.
            let reflectance =
                t.reflectance(entity, "reflectance", 0.25, &mut surface.reflectance)?;
            let transmittance =
                t.reflectance(entity, "transmittance", 0.25, &mut surface.transmittance)?;
            physical(
                Physical::DiffuseTransmission {
                    reflectance,
                    transmittance,
                },
                Color::WHITE * scale,
            )
        }
        other => {
            return Err(entity.error(format!(
                "the material type \"{}\" is not one rayforge reads; it reads diffuse, \
                 conductor, dielectric, thindielectric, coateddiffuse, coatedconductor, \
                 diffusetransmission, mix and interface",
                crate::error::clip_to(other, 60)
            )))
        }
    };
    if surface.textures_parameters() {
        material.textures = Some(Box::new(surface));
    }
    Ok(material)
}

/// The material type `entity` describes: a `Material`'s name, a `MakeNamedMaterial`'s
/// `"string type"`.
fn kind_of(entity: &Entity) -> Result<String, SceneError> {
    if entity.directive != "MakeNamedMaterial" {
        return Ok(entity.name.clone());
    }
    match entity.params.string("type")? {
        Some((t, _)) => Ok(t.to_string()),
        None => Err(entity.error(format!(
            "the material \"{}\" has no \"string type\"",
            entity.name
        ))),
    }
}

/// pbrt-v4's `mix`: `"string materials"`, two named materials, and `amount` (a float or a
/// float texture, 0.5 by default), the second's share ([`MaterialMix`]).
fn mix(
    entity: &Entity,
    textures: &SceneTextures,
    desc: &Description,
    warnings: &mut Vec<SceneError>,
    depth: usize,
) -> Result<Material, SceneError> {
    let params = &entity.params;
    let Some(names) = params.find("materials", &[ParamType::String]) else {
        return Err(entity.error("a mix material needs its two materials, \"string materials\""));
    };
    let Values::Strings(list) = &names.values else {
        return Err(names.error("takes two material names"));
    };
    let [first, second] = list.as_slice() else {
        return Err(names.error(format!("takes two material names, not {}", list.len())));
    };
    if depth >= MAX_MIX_DEPTH {
        return Err(names.error(format!(
            "mix materials name mixes more than {MAX_MIX_DEPTH} deep (does a mix name itself?)"
        )));
    }
    let mut built = Vec::with_capacity(2);
    for name in [first, second] {
        let named = desc.named_materials.get(name).ok_or_else(|| {
            names.error(format!(
                "no material is named \"{}\" (`MakeNamedMaterial` makes one)",
                crate::error::clip_to(name, 60)
            ))
        })?;
        built.push(material_within(named, textures, desc, warnings, depth + 1)?);
    }
    let amount = textures
        .float(entity, "amount", desc)?
        .unwrap_or(FloatInput::Fixed(0.5));
    let second = built.pop().expect("two built");
    let first = built.pop().expect("two built");
    let mut surface = SurfaceTextures::new(textures.graph.clone());
    surface.mix = Some(Arc::new(MaterialMix {
        amount,
        materials: [first, second],
    }));
    Ok(Material {
        physical: None,
        textures: Some(Box::new(surface)),
        ..Material::DEFAULT
    })
}

/// The scene's textures, for a material's parameters.
struct Textured<'a> {
    textures: &'a SceneTextures,
    desc: &'a Description,
}

impl Textured<'_> {
    /// A reflectance: a spectrum texture (its node put in `slot`, the fixed colour then
    /// white), rgb or a spectrum (at most 1 in each channel), or `default` grey.
    fn reflectance(
        &self,
        entity: &Entity,
        name: &str,
        default: f64,
        slot: &mut Option<NodeId>,
    ) -> Result<Color, SceneError> {
        let params = &entity.params;
        if let Some(p) = params.find(name, &[ParamType::Texture]) {
            *slot = Some(self.textures.named(p, "spectrum", self.desc)?);
            // A value given beside the texture (as exporters write) is read and not used:
            // pbrt-v4 takes the texture.
            let _ = params.find(name, &[ParamType::Rgb, ParamType::Spectrum]);
            return Ok(Color::WHITE);
        }
        let Some(p) = params.find(name, &[ParamType::Rgb, ParamType::Spectrum]) else {
            return Ok(Color::WHITE * default);
        };
        let c = spectra::color(p, SpectrumUse::Albedo)?;
        if c.red.max(c.green).max(c.blue) > 1.0 {
            return Err(p.error("a reflectance is at most 1 in each channel"));
        }
        Ok(c)
    }

    /// A metal's index: `{prefix}eta` and `{prefix}k` (rgb, pbrt's named metal spectra or
    /// spectrum textures; copper by default), or `reflectance` in their place (rgb, spectrum or
    /// texture), read as pbrt-v4 reads it ([`conductor_of_reflectance`]). The fixed values,
    /// and in `slot` the textured ones.
    fn metal(
        &self,
        entity: &Entity,
        prefix: &str,
        slot: &mut Option<MetalTextures>,
    ) -> Result<(Color, Color), SceneError> {
        let params = &entity.params;
        let given = |name: &str| {
            params.find(
                name,
                &[ParamType::Texture, ParamType::Rgb, ParamType::Spectrum],
            )
        };
        if given("reflectance").is_some() {
            if let Some(p) = given(&format!("{prefix}eta")).or(given(&format!("{prefix}k"))) {
                return Err(p.error(
                    "a conductor has \"reflectance\" or \"eta\" and \"k\", not both (as in \
                     pbrt-v4)",
                ));
            }
        }
        if let Some(p) = params.find("reflectance", &[ParamType::Texture]) {
            *slot = Some(MetalTextures::Reflectance(
                self.textures.named(p, "spectrum", self.desc)?,
            ));
            return Ok(conductor_of_reflectance(Color::WHITE * 0.5));
        }
        let (eta, k) = match params.find("reflectance", &[ParamType::Rgb, ParamType::Spectrum]) {
            Some(r) => conductor_of_reflectance(spectra::color(r, SpectrumUse::Albedo)?),
            None => {
                let (cu_eta, cu_k) =
                    rayforge::shading::bsdf::metal("copper").expect("rayforge names copper");
                let [eta_name, k_name] = ["eta", "k"].map(|n| format!("{prefix}{n}"));
                let textured = |name: &str| -> Result<Option<NodeId>, SceneError> {
                    params
                        .find(name, &[ParamType::Texture])
                        .map(|p| self.textures.named(p, "spectrum", self.desc))
                        .transpose()
                };
                let (eta_tex, k_tex) = (textured(&eta_name)?, textured(&k_name)?);
                if eta_tex.is_some() || k_tex.is_some() {
                    *slot = Some(MetalTextures::Index {
                        eta: eta_tex,
                        k: k_tex,
                    });
                }
                let eta = index(entity, &eta_name)?.unwrap_or(cu_eta);
                let k = index(entity, &k_name)?.unwrap_or(cu_k);
                (eta, k)
            }
        };
        if eta.red.min(eta.green).min(eta.blue) <= 0.0 || k.red.min(k.green).min(k.blue) < 0.0 {
            return Err(entity.error("a conductor's eta is above 0 and its k not negative"));
        }
        Ok((eta, k))
    }

    /// The medium between a layered material's coat and base ([`layers`]), with its
    /// `thickness`, `albedo` and `g` textures, where given, in `slot`.
    fn layers(
        &self,
        entity: &Entity,
        slot: &mut Option<LayerTextures>,
    ) -> Result<Layers, SceneError> {
        let params = &entity.params;
        let float = |name: &str| -> Result<Option<FloatInput>, SceneError> {
            match params.find(name, &[ParamType::Texture]) {
                Some(p) => Ok(Some(FloatInput::Texture(
                    self.textures.named(p, "float", self.desc)?,
                ))),
                None => Ok(None),
            }
        };
        let textured = LayerTextures {
            thickness: float("thickness")?,
            albedo: params
                .find("albedo", &[ParamType::Texture])
                .map(|p| self.textures.named(p, "spectrum", self.desc))
                .transpose()?,
            g: float("g")?,
        };
        if textured != LayerTextures::default() {
            *slot = Some(textured);
        }
        layers(entity)
    }

    /// The GGX widths along the two tangents of `entity`'s roughness parameters named with
    /// `prefix` (see the [module](self)), fixed; where any of them is a texture, the textured
    /// widths are put in `slot` too.
    fn widths(
        &self,
        entity: &Entity,
        prefix: &str,
        slot: &mut Option<TexturedWidths>,
        warnings: &mut Vec<SceneError>,
    ) -> Result<(f64, f64), SceneError> {
        let params = &entity.params;
        let [rough, u_name, v_name] =
            ["roughness", "uroughness", "vroughness"].map(|n| format!("{prefix}{n}"));
        let input = |name: &str| self.textures.float(entity, name, self.desc);
        let roughness = input(&rough)?;
        let u = input(&u_name)?
            .or(roughness)
            .unwrap_or(FloatInput::Fixed(0.0));
        let v = input(&v_name)?
            .or(roughness)
            .unwrap_or(FloatInput::Fixed(0.0));
        let remap = params.bool_or("remaproughness", true)?;
        for r in [u, v] {
            if let FloatInput::Fixed(r) = r {
                if r.is_nan() || r < 0.0 {
                    return Err(entity.error("roughness is not negative"));
                }
            }
        }
        if matches!(u, FloatInput::Texture(_)) || matches!(v, FloatInput::Texture(_)) {
            *slot = Some(TexturedWidths { u, v, remap });
        }
        let mut width = |r: FloatInput| {
            let FloatInput::Fixed(r) = r else {
                return 0.0;
            };
            let alpha = if remap { r.sqrt() } else { r };
            if alpha > 1.0 {
                warnings.push(entity.error(format!(
                    "a GGX width of {alpha} is rendered as 1, rayforge's widest"
                )));
            }
            alpha.min(1.0)
        };
        Ok((width(u), width(v)))
    }
}

/// A conductor's `eta` or `k`: rgb or a spectrum.
fn index(entity: &Entity, name: &str) -> Result<Option<Color>, SceneError> {
    entity
        .params
        .find(name, &[ParamType::Rgb, ParamType::Spectrum])
        .map(|p| spectra::color(p, SpectrumUse::Index))
        .transpose()
}

/// A dielectric's `eta`: a float, or a spectrum (its value at 550 nm); 1.5 by default.
fn dielectric_index(entity: &Entity) -> Result<f64, SceneError> {
    refuse_texture(entity, "eta")?;
    let params = &entity.params;
    let eta = match params.float("eta")? {
        Some(eta) => eta,
        None => match params.find("eta", &[ParamType::Spectrum, ParamType::Rgb]) {
            Some(p) => spectra::color(p, SpectrumUse::Index)?.green,
            None => 1.5,
        },
    };
    if eta <= 0.0 {
        return Err(entity.error(format!("a dielectric's eta is above 0, found {eta}")));
    }
    Ok(eta)
}

/// A coat's index, the float or spectrum parameter `name` (1.5 by default).
fn coat_index(entity: &Entity, name: &str) -> Result<f64, SceneError> {
    refuse_texture(entity, name)?;
    let params = &entity.params;
    let eta = match params.float(name)? {
        Some(eta) => eta,
        None => match params.find(name, &[ParamType::Spectrum, ParamType::Rgb]) {
            Some(p) => spectra::color(p, SpectrumUse::Index)?.green,
            None => 1.5,
        },
    };
    if eta <= 0.0 {
        return Err(entity.error(format!("a coat's {name} is above 0, found {eta}")));
    }
    Ok(eta)
}

/// The medium between a layered material's coat and base, and its walks' limits.
fn layers(entity: &Entity) -> Result<Layers, SceneError> {
    let params = &entity.params;
    let default = Layers::PBRT_DEFAULT;
    let thickness = params.float_or("thickness", default.thickness)?;
    if !(thickness > 0.0 && thickness.is_finite()) {
        return Err(entity.error(format!("a thickness is above 0, found {thickness}")));
    }
    let albedo = match params.find("albedo", &[ParamType::Rgb, ParamType::Spectrum]) {
        Some(p) => spectra::color(p, SpectrumUse::Albedo)?,
        None => match params.float("albedo")? {
            Some(a) => Color::WHITE * a,
            None => default.albedo,
        },
    };
    if albedo.red.min(albedo.green).min(albedo.blue) < 0.0
        || albedo.red.max(albedo.green).max(albedo.blue) > 1.0
    {
        return Err(entity.error("a layer's albedo is from 0 to 1 in each channel"));
    }
    let g = params.float_or("g", default.g)?;
    if !(g > -1.0 && g < 1.0) {
        return Err(entity.error(format!("g is between -1 and 1, found {g}")));
    }
    let count = |name: &str, default: u32, most: u32| -> Result<u32, SceneError> {
        let n = params.integer(name)?.map_or(i64::from(default), |(n, _)| n);
        if !(1..=i64::from(most)).contains(&n) {
            return Err(entity.error(format!("{name} is from 1 to {most}, found {n}")));
        }
        Ok(n as u32)
    };
    Ok(Layers {
        thickness,
        albedo,
        g,
        max_depth: count("maxdepth", default.max_depth, MAX_WALK_DEPTH)?,
        samples: count("nsamples", default.samples, MAX_WALK_SAMPLES)?,
    })
}

/// The most scattering events of a layered material's walk, and the most walks per estimate:
/// each costs time per shading point, so a file cannot ask for unbounded work there.
const MAX_WALK_DEPTH: u32 = 1000;
/// See [`MAX_WALK_DEPTH`].
const MAX_WALK_SAMPLES: u32 = 256;

/// Refuses a float parameter given as a texture (rayforge's widths and indices are fixed per
/// material).
fn refuse_texture(entity: &Entity, name: &str) -> Result<(), SceneError> {
    match entity.params.find(name, &[ParamType::Texture]) {
        Some(p) => Err(p.error(format!(
            "{}: a textured \"{name}\" is not read; give a number",
            entity.what()
        ))),
        None => Ok(()),
    }
}
