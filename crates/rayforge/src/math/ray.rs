//! Rays (chapter 5).

use super::{Point3, Transform, Vec3};

/// A ray: an origin and a direction (not necessarily unit length: transformed rays keep the
/// scale of their transform, which is what keeps `t` comparable between world and object space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Point3,
    /// Where it goes, per unit of `t`.
    pub direction: Vec3,
    /// When it is cast, as a fraction of the shutter interval (0 when it opens, 1 when it
    /// closes): moving objects are met where they are at that instant (motion blur).
    pub time: f64,
    /// The nearest `t` at which the ray may hit anything: 0 for most rays; a viewport camera's
    /// rays start counting at its projection plane, `t = 1` (Computer Graphics from Scratch).
    pub t_min: f64,
}

impl Ray {
    /// The book's `ray(origin, direction)`.
    #[inline]
    pub const fn new(origin: Point3, direction: Vec3) -> Self {
        Self {
            origin,
            direction,
            time: 0.0,
            t_min: 0.0,
        }
    }

    /// The same ray, blind to anything before `t_min`.
    #[inline]
    pub const fn from_t(mut self, t_min: f64) -> Self {
        self.t_min = t_min;
        self
    }

    /// The same ray cast at another instant.
    #[inline]
    pub const fn at_time(mut self, time: f64) -> Self {
        self.time = time;
        self
    }

    /// The book's `position(ray, t)`.
    #[inline]
    pub fn position(&self, t: f64) -> Point3 {
        self.origin + self.direction * t
    }

    /// The book's `transform(ray, m)` for a matrix.
    pub fn transform(&self, m: glam::DMat4) -> Self {
        Self::new(
            m.transform_point3(self.origin),
            m.transform_vector3(self.direction),
        )
        .at_time(self.time)
        .from_t(self.t_min)
    }

    /// The ray moved into the object space of `transform` (its inverse applied).
    #[inline]
    pub fn to_object(&self, transform: &Transform) -> Self {
        Self::new(
            transform.inverse_point(self.origin),
            transform.inverse_vector(self.direction),
        )
        .at_time(self.time)
        .from_t(self.t_min)
    }
}
