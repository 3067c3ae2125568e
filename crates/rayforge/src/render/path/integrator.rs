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

mod volume;

use super::continuation::ContinuationCache;
use super::sampler::SampleStream;
use crate::color::Color;
use crate::geometry::LocalHit;
use crate::lights::{mirror_spread, Emitters, MirrorBall, SkyEmitter};
use crate::math::{Frame, Point3, Ray, Vec3};
use crate::options::Techniques;
use crate::scene::{
    surface_offset, Intersection, LightingModel, Object, World, WorldIndex, NO_OBJECT,
};
use crate::shading::bsdf::{Bsdf, BsdfSample};
use crate::shading::{Layer, Scattering, SkyDraw, SurfacePoint};

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
    /// Which techniques run (all, by default).
    pub techniques: Techniques,
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

/// A path as it is traced (one branch of it, where it splits at glass): its ray, what it
/// carries and has gathered, and what its last bounce was, as the next vertex needs to know.
struct PathState {
    ray: Ray,
    throughput: Color,
    /// The radiance gathered so far, by every branch of the path.
    radiance: Color,
    /// The density of the direction just sampled, and whether it was a delta (the camera
    /// ray counts as one: what it sees is taken as it is).
    bsdf_pdf: f64,
    specular: bool,
    /// Where the ray left from.
    from: Point3,
    /// The shading normal there (none at the camera, or after a delta bounce of a split):
    /// the light tree's choice of a light depends on it, so MIS asks it again.
    from_normal: Option<Vec3>,
    /// Bounces so far.
    depth: u32,
    /// Where the path last left a non-delta surface for a mirror ball: the density of that
    /// direction and the density of the mirror-ball sampling's over it (the ball's spread,
    /// times how often the ball is solved there), for weighing the sky beyond the ball
    /// against sampling it through the ball.
    mirror_leg: Option<(f64, f64)>,
    /// Whether the mirror-ball sampling ran where the ray left from.
    mirror_sampled: bool,
    /// The first smooth glass on the camera's chain of mirror-like bounces splits the path
    /// in two, reflected and transmitted (see `Bsdf::split`): a path may split while it has
    /// bounced only off deltas and has not split yet.
    may_split: bool,
    /// The share of its path's light a branch of a split carries (1 unsplit): the roulette
    /// weighs a branch by its throughput over this share, as it would the unsplit path, so
    /// that splitting does not end paths sooner.
    share: f64,
    /// This vertex's light point, where the vertex before drew it with its direction (from
    /// the same Sobol point, so that it costs nothing more).
    light_pair: Option<[f64; 2]>,
}

impl PathState {
    /// A path starting along the camera ray `ray`.
    fn camera(ray: Ray) -> Self {
        let ray = Ray {
            direction: unit(ray.direction),
            ..ray
        };
        Self {
            from: ray.origin,
            from_normal: None,
            ray,
            throughput: Color::WHITE,
            radiance: Color::BLACK,
            bsdf_pdf: 0.0,
            specular: true,
            depth: 0,
            mirror_leg: None,
            mirror_sampled: false,
            may_split: true,
            share: 1.0,
            light_pair: None,
        }
    }

    /// Light `light` arriving where the path is, towards it, gathered at weight `weight`.
    #[inline]
    fn gather(&mut self, light: Color, weight: f64) {
        self.radiance += self.throughput.hadamard(light) * weight;
    }

    /// The path goes on from `vertex` as the BSDF's `sample` (of the layer scaled by
    /// `scale`, in `frame`) says.
    fn bounce(&mut self, vertex: &SurfaceVertex, frame: &Frame, sample: &BsdfSample, scale: f64) {
        self.may_split &= sample.delta;
        self.throughput = self.throughput.hadamard(sample.weight) * scale;
        self.bsdf_pdf = sample.pdf;
        self.specular = sample.delta;
        let direction = unit(frame.to_world(sample.wi));
        self.from = vertex.point;
        self.from_normal = Some(frame.n);
        self.ray = vertex.leaving(direction);
        self.depth += 1;
    }

