//! Unidirectional path tracing: from the camera, bounce by bounce, with next-event estimation
//! (a light sampled at every vertex that is not a perfect mirror or smooth glass) and multiple
//! importance sampling between light sampling and BSDF sampling by the power heuristic (Veach
//! 1997), Russian roulette after a few bounces, radiance in linear RGB.
//!
//! The environment map's light reflected onto a surface by a polished metal ball is also
//! sampled from the surface, through the ball's reflection point ([`MirrorBall`]), and
//! weighed by the power heuristic against the paths that reach the ball by BSDF sampling.
//!
//! Where the camera first sees smooth glass (directly, or through mirror-like bounces), the
//! path splits: the reflected half and the transmitted half are both followed, each weighed by
//! its Fresnel share, instead of one chosen by chance. A light reflected in glass then shows
//! in every sample at its true strength rather than at twenty-five times it in one sample of
//! twenty-five, and it costs a second path only where glass is seen.
//!
//! A path's random numbers come from its [`SampleStream`] in a fixed layout, so a Sobol
//! sampler stratifies together the numbers that one integral takes: the camera takes the
//! first [`CAMERA_DIMENSIONS`], then each vertex [`VERTEX_DIMENSIONS`] (its direction and the
//! next vertex's light point, then the layer, the light and the roulette's coin where they
//! are chosen). A vertex's light point is paired with what led to the vertex (the image point
//! at the first hit, the direction taken at the one before): the light that reaches the
//! camera by one bounce is a four-dimensional integral over those two pairs, which one Sobol
//! point of four dimensions then covers evenly, where a direction and a light point drawn at
//! the same vertex feed two separate estimates (on the Cornell box, 0.8 % less squared error
//! at 64 samples, for nothing).

use super::continuation::ContinuationCache;
use super::sampler::SampleStream;
use crate::color::Color;
use crate::lights::{mirror_spread, Emitters, MirrorBall};
use crate::math::{Frame, Point3, Ray, Vec3};
use crate::scene::{surface_offset, LightingModel, Object, World, WorldIndex, NO_OBJECT};
use crate::shading::bsdf::Bsdf;
use crate::shading::{EnvironmentMap, Layer, Scattering, SkyDraw};

/// Dimensions a camera sample uses: a group of four for the image point and the first
/// vertex's light point, then the lens point, the instant and one spare.
pub const CAMERA_DIMENSIONS: u32 = 8;
/// Where the first vertex's light point lies, beside the image point (see the module's
/// documentation).
pub const FIRST_LIGHT_DIMENSION: u32 = 2;
/// Where the lens point lies (the instant follows it): the camera's second group of four.
pub const LENS_DIMENSION: u32 = 4;
/// Dimensions each path vertex uses: a group of four for the next direction and the next
/// vertex's light point, drawn where the surface is not a mirror or smooth glass (which use
/// neither direction nor light), and one for its choices (the layer or lobe, the light, the
/// roulette's coin, and one spare), drawn only at vertices that make one: a diffuse surface
/// lit by one lamp, before the roulette starts, chooses nothing, and a group of four drawn
/// costs as much as a ray against a few objects.
pub const VERTEX_DIMENSIONS: u32 = 8;

/// What a path tracer thread works with: the world, its index and lights, and the last object
/// that blocked a shadow ray (tried first by the next).
pub struct PathContext<'w> {
    /// The world traced.
    pub world: &'w World,
    /// Its index.
    pub index: &'w WorldIndex,
    /// Its lights.
    pub emitters: &'w Emitters,
    /// The most bounces.
    pub max_depth: u32,
    /// Bounces before Russian roulette.
    pub roulette_depth: u32,
    /// How much longer than the classic rule the roulette lets paths live: a path survives
    /// with probability `roulette_scale × throughput` (at most 0.95). 1 is the classic rule
    /// (Mitsuba's, pbrt's); [`learn_roulette`](super::learn_roulette) picks one
    /// for the scene.
    pub roulette_scale: f64,
    /// What paths still gather past diffuse vertices, where the pilot learned it: there the
    /// roulette ends a path into that prediction, from the first bounce on, by the classic
    /// rule (see [`ContinuationCache`]).
    pub continuation: Option<&'w ContinuationCache>,
    /// Whether [`FirstHit`]'s albedo and normal are wanted (an image of each is being made):
    /// a metal's albedo costs a Fresnel term per sample, for nothing when there is no image.
    pub first_hit_shading: bool,
    /// The last blocker of a shadow ray.
    hint: u32,
    /// Rays cast so far.
    pub rays: u64,
    /// Surfaces paths have met so far (each shaded, the costlier part of a bounce).
    pub vertices: u64,
    /// Reflections through a mirror ball solved so far (each a root found by iteration).
    pub solves: u64,
}

