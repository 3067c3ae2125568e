//! Computer Graphics from Scratch's directional light as the path tracer reads it: parallel
//! light from infinitely far away, giving a surface facing it the irradiance
//! `π · intensity · cos θ` (the book lights' meaning). A delta light: only light sampling
//! finds it, so it answers `sample_li` and `power` alone (see the [module](super)).

use super::sample::LightSample;
use crate::color::Color;
use crate::math::Vec3;
use crate::shading::DirectionalLight;
use std::f64::consts::PI;

/// A directional light in the path tracer's light list.
#[derive(Debug, Clone)]
pub struct DirectionalEmitter {
    /// The unit direction towards the light.
    towards: Vec3,
    /// `π · intensity`.
    irradiance: Color,
    power: f64,
}

impl DirectionalEmitter {
    /// The scene's `light`, weighed by what it sends through the scene's cross-section `disc`.
    pub(super) fn new(light: &DirectionalLight, disc: f64) -> Self {
        Self {
            towards: light.direction(),
            irradiance: light.intensity * PI,
            power: light.intensity.luminance() * PI * disc,
        }
    }

    /// The direction towards the light (from any point) and its irradiance, the light picked
    /// with probability `probability`.
    #[inline]
    pub fn sample_li(&self, probability: f64) -> LightSample {
        LightSample {
            direction: self.towards,
            distance: f64::INFINITY,
            radiance: self.irradiance,
            pdf: probability,
            delta: true,
        }
    }

    /// What the light samplers pick it by: its irradiance over the scene's cross-section.
    pub fn power(&self) -> f64 {
        self.power
    }
}
