//! Computer Graphics from Scratch's ray tracer (Gabriel Gambetta, part I) as an integrator over
//! any rayforge world, in two stages: `Flat` (the first chapter's colours, no light at all) and
//! lit (ambient, point and directional lights with scalar-like intensities, diffuse and
//! specular terms, shadows and reflections).
//!
//! The book's figures are reproduced bit for bit, so this code repeats the book's arithmetic
//! operation for operation, in the book's order: colours on the 0–255 scale multiplied by the
//! summed light intensity ([`crate::shading::cgfs`]); reflections blended on unclamped colours;
//! hit tests strict (`t_min < t < t_max`); primary rays from `t = 1` (the projection plane), all
//! other rays from `t = 0.001`; shadow rays to a point light stopping at `t = 1` (the light). The
//! colour is clamped to [0, 255] and rounded to nearest (ties to even, as a browser's canvas does)
//! once, when the camera ray returns.
//!
//! Spheres placed by a translation and a uniform scale are intersected with the book's own
//! quadratic (centre and radius in world space); every other shape goes through its usual
//! object-space intersection, so the model works on any scene.
//!
//! Beyond the book's demos, from its chapter "Extending the Raytracer": transparent surfaces
//! refract by Snell's law (with total internal reflection), and spotlights and area lights light
//! the scene too (a spotlight as a point light times its cone's falloff, an area light as its
//! samples, each with an equal share of the intensity).

use super::{Integrator, TraceState};
use crate::color::Color;
use crate::geometry::LocalHit;
use crate::math::{Point3, Ray, Vec3};
use crate::render::observer::{RayDetail, Secondary, TraceObserver};
use crate::scene::{Object, Shape};
use crate::shading::cgfs::{add, scale, CgfsLighting, Rgb};
use crate::shading::{Light, SurfacePoint};
use std::ops::ControlFlow;

/// The book's `EPSILON`: where secondary rays start counting hits.
const EPSILON: f64 = 0.001;

/// Computer Graphics from Scratch's lighting models: with `LIT` false, the first stage
/// ([`crate::scene::LightingModel::Flat`]: the nearest surface's colour, unlit); with `LIT`
/// true, the full model ([`crate::scene::LightingModel::Cgfs`]: lights, shadows, reflections and
/// refraction). The stage is a constant, so each is compiled on its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Cgfs<const LIT: bool>;

/// Computer Graphics from Scratch's first stage: the nearest surface's colour, unlit.
pub type CgfsFlat = Cgfs<false>;

/// Computer Graphics from Scratch's full model: lights, shadows, reflections (and refraction).
pub type CgfsLit = Cgfs<true>;

impl<const LIT: bool> Integrator for Cgfs<LIT> {
    /// The colour a camera ray sees, clamped and rounded to a whole step of the 0–255 scale
    /// (and returned on this crate's 0–1 scale).
    #[inline]
    fn radiance<O: TraceObserver>(
        &self,
        state: &mut TraceState<'_>,
        ray: &Ray,
        max_depth: u32,
        observer: &mut O,
    ) -> Option<Color> {
        let mut pass = Pass::<'_, '_, O, LIT> { state, observer };
        let rgb = pass.trace(
            ray.origin,
            ray.direction,
            ray.t_min,
            f64::INFINITY,
            max_depth,
            ray.time,
        );
        let [r, g, b] = rgb.map(|v| {
            let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 255.0) };
            v.round_ties_even() / 255.0
        });
        Some(Color::new(r, g, b))
    }
}

/// The nearest hit of a ray: the object, the distance and the unit normal (facing the ray's
/// origin for shapes other than the book's spheres, which the book never sees from inside).
struct Hit<'w> {
    /// The surface hit: the object, or the primitive of a CSG solid.
    surface: &'w Object,
    point: Point3,
    normal: Vec3,
    /// Whether the ray meets the surface from inside the solid.
    inside: bool,
}

/// The centre and radius of a sphere placed by a translation and a uniform scale: the book's
/// description of a sphere.
fn book_sphere(object: &Object) -> Option<(Point3, f64)> {
    if object.shape != Shape::Sphere || object.motion.is_some() {
        return None;
    }
    let m = object.transform.matrix();
    let r = m.x_axis.x;
    let diagonal = glam::DVec4::new(r, 0.0, 0.0, 0.0) == m.x_axis
        && glam::DVec4::new(0.0, r, 0.0, 0.0) == m.y_axis
        && glam::DVec4::new(0.0, 0.0, r, 0.0) == m.z_axis
        && r > 0.0;
    diagonal.then(|| (m.w_axis.truncate(), r))
}

