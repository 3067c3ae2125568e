//! Chapter 15: triangles and smooth triangles.
// The book's expected values are kept exactly as printed.
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::geometry::{LocalHit, Triangle};
use rayforge::{point, prepare_computations, vector, Intersection, Object, Ray, Shape};

fn book_triangle() -> Triangle {
    Triangle::new(
        point(0.0, 1.0, 0.0),
        point(-1.0, 0.0, 0.0),
        point(1.0, 0.0, 0.0),
    )
}

fn local_hits(shape: &Shape, r: &Ray) -> Vec<LocalHit> {
    let mut hits = Vec::new();
    shape.intersect_hits(r, |h| hits.push(h));
    hits
}

#[test]
fn constructing_a_triangle() {
    let t = book_triangle();
    assert_eq!(t.p1, point(0.0, 1.0, 0.0));
    assert_eq!(t.p2, point(-1.0, 0.0, 0.0));
    assert_eq!(t.p3, point(1.0, 0.0, 0.0));
    assert_vec_approx(t.e1, vector(-1.0, -1.0, 0.0));
    assert_vec_approx(t.e2, vector(1.0, -1.0, 0.0));
    assert_vec_approx(t.normal, vector(0.0, 0.0, -1.0));
}

#[test]
fn finding_the_normal_on_a_triangle() {
    let t = book_triangle();
    let shape = Shape::Triangle(Box::new(t));
    for p in [
        point(0.0, 0.5, 0.0),
        point(-0.5, 0.75, 0.0),
        point(0.5, 0.25, 0.0),
    ] {
        assert_vec_approx(shape.normal_at(p), t.normal);
    }
}

fn triangle_ts(origin: rayforge::Point3, direction: rayforge::Vec3) -> Vec<f64> {
    let shape = Shape::Triangle(Box::new(book_triangle()));
    local_hits(&shape, &Ray::new(origin, direction))
        .iter()
        .map(|h| h.t)
        .collect()
}

#[test]
fn intersecting_a_ray_parallel_to_the_triangle() {
    assert!(triangle_ts(point(0.0, -1.0, -2.0), vector(0.0, 1.0, 0.0)).is_empty());
}

#[test]
fn a_ray_misses_the_p1_p3_edge() {
    assert!(triangle_ts(point(1.0, 1.0, -2.0), vector(0.0, 0.0, 1.0)).is_empty());
}

#[test]
fn a_ray_misses_the_p1_p2_edge() {
    assert!(triangle_ts(point(-1.0, 1.0, -2.0), vector(0.0, 0.0, 1.0)).is_empty());
}

#[test]
fn a_ray_misses_the_p2_p3_edge() {
    assert!(triangle_ts(point(0.0, -1.0, -2.0), vector(0.0, 0.0, 1.0)).is_empty());
}

#[test]
fn a_ray_strikes_a_triangle() {
    let ts = triangle_ts(point(0.0, 0.5, -2.0), vector(0.0, 0.0, 1.0));
    assert_eq!(ts.len(), 1);
    assert_approx(ts[0], 2.0);
}

/// A tiny triangle (edges of 1e-4) is still hit: the parallel test does not scale with area.
#[test]
fn a_ray_strikes_a_tiny_triangle() {
    let s = 1e-4;
    let t = Triangle::new(point(0.0, s, 0.0), point(-s, 0.0, 0.0), point(s, 0.0, 0.0));
    let hits = local_hits(
        &Shape::Triangle(Box::new(t)),
        &Ray::new(point(0.0, s / 2.0, -2.0), vector(0.0, 0.0, 1.0)),
    );
    assert_eq!(hits.len(), 1);
}

fn smooth() -> Object {
    Object::smooth_triangle(
        point(0.0, 1.0, 0.0),
        point(-1.0, 0.0, 0.0),
        point(1.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
        vector(-1.0, 0.0, 0.0),
        vector(1.0, 0.0, 0.0),
    )
}

#[test]
fn constructing_a_smooth_triangle() {
    let Shape::Triangle(tri) = smooth().shape else {
        panic!("a triangle");
    };
    assert_eq!(tri.p1, point(0.0, 1.0, 0.0));
    assert_eq!(tri.p2, point(-1.0, 0.0, 0.0));
    assert_eq!(tri.p3, point(1.0, 0.0, 0.0));
    assert_eq!(
        tri.vertex_normals,
        Some([
            vector(0.0, 1.0, 0.0),
            vector(-1.0, 0.0, 0.0),
            vector(1.0, 0.0, 0.0)
        ])
    );
}

#[test]
fn an_intersection_with_a_smooth_triangle_stores_u_v() {
    let r = Ray::new(point(-0.2, 0.3, -2.0), vector(0.0, 0.0, 1.0));
    let hits = local_hits(&smooth().shape, &r);
    assert_approx(hits[0].u, 0.45);
    assert_approx(hits[0].v, 0.25);
}

#[test]
fn a_smooth_triangle_uses_u_v_to_interpolate_the_normal() {
    let tri = smooth();
    let i = Intersection::with_uv(1.0, &tri, 0.45, 0.25);
    let n = tri.normal_at_hit(point(0.0, 0.0, 0.0), &i);
    assert_vec_approx(n, vector(-0.5547, 0.83205, 0.0));
}

#[test]
fn preparing_the_normal_on_a_smooth_triangle() {
    let tri = smooth();
    let i = Intersection::with_uv(1.0, &tri, 0.45, 0.25);
    let r = Ray::new(point(-0.2, 0.3, -2.0), vector(0.0, 0.0, 1.0));
    let comps = prepare_computations(i, &r, &[i]);
    assert_vec_approx(comps.normalv, vector(-0.5547, 0.83205, 0.0));
}
