//! Chapter 1 (Tuples, Points, and Vectors), chapter 2's colour scenarios and chapter 6's `reflect`
//! (all of the book's `features/tuples.feature`).
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::color::color;
use rayforge::math::{reflect, Tuple};
use rayforge::vector;

fn tuple(x: f64, y: f64, z: f64, w: f64) -> Tuple {
    Tuple::new(x, y, z, w)
}

#[track_caller]
fn assert_tuple(actual: Tuple, expected: Tuple) {
    for (a, e) in [
        (actual.x, expected.x),
        (actual.y, expected.y),
        (actual.z, expected.z),
        (actual.w, expected.w),
    ] {
        assert_approx(a, e);
    }
}

#[test]
fn a_tuple_with_w_1_is_a_point() {
    let a = tuple(4.3, -4.2, 3.1, 1.0);
    assert_eq!((a.x, a.y, a.z, a.w), (4.3, -4.2, 3.1, 1.0));
    assert!(a.is_point());
    assert!(!a.is_vector());
}

#[test]
fn a_tuple_with_w_0_is_a_vector() {
    let a = tuple(4.3, -4.2, 3.1, 0.0);
    assert_eq!((a.x, a.y, a.z, a.w), (4.3, -4.2, 3.1, 0.0));
    assert!(!a.is_point());
    assert!(a.is_vector());
}

#[test]
fn point_creates_tuples_with_w_1() {
    assert_eq!(Tuple::point(4.0, -4.0, 3.0), tuple(4.0, -4.0, 3.0, 1.0));
}

#[test]
fn vector_creates_tuples_with_w_0() {
    assert_eq!(Tuple::vector(4.0, -4.0, 3.0), tuple(4.0, -4.0, 3.0, 0.0));
}

#[test]
fn adding_two_tuples() {
    let a1 = tuple(3.0, -2.0, 5.0, 1.0);
    let a2 = tuple(-2.0, 3.0, 1.0, 0.0);
    assert_tuple(a1 + a2, tuple(1.0, 1.0, 6.0, 1.0));
}

#[test]
fn subtracting_two_points() {
    let p1 = Tuple::point(3.0, 2.0, 1.0);
    let p2 = Tuple::point(5.0, 6.0, 7.0);
    assert_tuple(p1 - p2, Tuple::vector(-2.0, -4.0, -6.0));
}

#[test]
fn subtracting_a_vector_from_a_point() {
    let p = Tuple::point(3.0, 2.0, 1.0);
    let v = Tuple::vector(5.0, 6.0, 7.0);
    assert_tuple(p - v, Tuple::point(-2.0, -4.0, -6.0));
}

#[test]
fn subtracting_two_vectors() {
    let v1 = Tuple::vector(3.0, 2.0, 1.0);
    let v2 = Tuple::vector(5.0, 6.0, 7.0);
    assert_tuple(v1 - v2, Tuple::vector(-2.0, -4.0, -6.0));
}

#[test]
fn subtracting_a_vector_from_the_zero_vector() {
    let zero = Tuple::vector(0.0, 0.0, 0.0);
    let v = Tuple::vector(1.0, -2.0, 3.0);
    assert_tuple(zero - v, Tuple::vector(-1.0, 2.0, -3.0));
}

#[test]
fn negating_a_tuple() {
    let a = tuple(1.0, -2.0, 3.0, -4.0);
    assert_tuple(-a, tuple(-1.0, 2.0, -3.0, 4.0));
}

#[test]
fn multiplying_a_tuple_by_a_scalar() {
    let a = tuple(1.0, -2.0, 3.0, -4.0);
    assert_tuple(a * 3.5, tuple(3.5, -7.0, 10.5, -14.0));
}

#[test]
fn multiplying_a_tuple_by_a_fraction() {
    let a = tuple(1.0, -2.0, 3.0, -4.0);
    assert_tuple(a * 0.5, tuple(0.5, -1.0, 1.5, -2.0));
}

#[test]
fn dividing_a_tuple_by_a_scalar() {
    let a = tuple(1.0, -2.0, 3.0, -4.0);
    assert_tuple(a / 2.0, tuple(0.5, -1.0, 1.5, -2.0));
}

