//! The Whitted tracer (chapters 7, 8 and 11): `color_at`, `shade_hit`, shadows, reflection and
//! refraction, with per-thread scratch buffers so that tracing a ray allocates nothing.

use super::cgfs::Stage;
use super::computations::prepare_computations_with;
use super::index::NO_OBJECT;
use super::trace_log::{c, v};
use super::world::LightingModel;
use super::WorldIndex;
use crate::math::{Point3, Ray};
use crate::shading::{can_light, lighting_with, most_light, PointLight, SplitMix64, SpotLight};
use crate::{schlick, Color, Computations, Intersection, Light, Object, World};

/// The recursion limit the book's tests use (and a sensible default for renders).
pub const DEFAULT_MAX_DEPTH: u32 = 5;

/// Traces rays through one world, reusing its buffers between rays. One per thread.
#[derive(Debug)]
pub struct Tracer<'w> {
    pub(super) world: &'w World,
    pub(super) index: &'w WorldIndex,
    xs: Vec<Intersection<'w>>,
    containers: Vec<(&'w Object, f64)>,
    pub(super) rays: u64,
    /// Sample offsets for jittered area lights, reseeded per pixel by the render loop.
    pub(super) jitter: SplitMix64,
    /// Samples since the last reseed whose rays met a tie (the optics model's ambiguous hits).
    ambiguous: u32,
    /// The brightest channel of any sample so far (the optics model exposes by it).
    brightest: f64,
    /// The record of rays, when `--trace-pixel` asked for one.
    pub(super) log: Option<Box<super::trace_log::TraceLog>>,
    /// Under the Phong model, reflected and refracted rays that would bring less than this
    /// fraction of their light to the pixel are not traced (see [`Tracer::set_bailout`]).
    bailout: f64,
    /// How much of the ray being traced reaches the pixel: the product of the reflectivities
    /// and transparencies on its way from the camera.
    weight: f64,
    /// The last object that blocked a shadow ray towards each of a few lights (keyed by the
    /// light's address), tried first by the next (see [`WorldIndex::occluded_remembering`]).
    shadow_hints: [(usize, u32); SHADOW_HINTS],
}

/// Lights whose last blocker a tracer remembers at once.
const SHADOW_HINTS: usize = 4;

impl<'w> Tracer<'w> {
    /// A tracer for `world`, which `index` must have been built from.
    pub fn new(world: &'w World, index: &'w WorldIndex) -> Self {
        Self {
            world,
            index,
            xs: Vec::with_capacity(16),
            containers: Vec::with_capacity(8),
            rays: 0,
            jitter: SplitMix64::new(0),
            ambiguous: 0,
            brightest: 0.0,
            log: None,
            bailout: 0.0,
            weight: 1.0,
            shadow_hints: [(0, NO_OBJECT); SHADOW_HINTS],
        }
    }

