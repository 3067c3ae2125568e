//! pbrt-v4's lights as rayforge's.
//!
//! rayforge's point, spot and directional lights give a surface facing them the irradiance
//! `π · intensity` (over the distance squared, for lights that fall off), pbrt-v4's `I`
//! (radiant intensity) and a distant light's `L` (irradiance) are those irradiances: the
//! intensity is pbrt's value times `scale` over π. pbrt-v4's `power` and `illuminance` set the
//! scale as pbrt-v4 does (its normalisation counts the light's spectrum, not an rgb's
//! brightness). A uniform `infinite` light is the world's background, which the path tracer
//! takes as light from every direction; an `infinite` light with a `filename` is an
//! environment map read from EXR, PFM or Radiance HDR: a square image is in pbrt-v4's
//! equal-area octahedral layout ([`EnvironmentMap::equal_area`], the only one pbrt-v4 reads),
//! an image twice as wide as high in the latitude–longitude layout pbrt-v3 read and older
//! exporters write ([`EnvironmentMap::lat_long`]: +z up, `φ` from +x towards +y across, row 0
//! at +z), which no equal-area map can be; any other shape is refused. The map is placed by the
//! light's transform (which may mirror it), times `scale`, or scaled so that the upper
//! hemisphere (+z of the light's space) gives `illuminance` as pbrt-v4 computes it. Area
//! lights ([`emission`]) are emitting surfaces.

use super::image_lights;
use super::input::{Files, Loc};
use super::params::ParamType;
use super::reader::{Entity, LightEntity};
use super::spectra::{self, SpectrumUse};
use crate::error::SceneError;
use crate::images::ImageMemory;
use glam::DMat3;
use glam::DVec3;
use rayforge::shading::{equal_area_square_to_sphere, EnvironmentMap};
use rayforge::shading::{DirectionalLight, Light, PointLight, SpotLight};
use rayforge::Color;
use std::f64::consts::PI;

/// What a `LightSource` adds to the world.
pub enum Lit {
    /// A light of the world's list.
    Light(Light),
    /// Radiance from every direction, added to the background.
    Sky(Color),
    /// An image of the sky, equal-area or latitude–longitude.
    Map(SkyImage),
}

/// An `infinite` light's image, scaled, to become the world's environment map once the
/// uniform skies beside it are known.
pub struct SkyImage {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Whether the image is latitude–longitude (twice as wide as high) rather than
    /// equal-area (square).
    pub lat_long: bool,
    /// Radiance, row by row from the top, scaled, not negative.
    pub texels: Vec<Color>,
    /// From the world into the light's space (orthogonal).
    pub world_to_light: DMat3,
    /// Where the light is, for errors.
    pub at: Loc,
}

impl SkyImage {
    /// The environment map, with `uniform` radiance added from every direction.
    pub fn into_map(self, uniform: Color) -> Result<EnvironmentMap, SceneError> {
        let texels = self.texels.into_iter().map(|c| c + uniform).collect();
        let map = if self.lat_long {
            EnvironmentMap::lat_long(self.width, self.height, texels, 1.0)
        } else {
            EnvironmentMap::equal_area(self.width, self.height, texels, 1.0)
        };
        map.and_then(|m| m.with_frame(self.world_to_light))
            .map_err(|e| self.at.error(Some("LightSource"), e.to_string()))
    }
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

/// The light of a `LightSource` (images found through `files`, within `memory`; what is
/// approximated said in `warnings`).
pub fn light(
    light: &LightEntity,
    files: &Files,
    memory: &mut ImageMemory,
    warnings: &mut Vec<SceneError>,
) -> Result<Lit, SceneError> {
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
            if let Some((portal, p)) = params.points3("portal", ParamType::Point3)? {
                check_portal(&portal, p)?;
                warnings.push(p.error(
                    "the portal is checked but not sampled through: the sky is sampled over \
                     the whole sphere (the same light, noisier where the portal is the only \
                     way in)",
                ));
            }
            if let Some((file, p)) = params.string("filename")? {
                let given_l = params.find(
                    "L",
                    &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
                );
                if let Some(l) = given_l {
                    return Err(l.error(
                        "an infinite light has \"L\" or \"filename\", not both (as in pbrt-v4)",
                    ));
                }
                return sky_image(light, file, p, files, memory).map(Lit::Map);
            }
            let mut l = spectrum(entity, "L")?;
            if let Some(e) = target(entity, "illuminance")? {
                l = l * (e / PI);
            }
            Ok(Lit::Sky(l))
        }
        "goniometric" => {
            let i = spectrum(entity, "I")?;
            image_lights::goniometric(light, i, files, memory).map(Lit::Light)
        }
        "projection" => image_lights::projection(light, files, memory).map(Lit::Light),
        other => Err(entity.error(format!(
            "the light \"{}\" is not one rayforge reads; it reads point, spot, goniometric, \
             projection, distant, infinite and diffuse area lights",
            crate::error::clip_to(other, 60)
        ))),
    }
}

