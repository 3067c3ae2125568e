//! Chapter 3: matrices.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use glam::{DMat2, DMat3, DMat4};
use rayforge::math::{matrix2, matrix3, matrix4, BookMatrix, Tuple};

#[test]
fn constructing_and_inspecting_a_4x4_matrix() {
    let m = matrix4([
        [1.0, 2.0, 3.0, 4.0],
        [5.5, 6.5, 7.5, 8.5],
        [9.0, 10.0, 11.0, 12.0],
        [13.5, 14.5, 15.5, 16.5],
    ]);
    assert_eq!(m.at(0, 0), 1.0);
    assert_eq!(m.at(0, 3), 4.0);
    assert_eq!(m.at(1, 0), 5.5);
    assert_eq!(m.at(1, 2), 7.5);
    assert_eq!(m.at(2, 2), 11.0);
    assert_eq!(m.at(3, 0), 13.5);
    assert_eq!(m.at(3, 2), 15.5);
}

#[test]
fn a_2x2_matrix_ought_to_be_representable() {
    let m = matrix2([[-3.0, 5.0], [1.0, -2.0]]);
    assert_eq!(m.at(0, 0), -3.0);
    assert_eq!(m.at(0, 1), 5.0);
    assert_eq!(m.at(1, 0), 1.0);
    assert_eq!(m.at(1, 1), -2.0);
}

#[test]
fn a_3x3_matrix_ought_to_be_representable() {
    let m = matrix3([[-3.0, 5.0, 0.0], [1.0, -2.0, -7.0], [0.0, 1.0, 1.0]]);
    assert_eq!(m.at(0, 0), -3.0);
    assert_eq!(m.at(1, 1), -2.0);
    assert_eq!(m.at(2, 2), 1.0);
}

fn sequence_matrix() -> DMat4 {
    matrix4([
        [1.0, 2.0, 3.0, 4.0],
        [5.0, 6.0, 7.0, 8.0],
        [9.0, 8.0, 7.0, 6.0],
        [5.0, 4.0, 3.0, 2.0],
    ])
}

#[test]
fn matrix_equality_with_identical_matrices() {
    assert!(sequence_matrix().abs_diff_eq(sequence_matrix(), TOLERANCE));
}

#[test]
fn matrix_equality_with_different_matrices() {
    let b = matrix4([
        [2.0, 3.0, 4.0, 5.0],
        [6.0, 7.0, 8.0, 9.0],
        [8.0, 7.0, 6.0, 5.0],
        [4.0, 3.0, 2.0, 1.0],
    ]);
    assert!(!sequence_matrix().abs_diff_eq(b, TOLERANCE));
}

#[test]
fn multiplying_two_matrices() {
    let b = matrix4([
        [-2.0, 1.0, 2.0, 3.0],
        [3.0, 2.0, 1.0, -1.0],
        [4.0, 3.0, 6.0, 5.0],
        [1.0, 2.0, 7.0, 8.0],
    ]);
    let expected = matrix4([
        [20.0, 22.0, 50.0, 48.0],
        [44.0, 54.0, 114.0, 108.0],
        [40.0, 58.0, 110.0, 102.0],
        [16.0, 26.0, 46.0, 42.0],
    ]);
    assert_matrix_approx(sequence_matrix() * b, expected);
}

