//! Chapter 13: cylinders.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::math::{scaling, translation};
use rayforge::{
    hit, point, prepare_computations, vector, Color, Light, Object, Point3, Ray, Shape, Vec3, World,
};

fn cylinder(minimum: f64, maximum: f64, closed: bool) -> Shape {
    Shape::Cylinder {
        minimum,
        maximum,
        closed,
    }
}

fn misses(origin: Point3, direction: Vec3) {
    assert!(local_ts(&Shape::CYLINDER, origin, direction).is_empty());
}

scenario_rows! { misses;
    a_ray_misses_a_cylinder_on_the_surface_parallel: point(1.0, 0.0, 0.0), vector(0.0, 1.0, 0.0);
    a_ray_misses_a_cylinder_inside_parallel: point(0.0, 0.0, 0.0), vector(0.0, 1.0, 0.0);
    a_ray_misses_a_cylinder_outside_skewed: point(0.0, 0.0, -5.0), vector(1.0, 1.0, 1.0);
}

fn strikes(origin: Point3, direction: Vec3, t0: f64, t1: f64) {
    let ts = local_ts(&Shape::CYLINDER, origin, direction);
    assert_eq!(ts.len(), 2);
    assert_approx(ts[0], t0);
    assert_approx(ts[1], t1);
}

scenario_rows! { strikes;
    a_ray_strikes_a_cylinder_tangent: point(1.0, 0.0, -5.0), vector(0.0, 0.0, 1.0), 5.0, 5.0;
    a_ray_strikes_a_cylinder_through_the_middle: point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0), 4.0, 6.0;
    a_ray_strikes_a_cylinder_at_an_angle: point(0.5, 0.0, -5.0), vector(0.1, 1.0, 1.0), 6.80798, 7.08872;
}

fn side_normal(p: Point3, n: Vec3) {
    assert_vec_approx(Shape::CYLINDER.normal_at(p), n);
}

scenario_rows! { side_normal;
    normal_vector_on_a_cylinder_plus_x: point(1.0, 0.0, 0.0), vector(1.0, 0.0, 0.0);
    normal_vector_on_a_cylinder_minus_z: point(0.0, 5.0, -1.0), vector(0.0, 0.0, -1.0);
    normal_vector_on_a_cylinder_plus_z: point(0.0, -2.0, 1.0), vector(0.0, 0.0, 1.0);
    normal_vector_on_a_cylinder_minus_x: point(-1.0, 1.0, 0.0), vector(-1.0, 0.0, 0.0);
}

#[test]
fn the_default_minimum_and_maximum_for_a_cylinder() {
    let Shape::Cylinder {
        minimum, maximum, ..
    } = Object::cylinder().shape
    else {
        panic!("a cylinder");
    };
    assert_eq!(minimum, f64::NEG_INFINITY);
    assert_eq!(maximum, f64::INFINITY);
    assert_eq!(Object::cylinder().shape, Shape::CYLINDER);
}

fn constrained(origin: Point3, direction: Vec3, count: usize) {
    assert_eq!(
        local_ts(&cylinder(1.0, 2.0, false), origin, direction).len(),
        count
    );
}

scenario_rows! { constrained;
    intersecting_a_constrained_cylinder_1: point(0.0, 1.5, 0.0), vector(0.1, 1.0, 0.0), 0;
    intersecting_a_constrained_cylinder_2: point(0.0, 3.0, -5.0), vector(0.0, 0.0, 1.0), 0;
    intersecting_a_constrained_cylinder_3: point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0), 0;
    intersecting_a_constrained_cylinder_4: point(0.0, 2.0, -5.0), vector(0.0, 0.0, 1.0), 0;
    intersecting_a_constrained_cylinder_5: point(0.0, 1.0, -5.0), vector(0.0, 0.0, 1.0), 0;
    intersecting_a_constrained_cylinder_6: point(0.0, 1.5, -2.0), vector(0.0, 0.0, 1.0), 2;
}

#[test]
fn the_default_closed_value_for_a_cylinder() {
    assert!(matches!(
        Object::cylinder().shape,
        Shape::Cylinder { closed: false, .. }
    ));
}

fn capped(origin: Point3, direction: Vec3, count: usize) {
    assert_eq!(
        local_ts(&cylinder(1.0, 2.0, true), origin, direction).len(),
        count
    );
}

scenario_rows! { capped;
    intersecting_the_caps_of_a_closed_cylinder_1: point(0.0, 3.0, 0.0), vector(0.0, -1.0, 0.0), 2;
    intersecting_the_caps_of_a_closed_cylinder_2: point(0.0, 3.0, -2.0), vector(0.0, -1.0, 2.0), 2;
    intersecting_the_caps_of_a_closed_cylinder_3_corner: point(0.0, 4.0, -2.0), vector(0.0, -1.0, 1.0), 2;
    intersecting_the_caps_of_a_closed_cylinder_4: point(0.0, 0.0, -2.0), vector(0.0, 1.0, 2.0), 2;
    intersecting_the_caps_of_a_closed_cylinder_5_corner: point(0.0, -1.0, -2.0), vector(0.0, 1.0, 1.0), 2;
}

