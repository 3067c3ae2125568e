//! A thin ring: the part of the xz plane between two circles around the y axis (Fundamentals of
//! Ray Tracing's `ThinRing`, turned to the y-up convention; a disc is a ring without a hole).
//! It has no thickness, so it holds no volume and is seen from both sides.

use crate::math::{sin_cos_turns, Point3, Ray, Vec3, EPSILON};
use std::f64::consts::PI;

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

/// The ring's area.
pub fn area(inner: f64, outer: f64) -> f64 {
    PI * (outer * outer - inner * inner)
}

/// A point of the ring uniformly by area, from `u` in [0, 1)²: the area within radius ρ grows
/// with ρ², so ρ² is uniform between the two circles' squares.
pub fn sample_area(inner: f64, outer: f64, [u, v]: [f64; 2]) -> Point3 {
    let r = (inner * inner + u * (outer * outer - inner * inner)).sqrt();
    let (sin, cos) = sin_cos_turns(v);
    Point3::new(r * cos, 0.0, r * sin)
}
