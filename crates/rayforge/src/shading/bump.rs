//! Normal perturbation (a chapter 17 "next step"): bumps that tilt the shading normal without
//! moving the surface, so a flat plane looks like water or stucco, and normal maps, images
//! whose pixels are the normal itself in the surface's tangent frame.

use super::noise::perlin_noise;
use super::texture::{Texture, UvMapping};
use crate::math::{Point3, Transform, Vec3};
use std::sync::Arc;

/// A bump function, evaluated in its own space (placed by `transform` relative to the object).
#[derive(Debug, Clone, PartialEq)]
pub struct Bump {
    /// The kind of bumps.
    pub kind: BumpKind,
    /// Bump space relative to the object's space.
    pub transform: Transform,
}

/// The kinds of bump.
#[derive(Debug, Clone, PartialEq)]
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
    /// A normal map: each pixel's (r, g, b) in [0, 1] is the normal `2·c − 1` in the tangent
    /// frame of the mapping (red along increasing u, green along increasing v, blue out of
    /// the surface: the OpenGL convention), wrapped onto the surface by `mapping`.
    NormalMap {
        /// The image, read as raw values (no colour-space decoding).
        map: Arc<Texture>,
        /// How surface points find their (u, v).
        mapping: UvMapping,
        /// Scales the tilt: 0 leaves the surface flat, 1 is the map as painted.
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

    /// The tilt to add to the normal at an object-space point, in object space (none for a
    /// normal map, which replaces the normal instead: see [`Bump::perturb`]).
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
            BumpKind::NormalMap { .. } => Vec3::ZERO,
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
        if let BumpKind::NormalMap {
            map,
            mapping,
            strength,
        } = &self.kind
        {
            let object_normal = object_transform.normal_to_object(world_normal);
            let normal = self.transform.normal_to_object(object_normal);
            let p = self.transform.inverse_point(object_point);
            return match mapped_normal(map, *mapping, *strength, p, normal) {
                Some(n) => object_transform.normal(self.transform.normal(n)),
                None => world_normal,
            };
        }
        let tilt = object_transform.vector(self.tilt(object_point));
        (world_normal + tilt).normalize_or(world_normal)
    }
}

/// The normal a normal map gives at `p` (in bump space, where the surface's unit normal is
/// `normal`), or `None` where the mapping has no tangent frame (a sphere's poles).
///
/// The tangent frame is the gradient of u and of v along the surface, found by central
/// differences of the mapping itself, so it suits every mapping without a formula per mapping,
/// and is always consistent with where the image lands. A difference that crosses the
/// mapping's seam (u jumping from 1 to 0) is unwrapped.
fn mapped_normal(
    map: &Texture,
    mapping: UvMapping,
    strength: f64,
    p: Point3,
    normal: Vec3,
) -> Option<Vec3> {
    let h = 1e-5 * p.length().max(1.0);
    let wrap = |d: f64| d - d.round();
    let mut du = Vec3::ZERO;
    let mut dv = Vec3::ZERO;
    for axis in 0..3 {
        let mut step = Vec3::ZERO;
        step[axis] = h;
        let (u1, v1) = mapping.map(p + step);
        let (u0, v0) = mapping.map(p - step);
        du[axis] = wrap(u1 - u0);
        dv[axis] = wrap(v1 - v0);
    }
    let tangent = (du - normal * du.dot(normal)).try_normalize()?;
    let bitangent = (dv - normal * dv.dot(normal) - tangent * dv.dot(tangent)).try_normalize()?;
    let (u, v) = mapping.map(p);
    let c = map.sample(u, v);
    let (x, y, z) = (2.0 * c.red - 1.0, 2.0 * c.green - 1.0, 2.0 * c.blue - 1.0);
    (tangent * (x * strength) + bitangent * (y * strength) + normal * z).try_normalize()
}
