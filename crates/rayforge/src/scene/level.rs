//! Level rectangles: rectangles that stand still in a plane of the axes with their edges
//! along them (a floor, a wall, a lamp under a ceiling: every surface of a Cornell box but its
//! two blocks), which a world of few objects tests outright in world space.
//!
//! A world of a handful of solids tries its objects in turn (a BVH walk costs more to set up
//! than it saves), most behind their box: a ray that misses it is spared the object's
//! transform and its own test. A level rectangle is its box with no thickness, and is
//! cheaper to test outright than its box alone: one slab gives the crossing, the other two
//! are read at it, and no transform or test of its own is left to do. On a Cornell box this
//! took a seventh off the instructions of a render (Valgrind's count). The distance found may
//! differ from the rectangle's own test in its last digit; the reference scenes' images came
//! out the same to the bit.

use super::object::Object;
use super::shape::Shape;
use crate::math::{Point3, Vec3};

/// How far from an axis a rectangle's normal or edge may lean and still be taken as along it:
/// a rotation by a right angle leaves 6·10⁻¹⁷ of the other axes, and a lean this small moves
/// a point of a rectangle a thousand units across by a ten-billionth.
const LEAN: f64 = 1e-13;

/// How far (relative) a [`Level`] crossing may lie outside the span asked for, or beyond an
/// edge, and still be passed on by [`Level::may_meet`]: far above the rounding of either way of
/// finding a crossing (here in world space, the object's own test in object space, a few
/// units in the sixteenth digit).
const SLACK: f64 = 1e-9;

/// A rectangle lying in the plane `axis = at`, spanning `[min, max]` along the other two axes
/// (`across`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Level {
    axis: usize,
    at: f64,
    across: [usize; 2],
    min: [f64; 2],
    max: [f64; 2],
    /// A billionth of the rectangle's size and place along each of `across`: how far beyond
    /// an edge [`Level::may_meet`] still passes a crossing.
    pad: [f64; 2],
}

/// A ray as a level rectangle reads it, worked out once per ray: its reciprocal direction,
/// and its coordinates as arrays (a vector type read by an axis known only at run time is a
/// branch per read).
#[derive(Debug, Clone, Copy)]
pub struct Probe {
    origin: [f64; 3],
    direction: [f64; 3],
    inv_direction: [f64; 3],
}

impl Probe {
    /// The ray `origin + t · direction`.
    #[inline]
    pub fn new(origin: Point3, direction: Vec3) -> Self {
        Self {
            origin: origin.to_array(),
            direction: direction.to_array(),
            inv_direction: direction.recip().to_array(),
        }
    }

    /// Where the ray starts.
    #[inline]
    pub fn origin(&self) -> &[f64; 3] {
        &self.origin
    }

    /// Which way it goes.
    #[inline]
    pub fn direction(&self) -> &[f64; 3] {
        &self.direction
    }

    /// The reciprocal of its direction (what a box's slab test takes).
    #[inline]
    pub fn inv_direction(&self) -> Vec3 {
        Vec3::from_array(self.inv_direction)
    }

    /// The same, as an array.
    #[inline]
    pub fn inv_direction_array(&self) -> &[f64; 3] {
        &self.inv_direction
    }
}

/// The one axis `v` lies along, if it leans from it by less than [`LEAN`].
fn along(v: Vec3) -> Option<usize> {
    let a = v.abs();
    let axis = a.max_position();
    (a.element_sum() - a[axis] <= LEAN * a[axis]).then_some(axis)
}

impl Level {
    /// `object` as a level rectangle, if it is one: a rectangle that stands still, whose
    /// transform keeps its normal and edges along the axes.
    pub fn of(object: &Object) -> Option<Self> {
        if !matches!(object.shape, Shape::Rectangle) || object.motion.is_some() {
            return None;
        }
        let t = &object.transform;
        let axis = along(t.vector(Vec3::Y))?;
        let (u, v) = (along(t.vector(Vec3::X))?, along(t.vector(Vec3::Z))?);
        if u == axis || v == axis || u == v {
            return None;
        }
        let bounds = object.bounds();
        let across = [(axis + 1) % 3, (axis + 2) % 3];
        let (min, max) = (across.map(|a| bounds.min[a]), across.map(|a| bounds.max[a]));
        Some(Self {
            axis,
            at: t.point(Point3::ZERO)[axis],
            across,
            min,
            max,
            pad: [0, 1].map(|k| (max[k] - min[k] + min[k].abs() + max[k].abs()) * SLACK),
        })
    }

    /// Where the ray crosses the plane, and the point there along `across`.
    #[inline(always)]
    fn crossing(&self, ray: &Probe) -> (f64, f64, f64) {
        let (o, d) = (&ray.origin, &ray.direction);
        let t = (self.at - o[self.axis]) * ray.inv_direction[self.axis];
        let [i, j] = self.across;
        (t, o[i] + d[i] * t, o[j] + d[j] * t)
    }

    /// The hit of the ray with `t_min <= t < t_max`, as the rectangle's own test finds it
    /// (its edges included): a ray in the plane (whose crossing is `0 · ∞` or `∞`) meets
    /// nothing.
    #[inline]
    pub fn hit(&self, ray: &Probe, t_min: f64, t_max: f64) -> Option<f64> {
        self.crossing_at(ray).filter(|&t| t >= t_min && t < t_max)
    }

    /// Where the ray's line crosses the rectangle (its edges included), at any `t`.
    #[inline]
    pub fn crossing_at(&self, ray: &Probe) -> Option<f64> {
        let (t, x, y) = self.crossing(ray);
        let inside =
            (self.min[0]..=self.max[0]).contains(&x) && (self.min[1]..=self.max[1]).contains(&y);
        inside.then_some(t)
    }

