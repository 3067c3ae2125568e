//! The axis-aligned cube from -1 to 1 (chapter 12).

use crate::math::{Point3, Ray, Vec3};

/// The slab method: the ray is inside the cube between the largest entry and smallest exit.
pub fn intersect(ray: &Ray, mut hit: impl FnMut(f64)) {
    let mut tmin = f64::NEG_INFINITY;
    let mut tmax = f64::INFINITY;
    for axis in 0..3 {
        let Some((t0, t1)) = slab(ray.origin[axis], ray.direction[axis]) else {
            return;
        };
        tmin = tmin.max(t0);
        tmax = tmax.min(t1);
    }
    if tmin <= tmax {
        hit(tmin);
        hit(tmax);
    }
}

/// Where the ray enters and leaves the slab -1 ≤ x ≤ 1 along one axis.
///
/// A ray parallel to the slab (direction exactly 0) never divides by zero here: it is inside the
/// slab for all `t` or for none, which avoids the NaN the book's `0 · ∞` would produce for an
/// origin on the slab's face (the validation notebook's trap).
fn slab(origin: f64, direction: f64) -> Option<(f64, f64)> {
    if direction == 0.0 {
        return (-1.0..=1.0)
            .contains(&origin)
            .then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let t0 = (-1.0 - origin) / direction;
    let t1 = (1.0 - origin) / direction;
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// The normal is the axis of the largest absolute coordinate (the face the point lies on).
pub fn normal_at(point: Point3) -> Vec3 {
    let abs = point.abs();
    let max = abs.max_element();
    if max == abs.x {
        Vec3::new(point.x, 0.0, 0.0)
    } else if max == abs.y {
        Vec3::new(0.0, point.y, 0.0)
    } else {
        Vec3::new(0.0, 0.0, point.z)
    }
}
