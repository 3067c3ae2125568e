//! Chapter 9: planes.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::{point, vector, Object, Ray, Shape};

fn local_ts(r: &Ray) -> Vec<f64> {
    let mut ts = Vec::new();
    Shape::Plane.intersect(r, |t| ts.push(t));
    ts
}

#[test]
fn the_normal_of_a_plane_is_constant_everywhere() {
    for p in [
        point(0.0, 0.0, 0.0),
        point(10.0, 0.0, -10.0),
        point(-5.0, 0.0, 150.0),
    ] {
        assert_vec_approx(Shape::Plane.normal_at(p), vector(0.0, 1.0, 0.0));
    }
}

#[test]
fn intersect_with_a_ray_parallel_to_the_plane() {
    assert!(local_ts(&Ray::new(point(0.0, 10.0, 0.0), vector(0.0, 0.0, 1.0))).is_empty());
}

#[test]
fn intersect_with_a_coplanar_ray() {
    assert!(local_ts(&Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0))).is_empty());
}

#[test]
fn a_ray_intersecting_a_plane_from_above() {
    let p = Object::plane();
    let xs = p.intersections(&Ray::new(point(0.0, 1.0, 0.0), vector(0.0, -1.0, 0.0)));
    assert_eq!(xs.len(), 1);
    assert_approx(xs[0].t, 1.0);
    assert!(std::ptr::eq(xs[0].object, &p));
}

#[test]
fn a_ray_intersecting_a_plane_from_below() {
    let p = Object::plane();
    let xs = p.intersections(&Ray::new(point(0.0, -1.0, 0.0), vector(0.0, 1.0, 0.0)));
    assert_eq!(xs.len(), 1);
    assert_approx(xs[0].t, 1.0);
    assert!(std::ptr::eq(xs[0].object, &p));
}
