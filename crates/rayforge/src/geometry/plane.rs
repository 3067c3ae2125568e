//! The xz plane (chapter 9).

use crate::math::{Point3, Ray, Vec3, EPSILON};

/// One hit where the ray crosses y = 0; rays parallel to (or within) the plane miss it.
pub fn intersect(ray: &Ray, mut hit: impl FnMut(f64)) {
    if ray.direction.y.abs() < EPSILON {
        return;
    }
    hit(-ray.origin.y / ray.direction.y);
}

/// The plane's normal is +y everywhere.
pub fn normal_at(_point: Point3) -> Vec3 {
    Vec3::Y
}