    /// Adaptive depth control (POV-Ray's `adc_bailout`): under the Phong model, a reflected or
    /// refracted ray whose weight (the product of the reflectivities and transparencies that
    /// lead to it from the camera, with Schlick's share on surfaces that both reflect and
    /// refract) is below `bailout` is not traced, however much depth
    /// remains; nor is a shadow ray whose light, at the weight of the ray that hit, could add
    /// less than `bailout` (the light counts as blocked: see [`most_light`]). With `1/512`,
    /// what is left out is at most about a fifth of one step of an 8-bit channel per ray
    /// skipped, and a room of surfaces that all reflect a little no longer costs `max_depth`
    /// rays per pixel. `0` (the default) follows the book: every bounce up to the depth limit,
    /// every shadow ray.
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
        self.ambiguous = 0;
    }

    /// How many samples since the last [`Tracer::reseed`] were ambiguous (their rays met two
    /// surfaces at the same distance, under the optics model): they are black and should be
    /// left out of their pixel.
    pub fn ambiguous_samples(&self) -> u32 {
        self.ambiguous
    }

    /// The brightest channel of every sample this tracer has traced under the optics model
    /// (which divides the image by the brightest of all).
    pub fn brightest(&self) -> f64 {
        self.brightest
    }

    /// How many rays (camera, reflected, refracted and shadow) this tracer has cast.
    pub fn rays_cast(&self) -> u64 {
        self.rays
    }

    /// The colour seen along `ray`, following reflections and refractions `remaining` deep.
    ///
    /// Finds the nearest hit first; only when the hit surface is transparent does it gather the
    /// intersections before it, which the refractive indices n1 and n2 depend on. (For opaque
    /// surfaces n1 = n2 = 1 in the computations: nothing reads them there.)
    pub fn color_at(&mut self, ray: &Ray, remaining: u32) -> Color {
        self.weight = 1.0;
        match self.world.lighting {
            LightingModel::Phong => self.phong_color_at(ray, remaining),
            LightingModel::Flat => self.cgfs_color_at(ray, remaining, Stage::Flat),
            LightingModel::Cgfs => self.cgfs_color_at(ray, remaining, Stage::Lit),
            LightingModel::Optics => match self.optics_color_at(ray) {
                Ok(c) => {
                    self.brightest = self.brightest.max(c.red).max(c.green).max(c.blue);
                    c
                }
                Err(_) => {
                    self.ambiguous += 1;
                    Color::BLACK
                }
            },
        }
    }

    /// [`Tracer::color_at`] under The Ray Tracer Challenge's Phong model.
    fn phong_color_at(&mut self, ray: &Ray, remaining: u32) -> Color {
        self.rays += 1;
        self.note(|_| format!("ray from {} along {}", v(ray.origin), v(ray.direction)));
        let Some(hit) = self.index.closest_hit(self.world, ray) else {
            self.note(|t| format!("miss: background {}", c(t.world.background)));
            return self.world.background;
        };
        if hit.object.surface(hit.leaf).material.transparency > 0.0 {
            self.index
                .intersections_up_to(self.world, ray, hit.t, &mut self.xs);
        } else {
            self.xs.clear();
        }
        let comps = prepare_computations_with(hit, ray, &self.xs, &mut self.containers);
        self.note(|t| {
            format!(
                "hit {} at t = {:.5}: point {}, normal {}{}, media n1 = {} → n2 = {}",
                t.describe(comps.surface),
                comps.t,
                v(comps.point),
                v(comps.normalv),
                if comps.inside { " (from inside)" } else { "" },
                comps.n1,
                comps.n2
            )
        });
        let color = self.shade_hit(&comps, remaining);
        self.note(|_| format!("colour {}", c(color)));
        color
    }

    /// The colour at a prepared hit: every light's Phong term, plus reflection and refraction
    /// (mixed by Schlick's Fresnel factor when the material has both).
    pub fn shade_hit(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        let material = &comps.surface.material;
        let color = material.color_at(comps.surface, comps.over_point, comps.uv, comps.time);
        let mut surface = Color::BLACK;
        for light in &self.world.lights {
            // A light behind the surface adds only its ambient term, shadowed or not: no
            // shadow ray for it; nor for one too faint, this deep, to show (the bailout).
            let fraction = if !can_light(light, comps.over_point, comps.normalv) {
                self.note(|_| format!("light at {}: behind the surface", v(light.position())));
                0.0
            } else if self.weight * most_light(material, color, light) < self.bailout {
                let weight = self.weight;
                self.note(|_| {
                    format!(
                        "light at {}: too faint to show at weight {:.2e}, left out",
                        v(light.position()),
                        weight
                    )
                });
                0.0
            } else {
                let fraction = self.intensity_at_time(light, comps.over_point, comps.time);
                self.note(|_| {
                    format!(
                        "light at {}: {:.3} of it reaches the point",
                        v(light.position()),
                        fraction
                    )
                });
                fraction
            };
            surface += lighting_with(
                material,
                color,
                light,
                comps.over_point,
                comps.eyev,
                comps.normalv,
                fraction,
                &mut self.jitter,
            );
        }
        if material.reflective > 0.0 && material.transparency > 0.0 {
            // Fresnel's share goes into each ray's weight too, so the bailout sees what the
            // ray really brings to the pixel.
            let reflectance = schlick(comps);
            let reflected = self.reflected_color_sharing(comps, remaining, reflectance);
            let refracted = self.refracted_color_sharing(comps, remaining, 1.0 - reflectance);
            surface + reflected * reflectance + refracted * (1.0 - reflectance)
        } else {
            let reflected = self.reflected_color(comps, remaining);
            let refracted = self.refracted_color(comps, remaining);
            surface + reflected + refracted
        }
    }

    /// The book's `intensity_at(light, point, world)`: the fraction of `light` that reaches
    /// `point`: 0 or 1 for a point light, the fraction of unblocked samples for an area light.
    pub fn intensity_at(&mut self, light: &Light, point: Point3) -> f64 {
        self.intensity_at_time(light, point, 0.0)
    }

    /// [`Tracer::intensity_at`] at an instant of the shutter interval (what moving objects
    /// block depends on where they are).
    pub fn intensity_at_time(&mut self, light: &Light, point: Point3, time: f64) -> f64 {
        match light {
            Light::Point(PointLight { position, .. }) | Light::Spot(SpotLight { position, .. }) => {
                if self.shadowed_towards(light, *position, point, time) {
                    0.0
                } else {
                    1.0
                }
            }
            Light::Ambient(_) => 1.0,
            Light::Directional(l) => {
                self.rays += 1;
                let ray = Ray::new(point, l.towards.normalize_or_zero()).at_time(time);
                if self.index.occluded(self.world, &ray, f64::INFINITY) {
                    0.0
                } else {
                    1.0
                }
            }
            Light::Area(area) => {
                let mut jitter = self.jitter;
                let fraction = area.fraction_visible(&mut jitter, |s| {
                    self.shadowed_towards(light, s, point, time)
                });
                self.jitter = jitter;
                fraction
            }
        }
    }

    /// Whether an object that casts shadows lies between `point` and `light_position`.
    /// Stops at the first blocker found.
    pub fn is_shadowed(&mut self, light_position: Point3, point: Point3) -> bool {
        self.is_shadowed_at(light_position, point, 0.0)
    }

    /// [`Tracer::is_shadowed`] at an instant of the shutter interval.
    pub fn is_shadowed_at(&mut self, light_position: Point3, point: Point3, time: f64) -> bool {
        let (ray, distance) = self.shadow_ray(light_position, point, time);
        self.index.occluded(self.world, &ray, distance)
    }

    /// The shadow ray from `point` towards `light_position` (counted as cast) and the distance
    /// to the light.
    fn shadow_ray(&mut self, light_position: Point3, point: Point3, time: f64) -> (Ray, f64) {
        self.rays += 1;
        let to_light = light_position - point;
        let distance = to_light.length();
        (Ray::new(point, to_light / distance).at_time(time), distance)
    }

    /// [`Tracer::is_shadowed_at`] for a sample of `light`, trying the object that last
    /// blocked that light first.
    fn shadowed_towards(
        &mut self,
        light: &Light,
        light_position: Point3,
        point: Point3,
        time: f64,
    ) -> bool {
        let (ray, distance) = self.shadow_ray(light_position, point, time);
        // The light's address names it for as long as the world lives.
        let key = light as *const Light as usize;
        let slot = (key / std::mem::size_of::<Light>().max(1)) % SHADOW_HINTS;
        if self.shadow_hints[slot].0 != key {
            self.shadow_hints[slot] = (key, NO_OBJECT);
        }
        let (index, world) = (self.index, self.world);
        index.occluded_remembering(world, &ray, distance, &mut self.shadow_hints[slot].1)
    }

    /// The book's `reflected_color`: black for matte surfaces or when recursion is spent.
    pub fn reflected_color(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        self.reflected_color_sharing(comps, remaining, 1.0)
    }

    /// [`Tracer::reflected_color`] for a ray whose colour the caller scales by `share` (a
    /// Fresnel factor): the bailout weighs the ray with it.
    fn reflected_color_sharing(
        &mut self,
        comps: &Computations<'_>,
        remaining: u32,
        share: f64,
    ) -> Color {
        let reflective = comps.surface.material.reflective;
        if remaining == 0 || reflective == 0.0 {
            return Color::BLACK;
        }
        let Some(outer) = self.weigh(reflective * share, "reflected") else {
            return Color::BLACK;
        };
        let ray = Ray::new(comps.over_point, comps.reflectv).at_time(comps.time);
        self.note(|_| format!("reflected ray, weight {reflective}:"));
        self.deeper();
        let color = self.phong_color_at(&ray, remaining - 1) * reflective;
        self.shallower();
        self.weight = outer;
        color
    }

    /// The book's `refracted_color`: Snell's law from n1 into n2, black for opaque surfaces,
    /// spent recursion or total internal reflection.
    pub fn refracted_color(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        self.refracted_color_sharing(comps, remaining, 1.0)
    }

    /// [`Tracer::refracted_color`] for a ray whose colour the caller scales by `share`.
    fn refracted_color_sharing(
        &mut self,
        comps: &Computations<'_>,
        remaining: u32,
        share: f64,
    ) -> Color {
        let transparency = comps.surface.material.transparency;
        if remaining == 0 || transparency == 0.0 {
            return Color::BLACK;
        }
        let n_ratio = comps.n1 / comps.n2;
        let cos_i = comps.eyev.dot(comps.normalv);
        let sin2_t = n_ratio * n_ratio * (1.0 - cos_i * cos_i);
        if sin2_t > 1.0 {
            return Color::BLACK;
        }
        let cos_t = (1.0 - sin2_t).sqrt();
        let direction = comps.normalv * (n_ratio * cos_i - cos_t) - comps.eyev * n_ratio;
        let Some(outer) = self.weigh(transparency * share, "refracted") else {
            return Color::BLACK;
        };
        let ray = Ray::new(comps.under_point, direction).at_time(comps.time);
        self.note(|_| format!("refracted ray, weight {transparency}:"));
        self.deeper();
        let color = self.phong_color_at(&ray, remaining - 1) * transparency;
        self.shallower();
        self.weight = outer;
        color
    }

    /// Enters a secondary ray that carries `factor` of its parent's light: the parent's
    /// weight to restore afterwards, or `None` when the ray falls below the bailout.
    fn weigh(&mut self, factor: f64, kind: &str) -> Option<f64> {
        let outer = self.weight;
        let weight = outer * factor;
        if weight < self.bailout {
            self.note(|_| {
                format!("{kind} ray not traced: weight {weight:.2e} is below the bailout")
            });
            return None;
        }
        self.weight = weight;
        Some(outer)
    }
}
