//! Normal perturbation (a chapter 17 "next step"): bumps that tilt the shading normal without
//! moving the surface, so a flat plane looks like water or stucco.

use super::noise::perlin_noise;
use crate::math::{Point3, Transform, Vec3};

/// A bump function, evaluated in its own space (placed by `transform` relative to the object).
#[derive(Debug, Clone, PartialEq)]
pub struct Bump {
    /// The kind of bumps.
    pub kind: BumpKind,
    /// Bump space relative to the object's space.
    pub transform: Transform,
}

/// The kinds of bump.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BumpKind {
    /// Ripples: sine waves along x and z with the given wavelength and slope.
    Waves {
        /// How much the normal tilts (the waves' steepest slope).
        amplitude: f64,
        /// Distance between crests.
        wavelength: f64,
    },
    /// Irregular bumps from 3D Perlin noise.
    Noise {
        /// How much the normal tilts.
        strength: f64,
    },
}

impl Bump {
    /// A bump in the object's own space.
    pub fn new(kind: BumpKind) -> Self {
        Self {
            kind,
            transform: Transform::IDENTITY,
        }
    }

    /// The tilt to add to the normal at an object-space point, in object space.
    pub fn tilt(&self, object_point: Point3) -> Vec3 {
        let p = self.transform.inverse_point(object_point);
        let tilt = match self.kind {
            BumpKind::Waves {
                amplitude,
                wavelength,
            } => {
                let k = std::f64::consts::TAU / wavelength.abs().max(1e-9);
                // The gradient of sin(kx)·sin(kz): a smooth egg-crate of ripples.
                Vec3::new(
                    (k * p.x).cos() * (k * p.z).sin(),
                    0.0,
                    (k * p.x).sin() * (k * p.z).cos(),
                ) * amplitude
            }
            BumpKind::Noise { strength } => {
                Vec3::new(
                    perlin_noise(p),
                    perlin_noise(p + Vec3::new(17.3, 9.1, -4.7)),
                    perlin_noise(p + Vec3::new(-8.9, 31.7, 12.3)),
                ) * strength
            }
        };
        self.transform.vector(tilt)
    }

    /// The normal at an object-space point tilted by the bumps: `world_normal` plus the tilt
    /// carried into world space by `normal_transform`, normalised.
    pub fn perturb(
        &self,
        world_normal: Vec3,
        object_point: Point3,
        object_transform: &Transform,
    ) -> Vec3 {
        let tilt = object_transform.vector(self.tilt(object_point));
        (world_normal + tilt).normalize_or(world_normal)
    }
}
