//! Motion blur's moving transforms: an object placed by one transform when the shutter opens
//! (time 0) and by another when it closes (time 1), and everywhere in between.
//!
//! Interpolating the two matrices entry by entry would shrink a spinning object half way
//! through its turn (the average of two rotations is not a rotation). Instead each matrix is
//! split into translation · rotation · stretch (a polar decomposition: the stretch is a
//! symmetric matrix holding scale and shear), and the parts are interpolated on their own:
//! translation and stretch linearly, rotation along the great arc between two quaternions.
//! This is the scheme of Shoemake and Duff's "Matrix animation and polar decomposition" (1992),
//! which production renderers use for the same reason.
//!
//! A motion may sit between two fixed transforms, `outer · moving(t) · inner`: a shape's own
//! placement (a sphere's radius) inside the transform that moves, and an instance's placement
//! around it. Only the middle one is interpolated, as pbrt-v4's `AnimatedPrimitive`
//! interpolates only its `AnimatedTransform`: interpolating the products would swing an
//! instance's off-centre shape along a chord instead of the arc its instance turns through.

use super::{Aabb, Point3, SingularTransform, Transform};
use glam::{DMat3, DMat4, DQuat, DVec3};

/// One end of a motion, in parts.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Parts {
    translation: DVec3,
    rotation: DQuat,
    stretch: DMat3,
}

impl Parts {
    /// Splits `m = T · R · S` with `R` a proper rotation and `S` symmetric.
    fn of(m: DMat4) -> Self {
        let linear = DMat3::from_mat4(m);
        let mut rotation = linear;
        // Newton's iteration for the orthogonal polar factor: average the matrix with its
        // inverse transpose until it stops changing. Converges quadratically; a few dozen
        // steps reach rounding even for strong stretches.
        for _ in 0..64 {
            let next = (rotation + rotation.inverse().transpose()) * 0.5;
            let change = (next - rotation)
                .to_cols_array()
                .iter()
                .map(|c| c.abs())
                .sum::<f64>();
            rotation = next;
            if change < 1e-14 {
                break;
            }
        }
        // A mirroring transform has an improper orthogonal factor; move the mirror into the
        // stretch so that the rotation can become a quaternion.
        if rotation.determinant() < 0.0 {
            rotation = -rotation;
        }
        let stretch = rotation.transpose() * linear;
        Self {
            translation: m.w_axis.truncate(),
            rotation: DQuat::from_mat3(&rotation).normalize(),
            stretch,
        }
    }

    fn matrix(&self) -> DMat4 {
        DMat4::from_translation(self.translation)
            * DMat4::from_mat3(DMat3::from_quat(self.rotation) * self.stretch)
    }
}

/// A transform that moves while the shutter is open: `start` at time 0, `end` at time 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    start: Transform,
    end: Transform,
    /// The moving transform's two ends, in parts.
    parts: [Parts; 2],
    /// The fixed transforms before and after the moving one (`None`: the identity).
    outer: Option<DMat4>,
    inner: Option<Transform>,
}

impl Motion {
    /// The motion from `start` (time 0) to `end` (time 1).
    pub fn new(start: Transform, end: Transform) -> Self {
        let (a, mut b) = (Parts::of(start.matrix()), Parts::of(end.matrix()));
        // Take the short way round: q and -q are the same rotation.
        if a.rotation.dot(b.rotation) < 0.0 {
            b.rotation = -b.rotation;
        }
        Self {
            start,
            end,
            parts: [a, b],
            outer: None,
            inner: None,
        }
    }

    /// The motion from `start` to `end` applied after the fixed transform `inner` (an
    /// object's own): `moving(t) · inner`, only `moving` interpolated.
    pub fn after(
        start: &Transform,
        end: &Transform,
        inner: &Transform,
    ) -> Result<Self, SingularTransform> {
        let mut motion = Self::new(*start, *end);
        motion.start = start.then_after(inner)?;
        motion.end = end.then_after(inner)?;
        motion.inner = Some(*inner);
        Ok(motion)
    }

