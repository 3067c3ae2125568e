//! Chapter 4: matrix transformations.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use glam::DMat4;
use rayforge::math::{rotation_x, rotation_y, rotation_z, scaling, shearing, translation, Tuple};
use rayforge::{point, vector, Point3, Vec3};
use std::f64::consts::PI;

const HALF_SQRT2: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The book's `m * p` for a point: the full 4×4 product with the tuple `(x, y, z, 1)`, whose
/// result must still be a point. glam's `transform_point3`, which the renderer uses, must agree.
#[track_caller]
fn mul_point(m: DMat4, p: Point3) -> Point3 {
    let t = m * Tuple::point(p.x, p.y, p.z);
    assert_approx(t.w, 1.0);
    let product = point(t.x, t.y, t.z);
    assert_vec_approx(m.transform_point3(p), product);
    product
}

/// The book's `m * v` for a vector: the full 4×4 product with the tuple `(x, y, z, 0)`, whose
/// result must still be a vector. glam's `transform_vector3` must agree.
#[track_caller]
fn mul_vector(m: DMat4, v: Vec3) -> Vec3 {
    let t = m * Tuple::vector(v.x, v.y, v.z);
    assert_approx(t.w, 0.0);
    let product = vector(t.x, t.y, t.z);
    assert_vec_approx(m.transform_vector3(v), product);
    product
}

#[test]
fn multiplying_by_a_translation_matrix() {
    let transform = translation(5.0, -3.0, 2.0);
    let p = point(-3.0, 4.0, 5.0);
    assert_vec_approx(mul_point(transform, p), point(2.0, 1.0, 7.0));
}

#[test]
fn multiplying_by_the_inverse_of_a_translation_matrix() {
    let inv = translation(5.0, -3.0, 2.0).inverse();
    let p = point(-3.0, 4.0, 5.0);
    assert_vec_approx(mul_point(inv, p), point(-8.0, 7.0, 3.0));
}

#[test]
fn translation_does_not_affect_vectors() {
    let transform = translation(5.0, -3.0, 2.0);
    let v = vector(-3.0, 4.0, 5.0);
    assert_vec_approx(mul_vector(transform, v), v);
}

#[test]
fn a_scaling_matrix_applied_to_a_point() {
    let transform = scaling(2.0, 3.0, 4.0);
    assert_vec_approx(
        mul_point(transform, point(-4.0, 6.0, 8.0)),
        point(-8.0, 18.0, 32.0),
    );
}

#[test]
fn a_scaling_matrix_applied_to_a_vector() {
    let transform = scaling(2.0, 3.0, 4.0);
    assert_vec_approx(
        mul_vector(transform, vector(-4.0, 6.0, 8.0)),
        vector(-8.0, 18.0, 32.0),
    );
}

#[test]
fn multiplying_by_the_inverse_of_a_scaling_matrix() {
    let inv = scaling(2.0, 3.0, 4.0).inverse();
    assert_vec_approx(
        mul_vector(inv, vector(-4.0, 6.0, 8.0)),
        vector(-2.0, 2.0, 2.0),
    );
}

#[test]
fn reflection_is_scaling_by_a_negative_value() {
    let transform = scaling(-1.0, 1.0, 1.0);
    assert_vec_approx(
        mul_point(transform, point(2.0, 3.0, 4.0)),
        point(-2.0, 3.0, 4.0),
    );
}

#[test]
fn rotating_a_point_around_the_x_axis() {
    let p = point(0.0, 1.0, 0.0);
    let half_quarter = rotation_x(PI / 4.0);
    let full_quarter = rotation_x(PI / 2.0);
    assert_vec_approx(
        mul_point(half_quarter, p),
        point(0.0, HALF_SQRT2, HALF_SQRT2),
    );
    assert_vec_approx(mul_point(full_quarter, p), point(0.0, 0.0, 1.0));
}

/// SEED-NOTES.md erratum 1: the seed prints (0, -√2/2, -√2/2); the inverse rotation gives
/// (0, √2/2, -√2/2).
#[test]
fn the_inverse_of_an_x_rotation_rotates_in_the_opposite_direction() {
    let p = point(0.0, 1.0, 0.0);
    let inv = rotation_x(PI / 4.0).inverse();
    assert_vec_approx(mul_point(inv, p), point(0.0, HALF_SQRT2, -HALF_SQRT2));
}

