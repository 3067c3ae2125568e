//! The Phong reflection model (chapter 6), with the pattern hook of chapter 10 and the light
//! fraction of the soft-shadows bonus chapter (0 = in shadow, 1 = fully lit).

use super::{Light, Material};
use crate::math::{reflect, Point3, Vec3};
use crate::{Color, Object};

/// The book's `lighting(material, object, light, point, eyev, normalv, light_fraction)`.
///
/// `light_fraction` replaces chapter 8's `in_shadow` flag: pass 0.0 for a point in shadow and 1.0
/// for a lit one (the form the soft-shadow chapter generalises). Ambient light is never shadowed.
#[allow(clippy::too_many_arguments)]
pub fn lighting(
    material: &Material,
    object: &Object,
    light: &Light,
    point: Point3,
    eyev: Vec3,
    normalv: Vec3,
    light_fraction: f64,
) -> Color {
    let surface = match &material.pattern {
        Some(pattern) => pattern.color_at_object(object, point),
        None => material.color,
    };
    let effective = surface * light.intensity();
    let ambient = effective * material.ambient;
    if light_fraction <= 0.0 {
        return ambient;
    }
    let lightv = (light.position() - point).normalize();
    let light_dot_normal = lightv.dot(normalv);
    if light_dot_normal < 0.0 {
        // The light is on the other side of the surface.
        return ambient;
    }
    let diffuse = effective * material.diffuse * light_dot_normal;
    let reflectv = reflect(-lightv, normalv);
    let reflect_dot_eye = reflectv.dot(eyev);
    let specular = if reflect_dot_eye <= 0.0 {
        Color::BLACK
    } else {
        light.intensity() * material.specular * reflect_dot_eye.powf(material.shininess)
    };
    ambient + (diffuse + specular) * light_fraction
}
