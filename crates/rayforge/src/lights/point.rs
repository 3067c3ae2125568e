//! The book's point light (chapter 6) as the path tracer reads it: a point that gives a surface
//! facing it the irradiance `π · intensity · cos θ` at every distance, as the book's diffuse
//! term does, or `π · intensity · cos θ / d²` where it falls off with distance (a physical light
//! of its own, or any light under the optics model). A delta light: only light sampling finds it,
//! so it answers `sample_li` and `power` alone (see the [module](super)).

use super::light_bounds::{Cone, LightBounds};
use super::sample::LightSample;
use crate::color::Color;
use crate::math::{Aabb, Point3, Vec3};
use crate::shading::PointLight;
use std::f64::consts::PI;

/// A point light in the path tracer's light list.
#[derive(Debug, Clone)]
pub struct PointEmitter {
    /// The scene's light.
    light: PointLight,
    /// `π · intensity`: the irradiance it gives a surface facing it at unit distance.
    irradiance: Color,
    /// Whether it falls off with the square of the distance (its own choice or the model's).
    falloff: bool,
    power: f64,
}

impl PointEmitter {
    /// The scene's `light` in a world whose lighting model makes every light fall off with
    /// distance when `model_falloff`; `disc` is the scene's cross-section, over which a light
    /// without fall-off is weighed.
    pub(super) fn new(light: &PointLight, model_falloff: bool, disc: f64) -> Self {
        Self {
            light: *light,
            irradiance: light.intensity * PI,
            falloff: model_falloff || light.falloff,
            power: point_power(light.intensity, model_falloff || light.falloff, disc),
        }
    }

    /// The direction towards the light from `point` and the irradiance it brings there, the
    /// light picked with probability `probability` (the sample's `pdf`); `None` at the light
    /// itself, or where it gives nothing.
    #[inline]
    pub fn sample_li(&self, point: Point3, probability: f64) -> Option<LightSample> {
        self.shaped_sample(point, probability, |irradiance, _| irradiance)
    }

    /// [`sample_li`](Self::sample_li) with the irradiance at unit distance shaped by `shape`
    /// from itself and the unit direction towards the light (a spotlight's cone), before the
    /// fall-off with distance.
    #[inline]
    pub(super) fn shaped_sample(
        &self,
        point: Point3,
        probability: f64,
        shape: impl FnOnce(Color, Vec3) -> Color,
    ) -> Option<LightSample> {
        let to_light = self.light.position - point;
        let distance = to_light.length();
        let direction = to_light / distance;
        let mut radiance = shape(self.irradiance, direction);
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

    /// What the light samplers pick it by: its irradiance over a sphere about it where it falls
    /// off, else over the scene's cross-section.
    pub fn power(&self) -> f64 {
        self.power
    }

    /// Its bounds for the light tree: its point, shining every way; `None` without fall-off,
    /// whose light reaches every distance alike (the tree keeps such lights apart).
    pub(super) fn bounds(&self) -> Option<LightBounds> {
        self.bounds_in(Cone::EVERYWHERE)
    }

    /// Its bounds for the light tree if all its light goes into `cone`; `None` without
    /// fall-off.
    pub(super) fn bounds_in(&self, cone: Cone) -> Option<LightBounds> {
        self.falloff
            .then(|| at_point(self.light.position, cone, self.power))
    }
}

/// The power a light of the book's kinds (point, spot, area) is picked by: its irradiance
/// `π · intensity` over a sphere (falling off) or, not falling off, over the scene's
/// cross-section `disc`.
pub(super) fn point_power(intensity: Color, falloff: bool, disc: f64) -> f64 {
    intensity.luminance() * PI * if falloff { 4.0 * PI } else { disc }
}

/// The light tree's bounds of a light at `position` of power `power` shining into `cone`.
pub(super) fn at_point(position: Point3, cone: Cone, power: f64) -> LightBounds {
    LightBounds {
        bounds: Aabb::new(position, position),
        power,
        cone,
        two_sided: false,
    }
}