    /// The other half of a split path takes over, from the glass: a delta bounce, as the
    /// first was. What the first half gathered stays.
    fn follow(&mut self, branch: Branch) {
        self.ray = branch.ray;
        self.throughput = branch.throughput;
        self.from = branch.from;
        // A delta bounce leaves the glass: no light density is asked there.
        self.from_normal = None;
        self.depth = branch.depth;
        self.share = branch.share;
        self.specular = true;
        self.light_pair = None;
        self.mirror_leg = None;
    }
}

/// A surface a path has met, as the techniques at the vertex need it.
struct SurfaceVertex<'w> {
    hit: Intersection<'w>,
    /// The object (the leaf of a CSG solid) whose surface it is.
    surface: &'w Object,
    local: LocalHit,
    at: SurfacePoint,
    point: Point3,
    /// The unit direction back along the path.
    wo: Vec3,
    /// The geometric normal (outward, whichever side the path is on).
    geometric: Vec3,
}

impl SurfaceVertex<'_> {
    /// The surface's shading normal: the geometric one, bumped or normal-mapped.
    fn shading_normal(&self) -> Vec3 {
        let material = &self.surface.material;
        let shading = match &material.bump {
            Some(bump) => {
                let transform = self.surface.transform_at(self.hit.time);
                bump.perturb(
                    self.geometric,
                    transform.inverse_point(self.point),
                    &transform,
                )
            }
            None => self.geometric,
        };
        match &material.metal_rough {
            Some(m) => m.mapped_normal(&self.at, shading, self.surface.tangent_at(&self.local)),
            None => shading,
        }
    }

    /// The cosine between the geometric normal and the direction back along the path: its
    /// sign says which side of the surface the path is on.
    fn cos_out(&self) -> f64 {
        self.geometric.dot(self.wo)
    }

    /// The shading frame around `shading`. Only an anisotropic material needs its first
    /// tangent along the surface: the mesh's own tangent where it has one, else the direction
    /// around the object's z axis (`z × n`, or `z × (p − origin)` where the normal is along
    /// the axis), which is the `∂p/∂u` of pbrt-v4's quadrics (sphere, cylinder, disk); every
    /// other material keeps the frame of the normal alone.
    fn frame(&self, shading: Vec3, bsdf: &Bsdf) -> Frame {
        if !bsdf.is_anisotropic() {
            return Frame::from_normal(shading);
        }
        let tangent = match self.surface.tangent_at(&self.local) {
            Some((tangent, _)) => tangent,
            None => {
                let transform = self.surface.transform_at(self.hit.time);
                let axis = transform.vector(Vec3::Z);
                let around = axis.cross(shading);
                if around.length_squared() > 1e-12 * axis.length_squared() {
                    around
                } else {
                    let origin = transform.point(Point3::ZERO);
                    match axis.cross(self.point - origin).try_normalize() {
                        Some(t) => t,
                        None => transform.vector(Vec3::X),
                    }
                }
            }
        };
        Frame::from_normal_and_tangent(shading, tangent)
    }

    /// How the surface scatters light here, by its material and the world's lighting model.
    fn scattering(&self, world: &World) -> Scattering {
        let (surface, point) = (self.surface, self.point);
        let mut material = &surface.material;
        let ctx = || surface.texture_context(point, &self.at, &self.local, self.geometric);
        // pbrt-v4's mix: one of its materials scatters here.
        if (material.textures.as_deref()).is_some_and(|t| t.mix.is_some()) {
            material = material.chosen(&ctx(), point, self.wo);
        }
        let time = self.hit.time;
        let mut colour =
            material.surface_color(&self.at, || surface.world_to_object_at(point, time));
        let mut physical = material.physical_at(|| surface.world_to_object_at(point, time));
        if let Some(textures) = material.textures.as_deref() {
            let ctx = ctx();
            if let Some(c) = textures.color_at(&ctx) {
                colour = c;
            }
            physical = physical.map(|p| textures.physical_at(p, &ctx));
        }
        match (&material.metal_rough, physical) {
            (Some(m), _) => {
                Scattering::metal_rough(&m.sample_at(&self.at), m.ior, world.ambient_index)
            }
            (None, Some(physical)) => {
                Scattering::single(physical.bsdf(colour, world.ambient_index))
            }
            (None, None) => match world.lighting {
                LightingModel::Phong => Scattering::phong(material, colour, world.ambient_index),
                LightingModel::Flat | LightingModel::Cgfs => {
                    Scattering::cgfs(material, colour, world.ambient_index)
                }
                LightingModel::Optics => Scattering::optics(material, colour, world.ambient_index),
            },
        }
    }

    /// The geometric normal turned to the side the path is on.
    fn facing(&self) -> Vec3 {
        if self.geometric.dot(self.wo) < 0.0 {
            -self.geometric
        } else {
            self.geometric
        }
    }

    /// A ray leaving the surface along the unit `direction`.
    fn leaving(&self, direction: Vec3) -> Ray {
        Ray {
            origin: offset_towards(self.point, self.geometric, direction),
            direction,
            time: self.hit.time,
            t_min: 0.0,
        }
    }
}

