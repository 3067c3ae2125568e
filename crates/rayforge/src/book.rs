//! The book's one-call API: the entry points of *The Ray Tracer Challenge* that trace or shade
//! in one call, over the renderer's own pieces, so that the book's scenarios read naturally as
//! tests.
//!
//! - [`BookWorld`]: `color_at`, `shade_hit`, `reflected_color`, `refracted_color`,
//!   `intensity_at` and `is_shadowed` on a [`World`] (each builds the world's index and traces
//!   with its lighting model's integrator);
//! - [`Tracer`]: the same, reusing one index and one tracing state between calls (and counting
//!   rays), for tests that ask many questions of one world;
//! - [`lighting`], [`BookMaterial::color_at`] and [`BookPattern::color_at_object`]: the book's
//!   shading functions that take the object as an argument.
//!
//! This module sits on top of everything and nothing in the crate uses it: renders go through
//! [`crate::render`], which picks an integrator once per render.

use crate::color::Color;
use crate::math::random::SplitMix64;
use crate::math::{Point3, Ray, Vec3};
use crate::render::integrator::{dispatch, TraceState, Whitted};
use crate::render::OneRay;
use crate::scene::{Computations, Object, World, WorldIndex};
use crate::shading::{lighting_with, Light, Material, Pattern, SurfacePoint};

/// Traces rays through one world with the world's lighting model, reusing its index and its
/// buffers between calls (the book's functions, as methods).
#[derive(Debug)]
pub struct Tracer<'w> {
    state: TraceState<'w>,
}

impl<'w> Tracer<'w> {
    /// A tracer for `world`, which `index` must have been built from.
    pub fn new(world: &'w World, index: &'w WorldIndex) -> Self {
        Self {
            state: TraceState::new(world, index),
        }
    }

    /// Adaptive depth control: see [`TraceState::set_bailout`].
    pub fn set_bailout(&mut self, bailout: f64) {
        self.state.set_bailout(bailout);
    }

    /// How many rays (camera, reflected, refracted and shadow) this tracer has cast.
    pub fn rays_cast(&self) -> u64 {
        self.state.rays_cast()
    }

    /// The book's `color_at(world, ray, remaining)`: the colour seen along `ray`, following
    /// reflections and refractions `remaining` deep, under the world's lighting model (black
    /// for a ray the optics model finds ambiguous).
    pub fn color_at(&mut self, ray: &Ray, remaining: u32) -> Color {
        let model = self.state.world().lighting;
        dispatch(model, OneRay(&mut self.state, ray, remaining)).unwrap_or(Color::BLACK)
    }

    /// The book's `shade_hit(world, comps, remaining)` (the Phong model).
    pub fn shade_hit(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        Whitted::shade_hit(&mut self.state, comps, remaining)
    }

    /// The book's `reflected_color(world, comps, remaining)` (the Phong model).
    pub fn reflected_color(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        Whitted::reflected_color(&mut self.state, comps, remaining)
    }

    /// The book's `refracted_color(world, comps, remaining)` (the Phong model).
    pub fn refracted_color(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        Whitted::refracted_color(&mut self.state, comps, remaining)
    }

    /// The book's `intensity_at(light, point, world)`: the fraction of `light` that reaches
    /// `point`: 0 or 1 for a point light, the fraction of unblocked samples for an area light.
    pub fn intensity_at(&mut self, light: &Light, point: Point3) -> f64 {
        self.intensity_at_time(light, point, 0.0)
    }

    /// [`Tracer::intensity_at`] at an instant of the shutter interval (what moving objects
    /// block depends on where they are).
    pub fn intensity_at_time(&mut self, light: &Light, point: Point3, time: f64) -> f64 {
        Whitted::intensity_at(&mut self.state, light, point, time)
    }

    /// The book's `is_shadowed(world, light_position, point)`: whether an object that casts
    /// shadows lies between `point` and `light_position`. Stops at the first blocker found.
    pub fn is_shadowed(&mut self, light_position: Point3, point: Point3) -> bool {
        self.is_shadowed_at(light_position, point, 0.0)
    }

    /// [`Tracer::is_shadowed`] at an instant of the shutter interval.
    pub fn is_shadowed_at(&mut self, light_position: Point3, point: Point3, time: f64) -> bool {
        Whitted::is_shadowed(&mut self.state, light_position, point, time)
    }
}

