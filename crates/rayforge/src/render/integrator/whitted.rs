//! The Ray Tracer Challenge's Whitted integrator (chapters 7, 8 and 11, the soft-shadows bonus
//! chapter): the nearest hit shaded by every light's Phong term, shadow rays, and reflection
//! and refraction followed recursively (mixed by Schlick's Fresnel factor when a material has
//! both), with POV-Ray's adaptive depth control (the bailout) on top.

use super::{Integrator, TraceState};
use crate::color::Color;
use crate::math::{Point3, Ray};
use crate::render::observer::{LightReach, NoTrace, RayDetail, Secondary, TraceObserver};
use crate::scene::{prepare_computations_with, schlick, Computations};
use crate::shading::{
    can_light, lighting_with, most_light, Light, Material, PatternLight, PointLight, SpotLight,
};

/// The Ray Tracer Challenge's lighting model ([`crate::scene::LightingModel::Phong`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct Whitted;

impl Integrator for Whitted {
    #[inline]
    fn radiance<O: TraceObserver>(
        &self,
        state: &mut TraceState<'_>,
        ray: &Ray,
        max_depth: u32,
        observer: &mut O,
    ) -> Option<Color> {
        state.weight = 1.0;
        Some(Pass { state, observer }.color_at(ray, max_depth))
    }
}

impl Whitted {
    /// The book's `shade_hit`: the colour at a prepared hit, `remaining` bounces deep.
    pub fn shade_hit(
        state: &mut TraceState<'_>,
        comps: &Computations<'_>,
        remaining: u32,
    ) -> Color {
        let observer = &mut NoTrace;
        Pass { state, observer }.shade_hit(comps, remaining)
    }

    /// The book's `reflected_color`: black for matte surfaces or when recursion is spent.
    pub fn reflected_color(
        state: &mut TraceState<'_>,
        comps: &Computations<'_>,
        remaining: u32,
    ) -> Color {
        let observer = &mut NoTrace;
        Pass { state, observer }.reflected_color(comps, remaining, 1.0)
    }

    /// The book's `refracted_color`: Snell's law from n1 into n2, black for opaque surfaces,
    /// spent recursion or total internal reflection.
    pub fn refracted_color(
        state: &mut TraceState<'_>,
        comps: &Computations<'_>,
        remaining: u32,
    ) -> Color {
        let observer = &mut NoTrace;
        Pass { state, observer }.refracted_color(comps, remaining, 1.0)
    }

    /// The book's `intensity_at(light, point, world)` at an instant of the shutter interval:
    /// the fraction of `light` that reaches `point`: 0 or 1 for a point light, the fraction of
    /// unblocked samples for an area light.
    pub fn intensity_at(
        state: &mut TraceState<'_>,
        light: &Light,
        point: Point3,
        time: f64,
    ) -> f64 {
        intensity_at(state, light, point, time)
    }

    /// The book's `is_shadowed(world, light_position, point)` at an instant of the shutter
    /// interval: whether an object that casts shadows lies between the two points.
    pub fn is_shadowed(
        state: &mut TraceState<'_>,
        light_position: Point3,
        point: Point3,
        time: f64,
    ) -> bool {
        shadowed_towards(state, None, light_position, point, time)
    }
}

/// One camera ray's trace: the shared state and the observer told about it.
struct Pass<'a, 'w, O> {
    state: &'a mut TraceState<'w>,
    observer: &'a mut O,
}

