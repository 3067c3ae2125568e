//! The optics model of Don Cross's *Fundamentals of Ray Tracing*, chosen per scene.
//!
//! Each solid has a matte colour (the material's `color`), a gloss colour, an opacity and a
//! refractive index. A ray arriving at a hit with intensity `I` (a colour) splits:
//! - matte: `opacity · matte · I · Σ (n·l̂)/d² · light colour` over the point lights in view, at
//!   distance `d` (no ambient term, no specular highlight);
//! - refraction: the transparent part `(1 - opacity) · I`, less the Fresnel reflection `Fr`
//!   (the mean of the s and p polarisations; 1 under total internal reflection), goes on
//!   through the surface by Snell's law into the index of whatever solid contains the point
//!   just beyond (the first added wins; the scene's ambient index where none does);
//! - reflection: one mirror ray carries `(transparency · Fr + opacity · gloss) · I`.
//!
//! Rays go no deeper than 20 bounces and stop once every channel of their intensity is below
//! 0.001. Transparent solids still cast full shadows. The image is exposed automatically by
//! the render loop: every channel divided by the brightest one of all the samples.
//!
//! Hits closer than `1e-6` are ignored (secondary rays start on the surface), and a hit tied
//! with another one (squared distances within `1e-6`) is *ambiguous*: the ray is abandoned and
//! the render loop repairs its pixel from its neighbours, as the book does.

use super::trace_log::{c, v};
use super::tracer::Tracer;
use crate::math::{Point3, Ray, Vec3};
use crate::{Color, Light, Object};
use std::ops::ControlFlow;

/// The book's `EPSILON`: the smallest distance that counts as a hit, and the tie tolerance.
const EPSILON: f64 = 1e-6;
/// The deepest chain of reflections and refractions.
pub const MAX_DEPTH: u32 = 20;
/// A ray weaker than this in every channel is not traced.
const MIN_INTENSITY: f64 = 0.001;
/// How far past a hit the containment test looks for the medium beyond.
const SMALL_SHIFT: f64 = 0.001;

/// The nearest hit of a ray in the optics model.
struct Hit<'w> {
    surface: &'w Object,
    point: Point3,
    /// Unit normal pointing out of the solid.
    normal: Vec3,
}

/// Why a ray found no colour.
pub(super) struct Ambiguous;

fn significant(c: Color) -> bool {
    c.red >= MIN_INTENSITY || c.green >= MIN_INTENSITY || c.blue >= MIN_INTENSITY
}

impl<'w> Tracer<'w> {
    /// The colour a camera ray sees (unexposed), or `Ambiguous` when some ray on its way met
    /// two surfaces at the same distance.
    pub(super) fn optics_color_at(&mut self, ray: &Ray) -> Result<Color, Ambiguous> {
        let ambient = self.world.ambient_index;
        self.optics_trace(
            ray.origin,
            ray.direction,
            ambient,
            Color::WHITE,
            0,
            ray.time,
        )
    }

    /// The book's `TraceRay`.
    fn optics_trace(
        &mut self,
        vantage: Point3,
        direction: Vec3,
        index: f64,
        intensity: Color,
        depth: u32,
        time: f64,
    ) -> Result<Color, Ambiguous> {
        self.rays += 1;
        self.note(|_| {
            format!(
                "ray from {} along {}, in a medium of index {index}, carrying {}",
                v(vantage),
                v(direction),
                c(intensity)
            )
        });
        match self.optics_closest(vantage, direction, time) {
            Err(Ambiguous) => {
                self.note(|_| "ambiguous: two surfaces at the same distance".to_string());
                Err(Ambiguous)
            }
            Ok(None) => {
                self.note(|t| format!("miss: background {}", c(t.world.background)));
                Ok(intensity * self.world.background)
            }
            Ok(Some(hit)) => {
                self.note(|t| {
                    format!(
                        "hit {}: point {}, normal {}",
                        t.describe(hit.surface),
                        v(hit.point),
                        v(hit.normal)
                    )
                });
                self.deeper();
                let color =
                    self.optics_lighting(&hit, direction, index, intensity, depth + 1, time);
                self.shallower();
                color
            }
        }
    }