/// The book's world functions that trace (chapters 7, 8 and 11), as methods of [`World`]. Each
/// call indexes the world afresh; a [`Tracer`] keeps one index for many calls.
pub trait BookWorld {
    /// The book's `color_at(world, ray, remaining)`.
    fn color_at(&self, ray: &Ray, remaining: u32) -> Color;
    /// The book's `shade_hit(world, comps, remaining)`.
    fn shade_hit(&self, comps: &Computations<'_>, remaining: u32) -> Color;
    /// The book's `reflected_color(world, comps, remaining)`.
    fn reflected_color(&self, comps: &Computations<'_>, remaining: u32) -> Color;
    /// The book's `refracted_color(world, comps, remaining)`.
    fn refracted_color(&self, comps: &Computations<'_>, remaining: u32) -> Color;
    /// The book's `intensity_at(light, point, world)`.
    fn intensity_at(&self, light: &Light, point: Point3) -> f64;
    /// The book's `is_shadowed(world, light_position, point)`.
    fn is_shadowed(&self, light_position: Point3, point: Point3) -> bool;
}

impl BookWorld for World {
    fn color_at(&self, ray: &Ray, remaining: u32) -> Color {
        Tracer::new(self, &WorldIndex::build(self)).color_at(ray, remaining)
    }

    fn shade_hit(&self, comps: &Computations<'_>, remaining: u32) -> Color {
        Tracer::new(self, &WorldIndex::build(self)).shade_hit(comps, remaining)
    }

    fn reflected_color(&self, comps: &Computations<'_>, remaining: u32) -> Color {
        Tracer::new(self, &WorldIndex::build(self)).reflected_color(comps, remaining)
    }

    fn refracted_color(&self, comps: &Computations<'_>, remaining: u32) -> Color {
        Tracer::new(self, &WorldIndex::build(self)).refracted_color(comps, remaining)
    }

    fn intensity_at(&self, light: &Light, point: Point3) -> f64 {
        Tracer::new(self, &WorldIndex::build(self)).intensity_at(light, point)
    }

    fn is_shadowed(&self, light_position: Point3, point: Point3) -> bool {
        Tracer::new(self, &WorldIndex::build(self)).is_shadowed(light_position, point)
    }
}

/// The book's `lighting(material, object, light, point, eyev, normalv, light_fraction)`.
///
/// `light_fraction` replaces chapter 8's `in_shadow` flag: the fraction of the light that
/// reaches the point (0.0 in shadow, 1.0 fully lit; between for a partly hidden area light).
/// Ambient light is never shadowed. A jittered area light draws its sample offsets from a
/// fixed seed here; renders use [`lighting_with`] and a per-pixel generator.
#[allow(clippy::too_many_arguments)]
pub fn lighting(
    material: &Material,
    object: &Object,
    light: &Light,
    point: Point3,
    eyev: Vec3,
    normalv: Vec3,
    light_fraction: f64,
) -> Color {
    let mut jitter = SplitMix64::new(0);
    let surface = material.color_at(object, point, None, 0.0);
    lighting_with(
        material,
        surface,
        light,
        point,
        eyev,
        normalv,
        light_fraction,
        &mut jitter,
    )
}

/// The book's material colour on an object: the pattern hook of chapter 10.
pub trait BookMaterial {
    /// The surface colour at a world-space point (on `object` as it was at `time`): the texture
    /// at the surface's coordinates when both exist, else the pattern, else the plain colour.
    fn color_at(&self, object: &Object, point: Point3, uv: Option<(f64, f64)>, time: f64) -> Color;
}

impl BookMaterial for Material {
    fn color_at(&self, object: &Object, point: Point3, uv: Option<(f64, f64)>, time: f64) -> Color {
        let at = SurfacePoint {
            uv,
            vertex_color: None,
        };
        self.surface_color(&at, || object.world_to_object_at(point, time))
    }
}

/// The book's pattern on an object (chapter 10).
pub trait BookPattern {
    /// The book's `pattern_at_shape(pattern, object, world_point)`.
    fn color_at_object(&self, object: &Object, world_point: Point3) -> Color;
}

impl BookPattern for Pattern {
    fn color_at_object(&self, object: &Object, world_point: Point3) -> Color {
        self.nested_at(object.world_to_object(world_point))
    }
}