#[test]
fn a_matrix_multiplied_by_a_tuple() {
    let a = matrix4([
        [1.0, 2.0, 3.0, 4.0],
        [2.0, 4.0, 4.0, 2.0],
        [8.0, 6.0, 4.0, 1.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    let b = Tuple::new(1.0, 2.0, 3.0, 1.0);
    assert_eq!(a * b, Tuple::new(18.0, 24.0, 33.0, 1.0));
}

#[test]
fn multiplying_a_matrix_by_the_identity_matrix() {
    let a = matrix4([
        [0.0, 1.0, 2.0, 4.0],
        [1.0, 2.0, 4.0, 8.0],
        [2.0, 4.0, 8.0, 16.0],
        [4.0, 8.0, 16.0, 32.0],
    ]);
    assert_matrix_approx(a * DMat4::IDENTITY, a);
}

#[test]
fn multiplying_the_identity_matrix_by_a_tuple() {
    let a = Tuple::new(1.0, 2.0, 3.0, 4.0);
    assert_eq!(DMat4::IDENTITY * a, a);
}

#[test]
fn transposing_a_matrix() {
    let a = matrix4([
        [0.0, 9.0, 3.0, 0.0],
        [9.0, 8.0, 0.0, 8.0],
        [1.0, 8.0, 5.0, 3.0],
        [0.0, 0.0, 5.0, 8.0],
    ]);
    let expected = matrix4([
        [0.0, 9.0, 1.0, 0.0],
        [9.0, 8.0, 8.0, 0.0],
        [3.0, 0.0, 5.0, 5.0],
        [0.0, 8.0, 3.0, 8.0],
    ]);
    assert_matrix_approx(a.transpose(), expected);
}

#[test]
fn transposing_the_identity_matrix() {
    assert_eq!(DMat4::IDENTITY.transpose(), DMat4::IDENTITY);
}

#[test]
fn calculating_the_determinant_of_a_2x2_matrix() {
    let a = matrix2([[1.0, 5.0], [-3.0, 2.0]]);
    assert_approx(a.book_determinant(), 17.0);
    assert_approx(a.determinant(), 17.0);
}

#[test]
fn a_submatrix_of_a_3x3_matrix_is_a_2x2_matrix() {
    let a = matrix3([[1.0, 5.0, 0.0], [-3.0, 2.0, 7.0], [0.0, 6.0, -3.0]]);
    let expected: DMat2 = matrix2([[-3.0, 2.0], [0.0, 6.0]]);
    assert_eq!(a.submatrix(0, 2), expected);
}

#[test]
fn a_submatrix_of_a_4x4_matrix_is_a_3x3_matrix() {
    let a = matrix4([
        [-6.0, 1.0, 1.0, 6.0],
        [-8.0, 5.0, 8.0, 6.0],
        [-1.0, 0.0, 8.0, 2.0],
        [-7.0, 1.0, -1.0, 1.0],
    ]);
    let expected: DMat3 = matrix3([[-6.0, 1.0, 6.0], [-8.0, 8.0, 6.0], [-7.0, -1.0, 1.0]]);
    assert_eq!(a.submatrix(2, 1), expected);
}

fn minor_matrix() -> DMat3 {
    matrix3([[3.0, 5.0, 0.0], [2.0, -1.0, -7.0], [6.0, -1.0, 5.0]])
}

#[test]
fn calculating_a_minor_of_a_3x3_matrix() {
    let a = minor_matrix();
    let b = a.submatrix(1, 0);
    assert_approx(b.book_determinant(), 25.0);
    assert_approx(a.minor(1, 0), 25.0);
}

#[test]
fn calculating_a_cofactor_of_a_3x3_matrix() {
    let a = minor_matrix();
    assert_approx(a.minor(0, 0), -12.0);
    assert_approx(a.cofactor(0, 0), -12.0);
    assert_approx(a.minor(1, 0), 25.0);
    assert_approx(a.cofactor(1, 0), -25.0);
}

#[test]
fn calculating_the_determinant_of_a_3x3_matrix() {
    let a = matrix3([[1.0, 2.0, 6.0], [-5.0, 8.0, -4.0], [2.0, 6.0, 4.0]]);
    assert_approx(a.cofactor(0, 0), 56.0);
    assert_approx(a.cofactor(0, 1), 12.0);
    assert_approx(a.cofactor(0, 2), -46.0);
    assert_approx(a.book_determinant(), -196.0);
    assert_approx(a.determinant(), -196.0);
}

#[test]
fn calculating_the_determinant_of_a_4x4_matrix() {
    let a = matrix4([
        [-2.0, -8.0, 3.0, 5.0],
        [-3.0, 1.0, 7.0, 3.0],
        [1.0, 2.0, -9.0, 6.0],
        [-6.0, 7.0, 7.0, -9.0],
    ]);
    assert_approx(a.cofactor(0, 0), 690.0);
    assert_approx(a.cofactor(0, 1), 447.0);
    assert_approx(a.cofactor(0, 2), 210.0);
    assert_approx(a.cofactor(0, 3), 51.0);
    assert_approx(a.book_determinant(), -4071.0);
    assert_approx(a.determinant(), -4071.0);
}

#[test]
fn testing_an_invertible_matrix_for_invertibility() {
    let a = matrix4([
        [6.0, 4.0, 4.0, 4.0],
        [5.0, 5.0, 7.0, 6.0],
        [4.0, -9.0, 3.0, -7.0],
        [9.0, 1.0, 7.0, -6.0],
    ]);
    assert_approx(a.book_determinant(), -2120.0);
    assert!(rayforge::Transform::try_new(a).is_ok());
}

#[test]
fn testing_a_noninvertible_matrix_for_invertibility() {
    let a = matrix4([
        [-4.0, 2.0, -2.0, -3.0],
        [9.0, 6.0, 2.0, 6.0],
        [0.0, -5.0, 1.0, -5.0],
        [0.0, 0.0, 0.0, 0.0],
    ]);
    assert_approx(a.book_determinant(), 0.0);
    assert!(rayforge::Transform::try_new(a).is_err());
}

#[test]
fn calculating_the_inverse_of_a_matrix() {
    let a = matrix4([
        [-5.0, 2.0, 6.0, -8.0],
        [1.0, -5.0, 1.0, 8.0],
        [7.0, 7.0, -6.0, -7.0],
        [1.0, -3.0, 7.0, 4.0],
    ]);
    let b = a.inverse();
    assert_approx(a.book_determinant(), 532.0);
    assert_approx(a.cofactor(2, 3), -160.0);
    assert_approx(b.at(3, 2), -160.0 / 532.0);
    assert_approx(a.cofactor(3, 2), 105.0);
    assert_approx(b.at(2, 3), 105.0 / 532.0);
    let expected = matrix4([
        [0.21805, 0.45113, 0.24060, -0.04511],
        [-0.80827, -1.45677, -0.44361, 0.52068],
        [-0.07895, -0.22368, -0.05263, 0.19737],
        [-0.52256, -0.81391, -0.30075, 0.30639],
    ]);
    assert_matrix_approx(b, expected);
}

#[test]
fn calculating_the_inverse_of_another_matrix() {
    let a = matrix4([
        [8.0, -5.0, 9.0, 2.0],
        [7.0, 5.0, 6.0, 1.0],
        [-6.0, 0.0, 9.0, 6.0],
        [-3.0, 0.0, -9.0, -4.0],
    ]);
    let expected = matrix4([
        [-0.15385, -0.15385, -0.28205, -0.53846],
        [-0.07692, 0.12308, 0.02564, 0.03077],
        [0.35897, 0.35897, 0.43590, 0.92308],
        [-0.69231, -0.69231, -0.76923, -1.92308],
    ]);
    assert_matrix_approx(a.inverse(), expected);
}

#[test]
fn calculating_the_inverse_of_a_third_matrix() {
    let a = matrix4([
        [9.0, 3.0, 0.0, 9.0],
        [-5.0, -2.0, -6.0, -3.0],
        [-4.0, 9.0, 6.0, 4.0],
        [-7.0, 6.0, 6.0, 2.0],
    ]);
    let expected = matrix4([
        [-0.04074, -0.07778, 0.14444, -0.22222],
        [-0.07778, 0.03333, 0.36667, -0.33333],
        [-0.02901, -0.14630, -0.10926, 0.12963],
        [0.17778, 0.06667, -0.26667, 0.33333],
    ]);
    assert_matrix_approx(a.inverse(), expected);
}

#[test]
fn multiplying_a_product_by_its_inverse() {
    let a = matrix4([
        [3.0, -9.0, 7.0, 3.0],
        [3.0, -8.0, 2.0, -9.0],
        [-4.0, 4.0, 4.0, 1.0],
        [-6.0, 5.0, -1.0, 1.0],
    ]);
    let b = matrix4([
        [8.0, 2.0, 2.0, 2.0],
        [3.0, -1.0, 7.0, 0.0],
        [7.0, 0.0, 5.0, 4.0],
        [6.0, -2.0, 0.0, 5.0],
    ]);
    let c = a * b;
    assert_matrix_approx(c * b.inverse(), a);
}
