//! Chapter 8: shadows.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::math::translation;
use rayforge::{
    default_world, lighting, point, prepare_computations, vector, Intersection, Light, Material,
    Object, Ray, World, EPSILON,
};

/// The recursion depth the book's scenarios pass to `shade_hit` (SEED-NOTES.md).
const REMAINING: u32 = 5;

/// The book's `in_shadow = true` is a light fraction of 0 here (1 is fully lit).
#[test]
fn lighting_with_the_surface_in_shadow() {
    // The materials feature's Background: m ← material(), position ← point(0, 0, 0).
    let m = Material::default();
    let position = point(0.0, 0.0, 0.0);
    let eyev = vector(0.0, 0.0, -1.0);
    let normalv = vector(0.0, 0.0, -1.0);
    let light = Light::point(point(0.0, 0.0, -10.0), color(1.0, 1.0, 1.0));
    let object = Object::sphere();
    let result = lighting(&m, &object, &light, position, eyev, normalv, 0.0);
    assert_color_approx(result, color(0.1, 0.1, 0.1));
}

fn shadowed(p: rayforge::Point3) -> bool {
    let w = default_world();
    w.is_shadowed(w.lights[0].position(), p)
}

#[test]
fn there_is_no_shadow_when_nothing_is_collinear_with_point_and_light() {
    assert!(!shadowed(point(0.0, 10.0, 0.0)));
}

#[test]
fn the_shadow_when_an_object_is_between_the_point_and_the_light() {
    assert!(shadowed(point(10.0, -10.0, 10.0)));
}

#[test]
fn there_is_no_shadow_when_an_object_is_behind_the_light() {
    assert!(!shadowed(point(-20.0, 20.0, -20.0)));
}

#[test]
fn there_is_no_shadow_when_an_object_is_behind_the_point() {
    assert!(!shadowed(point(-2.0, 2.0, -2.0)));
}

#[test]
fn shade_hit_is_given_an_intersection_in_shadow() {
    let w = World {
        lights: vec![Light::point(point(0.0, 0.0, -10.0), color(1.0, 1.0, 1.0))],
        objects: vec![
            Object::sphere(),
            Object::sphere().with_transform(translation(0.0, 0.0, 10.0)),
        ],
        ..World::default()
    };
    let r = Ray::new(point(0.0, 0.0, 5.0), vector(0.0, 0.0, 1.0));
    let i = Intersection::new(4.0, &w.objects[1]);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(w.shade_hit(&comps, REMAINING), color(0.1, 0.1, 0.1));
}

#[test]
fn the_hit_should_offset_the_point() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let shape = Object::sphere().with_transform(translation(0.0, 0.0, 1.0));
    let i = Intersection::new(5.0, &shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert!(comps.over_point.z < -EPSILON / 2.0);
    assert!(comps.point.z > comps.over_point.z);
    // The validation notebook's trap: `point` itself stays on the surface, apart from `over_point`.
    assert_vec_approx(comps.point, point(0.0, 0.0, 0.0));
}

/// Objects marked `shadow: false` in scene files let light through.
#[test]
fn an_object_that_casts_no_shadow_does_not_shadow() {
    let mut w = default_world();
    for o in &mut w.objects {
        o.casts_shadow = false;
    }
    assert!(!w.is_shadowed(w.lights[0].position(), point(10.0, -10.0, 10.0)));
}
