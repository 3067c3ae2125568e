//! The cylinder of radius 1 around the y axis (chapter 13): infinite, truncated, or capped.

use crate::math::{roots::solve_quadratic, sin_cos_turns, Point3, Ray, Vec3, EPSILON};
use std::f64::consts::PI;

/// Side hits within `minimum < y < maximum` (exclusive, as the book has it), then cap hits.
pub fn intersect(ray: &Ray, minimum: f64, maximum: f64, closed: bool, mut hit: impl FnMut(f64)) {
    let (o, d) = (ray.origin, ray.direction);
    let a = d.x * d.x + d.z * d.z;
    // A ray parallel to the axis can only meet the caps.
    if a.abs() >= EPSILON {
        let b = 2.0 * (o.x * d.x + o.z * d.z);
        let c = o.x * o.x + o.z * o.z - 1.0;
        let Some((t0, t1)) = solve_quadratic(a, b, c) else {
            return;
        };
        for t in [t0, t1] {
            let y = o.y + t * d.y;
            if minimum < y && y < maximum {
                hit(t);
            }
        }
    }
    if closed {
        caps(ray, minimum, maximum, |_| 1.0, hit);
    }
}

/// Hits on the end caps at `minimum` and `maximum`, each a disc of radius `radius_at(y)`.
/// Shared with the cone, whose caps grow with |y|.
pub(super) fn caps(
    ray: &Ray,
    minimum: f64,
    maximum: f64,
    radius_at: impl Fn(f64) -> f64,
    mut hit: impl FnMut(f64),
) {
    let (o, d) = (ray.origin, ray.direction);
    if d.y.abs() < EPSILON {
        return;
    }
    for y in [minimum, maximum] {
        if !y.is_finite() {
            continue;
        }
        let t = (y - o.y) / d.y;
        let x = o.x + t * d.x;
        let z = o.z + t * d.z;
        let r = radius_at(y);
        if x * x + z * z <= r * r {
            hit(t);
        }
    }
}

/// Outward on the sides; ±y within `EPSILON` of a cap.
pub fn normal_at(point: Point3, minimum: f64, maximum: f64) -> Vec3 {
    let dist = point.x * point.x + point.z * point.z;
    if dist < 1.0 && point.y >= maximum - EPSILON {
        Vec3::Y
    } else if dist < 1.0 && point.y <= minimum + EPSILON {
        Vec3::NEG_Y
    } else {
        Vec3::new(point.x, 0.0, point.z)
    }
}

/// The area of the finite cylinder between `minimum` and `maximum`, with its two unit discs
/// when `closed`.
pub fn area(minimum: f64, maximum: f64, closed: bool) -> f64 {
    2.0 * PI * (maximum - minimum) + if closed { 2.0 * PI } else { 0.0 }
}

/// A point of the finite cylinder uniformly by area and its unit outward normal: the side or
/// a cap from `pick` in [0, 1), in proportion to their areas, the point on it from `u`.
pub fn sample_area(
    minimum: f64,
    maximum: f64,
    closed: bool,
    pick: f64,
    [u, v]: [f64; 2],
) -> (Point3, Vec3) {
    let side = 2.0 * PI * (maximum - minimum);
    let (sin, cos) = sin_cos_turns(v);
    let at = pick * area(minimum, maximum, closed);
    if at < side || !closed {
        let y = minimum + u * (maximum - minimum);
        let n = Vec3::new(cos, 0.0, sin);
        (Point3::new(n.x, y, n.z), n)
    } else {
        let (y, n) = if at < side + PI {
            (minimum, -Vec3::Y)
        } else {
            (maximum, Vec3::Y)
        };
        let r = u.sqrt();
        (Point3::new(r * cos, y, r * sin), n)
    }
}
