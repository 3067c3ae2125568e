//! A ray prepared for a BVH walk: single precision, in the hierarchy's own frame, with what
//! every box and triangle test needs computed once per ray instead of once per test.
//!
//! The hierarchy stores its boxes (and a mesh its triangles) in `f32`, relative to a base
//! point at the centre of everything it holds. A ray far from that point would lose its
//! precision in `f32`, so before the conversion its origin is slid along the ray to the point
//! nearest the base: every coordinate the tests see is then no larger than the hierarchy
//! itself, whatever the ray's own distance (a camera a million units away sees the same
//! sharp triangles). Distances along the ray are kept relative to that slide (`shift`), and
//! [`RayQuery::t_below`] and [`RayQuery::t_above`] convert the caller's `f64` limits with
//! rounding that never narrows them.

use crate::math::Point3;
use glam::DVec3;
use wide::f32x4;

/// Reciprocal direction components are clamped to this magnitude: a zero component gives a
/// huge but finite slope, so a slab test never computes `0 · ∞` (which is NaN) and a box
/// whose face lies exactly on the ray still has a well-defined entry and exit.
const MAX_SLOPE: f32 = 1.0e30;

/// The most `origin / direction` may be on any axis, below `f32::MAX` by a margin. A box's
/// plane `p` is crossed at `p · inv − origin / direction`; if the offset overflowed to ∞ (an
/// origin 10^29 units out, a direction nearly parallel to that axis), the crossing would be
/// `∞ − ∞` (NaN) computed in two steps, or ±∞ of the wrong sign in one fused step, and the
/// box would be missed. Keeping the offset finite keeps the crossing's sign right whichever
/// way it is computed: a product that overflows then outweighs the offset.
const MAX_OFFSET: f32 = 1.0e38;

/// A ray in a hierarchy's `f32` frame.
#[derive(Debug, Clone, Copy)]
pub struct RayQuery {
    /// The origin relative to the base point, slid along the ray by `shift`.
    pub(crate) origin: [f32; 3],
    /// `1 / direction`, clamped to ±[`MAX_SLOPE`].
    pub(crate) inv_direction: [f32; 3],
    /// `origin / direction`: a slab's plane `p` is crossed at `p · inv - origin_over_direction`
    /// (one fused multiply-add where the processor has it).
    pub(crate) origin_over_direction: [f32; 3],
    /// Per axis, which of a node's six plane rows the ray enters through (the minimum when
    /// it travels up the axis, the maximum when it travels down)…
    pub(crate) entry_plane: [usize; 3],
    /// …and which it leaves through.
    pub(crate) exit_plane: [usize; 3],
    /// The direction in `f32` (what a triangle test sets itself up from).
    pub(crate) direction: [f32; 3],
    /// How far the origin was slid: a `t` of the query is `t - shift` of the original ray.
    pub(crate) shift: f64,
}

impl RayQuery {
    /// Prepares the ray `origin + t·direction` for a hierarchy whose frame is centred on
    /// `base`.
    #[inline]
    pub fn new(base: Point3, origin: Point3, direction: DVec3) -> Self {
        let shift = (base - origin).dot(direction) / direction.length_squared();
        let shift = if shift.is_finite() { shift } else { 0.0 };
        let o = (origin - base + direction * shift).as_vec3().to_array();
        let d = direction.as_vec3().to_array();
        // The slope is clamped so that `origin · slope` stays within MAX_OFFSET. The lower
        // clamp only bites for a ray `reach` > 10^8 units from the base whose direction (about
        // a unit long) is within `reach` · 10^-38 of parallel to an axis: across the whole of
        // a frame (at most 10^30 wide) it moves less along that axis than a sixth of what f32
        // resolves at that distance, so to f32 it is parallel anyway.
        let reach = o[0].abs().max(o[1].abs()).max(o[2].abs());
        let slope = if reach > MAX_OFFSET / MAX_SLOPE {
            slope_far_away(reach)
        } else {
            MAX_SLOPE
        };
        // One four-lane division for all three reciprocals; the clamp also turns a NaN
        // into a finite slope (`fast_max` picks its second operand over a NaN).
        let inv = (f32x4::ONE / f32x4::new([d[0], d[1], d[2], 1.0]))
            .fast_max(f32x4::splat(-slope))
            .fast_min(f32x4::splat(slope))
            .to_array();
        let negative = [inv[0] < 0.0, inv[1] < 0.0, inv[2] < 0.0];
        let plane = |axis: usize, far: bool| axis + 3 * usize::from(negative[axis] != far);
        Self {
            origin: o,
            inv_direction: [inv[0], inv[1], inv[2]],
            // Written out rather than with `array::map`, which the optimiser does not always
            // see through (its drain machinery cost a tenth of a path tracer's time).
            origin_over_direction: [o[0] * inv[0], o[1] * inv[1], o[2] * inv[2]],
            entry_plane: [plane(0, false), plane(1, false), plane(2, false)],
            exit_plane: [plane(0, true), plane(1, true), plane(2, true)],
            direction: d,
            shift,
        }
    }

    /// The query's `t` for the original ray's `t`, rounded down (a lower limit that never
    /// excludes what the `f64` limit includes).
    #[inline]
    pub fn t_below(&self, t: f64) -> f32 {
        let relative = t - self.shift;
        let r = relative as f32;
        if (r as f64) > relative {
            r.next_down()
        } else {
            r
        }
    }

    /// The query's `t` for the original ray's `t`, rounded up (an upper limit).
    #[inline]
    pub fn t_above(&self, t: f64) -> f32 {
        let relative = t - self.shift;
        let r = relative as f32;
        if (r as f64) < relative {
            r.next_up()
        } else {
            r
        }
    }

    /// The original ray's `t` for a query's `t`.
    #[inline]
    pub fn t_of(&self, t: f32) -> f64 {
        self.shift + t as f64
    }
}

/// The slope limit of a ray `reach` units from the base (beyond `MAX_OFFSET / MAX_SLOPE`).
/// Out of line: almost no ray needs it, and computed in line the division would sit on every
/// ray's path to its first box test.
#[cold]
#[inline(never)]
fn slope_far_away(reach: f32) -> f32 {
    if reach.is_finite() {
        MAX_OFFSET / reach
    } else {
        MAX_SLOPE
    }
}