/// The book's `IntersectRaySphere`: both roots, or infinities for a miss.
fn intersect_ray_sphere(origin: Point3, direction: Vec3, centre: Point3, radius: f64) -> [f64; 2] {
    let oc = origin - centre;
    let k1 = direction.dot(direction);
    let k2 = 2.0 * oc.dot(direction);
    let k3 = oc.dot(oc) - radius * radius;
    let discriminant = k2 * k2 - 4.0 * k1 * k3;
    if discriminant < 0.0 {
        return [f64::INFINITY; 2];
    }
    let root = discriminant.sqrt();
    [(-k2 + root) / (2.0 * k1), (-k2 - root) / (2.0 * k1)]
}

/// One camera ray's trace at stage `LIT`: the shared state and the observer told about it.
struct Pass<'a, 'w, O, const LIT: bool> {
    state: &'a mut TraceState<'w>,
    observer: &'a mut O,
}

impl<'w, O: TraceObserver, const LIT: bool> Pass<'_, 'w, O, LIT> {
    /// The book's `TraceRay`, on the 0–255 scale.
    fn trace(
        &mut self,
        origin: Point3,
        direction: Vec3,
        t_min: f64,
        t_max: f64,
        depth: u32,
        time: f64,
    ) -> Rgb {
        if !self.state.count_ray() {
            return [0.0; 3];
        }
        self.observer
            .ray_cast(origin, direction, RayDetail::Between { t_min, t_max });
        let world = self.state.world;
        let Some(hit) = self.closest(origin, direction, t_min, t_max, time) else {
            self.observer.missed(world.background);
            return scale(world.background.to_array(), 255.0);
        };
        self.observer.hit(hit.surface, hit.point, hit.normal);
        let surface = hit.surface;
        let material = &surface.material;
        let color = scale(
            surface
                .surface_color(hit.point, &SurfacePoint::default(), time)
                .to_array(),
            255.0,
        );
        if !LIT {
            return color;
        }
        let view = direction * -1.0;
        let lighting = self.lighting(hit.point, hit.normal, view, material.shininess, time);
        let local = [0, 1, 2].map(|i| color[i] * lighting[i]);
        self.observer.light_sum(lighting, local);
        let r = material.reflective;
        let transparency = material.transparency;
        if depth == 0 || (r <= 0.0 && transparency <= 0.0) {
            return local;
        }
        let mut result = local;
        if r > 0.0 {
            let reflected_ray = hit.normal * (2.0 * view.dot(hit.normal)) - view;
            self.observer.secondary(Secondary::Reflected, r);
            self.observer.enter();
            let reflected = self.trace(
                hit.point,
                reflected_ray,
                EPSILON,
                f64::INFINITY,
                depth - 1,
                time,
            );
            self.observer.leave();
            result = add(scale(local, 1.0 - r), scale(reflected, r));
        }
        if transparency > 0.0 {
            self.observer.secondary(Secondary::Refracted, transparency);
            self.observer.enter();
            // Under total internal reflection all the light is reflected.
            let bent = refract(direction, &hit, material.refractive_index)
                .unwrap_or_else(|| hit.normal * (2.0 * view.dot(hit.normal)) - view);
            let refracted = self.trace(hit.point, bent, EPSILON, f64::INFINITY, depth - 1, time);
            self.observer.leave();
            result = add(
                scale(result, 1.0 - transparency),
                scale(refracted, transparency),
            );
        }
        result
    }

    /// The book's `ClosestIntersection`: the nearest hit with `t_min < t < t_max`.
    fn closest(
        &self,
        origin: Point3,
        direction: Vec3,
        t_min: f64,
        t_max: f64,
        time: f64,
    ) -> Option<Hit<'w>> {
        let world = self.state.world;
        let ray = Ray::new(origin, direction).at_time(time);
        let mut closest_t = f64::INFINITY;
        let mut closest: Option<(usize, Option<LocalHit>)> = None;
        self.state.index.candidates(&ray, t_min, t_max, |i, limit| {
            let object = &world.objects[i];
            let mut consider = |t: f64, local| {
                if t < closest_t && t_min < t && t < t_max {
                    closest_t = t;
                    closest = Some((i, local));
                }
            };
            match book_sphere(object) {
                Some((centre, radius)) => {
                    for t in intersect_ray_sphere(origin, direction, centre, radius) {
                        consider(t, None);
                    }
                }
                None => {
                    let local = object.ray_to_object(&ray);
                    object
                        .shape
                        .intersect_hits(&local, |h| consider(h.t, Some(h)));
                }
            }
            *limit = limit.min(closest_t);
            ControlFlow::Continue(())
        });
        let (i, local) = closest?;
        let object = &world.objects[i];
        let point = origin + direction * closest_t;
        let normal = match local {
            None => {
                let (centre, _) = book_sphere(object)?;
                let n = point - centre;
                n * (1.0 / n.length())
            }
            Some(h) => object.normal_at_local_hit(point, &h),
        };
        let inside = normal.dot(direction) > 0.0;
        // The book's spheres are only ever seen from outside and keep the outward normal, as
        // the book computes it; other shapes (a plane's underside) turn theirs towards the ray.
        let normal = if inside && local.is_some() {
            -normal
        } else {
            normal
        };
        Some(Hit {
            surface: object.surface(local.map_or(0, |h| h.leaf)),
            point,
            normal,
            inside,
        })
    }

    /// The book's `ComputeLighting`, every light's shadow ray cast first: the summed intensity
    /// reaching `point`.
    fn lighting(
        &mut self,
        point: Point3,
        normal: Vec3,
        view: Vec3,
        shininess: f64,
        time: f64,
    ) -> Rgb {
        let mut lit = CgfsLighting::new(point, normal, view, shininess);
        let world = self.state.world;
        for light in &world.lights {
            match light {
                Light::Ambient(c) => lit.add_ambient(c.to_array()),
                Light::Point(l) => self.light_from(
                    &mut lit,
                    l.position - point,
                    1.0,
                    l.intensity.to_array(),
                    time,
                ),
                Light::Directional(l) => self.light_from(
                    &mut lit,
                    l.towards,
                    f64::INFINITY,
                    l.intensity.to_array(),
                    time,
                ),
                Light::Spot(l) => {
                    let falloff = l.cone_at(point);
                    let intensity = (l.intensity * falloff).to_array();
                    self.light_from(&mut lit, l.position - point, 1.0, intensity, time);
                }
                Light::Pattern(l) => {
                    let intensity = l.intensity_at(point).to_array();
                    self.light_from(&mut lit, l.position - point, 1.0, intensity, time);
                }
                Light::Area(area) => {
                    let share = (area.intensity / area.samples() as f64).to_array();
                    let mut jitter = self.state.jitter;
                    for (u, v) in area.cells() {
                        let sample = area.point_on_light(u, v, &mut jitter);
                        self.light_from(&mut lit, sample - point, 1.0, share, time);
                    }
                    self.state.jitter = jitter;
                }
            }
        }
        lit.intensity
    }

    /// One light's diffuse and specular terms unless it is blocked: `vec_l` is the book's
    /// unnormalised `L` from the point towards the light, which is reached at `t_max` (1 for a
    /// point, ∞ for a direction). The book's shadow test: anything that casts shadows with
    /// `EPSILON < t < t_max` along `vec_l` blocks.
    fn light_from(
        &mut self,
        lit: &mut CgfsLighting,
        vec_l: Vec3,
        t_max: f64,
        light: Rgb,
        time: f64,
    ) {
        let point = lit.point();
        let ray = Ray::new(point, vec_l).at_time(time);
        let blocks = |object: &Object| {
            object.casts_shadow && {
                let hit = |t: f64| EPSILON < t && t < t_max;
                match book_sphere(object) {
                    Some((centre, radius)) => intersect_ray_sphere(point, vec_l, centre, radius)
                        .into_iter()
                        .any(hit),
                    None => {
                        let mut found = false;
                        let local = object.ray_to_object(&ray);
                        object.shape.intersect_hits(&local, |h| found |= hit(h.t));
                        found
                    }
                }
            }
        };
        if !self.state.shadow_test(&ray, EPSILON, t_max, None, blocks) {
            lit.add_light(vec_l, light);
        }
    }
}

