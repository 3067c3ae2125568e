//! A rectangle: the square from -1 to 1 in x and z of the xz plane, normal +y (a bounded
//! [`plane`](super::plane)). The path tracer's reference scenes are built of them: the walls of
//! the Cornell box, its light, a floor. It has no thickness and holds no volume; which side an
//! emitter lights is its normal's (see the path tracer), while surfaces scatter on both sides.

use crate::math::{Point3, Ray, Vec3, EPSILON};

/// The one hit of the ray with the rectangle, if it crosses the plane inside the square.
pub fn intersect(ray: &Ray, mut hit: impl FnMut(f64)) {
    let (o, d) = (ray.origin, ray.direction);
    if d.y.abs() < EPSILON * EPSILON {
        return;
    }
    let t = -o.y / d.y;
    let (x, z) = (o.x + t * d.x, o.z + t * d.z);
    if x.abs() <= 1.0 && z.abs() <= 1.0 {
        hit(t);
    }
}

/// The rectangle's normal: +y, the side it faces.
pub fn normal_at(_point: Point3) -> Vec3 {
    Vec3::Y
}

/// The square's area.
pub const AREA: f64 = 4.0;

/// The point of the square at `u`, `v` in [0, 1)²: uniform by area (the square's area is 4).
pub fn point_at(u: f64, v: f64) -> Point3 {
    Point3::new(2.0 * u - 1.0, 0.0, 2.0 * v - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{point, vector};

    #[test]
    fn a_ray_through_the_square_hits_it_once_and_one_beside_it_misses() {
        let mut hits = Vec::new();
        intersect(
            &Ray::new(point(0.5, 2.0, -0.9), vector(0.0, -1.0, 0.0)),
            |t| hits.push(t),
        );
        assert_eq!(hits, vec![2.0]);
        hits.clear();
        intersect(
            &Ray::new(point(1.1, 2.0, 0.0), vector(0.0, -1.0, 0.0)),
            |t| hits.push(t),
        );
        assert!(hits.is_empty());
        intersect(
            &Ray::new(point(0.0, 1.0, 0.0), vector(1.0, 0.0, 0.0)),
            |t| hits.push(t),
        );
        assert!(hits.is_empty(), "a ray in the plane misses");
    }

    #[test]
    fn points_by_area_cover_the_square() {
        assert_eq!(point_at(0.0, 0.0), point(-1.0, 0.0, -1.0));
        assert_eq!(point_at(0.5, 0.5), point(0.0, 0.0, 0.0));
    }
}
