//! The scene's lighting model at a pixel or vertex, as far as a rasterizer can follow it: every
//! light is taken as visible (no shadow rays), and nothing arrives by reflection or refraction
//! (no rays at all).
//!
//! - `phong` (The Ray Tracer Challenge): the ray tracer's own [`lighting_with`] per light.
//! - `flat` (Computer Graphics from Scratch's first stage): the surface's colour.
//! - `cgfs` (Computer Graphics from Scratch): the colour times the book's summed intensity.
//! - `optics` (Fundamentals of Ray Tracing): the matte term alone, `opacity · matte ·
//!   Σ (n·l̂)/d² · light` over the point lights (spotlights and area lights count as points, as
//!   the ray tracer counts them; ambient and directional lights add nothing in this model). The
//!   gloss and the transparent share travel on rays the rasterizer does not cast, so a mirror
//!   shows only its matte part and glass is as dark as its opacity leaves it. The image is then
//!   exposed as the ray tracer's is, by its brightest channel (see `render.rs`).

use super::instance::Instance;
use super::shade::ShadeContext;
use crate::color::Color;
use crate::math::random::SplitMix64;
use crate::math::{Point3, Vec3};
use crate::scene::LightingModel;
use crate::shading::cgfs::unshadowed_intensity;
use crate::shading::optics::matte_light;
use crate::shading::{lighting_with, Material};

impl ShadeContext<'_, '_> {
    /// The normal lighting uses at a point: `normal` turned towards the eye (as the ray
    /// tracer's `prepare_computations` does) and tilted by the material's bumps. Under the
    /// optics model a solid keeps its outward normal, as the ray tracer's model does (light
    /// inside a solid does not reach its outside); only surfaces without thickness, and CSG
    /// primitives (a difference's bite shows the inside of what it removes), turn to the eye.
    pub(crate) fn shading_normal(
        &self,
        instance: &Instance<'_>,
        point: Point3,
        normal: Vec3,
        eyev: Vec3,
    ) -> Vec3 {
        let surface = instance.surface;
        let outward = self.lighting == LightingModel::Optics
            && surface.shape.has_volume()
            && instance.csg.is_none();
        let normal = if !outward && normal.dot(eyev) < 0.0 {
            -normal
        } else {
            normal
        };
        match &surface.material.bump {
            Some(bump) => bump.perturb(normal, surface.world_to_object(point), &surface.transform),
            None => normal,
        }
    }

    /// Every light's term at a point, summed, for a surface colour `colour`, under the
    /// scene's lighting model (see the module's notes).
    pub(crate) fn light(
        &self,
        material: &Material,
        colour: Color,
        point: Point3,
        eyev: Vec3,
        normal: Vec3,
    ) -> Color {
        match self.lighting {
            LightingModel::Flat => colour,
            LightingModel::Cgfs => {
                colour * unshadowed_intensity(&self.lights, point, normal, eyev, material.shininess)
            }
            LightingModel::Optics => {
                colour * matte_light(&self.lights, point, normal, |_| true) * material.opacity
            }
            LightingModel::Phong => {
                let mut jitter = SplitMix64::new(0);
                self.lights
                    .iter()
                    .map(|light| {
                        lighting_with(
                            material,
                            colour,
                            light,
                            point,
                            eyev,
                            normal,
                            1.0,
                            &mut jitter,
                        )
                    })
                    .sum()
            }
        }
    }
}
