//! pbrt-v4's lights whose intensity an image shapes, as rayforge's [`PatternLight`]: the
//! goniometric light (pbrt-v4's `GoniometricLight`: a square image over the sphere of
//! directions in the equal-area layout, its channels averaged to one, the light's +y the
//! square's centre as pbrt-v4 swaps y and z) and the projection light (pbrt-v4's
//! `ProjectionLight`: an RGB image through a frustum of `fov` down the light's +z, the image's
//! shorter side spanning the field of view, its top row at +y). Both sit at the light space's
//! origin, their intensity the image's texel times `I` (a goniometric light's) times `scale`;
//! `power` scales them so that their power (the image over the sphere, a frustum's texels
//! weighed by the solid angle each subtends) is the one given, as pbrt-v4 does. The images are
//! read as every image of the scene, within its image memory ([`read_light_image`]).

use super::input::Files;
use super::params::{Param, ParamType};
use super::reader::{Entity, LightEntity};
use super::textures::{read_linear, Encoding};
use crate::error::SceneError;
use crate::images::ImageMemory;
use glam::{DMat3, DVec3};
use rayforge::shading::{Light, LightImage, PatternLight, PatternShape};
use rayforge::Color;
use std::f64::consts::PI;
use std::sync::Arc;

/// The image the `filename` parameter `p` names (`file`), found through `files` and read
/// within `memory`, each texel through `texel`: linear RGB, negative values taken as 0 (as
/// pbrt-v4 clamps a light's image), refused where a value is not finite (as pbrt-v4 refuses
/// it).
pub(crate) fn read_light_image(
    file: &str,
    p: &Param,
    files: &Files,
    memory: &mut ImageMemory,
    texel: impl Fn(Color) -> Color,
) -> Result<LightImage, SceneError> {
    let path = files.resolve(file);
    files.check(&path, &p.loc, "filename")?;
    let (width, height, texels) = read_linear(&path, Encoding::default_for(file), memory)
        .map_err(|e| p.error(format!("cannot read `{}`: {e}", path.display())))?;
    if let Some(i) = texels
        .iter()
        .position(|c| !c.to_array().iter().all(|v| v.is_finite()))
    {
        return Err(p.error(format!(
            "`{}`: pixel (column {}, row {} from the top) is not finite, which no light may \
             give (as pbrt-v4 refuses it)",
            path.display(),
            i % width,
            i / width
        )));
    }
    let texels = texels
        .into_iter()
        .map(|c| {
            texel(Color::new(
                c.red.max(0.0),
                c.green.max(0.0),
                c.blue.max(0.0),
            ))
        })
        .collect();
    LightImage::new(width, height, texels)
        .ok_or_else(|| p.error(format!("`{}` is an empty image", path.display())))
}

/// The `filename` of a light that must have one.
fn filename<'a>(entity: &'a Entity, what: &str) -> Result<(&'a str, &'a Param), SceneError> {
    entity.params.string("filename")?.ok_or_else(|| {
        entity.error(format!(
            "a {what} light names its image: \"string filename\" (pbrt-v4 {})",
            if what == "goniometric" {
                "only warns, and its light is then undefined"
            } else {
                "requires it"
            }
        ))
    })
}

/// From the light's space into the world's directions, for `light`: its transform's 3×3,
/// refused when singular.
fn light_to_world(light: &LightEntity) -> Result<DMat3, SceneError> {
    let m = DMat3::from_mat4(light.world_from_light);
    let det = m.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(light
            .entity
            .error("the light is placed by a singular transform"));
    }
    Ok(m)
}

/// The `power` a light is scaled to, where given and positive.
fn power(entity: &Entity) -> Result<Option<f64>, SceneError> {
    Ok(entity.params.float("power")?.filter(|v| *v > 0.0))
}

/// `light` scaled so that its power (`4π` times the luminance of pbrt's intensity, rayforge's
/// times π, averaged over the sphere) is `power`; unchanged where it gives nothing to scale.
fn with_power(mut light: PatternLight, power: f64) -> PatternLight {
    let k = 4.0 * PI * PI * (light.intensity * light.mean_pattern()).luminance();
    if k > 0.0 && k.is_finite() {
        light.intensity = light.intensity * (power / k);
    }
    light
}

/// A `goniometric` light: `I` (times `scale`) in each direction times the texel of its
/// equal-area square image there (the image's channels averaged, as pbrt-v4 makes its one
/// channel of them).
pub(crate) fn goniometric(
    light: &LightEntity,
    intensity: Color,
    files: &Files,
    memory: &mut ImageMemory,
) -> Result<Light, SceneError> {
    let entity = &light.entity;
    let (file, p) = filename(entity, "goniometric")?;
    // pbrt-v4 keeps one channel, the average of the three.
    let average = |c: Color| {
        let y = (c.red + c.green + c.blue) / 3.0;
        Color::new(y, y, y)
    };
    let image = read_light_image(file, p, files, memory, average)?;
    if image.width() != image.height() {
        return Err(p.error(format!(
            "`{file}` is {}×{}: a goniometric light's image is square (the equal-area layout \
             over the sphere), as pbrt-v4 requires",
            image.width(),
            image.height()
        )));
    }
    let m = light_to_world(light)?;
    // pbrt-v4 swaps the light space's y and z before it looks directions up in the square.
    let swap = DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::Y);
    let pattern = PatternLight {
        position: light.world_from_light.transform_point3(DVec3::ZERO),
        intensity: intensity * (1.0 / PI),
        falloff: true,
        to_light: swap * m.inverse(),
        shape: PatternShape::Sphere,
        image: Arc::new(image),
    };
    Ok(Light::Pattern(match power(entity)? {
        Some(phi) => with_power(pattern, phi),
        None => pattern,
    }))
}

/// A `projection` light: its image (times `scale`) through the frustum of `fov` degrees
/// (pbrt-v4's 90 by default) about the light's +z, over the image's shorter side.
pub(crate) fn projection(
    light: &LightEntity,
    files: &Files,
    memory: &mut ImageMemory,
) -> Result<Light, SceneError> {
    let entity = &light.entity;
    let params = &entity.params;
    let scale = params.float_or("scale", 1.0)?;
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(entity.error(format!(
            "a projection light's scale is not negative, found {scale}"
        )));
    }
    let fov = params.float_or("fov", 90.0)?;
    if !(fov > 0.0 && fov < 180.0) {
        let message = format!("a projection light's fov is between 0 and 180 degrees, found {fov}");
        return Err(match params.find("fov", &[ParamType::Float]) {
            Some(p) => p.error(message),
            None => entity.error(message),
        });
    }
    let (file, p) = filename(entity, "projection")?;
    let image = read_light_image(file, p, files, memory, |c| c)?;
    let aspect = image.width() as f64 / image.height() as f64;
    let t = (fov.to_radians() / 2.0).tan();
    let (half_width, half_height) = if aspect > 1.0 {
        (aspect * t, t)
    } else {
        (t, t / aspect)
    };
    let m = light_to_world(light)?;
    let pattern = PatternLight {
        position: light.world_from_light.transform_point3(DVec3::ZERO),
        intensity: Color::new(scale, scale, scale) * (1.0 / PI),
        falloff: true,
        to_light: m.inverse(),
        shape: PatternShape::Frustum {
            half_width,
            half_height,
        },
        image: Arc::new(image),
    };
    Ok(Light::Pattern(match power(entity)? {
        Some(phi) => with_power(pattern, phi),
        None => pattern,
    }))
}
