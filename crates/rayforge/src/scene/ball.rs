//! Round balls: spheres that stand still, scaled alike along every axis, which a world of few
//! objects tests outright in world space, as it does its level rectangles (see
//! [`Level`](super::level::Level)).
//!
//! Such a sphere is a centre and a radius in the world: the quadratic of the ray against it
//! is the object-space one times the radius squared, so it has the same roots, found without
//! the object's transform or a box test first. Its own test (and its box, for the searches
//! whose visitor decides) is still what every other kind of search uses.

use super::level::Probe;
use super::object::Object;
use super::shape::Shape;
use crate::math::roots::solve_quadratic;
use crate::math::{Point3, Vec3};

/// How far the lengths of a sphere's transformed axes, and their dot products, may differ
/// from a uniform scale's (relative) for it to be taken as round.
const ROUND: f64 = 1e-12;

/// A sphere about `centre` whose radius, squared, is `radius_squared`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    centre: [f64; 3],
    radius_squared: f64,
    /// One over the radius, for the normal.
    inv_radius: f64,
}

impl Ball {
    /// `object` as a round ball, if it is one: a sphere that stands still, whose transform
    /// scales every axis alike (turns, mirrors and moves it as it will).
    pub fn of(object: &Object) -> Option<Self> {
        if !matches!(object.shape, Shape::Sphere) || object.motion.is_some() {
            return None;
        }
        let t = &object.transform;
        let axes = [t.vector(Vec3::X), t.vector(Vec3::Y), t.vector(Vec3::Z)];
        let scale = axes[0].length_squared();
        let alike = |a: f64, b: f64| (a - b).abs() <= ROUND * scale;
        let round = (scale > 0.0 && scale.is_finite())
            && alike(axes[1].length_squared(), scale)
            && alike(axes[2].length_squared(), scale)
            && alike(axes[0].dot(axes[1]), 0.0)
            && alike(axes[0].dot(axes[2]), 0.0)
            && alike(axes[1].dot(axes[2]), 0.0);
        round.then(|| Self {
            centre: t.point(Point3::ZERO).to_array(),
            radius_squared: scale,
            inv_radius: 1.0 / scale.sqrt(),
        })
    }

    /// The outward unit normal at `point` of the surface: from the centre, over the radius
    /// (what the sphere's transform gives its object-space normal, without the transform; a
    /// mirroring one turns the sphere inside out no more than it does there).
    #[inline]
    pub fn normal_at(&self, point: Point3) -> Vec3 {
        (point - Point3::from_array(self.centre)) * self.inv_radius
    }

    /// Both crossings of the ray's line with the sphere, nearer first (a tangent ray gives the
    /// same twice), as the sphere's own test finds them.
    #[inline]
    pub fn crossings(&self, ray: &Probe) -> Option<(f64, f64)> {
        let (o, d) = (ray.origin(), ray.direction());
        let oc = [
            o[0] - self.centre[0],
            o[1] - self.centre[1],
            o[2] - self.centre[2],
        ];
        let a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let b = 2.0 * (d[0] * oc[0] + d[1] * oc[1] + d[2] * oc[2]);
        let c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - self.radius_squared;
        solve_quadratic(a, b, c)
    }

