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
/// written to `out`; returns how many there are. A double root is reported once.
///
/// Cubics and quartics are solved in closed form (Cardano's and Ferrari's methods, in real
/// arithmetic) and every root is then polished by Newton steps on the original polynomial. The
/// closed forms alone lose digits where two roots are close (a ray grazing a torus), but they put
/// each root well inside its basin of attraction, so the polish brings it back to the rounding
/// level of the polynomial itself in a step or two; iterating from a bracket instead costs about
/// ten steps a root, which made the solver most of the time of a torus scene.
pub fn polynomial_roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
    let mut degree = c.len().min(MAX_DEGREE + 1).saturating_sub(1);
    while degree > 0 && c[degree] == 0.0 {
        degree -= 1;
    }
    let c = &c[..=degree];
    if lo.is_nan() || hi.is_nan() || lo > hi || degree == 0 {
        return 0;
    }
    let mut roots = [0.0; MAX_DEGREE];
    let found = match degree {
        1 => {
            roots[0] = -c[0] / c[1];
            1
        }
        2 => match solve_quadratic(c[2], c[1], c[0]) {
            Some((t0, t1)) => {
                roots[0] = t0;
                roots[1] = t1;
                2
            }
            None => 0,
        },
        3 => {
            let (a, b, cc) = (c[2] / c[3], c[1] / c[3], c[0] / c[3]);
            let shift = a / 3.0;
            let (depressed, n) =
                depressed_cubic_roots(b - a * shift, cc - b * shift + 2.0 * shift * shift * shift);
            for (root, z) in roots.iter_mut().zip(&depressed[..n]) {
                *root = z - shift;
            }
            n
        }
        _ => quartic_roots(c, &mut roots),
    };
    if degree >= 3 {
        let mut derivative = [0.0; MAX_DEGREE];
        for i in 1..=degree {
            derivative[i - 1] = i as f64 * c[i];
        }
        for root in &mut roots[..found] {
            *root = polish(c, &derivative[..degree], *root);
        }
    }
    let mut n = 0;
    for &t in &roots[..found] {
        if t >= lo && t <= hi {
            // Insertion keeps `out` ascending; an equal root (a double one) is kept once.
            let mut i = n;
            while i > 0 && out[i - 1] > t {
                out[i] = out[i - 1];
                i -= 1;
            }
            if i > 0 && out[i - 1] == t {
                out.copy_within(i + 1..=n, i);
                continue;
            }
            out[i] = t;
            n += 1;
        }
    }
    n
}

/// The real roots of `z³ + p·z + q`, the largest first: one (Cardano's formula, written so that
/// its two cube roots never cancel) or three (the trigonometric form).
fn depressed_cubic_roots(p: f64, q: f64) -> ([f64; 3], usize) {
    let half_q = 0.5 * q;
    let third_p = p / 3.0;
    let discriminant = half_q * half_q + third_p * third_p * third_p;
    if discriminant > 0.0 || p >= 0.0 {
        let u = (-half_q - discriminant.max(0.0).sqrt().copysign(half_q)).cbrt();
        let z = if u == 0.0 { 0.0 } else { u - third_p / u };
        return ([z, z, z], 1);
    }
    let radius = 2.0 * (-third_p).sqrt();
    let angle = ((3.0 * q) / (p * radius)).clamp(-1.0, 1.0).acos() / 3.0;
    let (sin, cos) = angle.sin_cos();
    let (cos_third, sin_third) = (-0.5, 0.5 * 3.0_f64.sqrt());
    (
        [
            radius * cos,
            radius * (cos * cos_third + sin * sin_third),
            radius * (cos * cos_third - sin * sin_third),
        ],
        3,
    )
}

/// Ferrari's method: the real roots of the quartic `c` (degree exactly 4) written to `roots`,
/// unpolished and in no order; returns how many.
///
/// The quartic, made monic and depressed (`u⁴ + p·u² + q·u + r`, `t = u − c₃/4c₄`), is the
/// difference of two squares `(u² + p/2 + m)² − (w·u − q/2w)²` with `w = √2m` once `m` is a
/// root of the resolvent cubic `m³ + p·m² + (p²/4 − r)·m − q²/8`; the largest root is used,
/// which is positive and keeps `q/2w` small. Its two quadratic factors give the roots.
fn quartic_roots(c: &[f64], roots: &mut [f64; MAX_DEGREE]) -> usize {
    let (a3, a2, a1, a0) = (c[3] / c[4], c[2] / c[4], c[1] / c[4], c[0] / c[4]);
    let shift = 0.25 * a3;
    let shift2 = shift * shift;
    let p = a2 - 6.0 * shift2;
    let q = a1 - 2.0 * a2 * shift + 8.0 * shift2 * shift;
    let r = a0 - a1 * shift + a2 * shift2 - 3.0 * shift2 * shift2;
    let mut n = 0;
    let mut push = |u: f64| {
        roots[n] = u - shift;
        n += 1;
    };
    let resolvent = [-0.125 * q * q, 0.25 * p * p - r, p, 1.0];
    let (depressed, _) = depressed_cubic_roots(
        -p * p / 12.0 - r,
        -p * p * p / 108.0 + p * r / 3.0 - 0.125 * q * q,
    );
    let m = polish(
        &resolvent,
        &[resolvent[1], 2.0 * p, 3.0],
        depressed[0] - p / 3.0,
    );
    if q == 0.0 || m <= 0.0 {
        // A biquadratic (or one whose odd term is lost in rounding): u² solves z² + p·z + r.
        if let Some((z0, z1)) = solve_quadratic(1.0, p, r) {
            for z in [z0, z1] {
                if z >= 0.0 {
                    let u = z.sqrt();
                    push(u);
                    push(-u);
                }
            }
        }
        return n;
    }
    let w = (2.0 * m).sqrt();
    let offset = q / (2.0 * w);
    let base = 0.5 * p + m;
    for (b, constant) in [(-w, base + offset), (w, base - offset)] {
        if let Some((u0, u1)) = solve_quadratic(1.0, b, constant) {
            push(u0);
            push(u1);
        }
    }
    n
}

/// Newton steps on `c` (whose derivative is `derivative`) from `t`. A step below a billionth of
/// `|t|` ends the polish: convergence is quadratic, so what it leaves is below the rounding of
/// `c` itself. A larger step is taken only if it lowers `|c(t)|`, so a poor estimate next to a
/// double root stops where rounding takes over instead of wandering off.
fn polish(c: &[f64], derivative: &[f64], mut t: f64) -> f64 {
    let mut f = evaluate(c, t);
    for _ in 0..8 {
        let slope = evaluate(derivative, t);
        if f == 0.0 || slope == 0.0 {
            break;
        }
        let step = f / slope;
        let next = t - step;
        if step.abs() <= 1e-9 * t.abs() {
            return next;
        }
        let f_next = evaluate(c, next);
        // Not lower (or a NaN): rounding has taken over.
        if f_next.abs().partial_cmp(&f.abs()) != Some(std::cmp::Ordering::Less) {
            break;
        }
        t = next;
        f = f_next;
    }
    t
}
