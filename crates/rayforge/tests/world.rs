//! Chapter 7: the world, `prepare_computations`, `shade_hit` and `color_at`.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::math::scaling;
use rayforge::{
    default_world, point, prepare_computations, vector, Intersection, Light, Material, Object, Ray,
    World,
};

/// The recursion depth the book's scenarios pass to `shade_hit` and `color_at` (SEED-NOTES.md).
const REMAINING: u32 = 5;

#[test]
fn creating_a_world() {
    let w = World::new();
    assert!(w.objects.is_empty());
    assert!(w.lights.is_empty());
}

#[test]
fn the_default_world() {
    let light = Light::point(point(-10.0, 10.0, -10.0), color(1.0, 1.0, 1.0));
    let s1 = Object::sphere().with_material(Material {
        color: color(0.8, 1.0, 0.6),
        diffuse: 0.7,
        specular: 0.2,
        ..Material::default()
    });
    let s2 = Object::sphere().with_transform(scaling(0.5, 0.5, 0.5));
    let w = default_world();
    assert_eq!(w.lights, [light]);
    assert!(w.objects.contains(&s1));
    assert!(w.objects.contains(&s2));
}

#[test]
fn intersect_a_world_with_a_ray() {
    let w = default_world();
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let xs = w.intersect(&r);
    assert_eq!(xs.len(), 4);
    for (x, expected) in xs.iter().zip([4.0, 4.5, 5.5, 6.0]) {
        assert_approx(x.t, expected);
    }
}

#[test]
fn precomputing_the_state_of_an_intersection() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let shape = Object::sphere();
    let i = Intersection::new(4.0, &shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert_eq!(comps.t, i.t);
    assert!(std::ptr::eq(comps.object, &shape));
    assert_vec_approx(comps.point, point(0.0, 0.0, -1.0));
    assert_vec_approx(comps.eyev, vector(0.0, 0.0, -1.0));
    assert_vec_approx(comps.normalv, vector(0.0, 0.0, -1.0));
}

#[test]
fn the_hit_when_an_intersection_occurs_on_the_outside() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let shape = Object::sphere();
    let i = Intersection::new(4.0, &shape);
    assert!(!prepare_computations(i, &r, &[i]).inside);
}

#[test]
fn the_hit_when_an_intersection_occurs_on_the_inside() {
    let r = Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let shape = Object::sphere();
    let i = Intersection::new(1.0, &shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert_vec_approx(comps.point, point(0.0, 0.0, 1.0));
    assert_vec_approx(comps.eyev, vector(0.0, 0.0, -1.0));
    assert!(comps.inside);
    // The normal is inverted to face the eye.
    assert_vec_approx(comps.normalv, vector(0.0, 0.0, -1.0));
}

#[test]
fn shading_an_intersection() {
    let w = default_world();
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let shape = &w.objects[0];
    let i = Intersection::new(4.0, shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(
        w.shade_hit(&comps, REMAINING),
        color(0.38066, 0.47583, 0.2855),
    );
}

#[test]
fn shading_an_intersection_from_the_inside() {
    let mut w = default_world();
    w.lights = vec![Light::point(point(0.0, 0.25, 0.0), color(1.0, 1.0, 1.0))];
    let r = Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let shape = &w.objects[1];
    let i = Intersection::new(0.5, shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert_color_approx(
        w.shade_hit(&comps, REMAINING),
        color(0.90498, 0.90498, 0.90498),
    );
}

#[test]
fn the_color_when_a_ray_misses() {
    let w = default_world();
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 1.0, 0.0));
    assert_color_approx(w.color_at(&r, REMAINING), color(0.0, 0.0, 0.0));
}

#[test]
fn the_color_when_a_ray_hits() {
    let w = default_world();
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    assert_color_approx(w.color_at(&r, REMAINING), color(0.38066, 0.47583, 0.2855));
}

#[test]
fn the_color_with_an_intersection_behind_the_ray() {
    let mut w = default_world();
    w.objects[0].material.ambient = 1.0;
    w.objects[1].material.ambient = 1.0;
    let r = Ray::new(point(0.0, 0.0, 0.75), vector(0.0, 0.0, -1.0));
    let inner_color = w.objects[1].material.color;
    assert_color_approx(w.color_at(&r, REMAINING), inner_color);
}
