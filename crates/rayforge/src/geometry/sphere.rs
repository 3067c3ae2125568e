//! The unit sphere (chapters 5 and 6).

use crate::math::{roots::solve_quadratic, Point3, Ray, Vec3};

/// Both roots of `|o + t·d|² = 1`, tangent rays giving the same `t` twice (as the book expects).
#[inline]
pub fn intersect(ray: &Ray, mut hit: impl FnMut(f64)) {
    let a = ray.direction.length_squared();
    let b = 2.0 * ray.direction.dot(ray.origin);
    let c = ray.origin.length_squared() - 1.0;
    if let Some((t0, t1)) = solve_quadratic(a, b, c) {
        hit(t0);
        hit(t1);
    }
}

/// The normal of the unit sphere is the point itself.
pub fn normal_at(point: Point3) -> Vec3 {
    point
}
