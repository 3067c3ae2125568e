//! What every integrator works with while it traces: the world and its index, scratch
//! buffers, the count of rays cast, the per-pixel jitter generator, the bailout and the weight
//! of the ray being traced, and the shadow hints; and the one shadow-ray loop they all use.

use crate::math::random::SplitMix64;
use crate::math::Ray;
use crate::scene::{Intersection, Object, World, WorldIndex, NO_OBJECT};
use crate::shading::Light;

/// Lights whose last blocker a tracing state remembers at once.
const SHADOW_HINTS: usize = 4;

/// One thread's tracing state over one world (see the [module](self)). Tracing a ray with it
/// allocates nothing once its buffers have grown to the scene's needs.
#[derive(Debug)]
pub struct TraceState<'w> {
    /// The world traced.
    pub(super) world: &'w World,
    /// Its index, built from it.
    pub(super) index: &'w WorldIndex,
    /// Intersections along a ray (refraction's containers are read from them).
    pub(super) xs: Vec<Intersection<'w>>,
    /// The objects a ray is inside, with their refractive indices.
    pub(super) containers: Vec<(&'w Object, f64)>,
    /// Every ray cast so far: camera, secondary and shadow rays.
    pub(super) rays: u64,
    /// Sample offsets for jittered area lights, reseeded per pixel by the render loop.
    pub(super) jitter: SplitMix64,
    /// Secondary rays and shadow rays that would bring less than this fraction of their light
    /// to the pixel are not traced (see [`TraceState::set_bailout`]).
    pub(super) bailout: f64,
    /// How much of the ray being traced reaches the pixel: the product of the reflectivities
    /// and transparencies on its way from the camera.
    pub(super) weight: f64,
    /// The last object that blocked a shadow ray towards each of a few lights (keyed by the
    /// light's address), tried first by the next (see [`WorldIndex::blocked`]).
    shadow_hints: [(usize, u32); SHADOW_HINTS],
}

impl<'w> TraceState<'w> {
    /// A state for tracing `world`, which `index` must have been built from.
    pub fn new(world: &'w World, index: &'w WorldIndex) -> Self {
        Self {
            world,
            index,
            xs: Vec::with_capacity(16),
            containers: Vec::with_capacity(8),
            rays: 0,
            jitter: SplitMix64::new(0),
            bailout: 0.0,
            weight: 1.0,
            shadow_hints: [(0, NO_OBJECT); SHADOW_HINTS],
        }
    }

    /// The world traced.
    pub fn world(&self) -> &'w World {
        self.world
    }

    /// Adaptive depth control (POV-Ray's `adc_bailout`): under the Phong model, a reflected or
    /// refracted ray whose weight (the product of the reflectivities and transparencies that
    /// lead to it from the camera, with Schlick's share on surfaces that both reflect and
    /// refract) is below `bailout` is not traced, however much depth remains; nor is a shadow
    /// ray whose light, at the weight of the ray that hit, could add less than `bailout` (the
    /// light counts as blocked: see [`crate::shading::most_light`]). With `1/512`, what is left
    /// out is at most about a fifth of one step of an 8-bit channel per ray skipped, and a room
    /// of surfaces that all reflect a little no longer costs `max_depth` rays per pixel. `0`
    /// (the default) follows the book: every bounce up to the depth limit, every shadow ray.
    pub fn set_bailout(&mut self, bailout: f64) {
        self.bailout = if bailout.is_finite() {
            bailout.max(0.0)
        } else {
            0.0
        };
    }

    /// Restarts the sample sequence from `seed` (the render loop passes the pixel's index, so
    /// every pixel's samples are the same whichever thread renders it).
    pub fn reseed(&mut self, seed: u64) {
        self.jitter = SplitMix64::new(seed);
    }

    /// How many rays (camera, reflected, refracted and shadow) have been cast.
    pub fn rays_cast(&self) -> u64 {
        self.rays
    }

    /// Casts a shadow ray (counted): whether an object for which `blocks` holds lies along
    /// `ray` between `t_min` and `t_max` (what `blocks` tests exactly is each lighting model's
    /// own rule). Stops at the first blocker; with `light` given, tries first the object that
    /// last blocked a ray towards it.
    pub fn shadow_test(
        &mut self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        light: Option<&Light>,
        blocks: impl FnMut(&'w Object) -> bool,
    ) -> bool {
        self.rays += 1;
        let mut none = NO_OBJECT;
        let last = match light {
            Some(light) => {
                // The light's address names it for as long as the world lives.
                let key = light as *const Light as usize;
                let slot = (key / std::mem::size_of::<Light>().max(1)) % SHADOW_HINTS;
                if self.shadow_hints[slot].0 != key {
                    self.shadow_hints[slot] = (key, NO_OBJECT);
                }
                &mut self.shadow_hints[slot].1
            }
            None => &mut none,
        };
        self.index
            .blocked(self.world, ray, t_min, t_max, last, blocks)
    }
}