    /// Whether the ray may meet the rectangle at some `t` in `[t_min, t_max]` (`false` only
    /// when it surely does not): the same crossing, let through within its rounding, of its
    /// distance and of where it lies, so that the object's own test (which decides, for the
    /// lighting models' shadow rules) is never skipped for a ray it would find on an edge.
    #[inline]
    pub fn may_meet(&self, ray: &Probe, t_min: f64, t_max: f64) -> bool {
        let (t, x, y) = self.crossing(ray);
        let slack = SLACK * (t.abs() + 1.0);
        let within =
            |p: f64, k: usize| p >= self.min[k] - self.pad[k] && p <= self.max[k] + self.pad[k];
        t >= t_min - slack && t <= t_max + slack && within(x, 0) && within(y, 1)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{
        point, rotation_x, rotation_y, rotation_z, scaling, translation, vector, Ray,
    };
    use std::f64::consts::{FRAC_PI_2, PI};

    /// A ray from anywhere in a box around the origin (8 × 4 × 8), in any direction, and a
    /// span along it, from the unit numbers `unit` draws: what the tests of the shapes hit in
    /// world space try them with.
    pub(in crate::scene) fn ray_from_anywhere(
        unit: &mut impl FnMut() -> f64,
    ) -> (Point3, Vec3, f64, f64) {
        let origin = point(unit() * 8.0 - 4.0, unit() * 4.0 - 2.0, unit() * 8.0 - 4.0);
        let direction = vector(unit() - 0.5, unit() - 0.5, unit() - 0.5);
        (origin, direction, unit() * 0.1, 0.5 + unit() * 8.0)
    }

    fn rectangle(matrix: glam::DMat4) -> Object {
        Object::new(Shape::Rectangle).with_transform(matrix)
    }

    #[test]
    fn only_a_still_rectangle_along_the_axes_is_level() {
        let wall = rectangle(translation(1.0, 0.0, 0.0) * rotation_z(FRAC_PI_2));
        let level = Level::of(&wall).expect("a wall is level");
        assert_eq!((level.axis, level.at), (0, 1.0));
        assert!(
            Level::of(&rectangle(rotation_y(0.3))).is_none(),
            "turned in its plane"
        );
        assert!(Level::of(&rectangle(rotation_x(0.1))).is_none(), "tilted");
        assert!(Level::of(&Object::cube()).is_none());
    }

    /// Level rectangles placed as a Cornell box places them, and rays from everywhere: the
    /// world-space hit is the object's own (the same `t` to rounding, the same miss), and a
    /// ray that hits is never ruled out by `may_meet`.
    #[test]
    fn a_level_rectangle_is_hit_where_its_own_test_hits_it() {
        let mut rng = SplitMix64::new(5);
        let mut unit = move || rng.next_offset();
        let placements = [
            translation(0.0, -1.0, 0.0),
            translation(0.0, 1.0, 0.0) * rotation_x(PI),
            translation(0.0, 0.0, -1.0) * rotation_x(FRAC_PI_2),
            translation(-1.0, 0.0, 0.0) * rotation_z(-FRAC_PI_2),
            translation(0.0, 0.99, 0.01) * rotation_x(PI) * scaling(0.23, 1.0, 0.19),
            translation(3.0, 0.0, 2.0) * rotation_y(FRAC_PI_2) * scaling(5.0, 1.0, 0.5),
        ];
        let (mut hits, mut disagreements) = (0, 0);
        for matrix in placements {
            let object = rectangle(matrix);
            let level = Level::of(&object).expect("placed along the axes");
            for _ in 0..5000 {
                let (origin, direction, t_min, t_max) = ray_from_anywhere(&mut unit);
                let probe = Probe::new(origin, direction);
                let mine = level.hit(&probe, t_min, t_max);
                let local = object.ray_to_object(&Ray::new(origin, direction));
                let own = object.closest_local_hit(&local, t_min, t_max).map(|h| h.t);
                match (mine, own) {
                    (Some(a), Some(b)) => {
                        hits += 1;
                        assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} against {b}");
                    }
                    (None, None) => {}
                    // Rounding may put a crossing just on either side of an edge or a limit.
                    _ => disagreements += 1,
                }
                if own.is_some() {
                    assert!(level.may_meet(&probe, t_min, t_max));
                }
            }
        }
        assert!(hits > 300, "the rays hit: {hits}");
        assert!(disagreements <= 2, "{disagreements} disagreements");
    }

    #[test]
    fn a_ray_in_the_plane_misses_and_an_edge_counts() {
        let floor = Level::of(&rectangle(translation(0.0, -1.0, 0.0))).unwrap();
        let along = vector(1.0, 0.0, 0.0);
        let on_floor = point(-3.0, -1.0, 0.0);
        assert_eq!(floor.hit(&Probe::new(on_floor, along), 0.0, 10.0), None);
        let down = vector(0.0, -1.0, 0.0);
        let over_edge = point(1.0, 0.0, -1.0);
        let probe = Probe::new(over_edge, down);
        assert_eq!(floor.hit(&probe, 0.0, 5.0), Some(1.0));
        assert_eq!(floor.hit(&probe, 0.0, 1.0), None, "t < t_max");
        let beside = point(1.0 + 1e-6, 0.0, 0.0);
        assert_eq!(floor.hit(&Probe::new(beside, down), 0.0, 5.0), None);
    }
}
