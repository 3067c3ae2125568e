//! Clarberg's equal-area octahedral mapping between the unit square and the sphere of
//! directions, as pbrt-v4 has it: the layout of its image lights and of its spherical
//! camera's default image (each square's area the same solid angle).

use super::Vec3;
use std::f64::consts::PI;

/// The direction (unit, +z the pole) of the point `(u, v)` of the unit square in Clarberg's
/// equal-area octahedral mapping, as pbrt-v4's `EqualAreaSquareToSphere`: the square's
/// centre is +z, its corners −z, and equal areas of the square are equal solid angles.
pub fn equal_area_square_to_sphere(u: f64, v: f64) -> Vec3 {
    let (u, v) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    // The signed distance from the diagonal |u| + |v| = 1, and the radius from the centre.
    let signed = 1.0 - (up + vp);
    let r = 1.0 - signed.abs();
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * PI / 4.0;
    let z = (1.0 - r * r).copysign(signed);
    let cos_phi = phi.cos().copysign(u);
    let sin_phi = phi.sin().copysign(v);
    let k = r * (2.0 - r * r).max(0.0).sqrt();
    Vec3::new(cos_phi * k, sin_phi * k, z)
}

/// The point of the unit square of the unit direction `d` (+z the pole): the inverse of
/// [`equal_area_square_to_sphere`], as pbrt-v4's `EqualAreaSphereToSquare`.
pub fn equal_area_sphere_to_square(d: Vec3) -> (f64, f64) {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let (a, b) = (x.max(y), x.min(y));
    let b = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = b.atan() * 2.0 / PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    let u = u.copysign(d.x);
    let v = v.copysign(d.y);
    (0.5 * (u + 1.0), 0.5 * (v + 1.0))
}