    /// The book's `CalculateLighting`.
    fn optics_lighting(
        &mut self,
        hit: &Hit<'w>,
        direction: Vec3,
        index: f64,
        intensity: Color,
        depth: u32,
        time: f64,
    ) -> Result<Color, Ambiguous> {
        let mut sum = Color::BLACK;
        if depth > MAX_DEPTH || !significant(intensity) {
            return Ok(sum);
        }
        let material = &hit.surface.material;
        let opacity = material.opacity;
        let transparency = 1.0 - opacity;
        if opacity > 0.0 {
            let matte = material.color_at(hit.surface, hit.point, None, time);
            let light = self.optics_matte(hit, time);
            self.note(|_| format!("matte: light arriving {}, opacity {opacity}", c(light)));
            sum += matte * intensity * light * opacity;
        }
        let mut fresnel = 0.0;
        if transparency > 0.0 {
            let (refracted, reflected_share) = self.optics_refraction(
                hit,
                direction,
                index,
                intensity * transparency,
                depth,
                time,
            )?;
            sum += refracted;
            fresnel = reflected_share;
        }
        let reflection =
            (Color::WHITE * (transparency * fresnel) + material.gloss * opacity) * intensity;
        if significant(reflection) {
            let n = hit.normal;
            let mirror = direction - n * (2.0 * direction.dot(n));
            sum += self.optics_trace(hit.point, mirror, index, reflection, depth, time)?;
        }
        Ok(sum)
    }

    /// The book's `CalculateMatte`: every point light in view, by the cosine of incidence over
    /// the squared distance.
    fn optics_matte(&mut self, hit: &Hit<'w>, time: f64) -> Color {
        let world = self.world;
        matte_light(&world.lights, hit.point, hit.normal, |position| {
            self.optics_clear(hit.point, position, time)
        })
    }

    /// Whether nothing lies between two points (transparent solids block too).
    fn optics_clear(&mut self, from: Point3, to: Point3, time: f64) -> bool {
        self.rays += 1;
        let gap = to - from;
        let distance = gap.length();
        let ray = Ray::new(from, gap / distance).at_time(time);
        let world = self.world;
        let mut clear = true;
        self.index.candidates(&ray, EPSILON, distance, |i, _| {
            let object = &world.objects[i];
            let local = object.ray_to_object(&ray);
            object.shape.intersect_hits(&local, |h| {
                if h.t > EPSILON && h.t < distance {
                    clear = false;
                }
            });
            if clear {
                ControlFlow::Continue(())
            } else {
                ControlFlow::Break(())
            }
        });
        clear
    }

    /// The book's `CalculateRefraction`: the refracted ray's colour and the Fresnel reflection
    /// factor (which the caller adds to the mirror ray).
    fn optics_refraction(
        &mut self,
        hit: &Hit<'w>,
        direction: Vec3,
        index: f64,
        intensity: Color,
        depth: u32,
        time: f64,
    ) -> Result<(Color, f64), Ambiguous> {
        let d = direction.normalize();
        let cos_a1 = d.dot(hit.normal).clamp(-1.0, 1.0);
        let sin_a1 = (1.0 - cos_a1 * cos_a1).sqrt();
        let beyond = hit.point + d * SMALL_SHIFT;
        let target = self
            .world
            .objects
            .iter()
            .find(|o| o.contains(beyond))
            .map_or(self.world.ambient_index, |o| {
                o.surface_containing(beyond).material.refractive_index
            });
        self.note(|_| format!("refraction from index {index} into {target}"));
        let ratio = index / target;
        let sin_a2 = ratio * sin_a1;
        if sin_a2.abs() >= 1.0 {
            return Ok((Color::BLACK, 1.0)); // total internal reflection
        }
        let mut cos_a2 = (1.0 - sin_a2 * sin_a2).sqrt();
        if cos_a1 < 0.0 {
            cos_a2 = -cos_a2;
        }
        // The refracted direction: along the incoming one, bent about the normal.
        let n = if cos_a1 < 0.0 {
            hit.normal
        } else {
            -hit.normal
        };
        let cos_i = cos_a1.abs();
        let bent = d * ratio + n * (ratio * cos_i - cos_a2.abs());
        let rs = polarized_reflection(index, target, cos_a1, cos_a2);
        let rp = polarized_reflection(index, target, cos_a2, cos_a1);
        let fresnel = (rs + rp) / 2.0;
        let color = self.optics_trace(
            hit.point,
            bent,
            target,
            intensity * (1.0 - fresnel),
            depth,
            time,
        )?;
        Ok((color, fresnel))
    }