/// What the first surface a camera ray meets looks like, for a denoiser. The albedo and normal
/// of a surface are left zero where the context's `first_hit_shading` is off.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FirstHit {
    /// Its albedo (the sky's radiance where the ray escapes).
    pub albedo: Color,
    /// Its shading normal facing the camera, in world space (zero where the ray escapes).
    pub normal: Vec3,
    /// How far along the camera ray it is (infinite where the ray escapes).
    pub depth: f64,
}

/// The power heuristic with exponent 2: the weight of a sample drawn with density `a` when
/// another strategy would have drawn it with density `b`.
#[inline]
fn power_heuristic(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && a2.is_finite() {
        a2 / (a2 + b2)
    } else if a.is_infinite() {
        1.0
    } else {
        0.0
    }
}

/// The index of `object` in `world.objects` (it is always one of them).
#[inline]
fn object_index(world: &World, object: &Object) -> usize {
    let size = std::mem::size_of::<Object>().max(1);
    (object as *const Object as usize).wrapping_sub(world.objects.as_ptr() as usize) / size
}

/// `v` itself where it is of unit length to within rounding, else `v` normalised: the
/// directions a path takes come unit already (a camera's rays, a BSDF's unit sample turned by
/// an orthonormal frame), and normalising them again cost a square root and a division at
/// every vertex for nothing.
#[inline]
fn unit(v: Vec3) -> Vec3 {
    if (v.length_squared() - 1.0).abs() <= 1e-12 {
        v
    } else {
        v.normalize_or_zero()
    }
}

/// A point nudged off its surface to the side of `normal` that `direction` leaves by.
#[inline]
fn offset_towards(point: Point3, normal: Vec3, direction: Vec3) -> Point3 {
    let side = if normal.dot(direction) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    point + normal * (side * surface_offset(point))
}

/// A shadow ray from `point` (on a surface of geometric normal `normal`) towards `target`,
/// and how far it must stay clear. It leaves from the point nudged to the side it goes
/// towards and stops just short of the target: measured from the point itself, a ray leaving
/// at a grazing angle would meet the target's own surface before its end.
#[inline]
fn shadow_ray_to(point: Point3, normal: Vec3, target: Point3, time: f64) -> (Ray, f64) {
    let origin = offset_towards(point, normal, target - point);
    let to_target = target - origin;
    let length = to_target.length();
    let ray = Ray {
        origin,
        direction: to_target / length,
        time,
        t_min: 0.0,
    };
    (ray, length - 2.0 * surface_offset(target))
}

/// What a pilot pass is told of a path as it is traced: each Russian roulette decision.
pub trait PathLog {
    /// The roulette ended the path here.
    fn ended(&mut self);
    /// The path survived the roulette, with probability `survive`; its throughput's largest
    /// channel is now `throughput`, the radiance it has gathered so far `gathered`, and the
    /// rays cast by its context so far `rays`.
    fn survived(&mut self, survive: f64, throughput: f64, gathered: Color, rays: u64);
    /// A branch of the path ended (the path itself, or one of the two a split made), the
    /// radiance gathered so far being `gathered`: what its decisions led to.
    fn branch_ended(&mut self, gathered: Color);
    /// The path goes on from its `bounce`th vertex, a diffuse one.
    fn left_diffuse(&mut self, bounce: u32, departure: DiffuseDeparture);
}

/// A diffuse vertex a path goes on from, as [`PathLog::left_diffuse`] is told of it.
#[derive(Debug, Clone, Copy)]
pub struct DiffuseDeparture {
    /// Where the vertex is.
    pub point: Point3,
    /// Its surface's unit normal on the side the path is on.
    pub facing: Vec3,
    /// The path's throughput as it leaves.
    pub throughput: Color,
    /// The radiance the path has gathered so far.
    pub gathered: Color,
}

