//! What every kind of light answers next-event estimation with: one direction towards it from a
//! shading point, the light arriving along it and how likely the choice was.

use crate::color::Color;
use crate::math::Vec3;

/// One direction towards light from a point, chosen by [`Emitters::sample`](super::Emitters::sample)
/// through one kind's `sample_li`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point towards the light.
    pub direction: Vec3,
    /// How far the light is along it (infinite for the sky and directional lights).
    pub distance: f64,
    /// The radiance arriving along `direction`; for a delta light (a point, a direction), the
    /// irradiance it gives a surface facing it, per unit of `pdf`.
    pub radiance: Color,
    /// The solid-angle density of `direction` times the probability of picking this emitter;
    /// for a delta light, that probability alone.
    pub pdf: f64,
    /// Whether the light is a point or a direction, which scattering can never find.
    pub delta: bool,
}