    /// The nearest hit beyond `EPSILON`, or `Ambiguous` when two surfaces tie for it.
    fn optics_closest(
        &self,
        vantage: Point3,
        direction: Vec3,
        time: f64,
    ) -> Result<Option<Hit<'w>>, Ambiguous> {
        let world = self.world;
        let length = direction.length();
        let ray = Ray::new(vantage, direction / length).at_time(time);
        // (distance, object, local hit) of the best and whether another ties with it.
        let mut best: Option<(f64, usize, crate::geometry::LocalHit)> = None;
        let mut tied = false;
        self.index
            .candidates(&ray, EPSILON, f64::INFINITY, |i, limit| {
                let object = &world.objects[i];
                let local = object.ray_to_object(&ray);
                object.shape.intersect_hits(&local, |h| {
                    if h.t <= EPSILON {
                        return;
                    }
                    let d2 = h.t * h.t;
                    match best {
                        Some((best_t, ..)) if (d2 - best_t * best_t).abs() < EPSILON => tied = true,
                        Some((best_t, ..)) if h.t > best_t => {}
                        _ => {
                            tied = false;
                            best = Some((h.t, i, h));
                        }
                    }
                });
                // Keep looking a little past the best, so that a tie is seen.
                if let Some((t, ..)) = best {
                    *limit = limit.min(t + EPSILON);
                }
                ControlFlow::Continue(())
            });
        if tied {
            return Err(Ambiguous);
        }
        Ok(best.map(|(t, i, h)| {
            let object = &world.objects[i];
            let point = ray.position(t);
            let mut normal = object.normal_at_local_hit(point, &h);
            // A set operation's surface may be a primitive's inside (the bite out of a
            // difference): its normal must point out of the solid, which refraction and the
            // matte term rely on.
            if matches!(object.shape, crate::Shape::Csg(_))
                && object.contains(point + normal * (1e-6 * (1.0 + point.abs().max_element())))
            {
                normal = -normal;
            }
            // A surface with no thickness (a ring) is seen from whichever side the ray comes.
            if !object.surface(h.leaf).shape.has_volume() && normal.dot(ray.direction) > 0.0 {
                normal = -normal;
            }
            Hit {
                surface: object.surface(h.leaf),
                point,
                normal,
            }
        }))
    }
}

/// One polarisation's Fresnel reflection (the book's `PolarizedReflection`).
fn polarized_reflection(n1: f64, n2: f64, cos_a1: f64, cos_a2: f64) -> f64 {
    let left = n1 * cos_a1;
    let right = n2 * cos_a2;
    let numer = left - right;
    let denom = (left + right) * (left + right);
    if denom < EPSILON {
        return 1.0;
    }
    (numer * numer / denom).min(1.0)
}

/// Fundamentals of Ray Tracing's matte sum at `point`: each point light for which `in_view`
/// holds (given its position), by its colour times the cosine of incidence over the squared
/// distance. Spotlights and area lights count as points; ambient and directional lights add
/// nothing in this model (a directional light is a point infinitely far away, whose 1/d²
/// leaves nothing). The rasterizer, which casts no shadow rays, takes every light as in view.
pub fn matte_light(
    lights: &[Light],
    point: Point3,
    normal: Vec3,
    mut in_view: impl FnMut(Point3) -> bool,
) -> Color {
    let mut sum = Color::BLACK;
    for light in lights {
        let (position, color) = match light {
            Light::Point(l) => (l.position, l.intensity),
            Light::Spot(l) => (l.position, l.intensity),
            Light::Area(l) => (l.position(), l.intensity),
            Light::Ambient(_) | Light::Directional(_) => continue,
        };
        if !in_view(position) {
            continue;
        }
        let to_light = position - point;
        let incidence = normal.dot(to_light.normalize());
        if incidence > 0.0 {
            sum += color * (incidence / to_light.length_squared());
        }
    }
    sum
}