/// The log of a render: nothing is kept (and nothing is left of it once inlined).
impl PathLog for () {
    #[inline]
    fn ended(&mut self) {}
    #[inline]
    fn survived(&mut self, _: f64, _: f64, _: Color, _: u64) {}
    #[inline]
    fn branch_ended(&mut self, _: Color) {}
    #[inline]
    fn left_diffuse(&mut self, _: u32, _: DiffuseDeparture) {}
}

/// The other half of a path split at smooth glass, waiting to be followed once the first
/// half ends: where it leaves the glass, and what it carries.
struct Branch {
    ray: Ray,
    throughput: Color,
    from: Point3,
    depth: u32,
    /// The chance a path that chose one lobe would have taken this one with.
    share: f64,
}

/// A path vertex as next-event estimation through a mirror ball needs it.
struct Vertex<'a> {
    point: Point3,
    geometric: Vec3,
    frame: &'a Frame,
    wo_local: Vec3,
    time: f64,
}

impl<'w> PathContext<'w> {
    /// A context for tracing `world`, whose index and lights these are.
    pub fn new(
        world: &'w World,
        index: &'w WorldIndex,
        emitters: &'w Emitters,
        max_depth: u32,
        roulette_depth: u32,
    ) -> Self {
        Self {
            world,
            index,
            emitters,
            max_depth,
            roulette_depth,
            roulette_scale: 1.0,
            continuation: None,
            first_hit_shading: true,
            hint: NO_OBJECT,
            rays: 0,
            vertices: 0,
            solves: 0,
        }
    }

    /// Whether something lies along `ray` closer than `distance`.
    fn occluded(&mut self, ray: &Ray, distance: f64) -> bool {
        self.rays += 1;
        let world = self.world;
        self.index
            .shadowed(world, ray, 0.0, distance, &mut self.hint, |object| {
                object.casts_shadow
            })
    }

    /// The environment map's light that the mirror ball `ball` reflects to the vertex `at`
    /// and its layer `layer` scatters back along the path, from the direction of the map in
    /// `draw` (the vertex's, which next-event estimation may have drawn already; the ball's
    /// reflection point solved for it), weighed by the power heuristic against the layer's
    /// own sampling finding the same path.
    fn sky_in_mirror(
        &mut self,
        ball: &MirrorBall,
        map: &EnvironmentMap,
        at: &Vertex,
        layer: &Layer,
        draw: &mut SkyDraw,
    ) -> Color {
        let Some((towards, sky, sky_pdf)) = draw.of(map) else {
            return Color::BLACK;
        };
        self.solves += 1;
        let Some(path) = ball.reflection_towards(at.point, towards) else {
            return Color::BLACK;
        };
        let bsdf: &Bsdf = &layer.bsdf;
        let wi_local = at.frame.to_local(path.direction);
        let f = bsdf.eval(at.wo_local, wi_local) * layer.scale;
        if f.max_channel() <= 0.0 {
            return Color::BLACK;
        }
        // To the ball, then from the ball to the sky.
        let (leg, reach) = shadow_ray_to(at.point, at.geometric, path.point, at.time);
        if reach <= 0.0 || self.occluded(&leg, reach) {
            return Color::BLACK;
        }
        let beyond = Ray {
            origin: path.point + path.normal * surface_offset(path.point),
            direction: towards,
            time: at.time,
            t_min: 0.0,
        };
        if self.occluded(&beyond, f64::INFINITY) {
            return Color::BLACK;
        }
        // The density of this direction from the vertex: the map's, narrowed by the spread.
        let pdf = sky_pdf * mirror_spread(path.distance, path.cos_incidence, ball.radius);
        let weight = power_heuristic(pdf, bsdf.pdf(at.wo_local, wi_local));
        f.hadamard(ball.reflectance(path.cos_incidence))
            .hadamard(sky)
            * (weight / pdf)
    }

    /// The radiance arriving along the camera ray `ray`, and what its first hit looks like.
    #[inline]
    pub fn radiance(&mut self, ray: Ray, stream: &mut SampleStream) -> (Color, FirstHit) {
        self.radiance_logged(ray, stream, &mut ())
    }

