//! The double-napped cone x² + z² = y² (chapter 13): infinite, truncated, or capped.

use super::cylinder::caps;
use crate::math::{roots::solve_quadratic, Point3, Ray, Vec3, EPSILON};

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
