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

/// The largest degree [`polynomial_roots_in`] handles: the torus needs a quartic.
pub const MAX_DEGREE: usize = 4;

/// Evaluates `Σ c[i]·tⁱ` by Horner's rule.
#[inline]
pub fn evaluate(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * t + ci)
}

/// The real roots of `Σ c[i]·tⁱ` (degree at most [`MAX_DEGREE`]) in `[lo, hi]`, ascending,
/// written to `out`; returns how many there are.
///
/// Closed-form quartic formulas (Ferrari's) lose most of their digits when two roots are close,
/// which is exactly the case of a ray grazing a torus. This solver instead isolates roots: the
/// real roots of the derivative split `[lo, hi]` into pieces on which the polynomial is monotonic,
/// so each piece holds at most one root, bracketed by a sign change, which a safeguarded Newton
/// iteration then pins to the last bit. A double root (a tangent ray) shows up as a critical point
/// where the polynomial is zero and is reported once.
pub fn polynomial_roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
    let mut degree = c.len().min(MAX_DEGREE + 1).saturating_sub(1);
    while degree > 0 && c[degree] == 0.0 {
        degree -= 1;
    }
    let c = &c[..=degree];
    if lo.is_nan() || hi.is_nan() || lo > hi || degree == 0 {
        return 0;
    }
    if degree == 1 {
        let t = -c[0] / c[1];
        return store_if_in(t, lo, hi, out, 0);
    }
    if degree == 2 {
        let mut n = 0;
        if let Some((t0, t1)) = solve_quadratic(c[2], c[1], c[0]) {
            n = store_if_in(t0, lo, hi, out, n);
            if t1 != t0 {
                n = store_if_in(t1, lo, hi, out, n);
            }
        }
        return n;
    }
    let mut derivative = [0.0; MAX_DEGREE];
    for i in 1..=degree {
        derivative[i - 1] = i as f64 * c[i];
    }
    let mut critical = [0.0; MAX_DEGREE];
    let n_critical = polynomial_roots_in(&derivative[..degree], lo, hi, &mut critical);

    let mut n = 0;
    let mut a = lo;
    let mut fa = evaluate(c, a);
    if fa == 0.0 {
        n = store_if_in(a, lo, hi, out, n);
    }
    for &b in critical[..n_critical].iter().chain(std::iter::once(&hi)) {
        let fb = evaluate(c, b);
        if fb == 0.0 {
            if n == 0 || out[n - 1] != b {
                n = store_if_in(b, lo, hi, out, n);
            }
        } else if fa != 0.0 && (fa < 0.0) != (fb < 0.0) {
            let root = refine(c, &derivative[..degree], a, b, fa);
            n = store_if_in(root, lo, hi, out, n);
        }
        a = b;
        fa = fb;
    }
    n
}

/// Appends `t` to `out[..n]` when it lies in `[lo, hi]` and there is room.
fn store_if_in(t: f64, lo: f64, hi: f64, out: &mut [f64; MAX_DEGREE], n: usize) -> usize {
    if t >= lo && t <= hi && n < MAX_DEGREE {
        out[n] = t;
        n + 1
    } else {
        n
    }
}

/// The one root in `(a, b)`, where the polynomial changes sign (`fa` is its value at `a`).
/// Newton steps from the bracket's middle, the bracket shrinking around the root at every step;
/// a step that would leave the bracket is replaced by bisection, so the iteration cannot diverge
/// and converges quadratically once it is close.
fn refine(c: &[f64], derivative: &[f64], mut a: f64, mut b: f64, fa: f64) -> f64 {
    let a_negative = fa < 0.0;
    let mut t = 0.5 * (a + b);
    for _ in 0..200 {
        let f = evaluate(c, t);
        if f == 0.0 {
            return t;
        }
        if (f < 0.0) == a_negative {
            a = t;
        } else {
            b = t;
        }
        let slope = evaluate(derivative, t);
        let newton = t - f / slope;
        let next = if newton > a && newton < b && slope != 0.0 {
            newton
        } else {
            0.5 * (a + b)
        };
        if (next - t).abs() <= 2.0 * f64::EPSILON * t.abs().max(1e-300) || b - a <= 1e-300 {
            return next;
        }
        t = next;
    }
    t
}
