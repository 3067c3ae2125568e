//! A thin ring: the part of the xz plane between two circles around the y axis (Fundamentals of
//! Ray Tracing's `ThinRing`, turned to the y-up convention; a disc is a ring without a hole).
//! It has no thickness, so it holds no volume and is seen from both sides.

use crate::math::{Point3, Ray, Vec3, EPSILON};

/// The one hit of the ray with the ring, if it crosses the plane between the circles.
pub fn intersect(ray: &Ray, inner: f64, outer: f64, mut hit: impl FnMut(f64)) {
    let (o, d) = (ray.origin, ray.direction);
    if d.y.abs() < EPSILON {
        return;
    }
    let t = -o.y / d.y;
    let (x, z) = (o.x + t * d.x, o.z + t * d.z);
    let m = x * x + z * z;
    if inner * inner <= m && m <= outer * outer {
        hit(t);
    }
}

/// The ring's normal: +y (the side a ray comes from is the caller's business).
pub fn normal_at(_point: Point3) -> Vec3 {
    Vec3::Y
}
