//! Still boxes: cubes that stand still, turned and scaled along their own axes but not
//! sheared (a closed room, a furnace, the two blocks of a Cornell box), whose hits a search
//! that visits them finds without their transform, as a world of few objects does its level
//! rectangles (see [`Level`](super::level::Level)) and round balls.
//!
//! Under such a transform the cube `[-1, 1]³` is a box about a centre with three
//! perpendicular axes and a half size along each: the slab test runs in the box's own frame,
//! taken by three dot products (no 4×4 inverse), or in world space where its axes are the
//! world's; its world normal is the axis of the face the point lies on, and its faces are the
//! six rectangles a light sample picks among. A closed furnace (the camera inside one such
//! box, which both lights and bounces every path) spent a third of a bounce taking points and
//! normals through the transform and back.
//!
//! A box is still visited behind its box in the world, in its turn among the objects, so
//! that which of two surfaces in one plane a ray meets first (a block standing on a floor)
//! is decided as before, by the order of the search and the rounding of each distance.

use super::level::Probe;
use super::object::Object;
use super::shape::Shape;
use crate::math::{Point3, Vec3};

/// How far from perpendicular (the cosine between two of them) a transformed cube's axes may
/// be for it to be taken as a box: a turn leaves a few units in the sixteenth digit.
const SQUARE: f64 = 1e-12;

/// A box about `centre`: its unit axes in the world, and its half size along each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cuboid {
    centre: [f64; 3],
    axes: [[f64; 3]; 3],
    half: [f64; 3],
    /// Its least and greatest corners, where its axes are the world's (turned by right angles
    /// at most): the slab test then runs in world space, with the ray's reciprocal direction
    /// worked out once for every object.
    level: Option<([f64; 3], [f64; 3])>,
}

/// Narrows `[enter, leave]` to where a ray (`origin + t · direction`, along one axis, `inv`
/// being `1 / direction`) is within the slab `[low, high]`; whether any of it is left. A ray
/// parallel to the slab is within it for every `t` or for none.
#[inline(always)]
fn slab(origin: f64, direction: f64, inv: f64, [low, high]: [f64; 2], span: &mut [f64; 2]) -> bool {
    if direction == 0.0 {
        return origin >= low && origin <= high;
    }
    let (t0, t1) = ((low - origin) * inv, (high - origin) * inv);
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    if near > span[0] {
        span[0] = near;
    }
    if far < span[1] {
        span[1] = far;
    }
    span[0] <= span[1]
}

