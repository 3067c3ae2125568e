//! A homogeneous medium: the same absorption, scattering and emission everywhere it fills.
//! Where it ends is told by the surfaces that bound it (an object's interior, or the world's
//! medium around everything), not by the medium itself.

use super::phase::HenyeyGreenstein;
use crate::color::Color;

/// Coefficients constant in space (per unit of distance, per RGB channel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Homogeneous {
    /// Absorption coefficient σa.
    pub sigma_a: Color,
    /// Scattering coefficient σs.
    pub sigma_s: Color,
    /// Radiance emitted per unit of absorption (pbrt-v4's `Le`: the medium gives σa·Le per
    /// unit length).
    pub emission: Color,
    /// How it scatters.
    pub phase: HenyeyGreenstein,
}

impl Homogeneous {
    /// The extinction coefficient σt = σa + σs.
    #[inline]
    pub fn sigma_t(&self) -> Color {
        self.sigma_a + self.sigma_s
    }
}
