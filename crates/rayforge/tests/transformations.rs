//! Chapter 4: matrix transformations.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::math::{rotation_x, rotation_y, rotation_z, scaling, shearing, translation};
use rayforge::{point, vector};
use std::f64::consts::PI;

const HALF_SQRT2: f64 = std::f64::consts::FRAC_1_SQRT_2;

#[test]
fn multiplying_by_a_translation_matrix() {
    let transform = translation(5.0, -3.0, 2.0);
    let p = point(-3.0, 4.0, 5.0);
    assert_vec_approx(transform.transform_point3(p), point(2.0, 1.0, 7.0));
}

#[test]
fn multiplying_by_the_inverse_of_a_translation_matrix() {
    let inv = translation(5.0, -3.0, 2.0).inverse();
    let p = point(-3.0, 4.0, 5.0);
    assert_vec_approx(inv.transform_point3(p), point(-8.0, 7.0, 3.0));
}

#[test]
fn translation_does_not_affect_vectors() {
    let transform = translation(5.0, -3.0, 2.0);
    let v = vector(-3.0, 4.0, 5.0);
    assert_vec_approx(transform.transform_vector3(v), v);
}

#[test]
fn a_scaling_matrix_applied_to_a_point() {
    let transform = scaling(2.0, 3.0, 4.0);
    assert_vec_approx(
        transform.transform_point3(point(-4.0, 6.0, 8.0)),
        point(-8.0, 18.0, 32.0),
    );
}

#[test]
fn a_scaling_matrix_applied_to_a_vector() {
    let transform = scaling(2.0, 3.0, 4.0);
    assert_vec_approx(
        transform.transform_vector3(vector(-4.0, 6.0, 8.0)),
        vector(-8.0, 18.0, 32.0),
    );
}

#[test]
fn multiplying_by_the_inverse_of_a_scaling_matrix() {
    let inv = scaling(2.0, 3.0, 4.0).inverse();
    assert_vec_approx(
        inv.transform_vector3(vector(-4.0, 6.0, 8.0)),
        vector(-2.0, 2.0, 2.0),
    );
}

#[test]
fn reflection_is_scaling_by_a_negative_value() {
    let transform = scaling(-1.0, 1.0, 1.0);
    assert_vec_approx(
        transform.transform_point3(point(2.0, 3.0, 4.0)),
        point(-2.0, 3.0, 4.0),
    );
}

#[test]
fn rotating_a_point_around_the_x_axis() {
    let p = point(0.0, 1.0, 0.0);
    let half_quarter = rotation_x(PI / 4.0);
    let full_quarter = rotation_x(PI / 2.0);
    assert_vec_approx(
        half_quarter.transform_point3(p),
        point(0.0, HALF_SQRT2, HALF_SQRT2),
    );
    assert_vec_approx(full_quarter.transform_point3(p), point(0.0, 0.0, 1.0));
}

/// SEED-NOTES.md erratum 1: the seed prints (0, -√2/2, -√2/2); the inverse rotation gives
/// (0, √2/2, -√2/2).
#[test]
fn the_inverse_of_an_x_rotation_rotates_in_the_opposite_direction() {
    let p = point(0.0, 1.0, 0.0);
    let inv = rotation_x(PI / 4.0).inverse();
    assert_vec_approx(inv.transform_point3(p), point(0.0, HALF_SQRT2, -HALF_SQRT2));
}

#[test]
fn rotating_a_point_around_the_y_axis() {
    let p = point(0.0, 0.0, 1.0);
    assert_vec_approx(
        rotation_y(PI / 4.0).transform_point3(p),
        point(HALF_SQRT2, 0.0, HALF_SQRT2),
    );
    assert_vec_approx(
        rotation_y(PI / 2.0).transform_point3(p),
        point(1.0, 0.0, 0.0),
    );
}

#[test]
fn rotating_a_point_around_the_z_axis() {
    let p = point(0.0, 1.0, 0.0);
    assert_vec_approx(
        rotation_z(PI / 4.0).transform_point3(p),
        point(-HALF_SQRT2, HALF_SQRT2, 0.0),
    );
    assert_vec_approx(
        rotation_z(PI / 2.0).transform_point3(p),
        point(-1.0, 0.0, 0.0),
    );
}

fn shear(xy: f64, xz: f64, yx: f64, yz: f64, zx: f64, zy: f64) -> rayforge::Point3 {
    shearing(xy, xz, yx, yz, zx, zy).transform_point3(point(2.0, 3.0, 4.0))
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
    let p2 = a.transform_point3(p);
    assert_vec_approx(p2, point(1.0, -1.0, 0.0));
    let p3 = b.transform_point3(p2);
    assert_vec_approx(p3, point(5.0, -5.0, 0.0));
    let p4 = c.transform_point3(p3);
    assert_vec_approx(p4, point(15.0, 0.0, 7.0));
}

#[test]
fn chained_transformations_must_be_applied_in_reverse_order() {
    let p = point(1.0, 0.0, 1.0);
    let t = translation(10.0, 5.0, 7.0) * scaling(5.0, 5.0, 5.0) * rotation_x(PI / 2.0);
    assert_vec_approx(t.transform_point3(p), point(15.0, 0.0, 7.0));
}