    /// The nearest crossing with `t_min <= t < t_max`.
    #[inline]
    pub fn hit(&self, ray: &Probe, t_min: f64, t_max: f64) -> Option<f64> {
        let (t0, t1) = self.crossings(ray)?;
        let within = |t: f64| t >= t_min && t < t_max;
        if within(t0) {
            Some(t0)
        } else {
            within(t1).then_some(t1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{point, rotation_x, rotation_y, scaling, shearing, translation, vector, Ray};

    fn sphere(matrix: glam::DMat4) -> Object {
        Object::sphere().with_transform(matrix)
    }

    #[test]
    fn only_a_still_sphere_scaled_alike_is_a_ball() {
        let ball = Ball::of(&sphere(translation(1.0, 2.0, 3.0) * scaling(0.5, 0.5, 0.5)));
        assert_eq!(
            ball,
            Some(Ball {
                centre: [1.0, 2.0, 3.0],
                radius_squared: 0.25,
                inv_radius: 2.0,
            })
        );
        assert!(Ball::of(&sphere(rotation_y(0.3) * scaling(2.0, 2.0, 2.0))).is_some());
        assert!(
            Ball::of(&sphere(scaling(1.0, 2.0, 1.0))).is_none(),
            "a spheroid"
        );
        let sheared = shearing(0.5, 0.0, 0.0, 0.0, 0.0, 0.0);
        assert!(Ball::of(&sphere(sheared)).is_none());
        assert!(Ball::of(&Object::cube()).is_none());
    }

    /// Balls placed many ways, and rays from everywhere: the world-space crossings are the
    /// object's own, to rounding.
    #[test]
    fn a_ball_is_crossed_where_its_own_test_crosses_it() {
        let mut rng = SplitMix64::new(9);
        let mut unit = move || rng.next_offset();
        let placements = [
            glam::DMat4::IDENTITY,
            translation(0.0, -1.0, 0.5) * scaling(0.3, 0.3, 0.3),
            translation(2.0, 0.0, -1.0) * rotation_x(0.7) * scaling(-1.5, 1.5, 1.5),
        ];
        let mut crossed = 0;
        for matrix in placements {
            let object = sphere(matrix);
            let ball = Ball::of(&object).expect("round");
            for _ in 0..4000 {
                let origin = point(unit() * 6.0 - 3.0, unit() * 6.0 - 3.0, unit() * 6.0 - 3.0);
                let direction = vector(unit() - 0.5, unit() - 0.5, unit() - 0.5);
                let probe = Probe::new(origin, direction);
                let mine = ball.crossings(&probe);
                let mut own = Vec::new();
                let local = object.ray_to_object(&Ray::new(origin, direction));
                object
                    .shape
                    .hits_up_to(&local, f64::INFINITY, |h| own.push(h.t));
                match (mine, own.as_slice()) {
                    (Some((a, b)), &[c, d]) => {
                        crossed += 1;
                        let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * y.abs().max(1.0);
                        assert!(close(a, c) && close(b, d), "{a}, {b} against {c}, {d}");
                    }
                    (None, []) => {}
                    (mine, own) => panic!("{mine:?} against {own:?}"),
                }
            }
        }
        assert!(crossed > 1000, "the rays crossed: {crossed}");
    }

    /// On balls placed many ways (one of them mirrored), the normal from the centre is the
    /// one the object's transform gives its shape's normal, to rounding.
    #[test]
    fn a_balls_normal_is_its_objects_normal() {
        let mut rng = SplitMix64::new(4);
        let mut unit = move || rng.next_offset();
        for matrix in [
            glam::DMat4::IDENTITY,
            translation(0.5, -1.0, 2.0) * rotation_y(0.4) * scaling(0.3, 0.3, 0.3),
            translation(2.0, 0.0, -1.0) * rotation_x(0.7) * scaling(-1.5, 1.5, 1.5),
        ] {
            let object = sphere(matrix);
            let ball = Ball::of(&object).expect("round");
            for _ in 0..200 {
                let on = vector(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize();
                let point = object.transform.point(Point3::ZERO + on);
                let own = object.normal_at(point);
                let mine = ball.normal_at(point);
                assert!((mine - own).length() < 1e-12, "{mine} against {own}");
            }
        }
    }

    #[test]
    fn the_nearest_crossing_in_the_span_is_the_hit() {
        let ball = Ball::of(&Object::sphere()).unwrap();
        let probe = Probe::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
        assert_eq!(ball.hit(&probe, 0.0, f64::INFINITY), Some(4.0));
        assert_eq!(ball.hit(&probe, 4.5, f64::INFINITY), Some(6.0));
        assert_eq!(ball.hit(&probe, 0.0, 4.0), None, "t < t_max");
        let beside = Probe::new(point(0.0, 1.5, -5.0), vector(0.0, 0.0, 1.0));
        assert_eq!(ball.hit(&beside, 0.0, f64::INFINITY), None);
    }
}
