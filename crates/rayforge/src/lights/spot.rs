//! The book's spotlight (chapter 17's extra) as the path tracer reads it: a point light
//! ([`PointEmitter`](super::PointEmitter)'s meaning) whose light is scaled by the spot's cone,
//! full inside the inner cone, none beyond the outer, a smooth step between
//! ([`SpotLight::falloff`], the same fall-off the Whitted renderers shade with).

use super::light_bounds::{Cone, LightBounds};
use super::point::{at_point, point_power};
use super::sample::LightSample;
use crate::color::Color;
use crate::math::Point3;
use crate::shading::SpotLight;
use std::f64::consts::PI;

/// A spotlight in the path tracer's light list.
#[derive(Debug, Clone)]
pub struct SpotEmitter {
    /// The scene's light.
    light: SpotLight,
    /// `π · intensity`: the irradiance it gives a surface facing it, inside its inner cone, at
    /// unit distance.
    irradiance: Color,
    /// Whether it falls off with the square of the distance (its own choice or the model's).
    falloff: bool,
    power: f64,
}

impl SpotEmitter {
    /// The scene's `light` (see [`PointEmitter::new`](super::PointEmitter) for
    /// `model_falloff` and `disc`).
    pub(super) fn new(light: &SpotLight, model_falloff: bool, disc: f64) -> Self {
        Self {
            light: *light,
            irradiance: light.intensity * PI,
            falloff: model_falloff || light.falloff,
            power: point_power(light.intensity, model_falloff || light.falloff, disc),
        }
    }

    /// The direction towards the light from `point` and the irradiance it brings there through
    /// its cone, the light picked with probability `probability`; `None` at the light itself
    /// and outside the cone.
    #[inline]
    pub fn sample_li(&self, point: Point3, probability: f64) -> Option<LightSample> {
        let to_light = self.light.position - point;
        let distance = to_light.length();
        let direction = to_light / distance;
        let cone = self.light.falloff(-direction);
        let mut radiance = self.irradiance * cone;
        if self.falloff {
            radiance = radiance * (1.0 / (distance * distance));
        }
        (radiance.max_channel() > 0.0 && distance > 0.0).then_some(LightSample {
            direction,
            distance,
            radiance,
            pdf: probability,
            delta: true,
        })
    }

    /// The density of a direction scattering found: 0, a point is never met.
    pub fn pdf_li(&self) -> f64 {
        0.0
    }

    /// What a ray sees that passes through it: nothing, a point has no area.
    pub fn radiance(&self) -> Color {
        Color::BLACK
    }

    /// What the light samplers pick it by: as a point light's (its whole sphere, though the
    /// cone sends light into part of it).
    pub fn power(&self) -> f64 {
        self.power
    }

    /// Its bounds for the light tree: its point, all its light within the outer cone and none
    /// beyond it; `None` without fall-off.
    pub(super) fn bounds(&self) -> Option<LightBounds> {
        let l = &self.light;
        self.falloff.then(|| {
            let cone = Cone {
                axis: l.direction.normalize_or_zero(),
                theta_o: l.cos_outer.clamp(-1.0, 1.0).acos(),
                theta_e: 0.0,
            };
            at_point(l.position, cone, self.power)
        })
    }
}
