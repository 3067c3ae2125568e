//! The double-napped cone x² + z² = y² (chapter 13): infinite, truncated, or capped.

use super::cylinder::caps;
use crate::math::{roots::solve_quadratic, sin_cos_turns, Point3, Ray, Vec3, EPSILON};
use std::f64::consts::{PI, SQRT_2};

/// Side hits within `minimum < y < maximum`, then cap hits (discs of radius |y|).
pub fn intersect(ray: &Ray, minimum: f64, maximum: f64, closed: bool, mut hit: impl FnMut(f64)) {
    let (o, d) = (ray.origin, ray.direction);
    let a = d.x * d.x - d.y * d.y + d.z * d.z;
    let b = 2.0 * (o.x * d.x - o.y * d.y + o.z * d.z);
    let c = o.x * o.x - o.y * o.y + o.z * o.z;
    let mut side = |t: f64| {
        let y = o.y + t * d.y;
        if minimum < y && y < maximum {
            hit(t);
        }
    };
    if a.abs() < EPSILON {
        // Parallel to one half: the quadratic degenerates to b·t + c = 0, one root at -c/b.
        // (SEED-NOTES.md erratum 5: the book prints -c/(2b), which lies off the cone.)
        if b.abs() >= EPSILON {
            side(-c / b);
        }
    } else if let Some((t0, t1)) = solve_quadratic(a, b, c) {
        side(t0);
        side(t1);
    }
    if closed {
        caps(ray, minimum, maximum, f64::abs, hit);
    }
}

/// Outward on the sides; ±y on the caps. At the apex the normal is the zero vector (the
/// book's answer; there is no tangent plane there).
pub fn normal_at(point: Point3, minimum: f64, maximum: f64) -> Vec3 {
    let dist = point.x * point.x + point.z * point.z;
    if dist < maximum * maximum && point.y >= maximum - EPSILON {
        Vec3::Y
    } else if dist < minimum * minimum && point.y <= minimum + EPSILON {
        Vec3::NEG_Y
    } else {
        let mut y = dist.sqrt();
        if point.y > 0.0 {
            y = -y;
        }
        Vec3::new(point.x, y, point.z)
    }
}

/// `y·|y|`: the area of the cone x² + z² = y² up to height `y` grows with it (the side's
/// area between two heights is √2·π times its difference), so inverting it samples heights
/// uniformly by area.
fn measure(y: f64) -> f64 {
    y * y.abs()
}

/// The area of the finite cone between `minimum` and `maximum`, with its end discs (of radii
/// |minimum| and |maximum|) when `closed`.
pub fn area(minimum: f64, maximum: f64, closed: bool) -> f64 {
    let side = SQRT_2 * PI * (measure(maximum) - measure(minimum));
    let caps = if closed {
        PI * (minimum * minimum + maximum * maximum)
    } else {
        0.0
    };
    side + caps
}

/// A point of the finite cone uniformly by area and its unit normal (the book's, outward on
/// the side): the side or a cap from `pick` in [0, 1), in proportion to their areas, the point
/// on it from `u`.
pub fn sample_area(
    minimum: f64,
    maximum: f64,
    closed: bool,
    pick: f64,
    [u, v]: [f64; 2],
) -> (Point3, Vec3) {
    let (low, high) = (measure(minimum), measure(maximum));
    let side = SQRT_2 * PI * (high - low);
    let bottom = PI * minimum * minimum;
    let at = pick * area(minimum, maximum, closed);
    let (sin, cos) = sin_cos_turns(v);
    if at < side || !closed {
        let t = low + u * (high - low);
        let y = t.signum() * t.abs().sqrt();
        let p = Point3::new(y.abs() * cos, y, y.abs() * sin);
        // The book's cone normal, (x, −y, z), normalised.
        let n = Vec3::new(p.x, -y, p.z).normalize_or_zero();
        (p, n)
    } else {
        let (y, n) = if at < side + bottom {
            (minimum, -Vec3::Y)
        } else {
            (maximum, Vec3::Y)
        };
        let r = y.abs() * u.sqrt();
        (Point3::new(r * cos, y, r * sin), n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    #[test]
    fn a_cone_is_sampled_uniformly_by_area() {
        // Over the side of x² + z² = y² from 0.2 to 1, the mean height by area is
        // ∫ y·y dy / ∫ y dy = (1 − 0.008)/3 / ((1 − 0.04)/2) = 0.68889; with its end discs
        // (areas π·0.04 and π, at 0.2 and 1) the mean moves to the weighted mean of the three.
        let mut rng = SplitMix64::new(7);
        for closed in [false, true] {
            let n = 200_000;
            let mean = (0..n)
                .map(|_| {
                    let (pick, u) = (rng.next_offset(), [rng.next_offset(), rng.next_offset()]);
                    sample_area(0.2, 1.0, closed, pick, u).0.y
                })
                .sum::<f64>()
                / n as f64;
            let side = SQRT_2 * PI * (1.0 - 0.04);
            let side_mean = (1.0 - 0.008) / 3.0 / ((1.0 - 0.04) / 2.0);
            let expected = if closed {
                let (bottom, top) = (PI * 0.04, PI);
                (side * side_mean + bottom * 0.2 + top * 1.0) / (side + bottom + top)
            } else {
                side_mean
            };
            // The heights' spread is under 0.3: four standard errors are 0.003.
            assert!(
                (mean - expected).abs() < 0.003,
                "{closed}: {mean} vs {expected}"
            );
            let caps = if closed { PI * 1.04 } else { 0.0 };
            assert!((area(0.2, 1.0, closed) - (side + caps)).abs() < 1e-12);
        }
    }
}
