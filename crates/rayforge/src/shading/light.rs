//! Light sources (chapter 6; several per world since chapter 7's extensions).

use crate::math::Point3;
use crate::Color;

/// A point light: no size, so its shadows are hard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    /// Where the light is.
    pub position: Point3,
    /// Its colour and brightness.
    pub intensity: Color,
}

impl PointLight {
    /// The book's `point_light(position, intensity)`.
    pub const fn new(position: Point3, intensity: Color) -> Self {
        Self {
            position,
            intensity,
        }
    }
}

/// A light source of any kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// A point light.
    Point(PointLight),
}

impl Light {
    /// The book's `point_light(position, intensity)` as a [`Light`].
    pub const fn point(position: Point3, intensity: Color) -> Self {
        Light::Point(PointLight::new(position, intensity))
    }

    /// The light's colour and brightness.
    pub fn intensity(&self) -> Color {
        match self {
            Light::Point(l) => l.intensity,
        }
    }

    /// The light's position (for shadow rays and the light vector).
    pub fn position(&self) -> Point3 {
        match self {
            Light::Point(l) => l.position,
        }
    }
}