/// The dot product of two arrays of three.
#[inline(always)]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Cuboid {
    /// `object` as a still box, if it is one: a cube that stands still, whose transform keeps
    /// its axes perpendicular (turns, mirrors, moves and scales it along its own axes).
    pub fn of(object: &Object) -> Option<Self> {
        if !matches!(object.shape, Shape::Cube) || object.motion.is_some() {
            return None;
        }
        let t = &object.transform;
        let columns = [Vec3::X, Vec3::Y, Vec3::Z].map(|e| t.vector(e));
        let half = columns.map(|v| v.length());
        if !half.iter().all(|h| *h > 0.0 && h.is_finite()) {
            return None;
        }
        let axes = [0, 1, 2].map(|k| (columns[k] / half[k]).to_array());
        let square = |i: usize, j: usize| dot(&axes[i], &axes[j]).abs() <= SQUARE;
        if !(square(0, 1) && square(0, 2) && square(1, 2)) {
            return None;
        }
        let centre = t.point(Point3::ZERO).to_array();
        // Along the world's axes, each of ours is one of them exactly (a right angle's turn
        // leaves a few units in the sixteenth digit, which the box's corners take no notice
        // of).
        let along = |a: &[f64; 3]| a.iter().filter(|c| c.abs() > SQUARE).count() == 1;
        let level = axes.iter().all(along).then(|| {
            let mut reach = [0.0; 3];
            for (axis, h) in axes.iter().zip(half) {
                for c in 0..3 {
                    reach[c] += (axis[c] * h).abs();
                }
            }
            (
                [0, 1, 2].map(|c| centre[c] - reach[c]),
                [0, 1, 2].map(|c| centre[c] + reach[c]),
            )
        });
        Some(Self {
            centre,
            axes,
            half,
            level,
        })
    }

    /// `point` in the box's frame: its coordinates along the axes, from the centre.
    #[inline(always)]
    fn local(&self, point: &[f64; 3]) -> [f64; 3] {
        let c = &self.centre;
        let v = [point[0] - c[0], point[1] - c[1], point[2] - c[2]];
        self.axes.map(|a| dot(&a, &v))
    }

    /// Where the ray's line enters and leaves the box, at any `t` (entry first; the same
    /// twice where it grazes an edge), as the cube's own slab test finds them. A ray parallel
    /// to a pair of faces is within their slab for every `t` or for none.
    #[inline]
    pub fn crossings(&self, ray: &Probe) -> Option<(f64, f64)> {
        let mut span = [f64::NEG_INFINITY, f64::INFINITY];
        let crossed = if let Some((min, max)) = &self.level {
            let (o, d, inv) = (ray.origin(), ray.direction(), ray.inv_direction_array());
            slab(o[0], d[0], inv[0], [min[0], max[0]], &mut span)
                && slab(o[1], d[1], inv[1], [min[1], max[1]], &mut span)
                && slab(o[2], d[2], inv[2], [min[2], max[2]], &mut span)
        } else {
            let o = self.local(ray.origin());
            let dir = ray.direction();
            let d = [0, 1, 2].map(|k| dot(&self.axes[k], dir));
            let h = self.half;
            let along =
                |k: usize, span: &mut [f64; 2]| slab(o[k], d[k], 1.0 / d[k], [-h[k], h[k]], span);
            along(0, &mut span) && along(1, &mut span) && along(2, &mut span)
        };
        crossed.then_some((span[0], span[1]))
    }

    /// The nearest crossing with `t_min <= t < t_max`.
    #[inline]
    pub fn hit(&self, ray: &Probe, t_min: f64, t_max: f64) -> Option<f64> {
        let (t0, t1) = self.crossings(ray)?;
        [t0, t1].into_iter().find(|&t| t >= t_min && t < t_max)
    }

    /// The outward unit normal of the face `point` lies on (the axis along which it is
    /// furthest out, relative to the box's size): what the cube's transform gives its
    /// object-space normal there, without the transform.
    #[inline]
    pub fn normal_at(&self, point: Point3) -> Vec3 {
        let l = self.local(&point.to_array());
        let q = [0, 1, 2].map(|k| (l[k] / self.half[k]).abs());
        let k = if q[0] >= q[1] && q[0] >= q[2] {
            0
        } else if q[1] >= q[2] {
            1
        } else {
            2
        };
        Vec3::from_array(self.axes[k]) * 1.0_f64.copysign(l[k])
    }

    /// The area of each face, in the order of [`face_point`](Self::face_point)'s faces: the
    /// two across the first axis (the far side, then the near), across the second, across
    /// the third.
    pub fn face_areas(&self) -> [f64; 6] {
        let h = self.half;
        let across = |k: usize| 4.0 * h[(k + 1) % 3] * h[(k + 2) % 3];
        [0, 0, 1, 1, 2, 2].map(across)
    }

    /// The point `u` of face `face` (`0..6`, see [`face_areas`](Self::face_areas)),
    /// uniform over its area, and the face's outward unit normal.
    #[inline]
    pub fn face_point(&self, face: usize, u: [f64; 2]) -> (Point3, Vec3) {
        let k = face / 2;
        let side = if face % 2 == 1 { 1.0 } else { -1.0 };
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (h, a) = (&self.half, &self.axes);
        let l = [
            side * h[k],
            h[i] * (2.0 * u[0] - 1.0),
            h[j] * (2.0 * u[1] - 1.0),
        ];
        let p =
            [0, 1, 2].map(|c| self.centre[c] + l[0] * a[k][c] + l[1] * a[i][c] + l[2] * a[j][c]);
        (Point3::from_array(p), Vec3::from_array(a[k]) * side)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{point, rotation_x, rotation_y, rotation_z, scaling, translation, vector};
    use crate::math::{Motion, Ray, Transform};
    use crate::scene::intersection::Intersection;
    use crate::scene::level::tests::ray_from_anywhere;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn cube(matrix: glam::DMat4) -> Object {
        Object::new(Shape::Cube).with_transform(matrix)
    }

    #[test]
    fn only_a_still_cube_turned_and_scaled_along_its_axes_is_a_box() {
        let placed =
            cube(translation(1.0, 2.0, 3.0) * rotation_z(FRAC_PI_2) * scaling(1.0, 2.0, 3.0));
        let b = Cuboid::of(&placed).expect("turned by a right angle");
        assert_eq!((b.centre, b.half), ([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]));
        assert!(Cuboid::of(&cube(rotation_y(0.3) * scaling(1.0, 2.0, 0.5))).is_some());
        let sheared = scaling(1.0, 2.0, 1.0) * rotation_z(0.4) * scaling(1.5, 1.0, 1.0);
        assert!(Cuboid::of(&cube(sheared)).is_none(), "sheared");
        assert!(Cuboid::of(&Object::new(Shape::Sphere)).is_none());
        let mut moving = Object::cube();
        let end = Transform::new(translation(1.0, 0.0, 0.0));
        moving.motion = Some(Box::new(Motion::new(Transform::IDENTITY, end)));
        assert!(Cuboid::of(&moving).is_none(), "moving");
    }

    /// Boxes placed along the axes, turned (a Cornell box's blocks) and mirrored, and rays
    /// from everywhere (inside and out): the world-space hit and normal are the object's own
    /// (the same `t` to rounding, the same miss, the same normal).
    #[test]
    fn a_box_is_hit_where_its_own_test_hits_it_with_its_normal() {
        let mut rng = SplitMix64::new(11);
        let mut unit = move || rng.next_offset();
        let placements = [
            glam::DMat4::IDENTITY,
            translation(0.335, -0.7, 0.38) * scaling(0.3, 0.3, 0.3),
            translation(-1.0, 0.5, 2.0) * scaling(2.0, 0.5, 1.5),
            translation(0.2, 0.0, -0.3) * rotation_x(PI) * scaling(1.0, 0.4, 2.0),
            translation(1.0, 1.0, 1.0) * rotation_y(FRAC_PI_2) * scaling(-0.5, 1.5, 0.8),
            translation(0.335, -0.7, 0.38)
                * rotation_y(-17f64.to_radians())
                * scaling(0.3, 0.3, 0.3),
            translation(-0.33, -0.4, -0.28)
                * rotation_y(18.25f64.to_radians())
                * scaling(0.3, 0.61, 0.3),
            rotation_x(0.3) * rotation_z(-1.1) * scaling(1.2, -0.4, 0.7),
        ];
        let (mut hits, mut disagreements) = (0, 0);
        for matrix in placements {
            let object = cube(matrix);
            let boxed = Cuboid::of(&object).expect("a box");
            for _ in 0..5000 {
                let (origin, direction, t_min, t_max) = ray_from_anywhere(&mut unit);
                let mine = boxed.hit(&Probe::new(origin, direction), t_min, t_max);
                let ray = Ray::new(origin, direction);
                let own = object.closest_local_hit(&object.ray_to_object(&ray), t_min, t_max);
                match (mine, own) {
                    (Some(a), Some(h)) => {
                        hits += 1;
                        assert!(
                            (a - h.t).abs() <= 1e-12 * h.t.abs().max(1.0),
                            "{a} against {}",
                            h.t
                        );
                        let at = ray.position(a);
                        let theirs =
                            object.normal_at_hit(at, &Intersection::from_local(&object, h));
                        assert!((boxed.normal_at(at) - theirs).length() < 1e-9, "{at:?}");
                    }
                    (None, None) => {}
                    // Rounding may put a crossing just on either side of an edge or a limit.
                    _ => disagreements += 1,
                }
            }
        }
        assert!(hits > 1000, "the rays hit: {hits}");
        assert!(disagreements <= 5, "{disagreements} disagreements");
    }

    #[test]
    fn a_ray_along_a_face_stays_in_its_slab_or_misses() {
        let unit_box = Cuboid::of(&Object::cube()).expect("a box");
        let along_x = vector(1.0, 0.0, 0.0);
        let inside = Probe::new(point(-5.0, 0.5, 0.0), along_x);
        assert_eq!(unit_box.crossings(&inside), Some((4.0, 6.0)));
        assert_eq!(unit_box.hit(&inside, 4.5, 10.0), Some(6.0));
        let on_face = Probe::new(point(-5.0, 1.0, 0.0), along_x);
        assert_eq!(unit_box.crossings(&on_face), Some((4.0, 6.0)));
        let above = Probe::new(point(-5.0, 1.0 + 1e-9, 0.0), along_x);
        assert_eq!(unit_box.crossings(&above), None);
    }

    #[test]
    fn faces_cover_the_box_with_outward_normals() {
        let level = cube(translation(1.0, 0.0, 0.0) * scaling(1.0, 2.0, 3.0));
        let b = Cuboid::of(&level).unwrap();
        assert_eq!(b.face_areas(), [24.0, 24.0, 12.0, 12.0, 8.0, 8.0]);
        let turned = cube(translation(1.0, 0.0, 0.0) * rotation_x(0.7) * scaling(1.0, 2.0, 3.0));
        for object in [level, turned] {
            let b = Cuboid::of(&object).unwrap();
            for face in 0..6 {
                let (p, n) = b.face_point(face, [0.25, 0.75]);
                assert!((b.normal_at(p) - n).length() < 1e-12, "face {face}");
                assert!((object.normal_at(p) - n).length() < 1e-12, "face {face}");
                let (centre, _) = b.face_point(face, [0.5, 0.5]);
                assert!((centre - point(1.0, 0.0, 0.0)).dot(n) > 0.0);
            }
        }
    }
}
