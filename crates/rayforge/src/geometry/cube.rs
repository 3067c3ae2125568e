//! The axis-aligned cube from -1 to 1 (chapter 12).

use crate::math::{Point3, Ray, Vec3};

/// The slab method: the ray is inside the cube between the largest entry and smallest exit.
///
/// The entry only grows and the exit only shrinks from one axis to the next, so once they
/// have crossed the ray misses, and the remaining axes (two divisions each) are not worked out.
#[inline]
pub fn intersect(ray: &Ray, mut hit: impl FnMut(f64)) {
    let mut tmin = f64::NEG_INFINITY;
    let mut tmax = f64::INFINITY;
    for axis in 0..3 {
        let Some((t0, t1)) = slab(ray.origin[axis], ray.direction[axis]) else {
            return;
        };
        tmin = tmin.max(t0);
        tmax = tmax.min(t1);
        if tmin > tmax {
            return;
        }
    }
    hit(tmin);
    hit(tmax);
}

/// Where the ray enters and leaves the slab -1 ≤ x ≤ 1 along one axis.
///
/// A ray parallel to the slab (direction exactly 0) never divides by zero here: it is inside the
/// slab for all `t` or for none, which avoids the NaN the book's `0 · ∞` would produce for an
/// origin on the slab's face (the validation notebook's trap).
#[inline]
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

/// The cube's area: six faces of 2 × 2.
pub const AREA: f64 = 24.0;

/// A point of the cube uniformly by area and its face's unit normal: the face from `pick` in
/// [0, 1) (the six are equal), the point on it from `u`.
pub fn sample_area(pick: f64, [u, v]: [f64; 2]) -> (Point3, Vec3) {
    let face = ((pick * 6.0) as usize).min(5);
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    let sign = if face % 2 == 0 { 1.0 } else { -1.0 };
    match face / 2 {
        0 => (Point3::new(sign, a, b), Vec3::X * sign),
        1 => (Point3::new(a, sign, b), Vec3::Y * sign),
        _ => (Point3::new(a, b, sign), Vec3::Z * sign),
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::SplitMix64;

    /// The slab method with every axis worked out before the entry and exit are compared.
    fn every_axis(ray: &Ray) -> Vec<f64> {
        let (mut tmin, mut tmax) = (f64::NEG_INFINITY, f64::INFINITY);
        for axis in 0..3 {
            let Some((t0, t1)) = slab(ray.origin[axis], ray.direction[axis]) else {
                return Vec::new();
            };
            tmin = tmin.max(t0);
            tmax = tmax.min(t1);
        }
        if tmin <= tmax {
            vec![tmin, tmax]
        } else {
            Vec::new()
        }
    }

    #[test]
    fn stopping_at_the_first_crossed_axis_finds_the_same_hits() {
        let mut rng = SplitMix64::new(7);
        let mut signed = || (rng.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0;
        let (mut hits, mut misses) = (0, 0);
        for i in 0..50_000 {
            let origin = Point3::new(signed(), signed(), signed()) * 3.0;
            let mut direction = Vec3::new(signed(), signed(), signed());
            // Rays parallel to a face, inside and outside its slab.
            if i % 7 == 0 {
                direction[i % 3] = 0.0;
            }
            let ray = Ray::new(origin, direction);
            let mut found = Vec::new();
            intersect(&ray, |t| found.push(t));
            assert_eq!(found, every_axis(&ray), "{ray:?}");
            if found.is_empty() {
                misses += 1;
            } else {
                hits += 1;
            }
        }
        assert!(hits > 5000 && misses > 5000, "{hits} {misses}");
    }
}