fn cap_normal(p: Point3, n: Vec3) {
    assert_vec_approx(cylinder(1.0, 2.0, true).normal_at(p), n);
}

scenario_rows! { cap_normal;
    the_normal_vector_on_a_cylinders_end_caps_1: point(0.0, 1.0, 0.0), vector(0.0, -1.0, 0.0);
    the_normal_vector_on_a_cylinders_end_caps_2: point(0.5, 1.0, 0.0), vector(0.0, -1.0, 0.0);
    the_normal_vector_on_a_cylinders_end_caps_3: point(0.0, 1.0, 0.5), vector(0.0, -1.0, 0.0);
    the_normal_vector_on_a_cylinders_end_caps_4: point(0.0, 2.0, 0.0), vector(0.0, 1.0, 0.0);
    the_normal_vector_on_a_cylinders_end_caps_5: point(0.5, 2.0, 0.0), vector(0.0, 1.0, 0.0);
    the_normal_vector_on_a_cylinders_end_caps_6: point(0.0, 2.0, 0.5), vector(0.0, 1.0, 0.0);
}

/// A capped cylinder placed in the world: the ray from above meets the top cap first.
#[test]
fn a_transformed_closed_cylinder_is_hit_on_its_cap_from_above() {
    let c = Object::new(cylinder(-1.0, 1.0, true)).with_transform(translation(0.0, 2.0, 0.0));
    let r = Ray::new(point(0.2, 10.0, 0.1), vector(0.0, -1.0, 0.0));
    let hit = hit(&c.intersections(&r)).expect("hits the cap");
    assert_approx(hit.t, 7.0);
    assert_vec_approx(c.normal_at(r.position(hit.t)), vector(0.0, 1.0, 0.0));
}

/// A world holding one cylinder of radius 2 spanning 0 ≤ y ≤ 2 (local -1..1, scaled then raised),
/// lit by a white point light at `eye`.
fn world_with_cylinder(closed: bool, eye: Point3) -> World {
    let transform = translation(0.0, 1.0, 0.0) * scaling(2.0, 1.0, 2.0);
    World {
        objects: vec![Object::new(cylinder(-1.0, 1.0, closed)).with_transform(transform)],
        lights: vec![Light::point(eye, Color::WHITE)],
        ..World::new()
    }
}

/// Through the world API: looking straight down at a transformed, capped cylinder with the light
/// at the eye, the top cap is the hit, its normal is +y, and it shades at full strength.
#[test]
fn a_transformed_closed_cylinder_in_a_world_shows_its_top_cap() {
    let eye = point(1.0, 10.0, 0.5);
    let w = world_with_cylinder(true, eye);
    let r = Ray::new(eye, vector(0.0, -1.0, 0.0));
    let xs = w.intersect(&r);
    // Top cap at y = 2, bottom cap at y = 0; the axis-parallel ray never meets the side.
    assert_eq!(xs.len(), 2);
    assert_approx(xs[0].t, 8.0);
    assert_approx(xs[1].t, 10.0);
    let h = hit(&xs).expect("hits the top cap");
    assert_vec_approx(h.object.normal_at(r.position(h.t)), vector(0.0, 1.0, 0.0));
    let comps = prepare_computations(h, &r, &xs);
    assert_vec_approx(comps.point, point(1.0, 2.0, 0.5));
    assert_vec_approx(comps.normalv, vector(0.0, 1.0, 0.0));
    assert!(!comps.inside);
    // Light, eye and normal all along +y: ambient 0.1 + diffuse 0.9 + specular 0.9, unshadowed.
    assert_color_approx(w.color_at(&r, 5), Color::new(1.9, 1.9, 1.9));
}

/// The same ray through the same cylinder left open passes down its hollow middle.
#[test]
fn a_transformed_open_cylinder_in_a_world_is_hollow_from_above() {
    let eye = point(1.0, 10.0, 0.5);
    let w = world_with_cylinder(false, eye);
    let r = Ray::new(eye, vector(0.0, -1.0, 0.0));
    assert!(w.intersect(&r).is_empty());
    assert_color_approx(w.color_at(&r, 5), Color::BLACK);
}

/// A horizontal ray meets the scaled side at z = -2, where the world normal is -z.
#[test]
fn a_transformed_closed_cylinder_in_a_world_has_side_normals() {
    let w = world_with_cylinder(true, point(0.0, 1.0, -10.0));
    let r = Ray::new(point(0.0, 1.0, -10.0), vector(0.0, 0.0, 1.0));
    let xs = w.intersect(&r);
    assert_eq!(xs.len(), 2);
    assert_approx(xs[0].t, 8.0);
    assert_approx(xs[1].t, 12.0);
    let h = hit(&xs).expect("hits the side");
    assert_vec_approx(h.object.normal_at(r.position(h.t)), vector(0.0, 0.0, -1.0));
}
