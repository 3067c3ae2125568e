//! Chapter 9: the shape abstraction. The book's `test_shape()` is any shape here: what it
//! records as `saved_ray` is the object-space ray, which `Object::ray_to_object` returns.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::math::{rotation_z, scaling, translation};
use rayforge::{point, vector, Material, Object, Ray};
use std::f64::consts::PI;

#[test]
fn the_default_transformation() {
    assert_eq!(Object::sphere().transform.matrix(), glam::DMat4::IDENTITY);
}

#[test]
fn assigning_a_transformation() {
    let mut s = Object::sphere();
    s.set_transform(translation(2.0, 3.0, 4.0));
    assert_eq!(s.transform.matrix(), translation(2.0, 3.0, 4.0));
}

#[test]
fn the_default_material() {
    assert_eq!(Object::sphere().material, Material::default());
}

#[test]
fn assigning_a_material() {
    let m = Material {
        ambient: 1.0,
        ..Material::default()
    };
    assert_eq!(Object::sphere().with_material(m.clone()).material, m);
}

#[test]
fn intersecting_a_scaled_shape_with_a_ray() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let s = Object::sphere().with_transform(scaling(2.0, 2.0, 2.0));
    let saved = s.ray_to_object(&r);
    assert_vec_approx(saved.origin, point(0.0, 0.0, -2.5));
    assert_vec_approx(saved.direction, vector(0.0, 0.0, 0.5));
}

#[test]
fn intersecting_a_translated_shape_with_a_ray() {
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let s = Object::sphere().with_transform(translation(5.0, 0.0, 0.0));
    let saved = s.ray_to_object(&r);
    assert_vec_approx(saved.origin, point(-5.0, 0.0, -5.0));
    assert_vec_approx(saved.direction, vector(0.0, 0.0, 1.0));
}

#[test]
fn computing_the_normal_on_a_translated_shape() {
    let s = Object::sphere().with_transform(translation(0.0, 1.0, 0.0));
    let n = s.normal_at(point(0.0, 1.70711, -0.70711));
    assert_vec_approx(n, vector(0.0, 0.70711, -0.70711));
}

#[test]
fn computing_the_normal_on_a_transformed_shape() {
    let s = Object::sphere().with_transform(scaling(1.0, 0.5, 1.0) * rotation_z(PI / 5.0));
    let k = 2f64.sqrt() / 2.0;
    assert_vec_approx(
        s.normal_at(point(0.0, k, -k)),
        vector(0.0, 0.97014, -0.24254),
    );
}
