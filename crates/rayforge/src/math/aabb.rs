//! Axis-aligned bounding boxes (the bonus chapter "Bounding boxes and hierarchies").
//!
//! Boxes may be infinite (planes, uncapped cylinders). Every operation here is written so that
//! infinities never meet a zero and produce NaN: transforms use interval arithmetic that treats
//! `0 · ∞` as 0, and the slab test orders its comparisons so a NaN cannot make a miss a hit.

use super::{Point3, Ray, Transform};
use glam::DVec3;

/// An axis-aligned box from `min` to `max`; empty when any `min` exceeds its `max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: Point3,
    /// The corner with the largest coordinates.
    pub max: Point3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The box that contains nothing: adding a point makes it that point.
    pub const EMPTY: Self = Self {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The box that contains everything.
    pub const INFINITE: Self = Self {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };

    /// The book's `bounding_box(min, max)`.
    pub const fn new(min: Point3, max: Point3) -> Self {
        Self { min, max }
    }

    /// Whether the box contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// The book's `add_point(box, point)`: grows the box to include `point`.
    pub fn add_point(&mut self, p: Point3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The book's `add_boxes(a, b)`: the smallest box containing both.
    pub fn union(&self, other: &Self) -> Self {
        Self::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// The book's `box_contains_point`.
    pub fn contains_point(&self, p: Point3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// The book's `box_contains_box`.
    pub fn contains_box(&self, other: &Self) -> bool {
        self.contains_point(other.min) && self.contains_point(other.max)
    }

    /// The centre of the box (infinite boxes have non-finite centres).
    pub fn centroid(&self) -> Point3 {
        (self.min + self.max) * 0.5
    }

    /// The size along each axis.
    pub fn extent(&self) -> DVec3 {
        (self.max - self.min).max(DVec3::ZERO)
    }

    /// Half the surface area (the SAH's cost measure; the factor 2 cancels).
    pub fn half_area(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// The book's `transform(box, matrix)`: the axis-aligned box around the transformed box.
    ///
    /// Computed per axis with interval arithmetic (Arvo's method), which equals transforming the
    /// eight corners, and where an infinite extent times a zero matrix entry contributes nothing.
    pub fn transform(&self, transform: &Transform) -> Self {
        if self.is_empty() {
            return *self;
        }
        let m = transform.matrix();
        let translation = m.w_axis.truncate();
        let mut out = Self::new(translation, translation);
        for col in 0..3 {
            let axis = m.col(col).truncate();
            for row in 0..3 {
                let a = axis[row];
                if a == 0.0 {
                    continue;
                }
                let (lo, hi) = (a * self.min[col], a * self.max[col]);
                out.min[row] += lo.min(hi);
                out.max[row] += lo.max(hi);
            }
        }
        out
    }

    /// The book's `intersects(box, ray)`: whether the ray's line meets the box at any `t` in
    /// `[t_min, t_max]`. Uses the precomputed reciprocal direction (`1/d`, infinite for zero
    /// components) so a parallel ray is handled without special cases.
    #[inline]
    pub fn hit_by(
        &self,
        origin: Point3,
        inv_direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<f64> {
        let t0 = (self.min - origin) * inv_direction;
        let t1 = (self.max - origin) * inv_direction;
        // A NaN comes from 0 · ∞: the ray runs parallel to a slab with its origin exactly on
        // one of the slab's faces, so it is inside that slab for every t.
        let on_face = t0.is_nan_mask() | t1.is_nan_mask();
        let lo = DVec3::select(on_face, DVec3::NEG_INFINITY, t0.min(t1));
        let hi = DVec3::select(on_face, DVec3::INFINITY, t0.max(t1));
        let near = lo.max_element().max(t_min);
        let far = hi.min_element().min(t_max);
        (near <= far).then_some(near)
    }

    /// Whether `ray` meets the box at any `t` (the book's test, over the whole line).
    pub fn intersects(&self, ray: &Ray) -> bool {
        self.hit_by(
            ray.origin,
            ray.direction.recip(),
            f64::NEG_INFINITY,
            f64::INFINITY,
        )
        .is_some()
    }

    /// The book's `split_bounds(box)`: halves along the longest axis.
    pub fn split(&self) -> (Self, Self) {
        let e = self.extent();
        let axis = if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        };
        let mid = self.min[axis] + e[axis] / 2.0;
        let (mut left_max, mut right_min) = (self.max, self.min);
        left_max[axis] = mid;
        right_min[axis] = mid;
        (
            Self::new(self.min, left_max),
            Self::new(right_min, self.max),
        )
    }
}
