//! Shapes in object space: each file holds one shape's intersection and normal.
//!
//! [`Shape`] is a closed enum (no virtual calls on the hot path); every method is one `match`
//! forwarding to the shape's own module. Rays arrive already in object space; transforms are the
//! business of [`crate::Object`].

mod cube;
mod plane;
mod sphere;

use crate::math::{Point3, Ray, Vec3};

/// A primitive shape in its own object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// The unit sphere at the origin (chapter 5).
    Sphere,
    /// The xz plane through the origin, normal +y (chapter 9).
    Plane,
    /// The axis-aligned cube from -1 to 1 on every axis (chapter 12).
    Cube,
}

impl Shape {
    /// Calls `hit(t)` for every intersection of the object-space `ray` with the shape, in
    /// increasing `t` (negative `t` included: refraction needs the whole list).
    #[inline]
    pub fn intersect(&self, ray: &Ray, hit: impl FnMut(f64)) {
        match self {
            Shape::Sphere => sphere::intersect(ray, hit),
            Shape::Plane => plane::intersect(ray, hit),
            Shape::Cube => cube::intersect(ray, hit),
        }
    }

    /// The object-space normal at an object-space point on the surface (not normalised for
    /// every shape: the caller normalises after the normal transform).
    #[inline]
    pub fn normal_at(&self, point: Point3) -> Vec3 {
        match self {
            Shape::Sphere => sphere::normal_at(point),
            Shape::Plane => plane::normal_at(point),
            Shape::Cube => cube::normal_at(point),
        }
    }
}
