//! The sky as the path tracer reads it: the world's environment map, importance-sampled by
//! luminance ([`EnvironmentMap`]), else the background as light of constant radiance from every
//! direction. A constant sky is found only by the paths that escape: sampling the BSDF follows
//! a uniform sky as well as light sampling could (perfectly, for a diffuse surface), and a white
//! furnace then has no variance at all.

use super::sample::LightSample;
use crate::color::Color;
use crate::math::Vec3;
use crate::shading::{EnvironmentMap, SkyDraw};
use std::f64::consts::PI;
use std::sync::Arc;

/// The sky of a world: a map, or the constant background.
#[derive(Debug, Clone)]
pub struct SkyEmitter {
    /// The sky when there is no environment map.
    background: Color,
    environment: Option<Arc<EnvironmentMap>>,
}

impl SkyEmitter {
    /// The sky of a world with `background` and, if it has one, `environment`.
    pub(super) fn new(background: Color, environment: Option<Arc<EnvironmentMap>>) -> Self {
        Self {
            background,
            environment,
        }
    }

    /// The environment map, if there is one.
    pub(super) fn map(&self) -> Option<&EnvironmentMap> {
        self.environment.as_deref()
    }

    /// A direction towards the sky from the draw `sky` (made there if no one has made it yet),
    /// the radiance along it, and its solid-angle density times `probability`, the chance the
    /// sky was picked; `None` for a constant sky, which is not sampled, or an empty draw.
    #[inline]
    pub fn sample_li(&self, sky: &mut SkyDraw, probability: f64) -> Option<LightSample> {
        let (direction, radiance, pdf) = sky.of(self.environment.as_ref()?)?;
        Some(LightSample {
            direction,
            distance: f64::INFINITY,
            radiance,
            pdf: probability * pdf,
            delta: false,
        })
    }

    /// The radiance of the sky along `direction` (what a path that escapes sees).
    #[inline]
    pub fn radiance(&self, direction: Vec3) -> Color {
        match &self.environment {
            Some(map) => map.radiance(direction),
            None => self.background,
        }
    }

    /// The radiance along `direction` (as [`radiance`](Self::radiance)) and the solid-angle
    /// density with which [`sample_li`](Self::sample_li) draws it, before the sky's pick: the
    /// map's, in the one look-up both take (the background and 0 for a constant sky, which is
    /// not sampled).
    #[inline]
    pub fn radiance_and_pdf_li(&self, direction: Vec3) -> (Color, f64) {
        match &self.environment {
            Some(map) => map.radiance_and_pdf(direction),
            None => (self.background, 0.0),
        }
    }

    /// What the light samplers pick it by: a map's mean radiance over the scene's cross-section
    /// `disc`; 0 for a constant sky, which is not sampled.
    pub fn power(&self, disc: f64) -> f64 {
        self.environment
            .as_ref()
            .map_or(0.0, |map| map.average_radiance().luminance() * PI * disc)
    }
}
