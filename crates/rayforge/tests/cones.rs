//! Chapter 13: cones.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::{point, vector, Point3, Ray, Shape, Vec3};

fn strikes(origin: Point3, direction: Vec3, t0: f64, t1: f64) {
    let ts = local_ts(&Shape::CONE, origin, direction);
    assert_eq!(ts.len(), 2);
    assert_approx(ts[0], t0);
    assert_approx(ts[1], t1);
}

scenario_rows! { strikes;
    intersecting_a_cone_with_a_ray_along_z: point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0), 5.0, 5.0;
    intersecting_a_cone_with_a_ray_diagonal: point(0.0, 0.0, -5.0), vector(1.0, 1.0, 1.0), 8.66025, 8.66025;
    intersecting_a_cone_with_a_ray_skewed: point(1.0, 1.0, -5.0), vector(-0.5, -1.0, 1.0), 4.55006, 49.44994;
}

/// SEED-NOTES.md erratum 5: the book prints t = 0.35355 (= -c/2b), which lies off the cone;
/// the single root of b·t + c = 0 is -c/b = 0.70711.
#[test]
fn intersecting_a_cone_with_a_ray_parallel_to_one_of_its_halves() {
    let ts = local_ts(&Shape::CONE, point(0.0, 0.0, -1.0), vector(0.0, 1.0, 1.0));
    assert_eq!(ts.len(), 1);
    assert_approx(ts[0], 0.70711);
    // And the point really is on the cone: x² + z² = y².
    let p = Ray::new(point(0.0, 0.0, -1.0), vector(0.0, 1.0, 1.0).normalize()).position(ts[0]);
    assert_approx(p.x * p.x + p.z * p.z, p.y * p.y);
}

fn capped(origin: Point3, direction: Vec3, count: usize) {
    let cone = Shape::Cone {
        minimum: -0.5,
        maximum: 0.5,
        closed: true,
    };
    assert_eq!(local_ts(&cone, origin, direction).len(), count);
}

scenario_rows! { capped;
    intersecting_a_cones_end_caps_1: point(0.0, 0.0, -5.0), vector(0.0, 1.0, 0.0), 0;
    intersecting_a_cones_end_caps_2: point(0.0, 0.0, -0.25), vector(0.0, 1.0, 1.0), 2;
    intersecting_a_cones_end_caps_3: point(0.0, 0.0, -0.25), vector(0.0, 1.0, 0.0), 4;
}

fn normal(p: Point3, n: Vec3) {
    assert_vec_approx(Shape::CONE.normal_at(p), n);
}

scenario_rows! { normal;
    computing_the_normal_vector_on_a_cone_apex: point(0.0, 0.0, 0.0), vector(0.0, 0.0, 0.0);
    computing_the_normal_vector_on_a_cone_upper: point(1.0, 1.0, 1.0), vector(1.0, -(2f64.sqrt()), 1.0);
    computing_the_normal_vector_on_a_cone_lower: point(-1.0, -1.0, 0.0), vector(-1.0, 1.0, 0.0);
}

/// The world normal at the apex is zero, not NaN (the validation notebook's trap).
#[test]
fn the_world_normal_at_a_cones_apex_is_not_nan() {
    let n = rayforge::Object::cone().normal_at(point(0.0, 0.0, 0.0));
    assert!(n.is_finite());
}