/// The layer of a vertex's material that scatters, in the vertex's shading frame.
struct Scatter {
    layer: Layer,
    frame: Frame,
    wo_local: Vec3,
}

/// The numbers a vertex draws from its path's stream (see [`VERTEX_DIMENSIONS`]).
struct VertexNumbers {
    /// Where the vertex's own dimensions begin.
    first: u32,
    u_lobe: f64,
    u_light: f64,
    u_direction: [f64; 2],
    u_point: [f64; 2],
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
            techniques: Techniques::default(),
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
        if self.world.has_media() {
            return self.radiance_in_media(ray, stream, log);
        }
        let mut path = PathState::camera(ray);
        let mut first = FirstHit::default();
        // The second half of a path split at glass, waiting for the first to end.
        let mut pending: Option<Branch> = None;
        loop {
            // One branch (the whole path, unless it splits): bounce by bounce, until it
            // escapes, is absorbed, reaches the most bounces or loses the roulette.
            loop {
                self.rays += 1;
                let Some(hit) = self.index.closest_hit(self.world, &path.ray) else {
                    let sky = self.sky_escaped(&mut path);
                    if path.depth == 0 {
                        first.albedo = sky;
                        first.depth = f64::INFINITY;
                    }
                    break;
                };
                self.vertices += 1;
                let vertex = self.surface_vertex(hit, &path.ray);
                if path.depth == 0 {
                    // The camera ray's direction is a unit vector: `t` is the distance.
                    first.depth = hit.t;
                }
                path.mirror_leg = self.mirror_leg(&path, &vertex);
                let shading = vertex.shading_normal();
                // Light given off here, towards where the path came from.
                let emitted =
                    self.emitters
                        .object_radiance(vertex.surface, &vertex.at, vertex.cos_out());
                if let Some(emission) = emitted {
                    let weight = self.emission_weight(&path, &vertex);
                    path.gather(emission, weight);
                }
                if path.depth >= self.max_depth {
                    break;
                }
                // A one-sided surface seen from behind is black: it scatters nothing.
                if !vertex.surface.material.two_sided && vertex.cos_out() < 0.0 {
                    if path.depth == 0 {
                        first.normal = -vertex.geometric;
                    }
                    break;
                }
                let scattering = vertex.scattering(self.world);
                if path.depth == 0 && self.first_hit_shading {
                    first.albedo = scattering.albedo();
                    first.normal = if shading.dot(vertex.wo) < 0.0 {
                        -shading
                    } else {
                        shading
                    };
                }
                let (layer, numbers) = self.vertex_numbers(&mut path, &scattering, stream);
                let frame = vertex.frame(shading, &layer.bsdf);
                let wo_local = frame.to_local(vertex.wo);
                let scatter = Scatter {
                    layer,
                    frame,
                    wo_local,
                };

                // Light sampled from here: the lights themselves, and the sky in mirror balls.
                path.mirror_sampled = false;
                if !layer.bsdf.is_delta() {
                    let mut sky_draw = SkyDraw::new(numbers.u_point);
                    if self.techniques.next_event {
                        let u_light = numbers.u_light;
                        self.next_event(&mut path, &vertex, &scatter, u_light, &mut sky_draw);
                    }
                    if self.techniques.mirror_balls {
                        let first = numbers.first;
                        self.sky_in_mirrors(
                            &mut path,
                            &vertex,
                            &scatter,
                            &mut sky_draw,
                            first,
                            stream,
                        );
                    }
                }

                // The next direction: both, where the camera first sees smooth glass.
                let sample = match self.split_at_glass(&mut path, &vertex, &scatter) {
                    Some((reflected, transmitted)) => {
                        pending = Some(transmitted);
                        reflected
                    }
                    None => {
                        let Some(sample) =
                            layer
                                .bsdf
                                .sample(wo_local, numbers.u_lobe, numbers.u_direction)
                        else {
                            break;
                        };
                        sample
                    }
                };
                path.bounce(&vertex, &scatter.frame, &sample, layer.scale);

                let diffuse = matches!(layer.bsdf, Bsdf::Diffuse { .. }) && !scattering.chooses();
                let facing = vertex.facing();
                if !self.roulette(&mut path, diffuse, &vertex, numbers.first, stream, log) {
                    break;
                }
                if path.throughput.max_channel() <= 0.0 {
                    break;
                }
                if diffuse {
                    let departure = DiffuseDeparture {
                        point: vertex.point,
                        facing,
                        throughput: path.throughput,
                        gathered: path.radiance,
                    };
                    log.left_diffuse(path.depth, departure);
                }
            }
            log.branch_ended(path.radiance);
            let Some(branch) = pending.take() else {
                break;
            };
            path.follow(branch);
        }
        (path.radiance, first)
    }

    /// The surface `hit` met by `ray`.
    fn surface_vertex(&self, hit: Intersection<'w>, ray: &Ray) -> SurfaceVertex<'w> {
        let point = ray.position(hit.t);
        let surface = hit.object.surface(hit.leaf);
        let local = hit.local();
        SurfaceVertex {
            at: surface.shape.surface_point(&local),
            geometric: self.index.normal_at_hit(self.world, point, &hit),
            hit,
            surface,
            local,
            point,
            wo: -ray.direction,
        }
    }

    /// The sky the path escapes to, gathered, weighed against the strategies that sample it
    /// (next-event estimation, or the sky in a mirror ball beyond which it escaped).
    fn sky_escaped(&self, path: &mut PathState) -> Color {
        let (sky, weight) = if let Some((leg_pdf, mirror_pdf)) = path.mirror_leg {
            let (sky, pdf) = self.emitters.sky_radiance_and_draw_pdf(path.ray.direction);
            (sky, self.bsdf_weight(leg_pdf, pdf * mirror_pdf))
        } else if path.specular || !self.techniques.next_event {
            (self.emitters.sky_radiance(path.ray.direction), 1.0)
        } else {
            let (sky, pdf) = self.emitters.sky_radiance_and_pdf(path.ray.direction);
            (sky, self.bsdf_weight(path.bsdf_pdf, pdf))
        };
        path.gather(sky, weight);
        sky
    }

    /// The MIS weight of the light a path found by its BSDF's sampling at `vertex`, against
    /// next-event estimation drawing the same point.
    fn emission_weight(&self, path: &PathState, vertex: &SurfaceVertex) -> f64 {
        if path.specular || !self.techniques.next_event {
            return 1.0;
        }
        let index = object_index(self.world, vertex.hit.object);
        let light_pdf = self.emitters.object_pdf(
            self.world,
            index,
            path.from,
            path.from_normal,
            vertex.point,
            path.ray.direction,
            &vertex.local,
        );
        self.bsdf_weight(path.bsdf_pdf, light_pdf)
    }

    /// The weight of light a path found by BSDF sampling with density `bsdf_pdf`, where
    /// another strategy (a light's sampling, or the sky's through a mirror ball) draws the
    /// same path with density `other_pdf`: the power heuristic, or without MIS all of it to
    /// the other strategy where it can draw the path at all.
    #[inline]
    fn bsdf_weight(&self, bsdf_pdf: f64, other_pdf: f64) -> f64 {
        if self.techniques.mis {
            power_heuristic(bsdf_pdf, other_pdf)
        } else if other_pdf > 0.0 {
            0.0
        } else {
            1.0
        }
    }

    /// The weight of light another strategy drew with density `pdf`, where BSDF sampling
    /// would draw the same path with density `bsdf_pdf` (the complement of
    /// [`bsdf_weight`](Self::bsdf_weight)).
    #[inline]
    fn sampled_weight(&self, pdf: f64, bsdf_pdf: impl FnOnce() -> f64) -> f64 {
        if self.techniques.mis {
            power_heuristic(pdf, bsdf_pdf())
        } else {
            1.0
        }
    }

    /// Met by a direction sampled at a non-delta surface: if `vertex` is on a mirror ball,
    /// the density of that direction and the ball's spread, for weighing what the sky beyond
    /// it gives against sampling the sky through the ball.
    fn mirror_leg(&self, path: &PathState, vertex: &SurfaceVertex) -> Option<(f64, f64)> {
        if path.specular || self.emitters.mirror_balls().is_empty() {
            return None;
        }
        if !path.mirror_sampled {
            return None;
        }
        let balls = self.emitters.mirror_balls();
        let at = balls.of_object(object_index(self.world, vertex.hit.object))?;
        // A ball left out where the path came from is found by BSDF sampling alone.
        let solves = balls.expected_solves(at, path.from, self.techniques.mirror_ball_budget)?;
        let ball = &balls.balls()[at];
        let cos = vertex.geometric.dot(vertex.wo).abs();
        let spread = mirror_spread(vertex.hit.t, cos, ball.radius);
        Some((path.bsdf_pdf, spread * solves))
    }

    /// This vertex's layer and numbers, in a fixed layout: two pairs (its direction and a
    /// light's point), then its choices, each drawn only where it is used (see
    /// [`VERTEX_DIMENSIONS`]): a mirror or smooth glass needs neither pair.
    fn vertex_numbers(
        &self,
        path: &mut PathState,
        scattering: &Scattering,
        stream: &mut SampleStream,
    ) -> (Layer, VertexNumbers) {
        let first = CAMERA_DIMENSIONS + path.depth * VERTEX_DIMENSIONS;
        let mut choice = |k: u32, wanted: bool| {
            if wanted {
                stream.seek(first + 4 + k);
                stream.next_1d()
            } else {
                0.0
            }
        };
        let (layer, u_lobe) = scattering.pick(choice(0, scattering.chooses()));
        let delta = layer.bsdf.is_delta();
        let u_light = choice(1, self.emitters.chooses() && !delta);
        let (u_direction, u_point) = if delta {
            path.light_pair = None;
            ([0.0; 2], [0.0; 2])
        } else {
            let u_point = path.light_pair.take().unwrap_or_else(|| {
                stream.seek(match path.depth {
                    0 => FIRST_LIGHT_DIMENSION,
                    _ => first - VERTEX_DIMENSIONS + 2,
                });
                stream.next_2d()
            });
            stream.seek(first);
            let u_direction = stream.next_2d();
            path.light_pair = Some(stream.next_2d());
            (u_direction, u_point)
        };
        let numbers = VertexNumbers {
            first,
            u_lobe,
            u_light,
            u_direction,
            u_point,
        };
        (layer, numbers)
    }

    /// Next-event estimation: a light (or the sky, its direction left in `sky_draw` for the
    /// mirror balls) sampled from `vertex`, its light gathered where nothing blocks it,
    /// weighed by the power heuristic against the BSDF sampling the same direction.
    fn next_event(
        &mut self,
        path: &mut PathState,
        vertex: &SurfaceVertex,
        scatter: &Scatter,
        u_light: f64,
        sky_draw: &mut SkyDraw,
    ) {
        let (point, time) = (vertex.point, path.ray.time);
        let Some(light) = self.emitters.sample_sharing_sky(
            self.world,
            point,
            Some(scatter.frame.n),
            time,
            u_light,
            sky_draw,
        ) else {
            return;
        };
        let bsdf = &scatter.layer.bsdf;
        let wi_local = scatter.frame.to_local(light.direction);
        let f = bsdf.eval(scatter.wo_local, wi_local) * scatter.layer.scale;
        if f.max_channel() <= 0.0 {
            return;
        }
        let (shadow, reach) = if light.distance.is_finite() {
            let target = point + light.direction * light.distance;
            shadow_ray_to(point, vertex.geometric, target, time)
        } else {
            let shadow = Ray {
                origin: offset_towards(point, vertex.geometric, light.direction),
                direction: light.direction,
                time,
                t_min: 0.0,
            };
            (shadow, f64::INFINITY)
        };
        if reach > 0.0 && !self.occluded(&shadow, reach) {
            let weight = if light.delta {
                1.0
            } else {
                self.sampled_weight(light.pdf, || bsdf.pdf(scatter.wo_local, wi_local))
            };
            path.radiance +=
                path.throughput.hadamard(f).hadamard(light.radiance) * (weight / light.pdf);
        }
    }

    /// The sky in the mirror balls, seen from `vertex` (whose dimensions begin at `first`):
    /// each ball's reflection of the sky's direction in `sky_draw`, gathered, for the balls
    /// whose share of the sky's light is at least the cull, at most the cap of them, chosen
    /// by their shares where there are more (see [`MirrorBallBudget`]). (A path ending at
    /// the next vertex could not reach the sky beyond a ball, so neither may this.)
    ///
    /// [`MirrorBallBudget`]: crate::options::MirrorBallBudget
    fn sky_in_mirrors(
        &mut self,
        path: &mut PathState,
        vertex: &SurfaceVertex,
        scatter: &Scatter,
        sky_draw: &mut SkyDraw,
        first: u32,
        stream: &mut SampleStream,
    ) {
        let emitters = self.emitters;
        let Some(sky) = emitters.sampled_sky() else {
            return;
        };
        if path.depth + 1 >= self.max_depth {
            return;
        }
        path.mirror_sampled = true;
        let (point, time) = (vertex.point, path.ray.time);
        let budget = self.techniques.mirror_ball_budget;
        let u = || {
            stream.seek(first + 7);
            stream.next_1d()
        };
        emitters
            .mirror_balls()
            .choose(point, budget, u, |ball, solves, weight| {
                let light = self.sky_in_mirror(ball, sky, vertex, time, scatter, sky_draw, solves);
                path.radiance += path.throughput.hadamard(light) * weight;
            });
    }

    /// The environment maps' light (`sky_light`'s) that the mirror ball `ball` reflects to `at`
    /// (at the instant `time`) and the layer of `scatter` scatters back along the path, from the
    /// direction of the sky in `draw` (the vertex's, which next-event estimation may have
    /// drawn already; the ball's reflection point solved for it), weighed by the power
    /// heuristic against the layer's own sampling finding the same path, the ball being
    /// solved `solves` times at the vertex on average.
    #[allow(clippy::too_many_arguments)] // the vertex's parts, and the ball's, each its own
    fn sky_in_mirror(
        &mut self,
        ball: &MirrorBall,
        sky_light: &SkyEmitter,
        at: &SurfaceVertex,
        time: f64,
        scatter: &Scatter,
        draw: &mut SkyDraw,
        solves: f64,
    ) -> Color {
        let Some((towards, sky, sky_pdf)) = draw.of(|u| sky_light.draw(u)) else {
            return Color::BLACK;
        };
        self.solves += 1;
        let Some(path) = ball.reflection_towards(at.point, towards) else {
            return Color::BLACK;
        };
        let bsdf = &scatter.layer.bsdf;
        let wi_local = scatter.frame.to_local(path.direction);
        let f = bsdf.eval(scatter.wo_local, wi_local) * scatter.layer.scale;
        if f.max_channel() <= 0.0 {
            return Color::BLACK;
        }
        // To the ball, then from the ball to the sky.
        let (leg, reach) = shadow_ray_to(at.point, at.geometric, path.point, time);
        if reach <= 0.0 || self.occluded(&leg, reach) {
            return Color::BLACK;
        }
        let beyond = Ray {
            origin: path.point + path.normal * surface_offset(path.point),
            direction: towards,
            time,
            t_min: 0.0,
        };
        if self.occluded(&beyond, f64::INFINITY) {
            return Color::BLACK;
        }
        // The density of this direction from the vertex: the map's, narrowed by the spread.
        let pdf = sky_pdf * mirror_spread(path.distance, path.cos_incidence, ball.radius);
        let weight = self.sampled_weight(pdf * solves, || bsdf.pdf(scatter.wo_local, wi_local));
        f.hadamard(ball.reflectance(path.cos_incidence))
            .hadamard(sky)
            * (weight / pdf)
    }

    /// The glass split: where the camera first sees smooth glass (directly or through
    /// mirror-like bounces), both halves are followed, each weighed by its Fresnel share.
    /// The reflected half goes on now; the transmitted half waits, as the returned branch.
    fn split_at_glass(
        &self,
        path: &mut PathState,
        vertex: &SurfaceVertex,
        scatter: &Scatter,
    ) -> Option<(BsdfSample, Branch)> {
        if !path.may_split || !self.techniques.glass_split {
            return None;
        }
        let [(reflected, reflected_share), (transmitted, transmitted_share)] =
            scatter.layer.bsdf.split(scatter.wo_local)?;
        path.may_split = false;
        path.share = reflected_share;
        let direction = unit(scatter.frame.to_world(transmitted.wi));
        let branch = Branch {
            ray: vertex.leaving(direction),
            throughput: path.throughput.hadamard(transmitted.weight) * scatter.layer.scale,
            from: vertex.point,
            depth: path.depth + 1,
            share: transmitted_share,
        };
        Some((reflected, branch))
    }

    /// Russian roulette, after the bounce from `vertex` (whose dimensions begin at `first`):
    /// a path carrying little light ends with a probability that grows as it dims, and one
    /// that survives carries more, so the mean is unchanged. Where what is still to come past
    /// a diffuse vertex is predicted, a path ends into the prediction, from the first bounce
    /// on, by the classic rule, and a survivor carries what the prediction misses; the
    /// pilot's log learns the scale from the other vertices' decisions alone. Whether the
    /// path goes on.
    fn roulette(
        &self,
        path: &mut PathState,
        diffuse: bool,
        vertex: &SurfaceVertex,
        first: u32,
        stream: &mut SampleStream,
        log: &mut impl PathLog,
    ) -> bool {
        if !self.techniques.roulette {
            return true;
        }
        let predicted = match self.continuation {
            Some(cache) if diffuse => cache.predict(vertex.point, vertex.facing()),
            _ => None,
        };
        if predicted.is_none() && path.depth < self.roulette_depth {
            return true;
        }
        stream.seek(first + 6);
        let u_roulette = stream.next_1d();
        let scale = if predicted.is_some() {
            1.0
        } else {
            self.roulette_scale
        };
        let survive = (path.throughput.max_channel() / path.share * scale).min(0.95);
        let expected = predicted.map(|rest| path.throughput.hadamard(rest));
        if survive.is_nan() || survive <= 0.0 || u_roulette >= survive {
            match expected {
                Some(expected) => path.radiance += expected,
                None => log.ended(),
            }
            return false;
        }
        path.throughput = path.throughput * (1.0 / survive);
        match expected {
            Some(expected) => path.radiance += expected * ((survive - 1.0) / survive),
            None => log.survived(
                survive,
                path.throughput.max_channel(),
                path.radiance,
                self.rays,
            ),
        }
        true
    }
}
