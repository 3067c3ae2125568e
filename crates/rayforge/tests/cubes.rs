//! Chapter 12: cubes.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::{point, vector, Point3, Ray, Shape, Vec3};

fn local_ts(origin: Point3, direction: Vec3) -> Vec<f64> {
    let mut ts = Vec::new();
    Shape::Cube.intersect(&Ray::new(origin, direction), |t| ts.push(t));
    ts.sort_by(f64::total_cmp);
    ts
}

/// Scenario outline "A ray intersects a cube": one test per example row, named by its label.
#[track_caller]
fn assert_hits(origin: Point3, direction: Vec3, t1: f64, t2: f64) {
    let ts = local_ts(origin, direction);
    assert_eq!(ts.len(), 2);
    assert_approx(ts[0], t1);
    assert_approx(ts[1], t2);
}

#[test]
fn a_ray_intersects_a_cube_plus_x() {
    assert_hits(point(5.0, 0.5, 0.0), vector(-1.0, 0.0, 0.0), 4.0, 6.0);
}

#[test]
fn a_ray_intersects_a_cube_minus_x() {
    assert_hits(point(-5.0, 0.5, 0.0), vector(1.0, 0.0, 0.0), 4.0, 6.0);
}

#[test]
fn a_ray_intersects_a_cube_plus_y() {
    assert_hits(point(0.5, 5.0, 0.0), vector(0.0, -1.0, 0.0), 4.0, 6.0);
}

#[test]
fn a_ray_intersects_a_cube_minus_y() {
    assert_hits(point(0.5, -5.0, 0.0), vector(0.0, 1.0, 0.0), 4.0, 6.0);
}

#[test]
fn a_ray_intersects_a_cube_plus_z() {
    assert_hits(point(0.5, 0.0, 5.0), vector(0.0, 0.0, -1.0), 4.0, 6.0);
}

#[test]
fn a_ray_intersects_a_cube_minus_z() {
    assert_hits(point(0.5, 0.0, -5.0), vector(0.0, 0.0, 1.0), 4.0, 6.0);
}

#[test]
fn a_ray_intersects_a_cube_inside() {
    assert_hits(point(0.0, 0.5, 0.0), vector(0.0, 0.0, 1.0), -1.0, 1.0);
}

/// Scenario outline "A ray misses a cube": one test per example row, named by its origin.
#[track_caller]
fn assert_misses(origin: Point3, direction: Vec3) {
    assert!(local_ts(origin, direction).is_empty());
}

#[test]
fn a_ray_misses_a_cube_from_minus_2_0_0() {
    assert_misses(point(-2.0, 0.0, 0.0), vector(0.2673, 0.5345, 0.8018));
}

#[test]
fn a_ray_misses_a_cube_from_0_minus_2_0() {
    assert_misses(point(0.0, -2.0, 0.0), vector(0.8018, 0.2673, 0.5345));
}

#[test]
fn a_ray_misses_a_cube_from_0_0_minus_2() {
    assert_misses(point(0.0, 0.0, -2.0), vector(0.5345, 0.8018, 0.2673));
}

#[test]
fn a_ray_misses_a_cube_from_2_0_2() {
    assert_misses(point(2.0, 0.0, 2.0), vector(0.0, 0.0, -1.0));
}

#[test]
fn a_ray_misses_a_cube_from_0_2_2() {
    assert_misses(point(0.0, 2.0, 2.0), vector(0.0, -1.0, 0.0));
}

#[test]
fn a_ray_misses_a_cube_from_2_2_0() {
    assert_misses(point(2.0, 2.0, 0.0), vector(-1.0, 0.0, 0.0));
}

/// The validation notebook's trap: a ray parallel to a face, starting exactly in that face's
/// plane, must not produce NaN.
#[test]
fn a_ray_parallel_to_a_face_in_its_plane_gives_no_nan() {
    let ts = local_ts(point(1.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    assert!(ts.iter().all(|t| t.is_finite()));
    assert_eq!(ts.len(), 2);
}

fn normal(p: Point3) -> Vec3 {
    Shape::Cube.normal_at(p)
}

/// Scenario outline "The normal on the surface of a cube": one test per example row.
macro_rules! cube_normal {
    ($($name:ident: ($px:expr, $py:expr, $pz:expr) => ($nx:expr, $ny:expr, $nz:expr);)*) => {$(
        #[test]
        fn $name() {
            assert_vec_approx(normal(point($px, $py, $pz)), vector($nx, $ny, $nz));
        }
    )*};
}

cube_normal! {
    the_normal_on_the_surface_of_a_cube_plus_x: (1.0, 0.5, -0.8) => (1.0, 0.0, 0.0);
    the_normal_on_the_surface_of_a_cube_minus_x: (-1.0, -0.2, 0.9) => (-1.0, 0.0, 0.0);
    the_normal_on_the_surface_of_a_cube_plus_y: (-0.4, 1.0, -0.1) => (0.0, 1.0, 0.0);
    the_normal_on_the_surface_of_a_cube_minus_y: (0.3, -1.0, -0.7) => (0.0, -1.0, 0.0);
    the_normal_on_the_surface_of_a_cube_plus_z: (-0.6, 0.3, 1.0) => (0.0, 0.0, 1.0);
    the_normal_on_the_surface_of_a_cube_minus_z: (0.4, 0.4, -1.0) => (0.0, 0.0, -1.0);
    the_normal_on_the_surface_of_a_cube_corner_plus: (1.0, 1.0, 1.0) => (1.0, 0.0, 0.0);
    the_normal_on_the_surface_of_a_cube_corner_minus: (-1.0, -1.0, -1.0) => (-1.0, 0.0, 0.0);
}
