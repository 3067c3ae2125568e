//! The book's spotlight (chapter 17's extra) as the path tracer reads it: a point light
//! ([`PointEmitter`](super::PointEmitter)'s meaning) whose light is scaled by the spot's cone,
//! full inside the inner cone, none beyond the outer, a smooth step between
//! ([`SpotLight::falloff`], the same fall-off the Whitted renderers shade with). A delta light,
//! as the point light is.

use super::light_bounds::{Cone, LightBounds};
use super::point::PointEmitter;
use super::sample::LightSample;
use crate::math::Point3;
use crate::shading::{PointLight, SpotLight};

/// A spotlight in the path tracer's light list: a point light with a cone.
#[derive(Debug, Clone)]
pub struct SpotEmitter {
    /// The scene's light.
    light: SpotLight,
    /// The point light it is within its inner cone.
    point: PointEmitter,
}

impl SpotEmitter {
    /// The scene's `light` (see [`PointEmitter::new`](super::PointEmitter) for
    /// `model_falloff` and `disc`).
    pub(super) fn new(light: &SpotLight, model_falloff: bool, disc: f64) -> Self {
        let point = PointLight {
            position: light.position,
            intensity: light.intensity,
            falloff: light.falloff,
        };
        Self {
            light: *light,
            point: PointEmitter::new(&point, model_falloff, disc),
        }
    }

    /// The direction towards the light from `point` and the irradiance it brings there through
    /// its cone, the light picked with probability `probability`; `None` at the light itself
    /// and outside the cone.
    #[inline]
    pub fn sample_li(&self, point: Point3, probability: f64) -> Option<LightSample> {
        self.point
            .shaped_sample(point, probability, |irradiance, direction| {
                irradiance * self.light.falloff(-direction)
            })
    }

    /// What the light samplers pick it by: as a point light's (its whole sphere, though the
    /// cone sends light into part of it).
    pub fn power(&self) -> f64 {
        self.point.power()
    }

    /// Its bounds for the light tree: its point, all its light within the outer cone and none
    /// beyond it; `None` without fall-off.
    pub(super) fn bounds(&self) -> Option<LightBounds> {
        let l = &self.light;
        self.point.bounds_in(Cone {
            axis: l.direction.normalize_or_zero(),
            theta_o: l.cos_outer.clamp(-1.0, 1.0).acos(),
            theta_e: 0.0,
        })
    }
}