#[test]
fn computing_the_magnitude_of_vector_1_0_0() {
    assert_approx(Tuple::vector(1.0, 0.0, 0.0).magnitude(), 1.0);
}

#[test]
fn computing_the_magnitude_of_vector_0_1_0() {
    assert_approx(Tuple::vector(0.0, 1.0, 0.0).magnitude(), 1.0);
}

#[test]
fn computing_the_magnitude_of_vector_0_0_1() {
    assert_approx(Tuple::vector(0.0, 0.0, 1.0).magnitude(), 1.0);
}

#[test]
fn computing_the_magnitude_of_vector_1_2_3() {
    assert_approx(Tuple::vector(1.0, 2.0, 3.0).magnitude(), 14f64.sqrt());
}

#[test]
fn computing_the_magnitude_of_vector_neg_1_neg_2_neg_3() {
    assert_approx(Tuple::vector(-1.0, -2.0, -3.0).magnitude(), 14f64.sqrt());
}

#[test]
fn normalizing_vector_4_0_0_gives_1_0_0() {
    assert_tuple(
        Tuple::vector(4.0, 0.0, 0.0).normalize(),
        Tuple::vector(1.0, 0.0, 0.0),
    );
}

#[test]
fn normalizing_vector_1_2_3() {
    assert_tuple(
        Tuple::vector(1.0, 2.0, 3.0).normalize(),
        Tuple::vector(0.26726, 0.53452, 0.80178),
    );
}

#[test]
fn the_magnitude_of_a_normalized_vector() {
    let norm = Tuple::vector(1.0, 2.0, 3.0).normalize();
    assert_approx(norm.magnitude(), 1.0);
}

#[test]
fn the_dot_product_of_two_tuples() {
    let a = Tuple::vector(1.0, 2.0, 3.0);
    let b = Tuple::vector(2.0, 3.0, 4.0);
    assert_approx(a.dot(b), 20.0);
}

#[test]
fn the_cross_product_of_two_vectors() {
    let a = Tuple::vector(1.0, 2.0, 3.0);
    let b = Tuple::vector(2.0, 3.0, 4.0);
    assert_tuple(a.cross(b), Tuple::vector(-1.0, 2.0, -1.0));
    assert_tuple(b.cross(a), Tuple::vector(1.0, -2.0, 1.0));
}

#[test]
fn colors_are_red_green_blue_tuples() {
    let c = color(-0.5, 0.4, 1.7);
    assert_eq!((c.red, c.green, c.blue), (-0.5, 0.4, 1.7));
}

#[test]
fn adding_colors() {
    let c1 = color(0.9, 0.6, 0.75);
    let c2 = color(0.7, 0.1, 0.25);
    assert_color_approx(c1 + c2, color(1.6, 0.7, 1.0));
}

#[test]
fn subtracting_colors() {
    let c1 = color(0.9, 0.6, 0.75);
    let c2 = color(0.7, 0.1, 0.25);
    assert_color_approx(c1 - c2, color(0.2, 0.5, 0.5));
}

#[test]
fn multiplying_a_color_by_a_scalar() {
    assert_color_approx(color(0.2, 0.3, 0.4) * 2.0, color(0.4, 0.6, 0.8));
}

#[test]
fn multiplying_colors() {
    let c1 = color(1.0, 0.2, 0.4);
    let c2 = color(0.9, 1.0, 0.1);
    assert_color_approx(c1 * c2, color(0.9, 0.2, 0.04));
}

#[test]
fn reflecting_a_vector_approaching_at_45() {
    let v = vector(1.0, -1.0, 0.0);
    let n = vector(0.0, 1.0, 0.0);
    assert_vec_approx(reflect(v, n), vector(1.0, 1.0, 0.0));
}

#[test]
fn reflecting_a_vector_off_a_slanted_surface() {
    let k = 2f64.sqrt() / 2.0;
    let v = vector(0.0, -1.0, 0.0);
    let n = vector(k, k, 0.0);
    assert_vec_approx(reflect(v, n), vector(1.0, 0.0, 0.0));
}
