//! Chapter 11, second half: transparency, refraction and the Fresnel effect.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::math::{scaling, translation};
use rayforge::{
    default_world, point, prepare_computations, schlick, vector, Intersection, Material, Object,
    Pattern, Ray, EPSILON,
};

/// The recursion depth the book's scenarios pass to `shade_hit` and friends (SEED-NOTES.md).
const REMAINING: u32 = 5;

const K: f64 = std::f64::consts::FRAC_1_SQRT_2;
const SQRT2: f64 = std::f64::consts::SQRT_2;

#[test]
fn transparency_and_refractive_index_for_the_default_material() {
    let m = Material::default();
    assert_eq!(m.transparency, 0.0);
    assert_eq!(m.refractive_index, 1.0);
}

#[test]
fn a_helper_for_producing_a_sphere_with_a_glassy_material() {
    let s = Object::glass_sphere();
    assert_eq!(s.transform.matrix(), glam::DMat4::IDENTITY);
    assert_eq!(s.material.transparency, 1.0);
    assert_eq!(s.material.refractive_index, 1.5);
}

fn glass(transform: glam::DMat4, index: f64) -> Object {
    let mut s = Object::glass_sphere().with_transform(transform);
    s.material.refractive_index = index;
    s
}

/// Scenario outline "Finding n1 and n2 at various intersections": one test per example row.
fn n1_n2_at(index: usize) -> (f64, f64) {
    let a = glass(scaling(2.0, 2.0, 2.0), 1.5);
    let b = glass(translation(0.0, 0.0, -0.25), 2.0);
    let c = glass(translation(0.0, 0.0, 0.25), 2.5);
    let r = Ray::new(point(0.0, 0.0, -4.0), vector(0.0, 0.0, 1.0));
    let xs = [
        Intersection::new(2.0, &a),
        Intersection::new(2.75, &b),
        Intersection::new(3.25, &c),
        Intersection::new(4.75, &b),
        Intersection::new(5.25, &c),
        Intersection::new(6.0, &a),
    ];
    let comps = prepare_computations(xs[index], &r, &xs);
    (comps.n1, comps.n2)
}

#[test]
fn finding_n1_and_n2_at_various_intersections_0() {
    assert_eq!(n1_n2_at(0), (1.0, 1.5));
}

#[test]
fn finding_n1_and_n2_at_various_intersections_1() {
    assert_eq!(n1_n2_at(1), (1.5, 2.0));
}

#[test]
fn finding_n1_and_n2_at_various_intersections_2() {
    assert_eq!(n1_n2_at(2), (2.0, 2.5));
}

#[test]
fn finding_n1_and_n2_at_various_intersections_3() {
    assert_eq!(n1_n2_at(3), (2.5, 2.5));
}

#[test]
fn finding_n1_and_n2_at_various_intersections_4() {
    assert_eq!(n1_n2_at(4), (2.5, 1.5));
}

#[test]
fn finding_n1_and_n2_at_various_intersections_5() {
    assert_eq!(n1_n2_at(5), (1.5, 1.0));
}

/// Containers are tracked by identity: two spheres with equal values are still two objects.
#[test]
fn equal_spheres_are_distinct_containers() {
    let a = glass(scaling(2.0, 2.0, 2.0), 1.5);
    let b = a.clone();
    let r = Ray::new(point(0.0, 0.0, -4.0), vector(0.0, 0.0, 1.0));
    let xs = [
        Intersection::new(2.0, &a),
        Intersection::new(2.0, &b),
        Intersection::new(6.0, &a),
        Intersection::new(6.0, &b),
    ];
    let comps = prepare_computations(xs[2], &r, &xs);
    assert_eq!((comps.n1, comps.n2), (1.5, 1.5));
}

#[test]
fn the_under_point_is_offset_below_the_surface() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let shape = Object::glass_sphere().with_transform(translation(0.0, 0.0, 1.0));
    let i = Intersection::new(5.0, &shape);
    let comps = prepare_computations(i, &r, &[i]);
    assert!(comps.under_point.z > EPSILON / 2.0);
    assert!(comps.point.z < comps.under_point.z);
}

#[test]
fn the_refracted_color_with_an_opaque_surface() {
    let w = default_world();
    let shape = &w.objects[0];
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let xs = [Intersection::new(4.0, shape), Intersection::new(6.0, shape)];
    let comps = prepare_computations(xs[0], &r, &xs);
    assert_color_approx(w.refracted_color(&comps, REMAINING), color(0.0, 0.0, 0.0));
}

