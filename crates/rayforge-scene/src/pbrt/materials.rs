//! pbrt-v4's materials as rayforge's path-tracer materials ([`Physical`]).
//!
//! - `diffuse` (`reflectance`, default 0.5): Lambertian.
//! - `conductor`: `eta` and `k` (rgb or pbrt's named metal spectra; copper by default), or
//!   `reflectance` instead, read as pbrt-v4 reads it: index 1 and `k = 2√r / √(1 − r)`, whose
//!   reflectance at normal incidence is `r`.
//! - `dielectric` (`eta`, default 1.5; a named glass is its index at 587.6 nm) and
//!   `thindielectric`.
//! - `interface` and `none`: no surface, light passes straight through (a dielectric of index 1,
//!   which bends and reflects nothing).
//!
//! Roughness (`roughness`, or `uroughness` and `vroughness`, which take its place where given)
//! becomes the GGX width as pbrt-v4's `TrowbridgeReitzDistribution::RoughnessToAlpha` makes
//! it, `α = √roughness`, unless `remaproughness` is false (then the roughness is the width).
//! rayforge's microfacets are isotropic: different `uroughness` and `vroughness` are rendered
//! with the geometric mean of their widths, and a warning says so.
//!
//! A `reflectance` may name a `Texture` of class `constant`; other texture classes, textured
//! roughness, and the materials rayforge does not read are refused at the parameter or the
//! material's type.

use super::params::{Param, ParamType};
use super::reader::{Entity, TextureEntity};
use super::spectra::{self, SpectrumUse};
use crate::error::SceneError;
use rayforge::shading::Physical;
use rayforge::{Color, Material};
use std::collections::HashMap;

/// The material described by `entity` (a `Material`, whose name is its type, or a
/// `MakeNamedMaterial`, whose `"string type"` is), with `textures` to look names up in.
pub fn material(
    entity: &Entity,
    textures: &HashMap<String, TextureEntity>,
    warnings: &mut Vec<SceneError>,
) -> Result<Material, SceneError> {
    let params = &entity.params;
    let kind = if entity.directive == "MakeNamedMaterial" {
        match params.string("type")? {
            Some((t, _)) => t.to_string(),
            None => {
                return Err(entity.error(format!(
                    "the material \"{}\" has no \"string type\"",
                    entity.name
                )))
            }
        }
    } else {
        entity.name.clone()
    };
    let physical = |physical: Physical, color: Color| Material {
        color,
        physical: Some(physical),
        ..Material::DEFAULT
    };
    Ok(match kind.as_str() {
        "diffuse" => physical(
            Physical::Diffuse,
            reflectance(entity, "reflectance", Color::WHITE * 0.5, textures)?,
        ),
        "conductor" => {
            let alpha = alpha(entity, warnings)?;
            let (eta, k) = match params.find("reflectance", &[ParamType::Rgb, ParamType::Spectrum])
            {
                Some(r) => {
                    let r = spectra::color(r, SpectrumUse::Albedo)?;
                    let k = |r: f64| {
                        let r = r.clamp(0.0, 0.9999);
                        2.0 * r.sqrt() / (1.0 - r).sqrt()
                    };
                    (Color::WHITE, Color::new(k(r.red), k(r.green), k(r.blue)))
                }
                None => {
                    let (cu_eta, cu_k) =
                        rayforge::shading::bsdf::metal("copper").expect("rayforge names copper");
                    let eta = index(entity, "eta")?.unwrap_or(cu_eta);
                    let k = index(entity, "k")?.unwrap_or(cu_k);
                    (eta, k)
                }
            };
            if eta.red.min(eta.green).min(eta.blue) <= 0.0 || k.red.min(k.green).min(k.blue) < 0.0 {
                return Err(entity.error("a conductor's eta is above 0 and its k not negative"));
            }
            physical(Physical::Conductor { eta, k, alpha }, Color::WHITE)
        }
        "dielectric" | "thindielectric" => {
            let eta = dielectric_index(entity)?;
            if kind == "dielectric" {
                let alpha = alpha(entity, warnings)?;
                physical(Physical::Dielectric { eta, alpha }, Color::WHITE)
            } else {
                physical(Physical::ThinDielectric { eta }, Color::WHITE)
            }
        }
        "interface" | "none" | "" => physical(
            Physical::Dielectric {
                eta: 1.0,
                alpha: 0.0,
            },
            Color::WHITE,
        ),
        "coateddiffuse" | "coatedconductor" => {
            return Err(entity.error(format!(
                "the material type \"{kind}\" (pbrt-v4's layered BSDF) is not read yet"
            )))
        }
        other => {
            return Err(entity.error(format!(
                "the material type \"{}\" is not one rayforge reads; it reads diffuse, \
                 conductor, dielectric, thindielectric and interface",
                crate::error::clip_to(other, 60)
            )))
        }
    })
}

