//! The book's four-component tuple (chapter 1).
//!
//! The renderer itself uses [`glam::DVec3`] for points and vectors; this type exists so that the
//! chapter's scenarios (tuples with `w`, adding a point to a vector, …) have the API they describe.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A tuple `(x, y, z, w)`: a point when `w = 1`, a vector when `w = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tuple {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
    /// z component.
    pub z: f64,
    /// 1 for points, 0 for vectors.
    pub w: f64,
}

impl Tuple {
    /// A tuple from its four components.
    pub const fn new(x: f64, y: f64, z: f64, w: f64) -> Self {
        Self { x, y, z, w }
    }
    /// A point: `w = 1`.
    pub const fn point(x: f64, y: f64, z: f64) -> Self {
        Self::new(x, y, z, 1.0)
    }
    /// A vector: `w = 0`.
    pub const fn vector(x: f64, y: f64, z: f64) -> Self {
        Self::new(x, y, z, 0.0)
    }
    /// Whether `w` is 1.
    pub fn is_point(self) -> bool {
        self.w == 1.0
    }
    /// Whether `w` is 0.
    pub fn is_vector(self) -> bool {
        self.w == 0.0
    }
    /// Length of the tuple (all four components, as the book defines it).
    pub fn magnitude(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// The tuple scaled to magnitude 1.
    pub fn normalize(self) -> Self {
        self / self.magnitude()
    }
    /// Dot product over all four components.
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z + self.w * o.w
    }
    /// Cross product of two vectors (a vector).
    pub fn cross(self, o: Self) -> Self {
        Self::vector(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// The components as a `glam` 4-vector, for matrix products.
    pub fn to_dvec4(self) -> glam::DVec4 {
        glam::DVec4::new(self.x, self.y, self.z, self.w)
    }
    /// A tuple from a `glam` 4-vector.
    pub fn from_dvec4(v: glam::DVec4) -> Self {
        Self::new(v.x, v.y, v.z, v.w)
    }
}

impl Add for Tuple {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z, self.w + o.w)
    }
}

impl Sub for Tuple {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z, self.w - o.w)
    }
}

impl Neg for Tuple {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z, -self.w)
    }
}

impl Mul<f64> for Tuple {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s, self.w * s)
    }
}

impl Div<f64> for Tuple {
    type Output = Self;
    fn div(self, s: f64) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s, self.w / s)
    }
}

impl Mul<Tuple> for glam::DMat4 {
    type Output = Tuple;
    fn mul(self, t: Tuple) -> Tuple {
        Tuple::from_dvec4(self * t.to_dvec4())
    }
}