#[test]
fn the_refracted_color_at_the_maximum_recursive_depth() {
    let mut w = default_world();
    w.objects[0].material.transparency = 1.0;
    w.objects[0].material.refractive_index = 1.5;
    let shape = &w.objects[0];
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let xs = [Intersection::new(4.0, shape), Intersection::new(6.0, shape)];
    let comps = prepare_computations(xs[0], &r, &xs);
    assert_color_approx(w.refracted_color(&comps, 0), color(0.0, 0.0, 0.0));
}

#[test]
fn the_refracted_color_under_total_internal_reflection() {
    let mut w = default_world();
    w.objects[0].material.transparency = 1.0;
    w.objects[0].material.refractive_index = 1.5;
    let shape = &w.objects[0];
    let r = Ray::new(point(0.0, 0.0, -K), vector(0.0, 1.0, 0.0));
    let xs = [Intersection::new(-K, shape), Intersection::new(K, shape)];
    // Inside the sphere, so look at the second intersection.
    let comps = prepare_computations(xs[1], &r, &xs);
    assert_color_approx(w.refracted_color(&comps, REMAINING), color(0.0, 0.0, 0.0));
}

#[test]
fn the_refracted_color_with_a_refracted_ray() {
    let mut w = default_world();
    w.objects[0].material.ambient = 1.0;
    w.objects[0].material.pattern = Some(Box::new(Pattern::position()));
    w.objects[1].material.transparency = 1.0;
    w.objects[1].material.refractive_index = 1.5;
    let (a, b) = (&w.objects[0], &w.objects[1]);
    let r = Ray::new(point(0.0, 0.0, 0.1), vector(0.0, 1.0, 0.0));
    let xs = [
        Intersection::new(-0.9899, a),
        Intersection::new(-0.4899, b),
        Intersection::new(0.4899, b),
        Intersection::new(0.9899, a),
    ];
    let comps = prepare_computations(xs[2], &r, &xs);
    assert_color_approx(
        w.refracted_color(&comps, REMAINING),
        color(0.0, 0.99888, 0.04725),
    );
}

/// The default world with a half-transparent floor below and a red ball beneath the floor.
fn world_with_glass_floor(reflective: f64) -> rayforge::World {
    let mut w = default_world();
    w.objects.push(
        Object::plane()
            .with_transform(translation(0.0, -1.0, 0.0))
            .with_material(Material {
                transparency: 0.5,
                refractive_index: 1.5,
                reflective,
                ..Material::default()
            }),
    );
    w.objects.push(
        Object::sphere()
            .with_transform(translation(0.0, -3.5, -0.5))
            .with_material(Material {
                color: color(1.0, 0.0, 0.0),
                ambient: 0.5,
                ..Material::default()
            }),
    );
    w
}

#[test]
fn shade_hit_with_a_transparent_material() {
    let w = world_with_glass_floor(0.0);
    let r = Ray::new(point(0.0, 0.0, -3.0), vector(0.0, -K, K));
    let xs = [Intersection::new(SQRT2, &w.objects[2])];
    let comps = prepare_computations(xs[0], &r, &xs);
    assert_color_approx(
        w.shade_hit(&comps, REMAINING),
        color(0.93642, 0.68642, 0.68642),
    );
}

#[test]
fn the_schlick_approximation_under_total_internal_reflection() {
    let shape = Object::glass_sphere();
    let r = Ray::new(point(0.0, 0.0, -K), vector(0.0, 1.0, 0.0));
    let xs = [Intersection::new(-K, &shape), Intersection::new(K, &shape)];
    let comps = prepare_computations(xs[1], &r, &xs);
    assert_approx(schlick(&comps), 1.0);
}

#[test]
fn the_schlick_approximation_with_a_perpendicular_viewing_angle() {
    let shape = Object::glass_sphere();
    let r = Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 1.0, 0.0));
    let xs = [
        Intersection::new(-1.0, &shape),
        Intersection::new(1.0, &shape),
    ];
    let comps = prepare_computations(xs[1], &r, &xs);
    assert_approx(schlick(&comps), 0.04);
}

#[test]
fn the_schlick_approximation_with_small_angle_and_n2_greater_than_n1() {
    let shape = Object::glass_sphere();
    let r = Ray::new(point(0.0, 0.99, -2.0), vector(0.0, 0.0, 1.0));
    let xs = [Intersection::new(1.8589, &shape)];
    let comps = prepare_computations(xs[0], &r, &xs);
    assert_approx(schlick(&comps), 0.48873);
}

#[test]
fn shade_hit_with_a_reflective_transparent_material() {
    let w = world_with_glass_floor(0.5);
    let r = Ray::new(point(0.0, 0.0, -3.0), vector(0.0, -K, K));
    let xs = [Intersection::new(SQRT2, &w.objects[2])];
    let comps = prepare_computations(xs[0], &r, &xs);
    assert_color_approx(
        w.shade_hit(&comps, REMAINING),
        color(0.93391, 0.69643, 0.69243),
    );
}