impl<'w, O: TraceObserver> Pass<'_, 'w, O> {
    /// The colour seen along `ray`, following reflections and refractions `remaining` deep.
    ///
    /// Finds the nearest hit first; only when the hit surface is transparent does it gather the
    /// intersections before it, which the refractive indices n1 and n2 depend on. (For opaque
    /// surfaces n1 = n2 = 1 in the computations: nothing reads them there.)
    fn color_at(&mut self, ray: &Ray, remaining: u32) -> Color {
        let state = &mut *self.state;
        if !state.count_ray() {
            return Color::BLACK;
        }
        self.observer
            .ray_cast(ray.origin, ray.direction, RayDetail::Plain);
        let Some(hit) = state.index.closest_hit(state.world, ray) else {
            self.observer.missed(state.world.background);
            return state.world.background;
        };
        if hit.object.surface(hit.leaf).material.transparency > 0.0 {
            state
                .index
                .intersections_up_to(state.world, ray, hit.t, &mut state.xs);
        } else {
            state.xs.clear();
        }
        let comps = prepare_computations_with(hit, ray, &state.xs, &mut state.containers);
        self.observer.prepared_hit(&comps);
        let color = self.shade_hit(&comps, remaining);
        self.observer.color(color);
        color
    }

    /// The colour at a prepared hit: every light's Phong term, plus reflection and refraction
    /// (mixed by Schlick's Fresnel factor when the material has both).
    fn shade_hit(&mut self, comps: &Computations<'_>, remaining: u32) -> Color {
        let material = &comps.surface.material;
        // A glTF occlusion texture darkens the ambient term where the surface is sheltered
        // (a copy of the material, only for those that have one: a few reference counts).
        let sheltered;
        let material = match material.metal_rough.as_deref() {
            Some(m) if m.occlusion.is_some() => {
                sheltered = Material {
                    ambient: material.ambient * m.occlusion_at(&comps.surface_point),
                    ..material.clone()
                };
                &sheltered
            }
            _ => material,
        };
        let color = comps
            .surface
            .surface_color(comps.over_point, &comps.surface_point, comps.time);
        let mut surface = Color::BLACK;
        let world = self.state.world;
        for light in &world.lights {
            // A light behind the surface adds only its ambient term, shadowed or not: no
            // shadow ray for it; nor for one too faint, this deep, to show (the bailout).
            let weight = self.state.weight;
            let (fraction, reach) = if !can_light(light, comps.over_point, comps.normalv) {
                (0.0, LightReach::Behind)
            } else if weight * most_light(material, color, light) < self.state.bailout {
                (0.0, LightReach::TooFaint { weight })
            } else {
                let fraction = intensity_at(self.state, light, comps.over_point, comps.time);
                (fraction, LightReach::Fraction(fraction))
            };
            self.observer.light(light.position(), reach);
            surface += lighting_with(
                material,
                color,
                light,
                comps.over_point,
                comps.eyev,
                comps.normalv,
                fraction,
                &mut self.state.jitter,
            );
        }
        if material.reflective > 0.0 && material.transparency > 0.0 {
            // Fresnel's share goes into each ray's weight too, so the bailout sees what the
            // ray really brings to the pixel.
            let reflectance = schlick(comps);
            let reflected = self.reflected_color(comps, remaining, reflectance);
            let refracted = self.refracted_color(comps, remaining, 1.0 - reflectance);
            surface + reflected * reflectance + refracted * (1.0 - reflectance)
        } else {
            let reflected = self.reflected_color(comps, remaining, 1.0);
            let refracted = self.refracted_color(comps, remaining, 1.0);
            surface + reflected + refracted
        }
    }

    /// The book's `reflected_color` for a ray whose colour the caller scales by `share` (a
    /// Fresnel factor, or 1): the bailout weighs the ray with it.
    fn reflected_color(&mut self, comps: &Computations<'_>, remaining: u32, share: f64) -> Color {
        let reflective = comps.surface.material.reflective;
        if remaining == 0 || reflective == 0.0 {
            return Color::BLACK;
        }
        let Some(outer) = self.weigh(reflective * share, Secondary::Reflected) else {
            return Color::BLACK;
        };
        let ray = Ray::new(comps.over_point, comps.reflectv).at_time(comps.time);
        self.observer.secondary(Secondary::Reflected, reflective);
        self.observer.enter();
        let color = self.color_at(&ray, remaining - 1) * reflective;
        self.observer.leave();
        self.state.weight = outer;
        color
    }

    /// The book's `refracted_color` for a ray whose colour the caller scales by `share`.
    fn refracted_color(&mut self, comps: &Computations<'_>, remaining: u32, share: f64) -> Color {
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
        let Some(outer) = self.weigh(transparency * share, Secondary::Refracted) else {
            return Color::BLACK;
        };
        let ray = Ray::new(comps.under_point, direction).at_time(comps.time);
        self.observer.secondary(Secondary::Refracted, transparency);
        self.observer.enter();
        let color = self.color_at(&ray, remaining - 1) * transparency;
        self.observer.leave();
        self.state.weight = outer;
        color
    }

    /// Enters a secondary ray that carries `factor` of its parent's light: the parent's
    /// weight to restore afterwards, or `None` when the ray falls below the bailout.
    fn weigh(&mut self, factor: f64, kind: Secondary) -> Option<f64> {
        let outer = self.state.weight;
        let weight = outer * factor;
        if weight < self.state.bailout {
            self.observer.skipped(kind, weight);
            return None;
        }
        self.state.weight = weight;
        Some(outer)
    }
}

/// The fraction of `light` that reaches `point` at `time`.
fn intensity_at(state: &mut TraceState<'_>, light: &Light, point: Point3, time: f64) -> f64 {
    match light {
        Light::Point(PointLight { position, .. })
        | Light::Spot(SpotLight { position, .. })
        | Light::Pattern(PatternLight { position, .. }) => {
            if shadowed_towards(state, Some(light), *position, point, time) {
                0.0
            } else {
                1.0
            }
        }
        Light::Ambient(_) => 1.0,
        Light::Directional(l) => {
            let ray = Ray::new(point, l.direction()).at_time(time);
            if state.shadow_test(&ray, 0.0, f64::INFINITY, None, blocks(&ray, f64::INFINITY)) {
                0.0
            } else {
                1.0
            }
        }
        Light::Area(area) => {
            let mut jitter = state.jitter;
            let fraction = area.fraction_visible(&mut jitter, |s| {
                shadowed_towards(state, Some(light), s, point, time)
            });
            state.jitter = jitter;
            fraction
        }
    }
}

/// Whether an object that casts shadows lies between `point` and `light_position` (a sample
/// of `light`, whose last blocker is tried first, when given).
fn shadowed_towards(
    state: &mut TraceState<'_>,
    light: Option<&Light>,
    light_position: Point3,
    point: Point3,
    time: f64,
) -> bool {
    let to_light = light_position - point;
    let distance = to_light.length();
    let ray = Ray::new(point, to_light / distance).at_time(time);
    state.shadow_test(&ray, 0.0, distance, light, blocks(&ray, distance))
}

/// The book's shadow test for one object: it casts shadows and meets `ray` with
/// `0 <= t < distance`.
fn blocks(ray: &Ray, distance: f64) -> impl Fn(&crate::scene::Object) -> bool + '_ {
    move |object| {
        object.casts_shadow && {
            let local = object.ray_to_object(ray);
            object.any_local_hit(&local, 0.0, distance)
        }
    }
}