    /// [`radiance`](Self::radiance), telling `log` of each Russian roulette decision.
    pub fn radiance_logged(
        &mut self,
        ray: Ray,
        stream: &mut SampleStream,
        log: &mut impl PathLog,
    ) -> (Color, FirstHit) {
        let world = self.world;
        let mut ray = Ray {
            direction: unit(ray.direction),
            ..ray
        };
        let mut radiance = Color::BLACK;
        let mut throughput = Color::WHITE;
        let mut first = FirstHit::default();
        // The density of the direction just sampled, and whether it was a delta (the camera
        // ray counts as one: what it sees is taken as it is).
        let mut bsdf_pdf = 0.0;
        let mut specular = true;
        let mut from = ray.origin;
        // The shading normal there (none at the camera): the light tree's pick depends on it.
        let mut from_normal = None;
        let mut depth = 0;
        // Where the path last left a non-delta surface for a mirror ball: the density of that
        // direction and the ball's spread, for weighing the sky beyond the ball against
        // sampling it through the ball.
        let mut mirror_leg: Option<(f64, f64)> = None;
        // The first smooth glass on the camera's chain of mirror-like bounces splits the path
        // in two, reflected and transmitted (see `Bsdf::split`); the second half waits here.
        // A path may split while it has bounced only off deltas and has not split yet.
        let mut may_split = true;
        let mut pending: Option<Branch> = None;
        // The share of its path's light a branch of a split carries (1 unsplit): the roulette
        // weighs a branch by its throughput over this share, as it would the unsplit path, so
        // that splitting does not end paths sooner.
        let mut share = 1.0;
        // This vertex's light point, where the vertex before drew it with its direction (from
        // the same Sobol point, so that it costs nothing more).
        let mut light_pair: Option<[f64; 2]> = None;
        loop {
            // One branch (the whole path, unless it splits): bounce by bounce, until it
            // escapes, is absorbed, reaches the most bounces or loses the roulette.
            loop {
                self.rays += 1;
                let Some(hit) = self.index.closest_hit(world, &ray) else {
                    let leg = mirror_leg.zip(self.emitters.environment());
                    let (sky, weight) = if let Some(((leg_pdf, spread), map)) = leg {
                        let (sky, pdf) = map.radiance_and_pdf(ray.direction);
                        (sky, power_heuristic(leg_pdf, pdf * spread))
                    } else if specular {
                        (self.emitters.sky_radiance(ray.direction), 1.0)
                    } else {
                        let (sky, pdf) = self.emitters.sky_radiance_and_pdf(ray.direction);
                        (sky, power_heuristic(bsdf_pdf, pdf))
                    };
                    radiance += throughput.hadamard(sky) * weight;
                    if depth == 0 {
                        first.albedo = sky;
                        first.depth = f64::INFINITY;
                    }
                    break;
                };
                self.vertices += 1;
                let point = ray.position(hit.t);
                if depth == 0 {
                    // The camera ray's direction is a unit vector: `t` is the distance.
                    first.depth = hit.t;
                }
                let wo = -ray.direction;
                let surface = hit.object.surface(hit.leaf);
                let material = &surface.material;
                let local = hit.local();
                let at = surface.shape.surface_point(&local);
                let geometric = self.index.normal_at_hit(world, point, &hit);
                // Met by a direction sampled at a non-delta surface: if this is a mirror ball, what
                // the sky beyond it gives is weighed against sampling the sky through the ball.
                mirror_leg = if specular || self.emitters.mirror_balls().is_empty() {
                    None
                } else {
                    let index = object_index(world, hit.object);
                    self.emitters.mirror_ball_of(index).map(|ball| {
                        let cos = geometric.dot(wo).abs();
                        (bsdf_pdf, mirror_spread(hit.t, cos, ball.radius))
                    })
                };
                let mut shading = match &material.bump {
                    Some(bump) => {
                        let transform = surface.transform_at(hit.time);
                        bump.perturb(geometric, transform.inverse_point(point), &transform)
                    }
                    None => geometric,
                };
                if let Some(m) = &material.metal_rough {
                    shading = m.mapped_normal(&at, shading, surface.tangent_at(&local));
                }

                // Light given off here, towards where the path came from.
                let emission = match &material.metal_rough {
                    Some(m) => m.emission_at(&at),
                    None => material.emission,
                };
                if emission.max_channel() > 0.0
                    && material.emission_side.emits_towards(geometric.dot(wo))
                {
                    let weight = if specular {
                        1.0
                    } else {
                        let index = object_index(world, hit.object);
                        let light_pdf = self.emitters.object_pdf(
                            world,
                            index,
                            from,
                            from_normal,
                            point,
                            ray.direction,
                            &local,
                        );
                        power_heuristic(bsdf_pdf, light_pdf)
                    };
                    radiance += throughput.hadamard(emission) * weight;
                }
                if depth >= self.max_depth {
                    break;
                }
                // A one-sided surface seen from behind is black: it scatters nothing.
                if !material.two_sided && geometric.dot(wo) < 0.0 {
                    if depth == 0 {
                        first.normal = -geometric;
                    }
                    break;
                }

                let colour = surface.surface_color(point, &at, hit.time);
                let physical = material.physical_at(|| surface.world_to_object_at(point, hit.time));
                let scattering = match (&material.metal_rough, physical) {
                    (Some(m), _) => {
                        Scattering::metal_rough(&m.sample_at(&at), m.ior, world.ambient_index)
                    }
                    (None, Some(physical)) => {
                        Scattering::single(physical.bsdf(colour, world.ambient_index))
                    }
                    (None, None) => match world.lighting {
                        LightingModel::Phong => {
                            Scattering::phong(material, colour, world.ambient_index)
                        }
                        LightingModel::Flat | LightingModel::Cgfs => {
                            Scattering::cgfs(material, colour, world.ambient_index)
                        }
                        LightingModel::Optics => {
                            Scattering::optics(material, colour, world.ambient_index)
                        }
                    },
                };
                if depth == 0 && self.first_hit_shading {
                    first.albedo = scattering.albedo();
                    first.normal = if shading.dot(wo) < 0.0 {
                        -shading
                    } else {
                        shading
                    };
                }

                // This vertex's numbers, in a fixed layout: two pairs (its direction and a
                // light's point), then its choices, each drawn only where it is used (see
                // `VERTEX_DIMENSIONS`): a mirror or smooth glass needs neither pair.
                let vertex = CAMERA_DIMENSIONS + depth * VERTEX_DIMENSIONS;
                let mut choice = |k: u32, wanted: bool| {
                    if wanted {
                        stream.seek(vertex + 4 + k);
                        stream.next_1d()
                    } else {
                        0.0
                    }
                };
                let (layer, u_lobe) = scattering.pick(choice(0, scattering.chooses()));
                let bsdf = layer.bsdf;
                let u_light = choice(1, self.emitters.chooses() && !bsdf.is_delta());
                let (u_direction, u_point) = if bsdf.is_delta() {
                    light_pair = None;
                    ([0.0; 2], [0.0; 2])
                } else {
                    let u_point = light_pair.take().unwrap_or_else(|| {
                        stream.seek(match depth {
                            0 => FIRST_LIGHT_DIMENSION,
                            _ => vertex - VERTEX_DIMENSIONS + 2,
                        });
                        stream.next_2d()
                    });
                    stream.seek(vertex);
                    let u_direction = stream.next_2d();
                    light_pair = Some(stream.next_2d());
                    (u_direction, u_point)
                };

                let frame = Frame::from_normal(shading);
                let wo_local = frame.to_local(wo);

                // Next-event estimation.
                if !bsdf.is_delta() {
                    let mut sky_draw = SkyDraw::new(u_point);
                    if let Some(light) = self.emitters.sample_sharing_sky(
                        world,
                        point,
                        Some(shading),
                        ray.time,
                        u_light,
                        &mut sky_draw,
                    ) {
                        let wi_local = frame.to_local(light.direction);
                        let f = bsdf.eval(wo_local, wi_local) * layer.scale;
                        if f.max_channel() > 0.0 {
                            let (shadow, reach) = if light.distance.is_finite() {
                                let target = point + light.direction * light.distance;
                                shadow_ray_to(point, geometric, target, ray.time)
                            } else {
                                let shadow = Ray {
                                    origin: offset_towards(point, geometric, light.direction),
                                    direction: light.direction,
                                    time: ray.time,
                                    t_min: 0.0,
                                };
                                (shadow, f64::INFINITY)
                            };
                            if reach > 0.0 && !self.occluded(&shadow, reach) {
                                let weight = if light.delta {
                                    1.0
                                } else {
                                    power_heuristic(light.pdf, bsdf.pdf(wo_local, wi_local))
                                };
                                radiance += throughput.hadamard(f).hadamard(light.radiance)
                                    * (weight / light.pdf);
                            }
                        }
                    }
                    // The sky in the mirror balls. (A path ending at the next vertex could not
                    // reach the sky beyond a ball, so neither may this.)
                    let emitters = self.emitters;
                    if let (Some(map), true) = (emitters.environment(), depth + 1 < self.max_depth)
                    {
                        let at = Vertex {
                            point,
                            geometric,
                            frame: &frame,
                            wo_local,
                            time: ray.time,
                        };
                        for ball in emitters.mirror_balls() {
                            let light = self.sky_in_mirror(ball, map, &at, &layer, &mut sky_draw);
                            radiance += throughput.hadamard(light);
                        }
                    }
                }

                // The next direction: both, where the camera first sees smooth glass.
                let split = may_split.then(|| bsdf.split(wo_local)).flatten();
                let sample =
                    if let Some([(reflected, reflected_share), (transmitted, transmitted_share)]) =
                        split
                    {
                        may_split = false;
                        share = reflected_share;
                        let direction = unit(frame.to_world(transmitted.wi));
                        pending = Some(Branch {
                            ray: Ray {
                                origin: offset_towards(point, geometric, direction),
                                direction,
                                time: ray.time,
                                t_min: 0.0,
                            },
                            throughput: throughput.hadamard(transmitted.weight) * layer.scale,
                            from: point,
                            depth: depth + 1,
                            share: transmitted_share,
                        });
                        reflected
                    } else {
                        let Some(sample) = bsdf.sample(wo_local, u_lobe, u_direction) else {
                            break;
                        };
                        sample
                    };
                may_split &= sample.delta;
                throughput = throughput.hadamard(sample.weight) * layer.scale;
                bsdf_pdf = sample.pdf;
                specular = sample.delta;
                let direction = unit(frame.to_world(sample.wi));
                from = point;
                from_normal = Some(shading);
                ray = Ray {
                    origin: offset_towards(point, geometric, direction),
                    direction,
                    time: ray.time,
                    t_min: 0.0,
                };
                depth += 1;

                // Russian roulette: a path carrying little light ends with a probability that
                // grows as it dims, and one that survives carries more, so the mean is unchanged.
                // Where what is still to come past a diffuse vertex is predicted, a path ends
                // into the prediction, and a survivor carries what the prediction misses.
                let diffuse = matches!(bsdf, Bsdf::Diffuse { .. }) && !scattering.chooses();
                let facing = if geometric.dot(wo) < 0.0 {
                    -geometric
                } else {
                    geometric
                };
                // Such a vertex plays the classic rule, from the first bounce; the pilot's log
                // learns the scale from the others' decisions alone.
                let predicted = match self.continuation {
                    Some(cache) if diffuse => cache.predict(point, facing),
                    _ => None,
                };
                if predicted.is_some() || depth >= self.roulette_depth {
                    stream.seek(vertex + 6);
                    let u_roulette = stream.next_1d();
                    let scale = if predicted.is_some() {
                        1.0
                    } else {
                        self.roulette_scale
                    };
                    let survive = (throughput.max_channel() / share * scale).min(0.95);
                    let expected = predicted.map(|rest| throughput.hadamard(rest));
                    if survive.is_nan() || survive <= 0.0 || u_roulette >= survive {
                        match expected {
                            Some(expected) => radiance += expected,
                            None => log.ended(),
                        }
                        break;
                    }
                    throughput = throughput * (1.0 / survive);
                    match expected {
                        Some(expected) => radiance += expected * ((survive - 1.0) / survive),
                        None => {
                            log.survived(survive, throughput.max_channel(), radiance, self.rays)
                        }
                    }
                }
                if throughput.max_channel() <= 0.0 {
                    break;
                }
                if diffuse {
                    let departure = DiffuseDeparture {
                        point,
                        facing,
                        throughput,
                        gathered: radiance,
                    };
                    log.left_diffuse(depth, departure);
                }
            }
            log.branch_ended(radiance);
            // The other half of a split path, from the glass: a delta bounce, as the first was.
            let Some(branch) = pending.take() else {
                break;
            };
            ray = branch.ray;
            throughput = branch.throughput;
            from = branch.from;
            from_normal = None; // a delta bounce leaves it: no light density is asked there
            depth = branch.depth;
            share = branch.share;
            specular = true;
            light_pair = None;
            mirror_leg = None;
        }
        (radiance, first)
    }
}
