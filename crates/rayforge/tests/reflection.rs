//! Chapter 11, first half: reflection.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::math::translation;
use rayforge::{
    default_world, point, prepare_computations, vector, Intersection, Light, Material, Object, Ray,
    World,
};

/// The recursion depth the book's scenarios pass to `shade_hit` and friends (SEED-NOTES.md).
const REMAINING: u32 = 5;

const K: f64 = std::f64::consts::FRAC_1_SQRT_2;
const SQRT2: f64 = std::f64::consts::SQRT_2;

#[test]
fn reflectivity_for_the_default_material() {
    assert_eq!(Material::default().reflective, 0.0);
}

#[test]
fn precomputing_the_reflection_vector() {
    let shape = Object::plane();
    let r = Ray::new(point(0.0, 1.0, -1.0), vector(0.0, -K, K));
    let i = Intersection::new(SQRT2, &shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert_vec_approx(comps.reflectv, vector(0.0, K, K));
}

#[test]
fn the_reflected_color_for_a_nonreflective_material() {
    let mut w = default_world();
    w.objects[1].material.ambient = 1.0;
    let r = Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let i = Intersection::new(1.0, &w.objects[1]);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(w.reflected_color(&comps, REMAINING), color(0.0, 0.0, 0.0));
}

/// The default world plus a half-reflective plane one unit below the origin.
fn world_with_reflective_plane() -> World {
    let mut w = default_world();
    w.objects.push(
        Object::plane()
            .with_transform(translation(0.0, -1.0, 0.0))
            .with_material(Material {
                reflective: 0.5,
                ..Material::default()
            }),
    );
    w
}

#[test]
fn the_reflected_color_for_a_reflective_material() {
    let w = world_with_reflective_plane();
    let r = Ray::new(point(0.0, 0.0, -3.0), vector(0.0, -K, K));
    let i = Intersection::new(SQRT2, &w.objects[2]);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(
        w.reflected_color(&comps, REMAINING),
        color(0.19032, 0.2379, 0.14274),
    );
}

#[test]
fn shade_hit_with_a_reflective_material() {
    let w = world_with_reflective_plane();
    let r = Ray::new(point(0.0, 0.0, -3.0), vector(0.0, -K, K));
    let i = Intersection::new(SQRT2, &w.objects[2]);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(
        w.shade_hit(&comps, REMAINING),
        color(0.87677, 0.92436, 0.82918),
    );
}

#[test]
fn color_at_with_mutually_reflective_surfaces() {
    let mirror = Material {
        reflective: 1.0,
        ..Material::default()
    };
    let w = World {
        lights: vec![Light::point(point(0.0, 0.0, 0.0), color(1.0, 1.0, 1.0))],
        objects: vec![
            Object::plane()
                .with_transform(translation(0.0, -1.0, 0.0))
                .with_material(mirror.clone()),
            Object::plane()
                .with_transform(translation(0.0, 1.0, 0.0))
                .with_material(mirror),
        ],
        ..World::default()
    };
    let r = Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 1.0, 0.0));
    // "Should terminate successfully": the recursion limit stops the bounces. Derived by hand
    // beyond the book: every bounce meets a mirror head-on, one unit from the light, unshadowed,
    // so it adds ambient 0.1 + diffuse 0.9 + specular 0.9 = 1.9; with 5 recursions left the ray
    // meets 6 surfaces before reflected_color gives up.
    let c = w.color_at(&r, REMAINING);
    assert_color_approx(c, color(11.4, 11.4, 11.4));
}

#[test]
fn the_reflected_color_at_the_maximum_recursive_depth() {
    let w = world_with_reflective_plane();
    let r = Ray::new(point(0.0, 0.0, -3.0), vector(0.0, -K, K));
    let i = Intersection::new(SQRT2, &w.objects[2]);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(w.reflected_color(&comps, 0), color(0.0, 0.0, 0.0));
}