/// A conductor's `eta` or `k`: rgb or a spectrum.
fn index(entity: &Entity, name: &str) -> Result<Option<Color>, SceneError> {
    refuse_texture(entity, name)?;
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

/// The GGX width of `entity`'s roughness parameters (see the [module](self)).
fn alpha(entity: &Entity, warnings: &mut Vec<SceneError>) -> Result<f64, SceneError> {
    let params = &entity.params;
    for name in ["roughness", "uroughness", "vroughness"] {
        refuse_texture(entity, name)?;
    }
    let roughness = params.float("roughness")?;
    let u = params.float("uroughness")?.or(roughness).unwrap_or(0.0);
    let v = params.float("vroughness")?.or(roughness).unwrap_or(0.0);
    if u < 0.0 || v < 0.0 {
        return Err(entity.error("roughness is not negative"));
    }
    let remap = params.bool_or("remaproughness", true)?;
    let width = |r: f64| if remap { r.sqrt() } else { r };
    let (au, av) = (width(u), width(v));
    let alpha = (au * av).sqrt();
    if au != av {
        warnings.push(entity.error(format!(
            "anisotropic roughness (widths {au} and {av}): rendered isotropic, of width {alpha}"
        )));
    }
    if alpha > 1.0 {
        warnings.push(entity.error(format!(
            "a GGX width of {alpha} is rendered as 1, rayforge's widest"
        )));
    }
    Ok(alpha.min(1.0))
}

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

/// A reflectance: rgb, a spectrum, or a `constant` texture; `default` when absent.
fn reflectance(
    entity: &Entity,
    name: &str,
    default: Color,
    textures: &HashMap<String, TextureEntity>,
) -> Result<Color, SceneError> {
    let params = &entity.params;
    if let Some((texture, p)) = params.one_string(name, ParamType::Texture)? {
        return constant_texture(p, texture, textures);
    }
    let Some(p) = params.find(name, &[ParamType::Rgb, ParamType::Spectrum]) else {
        return Ok(default);
    };
    let c = spectra::color(p, SpectrumUse::Albedo)?;
    if c.red.max(c.green).max(c.blue) > 1.0 {
        return Err(p.error("a reflectance is at most 1 in each channel"));
    }
    Ok(c)
}

/// The colour of the spectrum texture `name` named by `p`: a `constant` one's `value`.
fn constant_texture(
    p: &Param,
    name: &str,
    textures: &HashMap<String, TextureEntity>,
) -> Result<Color, SceneError> {
    let Some(texture) = textures.get(name) else {
        return Err(p.error(format!(
            "no texture is named \"{}\"",
            crate::error::clip_to(name, 60)
        )));
    };
    let entity = &texture.entity;
    if texture.kind != "spectrum" {
        return Err(p.error(format!(
            "the texture \"{name}\" is a float texture; a colour needs a spectrum texture"
        )));
    }
    if entity.name != "constant" {
        return Err(entity.error(format!(
            "textures of class \"{}\" are not read yet (only \"constant\" ones)",
            crate::error::clip_to(&entity.name, 60)
        )));
    }
    match entity
        .params
        .find("value", &[ParamType::Rgb, ParamType::Spectrum])
    {
        Some(v) => spectra::color(v, SpectrumUse::Albedo),
        None => Ok(Color::WHITE),
    }
}
