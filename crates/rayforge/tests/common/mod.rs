//! Helpers shared by the book's scenario tests: float comparison with the book's tolerance.
#![allow(dead_code)]

use rayforge::{Color, Vec3};

/// The book compares floats with this tolerance (SEED-NOTES.md).
pub const TOLERANCE: f64 = 1e-4;

/// Asserts two floats agree within the book's tolerance.
#[track_caller]
pub fn assert_approx(actual: f64, expected: f64) {
    assert!(
        (actual - expected).abs() < TOLERANCE,
        "expected {expected}, got {actual}"
    );
}

/// Asserts two points or vectors agree component-wise within the book's tolerance.
#[track_caller]
pub fn assert_vec_approx(actual: Vec3, expected: Vec3) {
    assert!(
        (actual - expected).abs().max_element() < TOLERANCE,
        "expected {expected:?}, got {actual:?}"
    );
}

/// Asserts two colours agree channel-wise within the book's tolerance.
#[track_caller]
pub fn assert_color_approx(actual: Color, expected: Color) {
    let diff = actual - expected;
    assert!(
        diff.red.abs() < TOLERANCE && diff.green.abs() < TOLERANCE && diff.blue.abs() < TOLERANCE,
        "expected {expected:?}, got {actual:?}"
    );
}

/// Asserts two 4×4 matrices agree element-wise within the book's tolerance.
#[track_caller]
pub fn assert_matrix_approx(actual: glam::DMat4, expected: glam::DMat4) {
    assert!(
        actual.abs_diff_eq(expected, TOLERANCE),
        "expected {expected:?}, got {actual:?}"
    );
}

/// One test per row of a scenario outline: `scenario_rows! { check; name: args…; … }` defines
/// `#[test] fn name() { check(args…) }` for each row.
#[macro_export]
macro_rules! scenario_rows {
    ($check:ident; $($name:ident: $($arg:expr),*;)*) => {$(
        #[test]
        fn $name() {
            $check($($arg),*);
        }
    )*};
}

/// The book's `local_intersect(shape, ray)` for a ray with the direction normalised, as the
/// scenario outlines write it: every `t`, sorted.
pub fn local_ts(shape: &rayforge::Shape, origin: rayforge::Point3, direction: Vec3) -> Vec<f64> {
    let mut ts = Vec::new();
    shape.intersect(&rayforge::Ray::new(origin, direction.normalize()), |t| {
        ts.push(t)
    });
    ts.sort_by(f64::total_cmp);
    ts
}
