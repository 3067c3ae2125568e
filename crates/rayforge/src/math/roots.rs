//! Polynomial root solvers shared by the quadric shapes.

/// Real roots of `a·t² + b·t + c = 0`, smaller first, or `None` when there are none.
///
/// Uses the cancellation-free form (`q = -(b + sign(b)·√Δ)/2`, roots `q/a` and `c/q`) so that
/// rays far from a small sphere keep full precision in the near root.
#[inline]
pub fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    let discriminant = b * b - 4.0 * a * c;
    if discriminant < 0.0 || a == 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    let q = -0.5 * (b + root.copysign(b));
    if q == 0.0 {
        // b and the discriminant are both zero: one double root at -b/2a = 0.
        return Some((0.0, 0.0));
    }
    let (t0, t1) = (q / a, c / q);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}