#[test]
fn rotating_a_point_around_the_y_axis() {
    let p = point(0.0, 0.0, 1.0);
    assert_vec_approx(
        mul_point(rotation_y(PI / 4.0), p),
        point(HALF_SQRT2, 0.0, HALF_SQRT2),
    );
    assert_vec_approx(mul_point(rotation_y(PI / 2.0), p), point(1.0, 0.0, 0.0));
}

#[test]
fn rotating_a_point_around_the_z_axis() {
    let p = point(0.0, 1.0, 0.0);
    assert_vec_approx(
        mul_point(rotation_z(PI / 4.0), p),
        point(-HALF_SQRT2, HALF_SQRT2, 0.0),
    );
    assert_vec_approx(mul_point(rotation_z(PI / 2.0), p), point(-1.0, 0.0, 0.0));
}

fn shear(xy: f64, xz: f64, yx: f64, yz: f64, zx: f64, zy: f64) -> Point3 {
    mul_point(shearing(xy, xz, yx, yz, zx, zy), point(2.0, 3.0, 4.0))
}

#[test]
fn a_shearing_transformation_moves_x_in_proportion_to_y() {
    assert_vec_approx(shear(1.0, 0.0, 0.0, 0.0, 0.0, 0.0), point(5.0, 3.0, 4.0));
}

#[test]
fn a_shearing_transformation_moves_x_in_proportion_to_z() {
    assert_vec_approx(shear(0.0, 1.0, 0.0, 0.0, 0.0, 0.0), point(6.0, 3.0, 4.0));
}

#[test]
fn a_shearing_transformation_moves_y_in_proportion_to_x() {
    assert_vec_approx(shear(0.0, 0.0, 1.0, 0.0, 0.0, 0.0), point(2.0, 5.0, 4.0));
}

#[test]
fn a_shearing_transformation_moves_y_in_proportion_to_z() {
    assert_vec_approx(shear(0.0, 0.0, 0.0, 1.0, 0.0, 0.0), point(2.0, 7.0, 4.0));
}

#[test]
fn a_shearing_transformation_moves_z_in_proportion_to_x() {
    assert_vec_approx(shear(0.0, 0.0, 0.0, 0.0, 1.0, 0.0), point(2.0, 3.0, 6.0));
}

#[test]
fn a_shearing_transformation_moves_z_in_proportion_to_y() {
    assert_vec_approx(shear(0.0, 0.0, 0.0, 0.0, 0.0, 1.0), point(2.0, 3.0, 7.0));
}

#[test]
fn individual_transformations_are_applied_in_sequence() {
    let p = point(1.0, 0.0, 1.0);
    let a = rotation_x(PI / 2.0);
    let b = scaling(5.0, 5.0, 5.0);
    let c = translation(10.0, 5.0, 7.0);
    let p2 = mul_point(a, p);
    assert_vec_approx(p2, point(1.0, -1.0, 0.0));
    let p3 = mul_point(b, p2);
    assert_vec_approx(p3, point(5.0, -5.0, 0.0));
    let p4 = mul_point(c, p3);
    assert_vec_approx(p4, point(15.0, 0.0, 7.0));
}

#[test]
fn chained_transformations_must_be_applied_in_reverse_order() {
    let p = point(1.0, 0.0, 1.0);
    let t = translation(10.0, 5.0, 7.0) * scaling(5.0, 5.0, 5.0) * rotation_x(PI / 2.0);
    assert_vec_approx(mul_point(t, p), point(15.0, 0.0, 7.0));
}

/// Scaling-and-translation transforms take a shortcut (three products instead of nine): its
/// answers are those of the full affine inverse, exactly.
#[test]
fn axis_aligned_transforms_give_the_full_inverses_answers() {
    use glam::DAffine3;
    use rayforge::math::{scaling, translation};
    use rayforge::Transform;
    let mut k = 0.0f64;
    for _ in 0..500 {
        k += 0.618_033_988_75;
        let s = |a: f64| ((k * a).sin() * 3.0).abs() + 0.05;
        let matrix = translation((k * 7.1).sin() * 9.0, (k * 3.3).cos() * 4.0, k.sin())
            * scaling(s(1.3), -s(2.9), s(5.1));
        let t = Transform::new(matrix);
        let full = DAffine3::from_mat4(matrix).inverse();
        let p = glam::DVec3::new((k * 1.7).cos() * 5.0, (k * 2.3).sin() * 7.0, k.cos() - 0.5);
        assert_eq!(t.inverse_point(p), full.transform_point3(p));
        assert_eq!(t.inverse_vector(p), full.transform_vector3(p));
        assert_eq!(
            t.normal(p),
            (full.matrix3.transpose() * p).normalize_or_zero()
        );
    }
}
