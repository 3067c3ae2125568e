//! The optics model of Don Cross's *Fundamentals of Ray Tracing* as an integrator.
//!
//! Each solid has a matte colour (the material's `color`), a gloss colour, an opacity and a
//! refractive index. A ray arriving at a hit with intensity `I` (a colour) splits:
//! - matte: `opacity · matte · I · Σ (n·l̂)/d² · light colour` over the point lights in view, at
//!   distance `d` (no ambient term, no specular highlight: [`crate::shading::optics`]);
//! - refraction: the transparent part `(1 - opacity) · I`, less the Fresnel reflection `Fr`
//!   (the mean of the s and p polarisations; 1 under total internal reflection), goes on
//!   through the surface by Snell's law into the index of whatever solid contains the point
//!   just beyond (the first added wins; the scene's ambient index where none does);
//! - reflection: one mirror ray carries `(transparency · Fr + opacity · gloss) · I`.
//!
//! Rays go no deeper than 20 bounces and stop once every channel of their intensity is below
//! 0.001. Transparent solids still cast full shadows. The image is exposed automatically after
//! the render: every channel divided by the brightest one of all the samples
//! ([`Integrator::AUTO_EXPOSURE`]).
//!
//! Hits closer than `1e-6` are ignored (secondary rays start on the surface), and a hit tied
//! with another one (squared distances within `1e-6`) is *ambiguous*: the ray is abandoned
//! (the sample has no colour) and the render loop repairs its pixel from its neighbours, as the
//! book does.

use super::{Integrator, TraceState};
use crate::color::Color;
use crate::geometry::LocalHit;
use crate::math::{Point3, Ray, Vec3};
use crate::render::observer::{RayDetail, TraceObserver};
use crate::scene::{Object, Shape};
use crate::shading::optics::{matte_light, polarized_reflection};
use crate::shading::SurfacePoint;
use std::ops::ControlFlow;

/// The book's `EPSILON`: the smallest distance that counts as a hit, and the tie tolerance.
const EPSILON: f64 = 1e-6;
/// The deepest chain of reflections and refractions.
pub const MAX_DEPTH: u32 = 20;
/// A ray weaker than this in every channel is not traced.
const MIN_INTENSITY: f64 = 0.001;
/// How far past a hit the containment test looks for the medium beyond.
const SMALL_SHIFT: f64 = 0.001;

/// Fundamentals of Ray Tracing's lighting model ([`crate::scene::LightingModel::Optics`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct Optics;

impl Integrator for Optics {
    const AUTO_EXPOSURE: bool = true;

    /// The colour a camera ray sees (unexposed), or `None` when some ray on its way met two
    /// surfaces at the same distance. Its own depth limit, [`MAX_DEPTH`], replaces `max_depth`.
    #[inline]
    fn radiance<O: TraceObserver>(
        &self,
        state: &mut TraceState<'_>,
        ray: &Ray,
        _max_depth: u32,
        observer: &mut O,
    ) -> Option<Color> {
        let ambient = state.world.ambient_index;
        let mut pass = Pass { state, observer };
        pass.trace(
            ray.origin,
            ray.direction,
            ambient,
            Color::WHITE,
            0,
            ray.time,
        )
        .ok()
    }
}

/// The nearest hit of a ray in the optics model.
struct Hit<'w> {
    surface: &'w Object,
    point: Point3,
    /// Unit normal pointing out of the solid.
    normal: Vec3,
}

/// Whether `object`'s surface meets `ray` (in world space) at some `t` with
/// `EPSILON < t < distance`: the shadow test of [`Pass::matte`], by [`Shape::any_hit`] from the
/// first number above `EPSILON` (the book counts no hit at `EPSILON` itself).
fn blocks(object: &Object, ray: &Ray, distance: f64) -> bool {
    let local = object.ray_to_object(ray);
    object.shape.any_hit(&local, EPSILON.next_up(), distance)
}

/// Why a ray found no colour.
struct Ambiguous;

fn significant(c: Color) -> bool {
    c.red >= MIN_INTENSITY || c.green >= MIN_INTENSITY || c.blue >= MIN_INTENSITY
}

