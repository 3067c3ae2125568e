//! Chapter 6: materials and the Phong lighting model (chapter 8's shadowed case is in shadows.rs;
//! chapter 6's `reflect` scenarios belong to `features/tuples.feature`, so live in tuples.rs).
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::color::color;
use rayforge::{lighting, point, vector, Light, Material, Object, Point3, Vec3};

const HALF_SQRT2: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The scenarios' background (`m ← material()`, `position ← point(0, 0, 0)`) with the normal they
/// all share, lit by a white point light at `light_position` (the chapter 6 form: fully lit).
fn light_at(eyev: Vec3, light_position: Point3) -> rayforge::Color {
    let m = Material::default();
    let position = point(0.0, 0.0, 0.0);
    let normalv = vector(0.0, 0.0, -1.0);
    let light = Light::point(light_position, color(1.0, 1.0, 1.0));
    lighting(&m, &Object::sphere(), &light, position, eyev, normalv, 1.0)
}

#[test]
fn the_default_material() {
    let m = Material::default();
    assert_eq!(m.color, color(1.0, 1.0, 1.0));
    assert_eq!(m.ambient, 0.1);
    assert_eq!(m.diffuse, 0.9);
    assert_eq!(m.specular, 0.9);
    assert_eq!(m.shininess, 200.0);
}

#[test]
fn lighting_with_the_eye_between_the_light_and_the_surface() {
    let result = light_at(vector(0.0, 0.0, -1.0), point(0.0, 0.0, -10.0));
    assert_color_approx(result, color(1.9, 1.9, 1.9));
}

/// The eye vector is the seed's `(0, -√2/2, -√2/2)`: 45° off the reflection vector, as the prose says.
#[test]
fn lighting_with_the_eye_between_light_and_surface_eye_offset_45() {
    let result = light_at(
        vector(0.0, -HALF_SQRT2, -HALF_SQRT2),
        point(0.0, 0.0, -10.0),
    );
    assert_color_approx(result, color(1.0, 1.0, 1.0));
}

#[test]
fn lighting_with_eye_opposite_surface_light_offset_45() {
    let result = light_at(vector(0.0, 0.0, -1.0), point(0.0, 10.0, -10.0));
    assert_color_approx(result, color(0.7364, 0.7364, 0.7364));
}

#[test]
fn lighting_with_eye_in_the_path_of_the_reflection_vector() {
    let result = light_at(
        vector(0.0, -HALF_SQRT2, -HALF_SQRT2),
        point(0.0, 10.0, -10.0),
    );
    assert_color_approx(result, color(1.6364, 1.6364, 1.6364));
}

#[test]
fn lighting_with_the_light_behind_the_surface() {
    let result = light_at(vector(0.0, 0.0, -1.0), point(0.0, 0.0, 10.0));
    assert_color_approx(result, color(0.1, 0.1, 0.1));
}
