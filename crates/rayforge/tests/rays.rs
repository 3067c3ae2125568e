//! Chapter 5: rays.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::math::{scaling, translation};
use rayforge::{point, vector, Ray};

#[test]
fn creating_and_querying_a_ray() {
    let origin = point(1.0, 2.0, 3.0);
    let direction = vector(4.0, 5.0, 6.0);
    let r = Ray::new(origin, direction);
    assert_eq!(r.origin, origin);
    assert_eq!(r.direction, direction);
}

#[test]
fn computing_a_point_from_a_distance() {
    let r = Ray::new(point(2.0, 3.0, 4.0), vector(1.0, 0.0, 0.0));
    assert_vec_approx(r.position(0.0), point(2.0, 3.0, 4.0));
    assert_vec_approx(r.position(1.0), point(3.0, 3.0, 4.0));
    assert_vec_approx(r.position(-1.0), point(1.0, 3.0, 4.0));
    assert_vec_approx(r.position(2.5), point(4.5, 3.0, 4.0));
}

#[test]
fn translating_a_ray() {
    let r = Ray::new(point(1.0, 2.0, 3.0), vector(0.0, 1.0, 0.0));
    let r2 = r.transform(translation(3.0, 4.0, 5.0));
    assert_vec_approx(r2.origin, point(4.0, 6.0, 8.0));
    assert_vec_approx(r2.direction, vector(0.0, 1.0, 0.0));
}

#[test]
fn scaling_a_ray() {
    let r = Ray::new(point(1.0, 2.0, 3.0), vector(0.0, 1.0, 0.0));
    let r2 = r.transform(scaling(2.0, 3.0, 4.0));
    assert_vec_approx(r2.origin, point(2.0, 6.0, 12.0));
    assert_vec_approx(r2.direction, vector(0.0, 3.0, 0.0));
}
