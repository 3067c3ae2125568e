//! pbrt-v4's lights as rayforge's.
//!
//! rayforge's point, spot and directional lights give a surface facing them the irradiance
//! `π · intensity` (over the distance squared, for lights that fall off), pbrt-v4's `I`
//! (radiant intensity) and a distant light's `L` (irradiance) are those irradiances: the
//! intensity is pbrt's value times `scale` over π. pbrt-v4's `power` and `illuminance` set the
//! scale as pbrt-v4 does (its normalisation counts the light's spectrum, not an rgb's
//! brightness). A uniform `infinite` light is the world's background, which the path tracer
//! takes as light from every direction. Area lights ([`emission`]) are emitting surfaces.

use super::params::ParamType;
use super::reader::{Entity, LightEntity};
use super::spectra::{self, SpectrumUse};
use crate::error::SceneError;
use glam::DVec3;
use rayforge::shading::{DirectionalLight, Light, PointLight, SpotLight};
use rayforge::Color;
use std::f64::consts::PI;

/// What a `LightSource` adds to the world.
pub enum Lit {
    /// A light of the world's list.
    Light(Light),
    /// Radiance from every direction, added to the background.
    Sky(Color),
}

/// The colour of a light's spectrum parameter `name` (white when absent), times `scale`.
fn spectrum(entity: &Entity, name: &str) -> Result<Color, SceneError> {
    let params = &entity.params;
    let colour = match params.find(
        name,
        &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
    ) {
        Some(p) => spectra::color(p, SpectrumUse::Illuminant)?,
        None => Color::WHITE,
    };
    Ok(colour * params.float_or("scale", 1.0)?)
}

/// An optional positive float parameter (`power`, `illuminance`).
fn target(entity: &Entity, name: &str) -> Result<Option<f64>, SceneError> {
    Ok(entity.params.float(name)?.filter(|v| *v > 0.0))
}

/// The light of a `LightSource`.
pub fn light(light: &LightEntity) -> Result<Lit, SceneError> {
    let entity = &light.entity;
    let params = &entity.params;
    let m = light.world_from_light;
    match entity.name.as_str() {
        "point" => {
            let mut i = spectrum(entity, "I")?;
            if let Some(power) = target(entity, "power")? {
                i = i * (power / (4.0 * PI));
            }
            let from = params.point3_or("from", DVec3::ZERO)?;
            Ok(Lit::Light(Light::Point(PointLight {
                falloff: true,
                ..PointLight::new(m.transform_point3(from), i * (1.0 / PI))
            })))
        }
        "spot" => {
            let mut i = spectrum(entity, "I")?;
            let cone = params.float_or("coneangle", 30.0)?;
            let delta = params.float_or("conedeltaangle", 5.0)?;
            if let Some(power) = target(entity, "power")? {
                let (end, start) = (cone.to_radians().cos(), (cone - delta).to_radians().cos());
                i = i * (power / (2.0 * PI * ((1.0 - start) + (start - end) / 2.0)));
            }
            let from = params.point3_or("from", DVec3::ZERO)?;
            let to = params.point3_or("to", DVec3::Z)?;
            let spot = SpotLight::new(
                m.transform_point3(from),
                m.transform_vector3(to - from),
                cone.to_radians(),
                delta.to_radians(),
                i * (1.0 / PI),
            )
            .ok_or_else(|| entity.error("a spotlight's `from` and `to` are apart"))?;
            Ok(Lit::Light(Light::Spot(SpotLight {
                falloff: true,
                ..spot
            })))
        }
        "distant" => {
            let mut l = spectrum(entity, "L")?;
            if let Some(e) = target(entity, "illuminance")? {
                l = l * e;
            }
            let from = params.point3_or("from", DVec3::ZERO)?;
            let to = params.point3_or("to", DVec3::Z)?;
            let towards = m.transform_vector3(from - to);
            if towards.length_squared() == 0.0 || !towards.is_finite() {
                return Err(entity.error("a distant light's `from` and `to` are apart"));
            }
            Ok(Lit::Light(Light::Directional(DirectionalLight {
                towards: towards.normalize(),
                intensity: l * (1.0 / PI),
            })))
        }
        "infinite" => {
            if let Some((file, p)) = params.string("filename")? {
                return Err(p.error(format!(
                    "an infinite light from an image (\"{}\") is not read yet; a uniform one \
                     (\"rgb L\") is",
                    crate::error::clip_to(file, 80)
                )));
            }
            if let Some(p) = params.find("portal", &[ParamType::Point3]) {
                return Err(p.error("portals are not read"));
            }
            let mut l = spectrum(entity, "L")?;
            if let Some(e) = target(entity, "illuminance")? {
                l = l * (e / PI);
            }
            Ok(Lit::Sky(l))
        }
        other => Err(entity.error(format!(
            "the light \"{}\" is not one rayforge reads; it reads point, spot, distant, \
             infinite (uniform) and diffuse area lights",
            crate::error::clip_to(other, 60)
        ))),
    }
}

/// An area light's emitted radiance and whether it shines from both sides, for a shape of
/// `area` (in the world).
pub fn emission(area_light: &Entity, area: f64) -> Result<(Color, bool), SceneError> {
    if area_light.name != "diffuse" {
        return Err(area_light.error(format!(
            "the area light \"{}\" is not one rayforge reads; it reads \"diffuse\"",
            crate::error::clip_to(&area_light.name, 60)
        )));
    }
    let params = &area_light.params;
    if let Some((file, p)) = params.string("filename")? {
        return Err(p.error(format!(
            "an area light's image (\"{}\") is not read; give \"rgb L\"",
            crate::error::clip_to(file, 80)
        )));
    }
    let two_sided = params.bool_or("twosided", false)?;
    let mut l = spectrum(area_light, "L")?;
    if let Some(power) = target(area_light, "power")? {
        let sides = if two_sided { 2.0 } else { 1.0 };
        if area > 0.0 {
            l = l * (power / (sides * area * PI));
        }
    }
    Ok((l, two_sided))
}
