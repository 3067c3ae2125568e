//! Chapters 5 and 6: spheres: intersections, transforms, normals and materials.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::math::{rotation_z, scaling, translation};
use rayforge::{point, vector, Material, Object, Ray};
use std::f64::consts::PI;

fn ts(s: &Object, r: &Ray) -> Vec<f64> {
    s.intersections(r).iter().map(|i| i.t).collect()
}

/// The book's `xs.count = n` and `xs[i] = t` steps: the same number of `t`s, each within tolerance.
#[track_caller]
fn assert_ts(actual: Vec<f64>, expected: &[f64]) {
    assert_eq!(actual.len(), expected.len(), "got {actual:?}");
    for (&a, &e) in actual.iter().zip(expected) {
        assert_approx(a, e);
    }
}

#[test]
fn a_ray_intersects_a_sphere_at_two_points() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    assert_ts(ts(&Object::sphere(), &r), &[4.0, 6.0]);
}

#[test]
fn a_ray_intersects_a_sphere_at_a_tangent() {
    let r = Ray::new(point(0.0, 1.0, -5.0), vector(0.0, 0.0, 1.0));
    assert_ts(ts(&Object::sphere(), &r), &[5.0, 5.0]);
}

#[test]
fn a_ray_misses_a_sphere() {
    let r = Ray::new(point(0.0, 2.0, -5.0), vector(0.0, 0.0, 1.0));
    assert!(ts(&Object::sphere(), &r).is_empty());
}

#[test]
fn a_ray_originates_inside_a_sphere() {
    let r = Ray::new(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    assert_ts(ts(&Object::sphere(), &r), &[-1.0, 1.0]);
}

#[test]
fn a_sphere_is_behind_a_ray() {
    let r = Ray::new(point(0.0, 0.0, 5.0), vector(0.0, 0.0, 1.0));
    assert_ts(ts(&Object::sphere(), &r), &[-6.0, -4.0]);
}

#[test]
fn intersect_sets_the_object_on_the_intersection() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let s = Object::sphere();
    let xs = s.intersections(&r);
    assert_eq!(xs.len(), 2);
    assert!(std::ptr::eq(xs[0].object, &s));
    assert!(std::ptr::eq(xs[1].object, &s));
}

#[test]
fn a_spheres_default_transformation() {
    assert_eq!(Object::sphere().transform.matrix(), glam::DMat4::IDENTITY);
}

#[test]
fn changing_a_spheres_transformation() {
    let mut s = Object::sphere();
    let t = translation(2.0, 3.0, 4.0);
    s.set_transform(t);
    assert_eq!(s.transform.matrix(), t);
}

#[test]
fn intersecting_a_scaled_sphere_with_a_ray() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let mut s = Object::sphere();
    s.set_transform(scaling(2.0, 2.0, 2.0));
    assert_ts(ts(&s, &r), &[3.0, 7.0]);
}

#[test]
fn intersecting_a_translated_sphere_with_a_ray() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let mut s = Object::sphere();
    s.set_transform(translation(5.0, 0.0, 0.0));
    assert!(ts(&s, &r).is_empty());
}

#[test]
fn the_normal_on_a_sphere_at_a_point_on_the_x_axis() {
    let n = Object::sphere().normal_at(point(1.0, 0.0, 0.0));
    assert_vec_approx(n, vector(1.0, 0.0, 0.0));
}

#[test]
fn the_normal_on_a_sphere_at_a_point_on_the_y_axis() {
    let n = Object::sphere().normal_at(point(0.0, 1.0, 0.0));
    assert_vec_approx(n, vector(0.0, 1.0, 0.0));
}

#[test]
fn the_normal_on_a_sphere_at_a_point_on_the_z_axis() {
    let n = Object::sphere().normal_at(point(0.0, 0.0, 1.0));
    assert_vec_approx(n, vector(0.0, 0.0, 1.0));
}

#[test]
fn the_normal_on_a_sphere_at_a_nonaxial_point() {
    let k = 3f64.sqrt() / 3.0;
    let n = Object::sphere().normal_at(point(-k, k, k));
    assert_vec_approx(n, vector(-k, k, k));
}

#[test]
fn the_normal_is_a_normalized_vector() {
    let k = 3f64.sqrt() / 3.0;
    let n = Object::sphere().normal_at(point(-k, k, k));
    assert_vec_approx(n, n.normalize());
}

#[test]
fn computing_the_normal_on_a_translated_sphere() {
    let mut s = Object::sphere();
    s.set_transform(translation(0.0, 1.0, 0.0));
    let n = s.normal_at(point(0.0, 1.70711, -0.70711));
    assert_vec_approx(n, vector(0.0, 0.70711, -0.70711));
}

#[test]
fn computing_the_normal_on_a_transformed_sphere() {
    let mut s = Object::sphere();
    let m = scaling(1.0, 0.5, 1.0) * rotation_z(PI / 5.0);
    s.set_transform(m);
    let k = 2f64.sqrt() / 2.0;
    let n = s.normal_at(point(0.0, k, -k));
    assert_vec_approx(n, vector(0.0, 0.97014, -0.24254));
}

#[test]
fn a_sphere_has_a_default_material() {
    assert_eq!(Object::sphere().material, Material::default());
}

#[test]
fn a_sphere_may_be_assigned_a_material() {
    let m = Material {
        ambient: 1.0,
        ..Material::default()
    };
    let s = Object::sphere().with_material(m.clone());
    assert_eq!(s.material, m);
}