/// One camera ray's trace: the shared state and the observer told about it.
struct Pass<'a, 'w, O> {
    state: &'a mut TraceState<'w>,
    observer: &'a mut O,
}

impl<'w, O: TraceObserver> Pass<'_, 'w, O> {
    /// The book's `TraceRay`.
    fn trace(
        &mut self,
        vantage: Point3,
        direction: Vec3,
        index: f64,
        intensity: Color,
        depth: u32,
        time: f64,
    ) -> Result<Color, Ambiguous> {
        if !self.state.count_ray() {
            return Ok(Color::BLACK);
        }
        self.observer
            .ray_cast(vantage, direction, RayDetail::Medium { index, intensity });
        match self.closest(vantage, direction, time) {
            Err(Ambiguous) => {
                self.observer.ambiguous();
                Err(Ambiguous)
            }
            Ok(None) => {
                let background = self.state.world.background;
                self.observer.missed(background);
                Ok(intensity * background)
            }
            Ok(Some(hit)) => {
                self.observer.hit(hit.surface, hit.point, hit.normal);
                self.observer.enter();
                let color = self.lighting(&hit, direction, index, intensity, depth + 1, time);
                self.observer.leave();
                color
            }
        }
    }

    /// The book's `CalculateLighting`.
    fn lighting(
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
            let matte = hit
                .surface
                .surface_color(hit.point, &SurfacePoint::default(), time);
            let light = self.matte(hit, time);
            self.observer.matte(light, opacity);
            sum += matte * intensity * light * opacity;
        }
        let mut fresnel = 0.0;
        if transparency > 0.0 {
            let (refracted, reflected_share) =
                self.refraction(hit, direction, index, intensity * transparency, depth, time)?;
            sum += refracted;
            fresnel = reflected_share;
        }
        let reflection =
            (Color::WHITE * (transparency * fresnel) + material.gloss * opacity) * intensity;
        if significant(reflection) {
            let n = hit.normal;
            let mirror = direction - n * (2.0 * direction.dot(n));
            sum += self.trace(hit.point, mirror, index, reflection, depth, time)?;
        }
        Ok(sum)
    }

    /// The book's `CalculateMatte`: every point light in view, by the cosine of incidence over
    /// the squared distance. In view means nothing at all lies between (transparent solids
    /// block too).
    ///
    /// A light behind the surface adds nothing, and [`matte_light`] casts no shadow ray
    /// towards it: on the book's chessboard a fifth of all the rays (21.6 M down to 17.0 M).
    fn matte(&mut self, hit: &Hit<'w>, time: f64) -> Color {
        let world = self.state.world;
        matte_light(&world.lights, hit.point, hit.normal, |position| {
            let gap = position - hit.point;
            let distance = gap.length();
            let ray = Ray::new(hit.point, gap / distance).at_time(time);
            !self
                .state
                .shadow_test(&ray, EPSILON, distance, None, |object| {
                    blocks(object, &ray, distance)
                })
        })
    }

    /// The book's `CalculateRefraction`: the refracted ray's colour and the Fresnel reflection
    /// factor (which the caller adds to the mirror ray).
    fn refraction(
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
        let world = self.state.world;
        let target = world
            .objects
            .iter()
            .find(|o| o.contains(beyond))
            .map_or(world.ambient_index, |o| {
                o.surface_containing(beyond).material.refractive_index
            });
        self.observer.refraction(index, target);
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
        let rs = polarized_reflection(index, target, cos_a1, cos_a2, EPSILON);
        let rp = polarized_reflection(index, target, cos_a2, cos_a1, EPSILON);
        let fresnel = (rs + rp) / 2.0;
        let color = self.trace(
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
    fn closest(
        &self,
        vantage: Point3,
        direction: Vec3,
        time: f64,
    ) -> Result<Option<Hit<'w>>, Ambiguous> {
        let world = self.state.world;
        let length = direction.length();
        let ray = Ray::new(vantage, direction / length).at_time(time);
        // (distance, object, local hit) of the best and whether another ties with it.
        let mut best: Option<(f64, usize, LocalHit)> = None;
        let mut tied = false;
        self.state
            .index
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
            if matches!(object.shape, Shape::Csg(_))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::SplitMix64;
    use crate::math::{rotation_y, scaling, translation};
    use crate::scene::CsgOperation;

    /// The shadow test as it was before [`blocks`]: every hit of the solid, looked at in turn.
    fn blocks_by_every_hit(object: &Object, ray: &Ray, distance: f64) -> bool {
        let mut found = false;
        let local = object.ray_to_object(ray);
        object.shape.intersect_hits(&local, |h| {
            found |= h.t > EPSILON && h.t < distance;
        });
        found
    }

    /// A number in `[-1, 1)`.
    fn signed(rng: &mut SplitMix64) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Counts (blocked, clear) over many shadow rays near `object`, asserting that [`blocks`]
    /// agrees with every one of them.
    fn agree_on_random_rays(object: &Object, seed: u64) -> (usize, usize) {
        let mut rng = SplitMix64::new(seed);
        let (mut blocked, mut clear) = (0, 0);
        for _ in 0..20_000 {
            let origin = Point3::new(signed(&mut rng), signed(&mut rng), signed(&mut rng)) * 3.0;
            let toward = Point3::new(signed(&mut rng), signed(&mut rng), signed(&mut rng)) * 3.0;
            let gap = toward - origin;
            let distance = gap.length();
            let ray = Ray::new(origin, gap / distance);
            let expected = blocks_by_every_hit(object, &ray, distance);
            assert_eq!(
                blocks(object, &ray, distance),
                expected,
                "{ray:?} to {distance}"
            );
            if expected {
                blocked += 1;
            } else {
                clear += 1;
            }
        }
        (blocked, clear)
    }

    #[test]
    fn the_shadow_test_agrees_with_every_hit_on_primitives() {
        let turned_box = Object::cube()
            .with_transform(translation(0.3, -0.2, 0.1) * rotation_y(0.5) * scaling(1.2, 0.4, 0.8));
        for (seed, object) in [Object::sphere(), turned_box, Object::plane()]
            .iter()
            .enumerate()
        {
            let (blocked, clear) = agree_on_random_rays(object, seed as u64);
            assert!(blocked > 1000 && clear > 1000, "{blocked} {clear}");
        }
    }

    #[test]
    fn the_shadow_test_agrees_with_every_hit_on_set_operations() {
        let bite = || Object::sphere().with_transform(translation(1.2, 0.0, 0.0));
        let far = || Object::sphere().with_transform(translation(0.0, 2.5, 0.0));
        let solids = [
            Object::csg(CsgOperation::Difference, Object::cube(), bite()).unwrap(),
            Object::csg(CsgOperation::Intersection, Object::cube(), bite()).unwrap(),
            Object::csg(CsgOperation::Union, Object::sphere(), far()).unwrap(),
            Object::csg(
                CsgOperation::Difference,
                Object::cube(),
                Object::complement(bite()).unwrap(),
            )
            .unwrap(),
        ];
        for (seed, object) in solids.iter().enumerate() {
            let (blocked, clear) = agree_on_random_rays(object, 100 + seed as u64);
            assert!(blocked > 1000 && clear > 1000, "{blocked} {clear}");
        }
    }

    #[test]
    fn a_primitive_hit_that_the_set_operation_drops_does_not_block() {
        // A cube less a sphere that lies wholly outside it: a ray through that sphere alone
        // meets a primitive twice within reach, but the difference keeps neither hit.
        let away = Object::sphere().with_transform(translation(4.0, 0.0, 0.0));
        let solid = Object::csg(CsgOperation::Difference, Object::cube(), away).unwrap();
        let ray = Ray::new(Point3::new(4.0, 5.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert!(!blocks(&solid, &ray, 10.0));
        assert!(!blocks_by_every_hit(&solid, &ray, 10.0));
        // Moved over the cube, the same ray is blocked.
        let ray = Ray::new(Point3::new(0.0, 5.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert!(blocks(&solid, &ray, 10.0));
    }
}
