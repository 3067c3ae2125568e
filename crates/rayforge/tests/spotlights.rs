//! Spotlights (a chapter 17 "next step"): a cone of light with a soft edge.
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::{lighting, point, vector, Light, Material, Object, SpotLight, World};

fn spot() -> SpotLight {
    // Straight down from y = 5, dark beyond 0.5 rad, fading over the outer 0.2 rad.
    SpotLight::new(
        point(0.0, 5.0, 0.0),
        vector(0.0, -2.0, 0.0),
        0.5,
        0.2,
        color(1.0, 1.0, 1.0),
    )
    .unwrap()
}

#[test]
fn a_spotlight_is_full_inside_its_inner_cone_and_dark_outside_its_cone() {
    let s = spot();
    assert_approx(s.falloff(vector(0.0, -1.0, 0.0)), 1.0);
    let at = |angle: f64| s.falloff(vector(angle.sin(), -angle.cos(), 0.0));
    assert_approx(at(0.29), 1.0);
    assert_approx(at(0.51), 0.0);
    // Halfway through the fade (at 0.4 rad) it is strictly between.
    let mid = at(0.4);
    assert!(mid > 0.2 && mid < 0.8, "{mid}");
    // The fade is monotonic.
    assert!(at(0.35) > at(0.45));
}

#[test]
fn a_zero_direction_is_refused() {
    assert!(SpotLight::new(
        point(0.0, 0.0, 0.0),
        vector(0.0, 0.0, 0.0),
        0.5,
        0.1,
        color(1.0, 1.0, 1.0)
    )
    .is_none());
}

#[test]
fn lighting_under_a_spotlight_is_bright_in_the_cone_and_ambient_outside() {
    let m = Material::default();
    let s = Object::plane();
    let light = Light::Spot(spot());
    let eyev = vector(0.0, 1.0, 0.0);
    let normalv = vector(0.0, 1.0, 0.0);
    let inside = lighting(&m, &s, &light, point(0.0, 0.0, 0.0), eyev, normalv, 1.0);
    let outside = lighting(&m, &s, &light, point(5.0, 0.0, 0.0), eyev, normalv, 1.0);
    assert!(inside.red > 0.9, "{inside:?}");
    assert_color_approx(outside, color(0.1, 0.1, 0.1));
}

#[test]
fn a_spotlight_casts_shadows() {
    let mut w = World::new();
    w.objects.push(Object::plane());
    w.objects
        .push(Object::sphere().with_transform(rayforge::math::translation(0.0, 2.0, 0.0)));
    w.lights.push(Light::Spot(spot()));
    assert_approx(w.intensity_at(&w.lights[0], point(0.0, 0.0, 0.0)), 0.0);
    // Just above the floor (shading points are lifted off their surface the same way).
    assert_approx(w.intensity_at(&w.lights[0], point(3.0, 1e-3, 0.0)), 1.0);
}