/// Refuses a `portal` (parameter `p`) that is not four points making a rectangle, as pbrt-v4
/// refuses it (opposite sides parallel and every corner square, within 0.001 of the cosines).
fn check_portal(portal: &[DVec3], p: &super::params::Param) -> Result<(), SceneError> {
    let [a, b, c, d] = portal else {
        return Err(p.error(format!(
            "a portal is four points (a rectangle's corners in order), not {}",
            portal.len()
        )));
    };
    let edge = |from: &DVec3, to: &DVec3| (*to - *from).try_normalize();
    let (Some(ab), Some(bc), Some(dc), Some(ad)) = (edge(a, b), edge(b, c), edge(d, c), edge(a, d))
    else {
        return Err(p.error("a portal's corners are four distinct finite points"));
    };
    let parallel = (ab.dot(dc) - 1.0).abs() <= 1e-3 && (bc.dot(ad) - 1.0).abs() <= 1e-3;
    let square = [ab.dot(bc), bc.dot(dc), dc.dot(ad), ad.dot(ab)]
        .iter()
        .all(|cos| cos.abs() <= 1e-3);
    if !(parallel && square) {
        return Err(p.error("a portal is a rectangle (its corners in order, as pbrt-v4 requires)"));
    }
    Ok(())
}

/// The image of the `infinite` light `light` whose `filename` parameter `p` names `file`.
fn sky_image(
    light: &LightEntity,
    file: &str,
    p: &super::params::Param,
    files: &Files,
    memory: &mut ImageMemory,
) -> Result<SkyImage, SceneError> {
    let entity = &light.entity;
    let path = files.resolve(file);
    files.check(&path, &p.loc, "filename")?;
    let image =
        crate::hdr::read_hdr_image(&path, memory.room()).map_err(|e| p.error(e.to_string()))?;
    memory.hold(image.texels.len() as u64 * crate::images::ENVIRONMENT_BYTES_PER_TEXEL);
    let (width, height) = (image.width, image.height);
    let lat_long = width != height;
    if lat_long && width != 2 * height {
        return Err(p.error(format!(
            "`{}` is {width}×{height}: an infinite light's image is a square equal-area \
             (octahedral) map, as pbrt-v4 requires, or an equirectangular (latitude–longitude) \
             map twice as wide as high, as pbrt-v3 read",
            path.display(),
        )));
    }
    // pbrt-v4 clamps negative values to zero where it reads the image.
    let texels: Vec<Color> = image
        .texels
        .into_iter()
        .map(|c| Color::new(c.red.max(0.0), c.green.max(0.0), c.blue.max(0.0)))
        .collect();
    let mut scale = entity.params.float_or("scale", 1.0)?;
    if let Some(e) = target(entity, "illuminance")? {
        let k = upper_illuminance(&texels, width, height, lat_long);
        if k > 0.0 {
            scale *= e / k;
        }
    }
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(entity.error(format!(
            "an infinite light's scale is not negative, found {scale}"
        )));
    }
    let texels = texels.into_iter().map(|c| c * scale).collect();
    // The light's space seen from the world: its rotation (and any mirror), a uniform scale
    // taken out; shear or a stretch has no meaning for directions and is refused.
    let m = DMat3::from_mat4(light.world_from_light);
    let det = m.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(entity.error("the light is placed by a singular transform"));
    }
    let world_to_light = (m * (1.0 / det.abs().cbrt())).inverse();
    Ok(SkyImage {
        width,
        height,
        lat_long,
        texels,
        world_to_light,
        at: entity.loc.clone(),
    })
}

/// The illuminance of a sky image's upper hemisphere (+z) as pbrt-v4 computes it for its
/// `illuminance` parameter: for an equal-area map, the sum over the pixels whose centres have
/// z > 0 of luminance × cos θ, times `2π / N` (as pbrt-v4 writes it: half the `4π / N` of
/// solid angle a pixel has); for a latitude–longitude map, the same sum with each pixel's own
/// solid angle, halved alike, so that a sky gives the same radiance in either layout.
fn upper_illuminance(texels: &[Color], width: usize, height: usize, lat_long: bool) -> f64 {
    let n = (width * height) as f64;
    let centre = |i: usize| {
        let (u, v) = (
            ((i % width) as f64 + 0.5) / width as f64,
            ((i / width) as f64 + 0.5) / height as f64,
        );
        if lat_long {
            let (a, b) = (PI * (i / width) as f64, PI * (i / width + 1) as f64);
            let solid_angle =
                2.0 * PI / width as f64 * ((a / height as f64).cos() - (b / height as f64).cos());
            ((PI * v).cos(), 0.5 * solid_angle)
        } else {
            (equal_area_square_to_sphere(u, v).z, 2.0 * PI / n)
        }
    };
    texels
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let (cos_theta, weight) = centre(i);
            if cos_theta > 0.0 {
                c.luminance() * cos_theta * weight
            } else {
                0.0
            }
        })
        .sum()
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