/// The direction of the ray refracted at `hit` (Snell's law, from outside into a solid of
/// index `index` or out of it into empty space, index 1), or `None` under total internal
/// reflection.
fn refract(direction: Vec3, hit: &Hit<'_>, index: f64) -> Option<Vec3> {
    let (n1, n2) = if hit.inside {
        (index, 1.0)
    } else {
        (1.0, index)
    };
    let d = direction.normalize();
    // The normal faces the incoming ray (turned above for shapes seen from inside; the book's
    // spheres keep theirs outward, so turn it here).
    let n = if d.dot(hit.normal) > 0.0 {
        -hit.normal
    } else {
        hit.normal
    };
    let eta = n1 / n2;
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(d * eta + n * (eta * cos_i - cos_t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snells_law_bends_sixty_degrees_into_water_to_forty_point_six() {
        // The book's example: 60° from the normal, from air (1.0) into water (1.33).
        let incoming = Vec3::new(60f64.to_radians().sin(), -60f64.to_radians().cos(), 0.0);
        let object = Object::sphere();
        let hit = Hit {
            surface: &object,
            point: Point3::ZERO,
            normal: Vec3::Y,
            inside: false,
        };
        let bent = refract(incoming, &hit, 1.33).unwrap();
        let angle = bent.x.atan2(-bent.y).to_degrees();
        assert!((angle - 40.628).abs() < 1e-3, "{angle}");
    }
}