    /// The same motion placed by the fixed transform `outer` (applied after it): an
    /// instance's placement of a moving shape.
    pub fn placed_by(&self, outer: &Transform) -> Result<Self, SingularTransform> {
        let mut motion = self.clone();
        motion.start = outer.then_after(&self.start)?;
        motion.end = outer.then_after(&self.end)?;
        motion.outer = Some(match self.outer {
            Some(m) => outer.matrix() * m,
            None => outer.matrix(),
        });
        Ok(motion)
    }

    /// The transform when the shutter opens.
    pub fn start(&self) -> &Transform {
        &self.start
    }

    /// The transform when the shutter closes.
    pub fn end(&self) -> &Transform {
        &self.end
    }

    /// The transform at `time` (clamped to `[0, 1]`). Should an interpolated stretch pass
    /// through a flat matrix (a scale from 1 to -1), the nearer end is used at that instant.
    pub fn at(&self, time: f64) -> Transform {
        let time = if time.is_nan() {
            0.0
        } else {
            time.clamp(0.0, 1.0)
        };
        if time == 0.0 {
            return self.start;
        }
        if time == 1.0 {
            return self.end;
        }
        let [a, b] = &self.parts;
        let parts = Parts {
            translation: a.translation.lerp(b.translation, time),
            rotation: a.rotation.slerp(b.rotation, time),
            stretch: a.stretch * (1.0 - time) + b.stretch * time,
        };
        let mut m = parts.matrix();
        if let Some(outer) = self.outer {
            m = outer * m;
        }
        if let Some(inner) = self.inner {
            m *= inner.matrix();
        }
        Transform::try_new(m).unwrap_or(if time < 0.5 { self.start } else { self.end })
    }

    /// A box around `local` (an object-space box) at every instant of the motion.
    ///
    /// The box is sampled at evenly spaced times and then widened by how far any corner can
    /// travel between two samples: its speed is at most the translation's change, plus the
    /// rotation's angle times the corner's largest distance from the pivot, plus the stretch's
    /// change applied to it (the corners of the box `inner` makes of `local`, and the speed
    /// scaled by at most `outer`'s largest stretch, which its Frobenius norm bounds); any
    /// instant is within half a step of a sample.
    pub fn bounds(&self, local: &Aabb) -> Aabb {
        const STEPS: usize = 32;
        if local.is_empty() {
            return *local;
        }
        let mut out = Aabb::EMPTY;
        for i in 0..=STEPS {
            out = out.union(&local.transform(&self.at(i as f64 / STEPS as f64)));
        }
        if !(local.min.is_finite() && local.max.is_finite()) {
            return out;
        }
        let local = match self.inner {
            Some(inner) => local.transform(&inner),
            None => *local,
        };
        let [a, b] = &self.parts;
        let angle = a.rotation.angle_between(b.rotation);
        let mut speed: f64 = 0.0;
        for corner in 0..8 {
            let c = Point3::new(
                if corner & 1 == 0 {
                    local.min.x
                } else {
                    local.max.x
                },
                if corner & 2 == 0 {
                    local.min.y
                } else {
                    local.max.y
                },
                if corner & 4 == 0 {
                    local.min.z
                } else {
                    local.max.z
                },
            );
            let reach = (a.stretch * c).length().max((b.stretch * c).length());
            let stretch_change = ((b.stretch - a.stretch) * c).length();
            speed = speed.max(angle * reach + stretch_change);
        }
        speed += (b.translation - a.translation).length();
        if let Some(outer) = self.outer {
            let linear = DMat3::from_mat4(outer).to_cols_array();
            speed *= linear.iter().map(|c| c * c).sum::<f64>().sqrt();
        }
        let pad = DVec3::splat(speed / (2.0 * STEPS as f64));
        Aabb::new(out.min - pad, out.max + pad)
    }
}
