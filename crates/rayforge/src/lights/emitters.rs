//! The light list: everything that gives off light in a world, as the path tracer samples it,
//! each light one of the kinds of this module's files ([`PointEmitter`], [`SpotEmitter`],
//! [`PatternEmitter`], [`DirectionalEmitter`], [`AreaEmitter`], [`SkyEmitter`], whose docs say
//! what each means physically), held in one enum so a light sample dispatches with a `match` (no `dyn`, no
//! allocation).
//!
//! Next-event estimation picks one emitter per path vertex through the scene's
//! [`LightSampler`] (uniformly, by power, or by a light tree that weighs the vertex's place)
//! ([`Emitters::sample`]), and a point or direction on it. A path that finds an emitter by
//! scattering asks what it gives off there ([`Emitters::object_radiance`],
//! [`Emitters::sky_radiance`]) and how likely light sampling would have been to choose that
//! point ([`Emitters::object_pdf`], [`Emitters::sky_radiance_and_pdf`]), so that multiple
//! importance sampling can weigh the two ways of finding it: the kinds' own `radiance` and
//! `pdf_li`, through the list.
//!
//! The cgfs model's ambient light has no physical meaning and is left out: the path tracer's
//! indirect light is what it stood for.

use super::area::AreaEmitter;
use super::directional::DirectionalEmitter;
use super::environment::SkyEmitter;
use super::mirror_ball::MirrorBalls;
use super::pattern::PatternEmitter;
use super::point::PointEmitter;
use super::sample::LightSample;
use super::sampler::LightSampler;
use super::spot::SpotEmitter;
use crate::color::Color;
use crate::geometry::LocalHit;
use crate::math::{Point3, Vec3};
use crate::media::Anchors;
use crate::options::{LightSamplerKind, PathOptions, Techniques};
use crate::scene::{LightingModel, Object, World};
use crate::shading::{Light, SkyDraw, SurfacePoint};
use std::f64::consts::PI;

/// Marks an object that is not a sampled emitter.
pub(super) const NOT_SAMPLED: u32 = u32::MAX;

/// One light source as next-event estimation sees it: one of the kinds.
#[derive(Debug, Clone)]
enum Emitter {
    Point(PointEmitter),
    Spot(SpotEmitter),
    Pattern(PatternEmitter),
    Directional(DirectionalEmitter),
    Area(AreaEmitter),
    /// The sky (the list's [`SkyEmitter`], present only where it is sampled: a map).
    Sky,
}

/// The lights of a world as the path tracer samples them (see the [module](self)).
#[derive(Debug, Clone)]
pub struct Emitters {
    list: Vec<Emitter>,
    /// Which emitter to pick (see [`LightSampler`]); `None` when nothing emits.
    pick: Option<LightSampler>,
    /// Per world object, its index in `list`, or [`NOT_SAMPLED`].
    by_object: Vec<u32>,
    /// The sky's index in `list`, if the sky gives light.
    sky: Option<u32>,
    /// The sky, sampled or not: what paths that escape see.
    sky_light: SkyEmitter,
    /// The polished metal balls through which the environment map's light is sampled
    /// (none without a map that gives light), and the hierarchy that chooses among them.
    mirror_balls: MirrorBalls,
    /// The places of the most powerful lights that have one, which the path tracer draws
    /// distances through a medium towards ([`Anchors`]).
    anchors: Anchors,
}

impl Emitters {
    /// The emitters of `world`, picked as [`LightSamplerKind::Auto`] picks.
    pub fn new(world: &World) -> Self {
        Self::with_sampler(world, LightSamplerKind::Auto)
    }

    /// The emitters of `world`, picked by a sampler of kind `kind`, sampled by every
    /// technique.
    pub fn with_sampler(world: &World, kind: LightSamplerKind) -> Self {
        Self::build(world, kind, &Techniques::default())
    }

    /// The emitters of `world` as a render with `options` samples them: by its light
    /// sampler, a ball in the cone it subtends only where its techniques say so.
    pub fn for_options(world: &World, options: &PathOptions) -> Self {
        Self::build(world, options.light_sampler, &options.techniques)
    }

    /// The emitters of `world`, picked by a sampler of kind `kind`, a ball sampled in the cone
    /// it subtends where the techniques' `sphere_cones` say so, with as many equiangular
    /// anchors as their `equiangular_lights`.
    fn build(world: &World, kind: LightSamplerKind, techniques: &Techniques) -> Self {
        let sphere_cones = techniques.sphere_cones;
        let radius = scene_radius(world);
        let falloff = world.lighting == LightingModel::Optics;
        let disc = PI * radius * radius;
        let mut list = Vec::new();
        let mut power = Vec::new();
        // Each emitter's bounds for the light tree; `None` for light from infinity, or light
        // that does not fall off with distance.
        let mut bounds = Vec::new();
        for light in &world.lights {
            let emitter = match light {
                Light::Point(l) => Emitter::Point(PointEmitter::new(l, falloff, disc)),
                Light::Spot(l) => Emitter::Spot(SpotEmitter::new(l, falloff, disc)),
                Light::Pattern(l) => Emitter::Pattern(PatternEmitter::new(l, falloff, disc)),
                Light::Directional(l) => Emitter::Directional(DirectionalEmitter::new(l, disc)),
                Light::Area(l) => Emitter::Area(AreaEmitter::of_book(l, falloff, disc)),
                Light::Ambient(_) => continue,
            };
            let (p, b) = match &emitter {
                Emitter::Point(e) => (e.power(), e.bounds()),
                Emitter::Spot(e) => (e.power(), e.bounds()),
                Emitter::Pattern(e) => (e.power(), e.bounds()),
                Emitter::Directional(e) => (e.power(), None),
                Emitter::Area(e) => (e.power(), e.bounds(world)),
                Emitter::Sky => continue,
            };
            list.push(emitter);
            power.push(p);
            bounds.push(b);
        }
        let mut by_object = vec![NOT_SAMPLED; world.objects.len()];
        for (i, object) in world.objects.iter().enumerate() {
            let Some(emitter) = AreaEmitter::of_object(object, i as u32, disc, sphere_cones) else {
                continue;
            };
            by_object[i] = list.len() as u32;
            bounds.push(emitter.bounds(world));
            power.push(emitter.power());
            list.push(Emitter::Area(emitter));
        }
        let maps = world
            .environment
            .iter()
            .chain(&world.more_environments)
            .cloned()
            .collect();
        let sky_light = SkyEmitter::new(world.background, maps);
        let sky_power = sky_light.power(disc);
        let sky = (sky_power > 0.0).then(|| {
            list.push(Emitter::Sky);
            power.push(sky_power);
            bounds.push(None);
            (list.len() - 1) as u32
        });
        let pick = LightSampler::new(kind, &power, &bounds);
        let anchors = Anchors::of_lights(
            bounds
                .iter()
                .flatten()
                .filter(|b| !b.bounds.is_empty())
                .map(|b| (b.bounds.centroid(), b.power)),
            techniques.equiangular_lights as usize,
        );
        let mirror_balls = if sky.is_some() {
            MirrorBalls::of_objects(&world.objects)
        } else {
            MirrorBalls::default()
        };
        Self {
            list,
            pick,
            by_object,
            sky,
            sky_light,
            mirror_balls,
            anchors,
        }
    }

    /// Where the most powerful lights with a place are (points, spots and emitting surfaces
    /// whose light falls off with distance), for equiangular sampling in media.
    pub fn anchors(&self) -> &Anchors {
        &self.anchors
    }

    /// The sky of environment maps, when it gives light (what
    /// [`mirror_balls`](Self::mirror_balls) reflect).
    pub fn sampled_sky(&self) -> Option<&SkyEmitter> {
        self.sky
            .and(self.sky_light.has_maps().then_some(&self.sky_light))
    }

    /// The polished metal balls through which the path tracer samples the environment map's
    /// light (see [`MirrorBalls`]); none when no map gives light.
    pub fn mirror_balls(&self) -> &MirrorBalls {
        &self.mirror_balls
    }

    /// Whether anything can be sampled.
    pub fn is_empty(&self) -> bool {
        self.pick.is_none()
    }

    /// The radiance of the sky along `direction` (what a path that escapes sees).
    #[inline]
    pub fn sky_radiance(&self, direction: Vec3) -> Color {
        self.sky_light.radiance(direction)
    }

    /// The radiance arriving from the sky along `direction`, as
    /// [`sky_radiance`](Self::sky_radiance), and the density with which
    /// [`sample`](Self::sample) chooses that direction towards the sky (0 where the sky is not
    /// sampled): what a path that escapes weighs its light by.
    pub fn sky_radiance_and_pdf(&self, direction: Vec3) -> (Color, f64) {
        let (radiance, pdf) = self.sky_light.radiance_and_pdf_li(direction);
        // The sky is apart from any tree: its probability is the same from every point.
        let pick = match (self.sky, &self.pick) {
            (Some(sky), Some(pick)) => pick.probability(Point3::ZERO, None, sky as usize),
            _ => 0.0,
        };
        (radiance, pick * pdf)
    }

    /// The radiance of the sky along `direction` and the density with which a draw of the
    /// sky ([`SkyDraw`]) gives that direction, before next-event estimation's pick of the sky:
    /// what a path that escapes beyond a mirror ball weighs its light by, against the sky's
    /// draw reflected in the ball ([`MirrorBall`]); the background and 0 for a constant sky.
    #[inline]
    pub fn sky_radiance_and_draw_pdf(&self, direction: Vec3) -> (Color, f64) {
        self.sky_light.radiance_and_pdf_li(direction)
    }

    /// What a path that meets the surface `surface` (a world object, or the primitive of a
    /// CSG solid) at `at` sees it give off, towards a direction back along the path at the
    /// cosine `cos_out` with its geometric normal; `None` where it gives nothing that way (see
    /// [`AreaEmitter::radiance`]: every emitting surface, whether it is sampled or not).
    #[inline]
    pub fn object_radiance(
        &self,
        surface: &Object,
        at: &SurfacePoint,
        cos_out: f64,
    ) -> Option<Color> {
        AreaEmitter::radiance(surface, at, cos_out)
    }

    /// The density (per solid angle at `from`) with which [`sample`](Self::sample) chooses the
    /// point `point` of world object `index`, seen along unit `direction` from `from` (a
    /// vertex of shading normal `from_normal`, where it has one: the light's pick may depend
    /// on both, as it did when that vertex sampled a light), where
    /// the object-space hit `hit` was (its face, for meshes, its primitive, for CSG solids, and
    /// its instant, for objects that move); 0 for objects not sampled, and for a point a CSG
    /// solid does not keep, which light sampling gives no light.
    #[allow(clippy::too_many_arguments)] // the hit as the path met it, each part its own
    pub fn object_pdf(
        &self,
        world: &World,
        index: usize,
        from: Point3,
        from_normal: Option<Vec3>,
        point: Point3,
        direction: Vec3,
        hit: &LocalHit,
    ) -> f64 {
        let (Some(&slot), Some(pick)) = (self.by_object.get(index), &self.pick) else {
            return 0.0;
        };
        let Some(Emitter::Area(area)) = self.list.get(slot as usize) else {
            return 0.0;
        };
        let density = area.pdf_li(world, from, point, direction, hit);
        // A point light sampling never gives: no pick to ask the (tree's costlier) sampler.
        if density == 0.0 {
            return 0.0;
        }
        pick.probability(from, from_normal, slot as usize) * density
    }

    /// Whether [`sample`](Self::sample) uses its number `pick`: to choose among several
    /// emitters, or a part of the one surface that emits (a mesh's triangle, a moving or
    /// sheared cube's face, a solid's primitive; a still box takes its face from the point's
    /// numbers). Where it does not (one lamp, one sky), a path tracer need not draw the
    /// number at all.
    pub fn chooses(&self) -> bool {
        self.list.len() > 1 || matches!(self.list.first(), Some(Emitter::Area(a)) if a.chooses())
    }

    /// Picks an emitter with `pick` and a point or direction on it with `u`, for lighting
    /// `point` (of shading normal `normal`, where it has one) in `world` at shutter instant
    /// `time`; `None` when nothing emits or the choice gives no light (the back of a one-sided
    /// emitter, a point outside a spotlight's cone).
    pub fn sample(
        &self,
        world: &World,
        point: Point3,
        normal: Option<Vec3>,
        time: f64,
        pick: f64,
        u: [f64; 2],
    ) -> Option<LightSample> {
        self.sample_sharing_sky(world, point, normal, time, pick, &mut SkyDraw::new(u))
    }

    /// [`sample`](Self::sample) with the numbers of `sky`, the sky's direction taken from it
    /// (made there if no one has made it yet): a path vertex that also looks for the sky in
    /// mirror balls draws it once for both.
    pub fn sample_sharing_sky(
        &self,
        world: &World,
        point: Point3,
        normal: Option<Vec3>,
        time: f64,
        pick: f64,
        sky: &mut SkyDraw,
    ) -> Option<LightSample> {
        let u = sky.numbers();
        let (slot, probability, rest) = self.pick.as_ref()?.sample(point, normal, pick)?;
        match &self.list[slot] {
            Emitter::Point(light) => light.sample_li(point, probability),
            Emitter::Spot(light) => light.sample_li(point, probability),
            Emitter::Pattern(light) => light.sample_li(point, probability),
            Emitter::Directional(light) => Some(light.sample_li(probability)),
            Emitter::Area(light) => light.sample_li(world, point, time, probability, rest, u),
            Emitter::Sky => self.sky_light.sample_li(sky, probability),
        }
    }
}

/// The radius of a sphere around the world's bounded objects (1 when there are none): the
/// scale against which lights that do not fall off, and the sky, are weighed.
fn scene_radius(world: &World) -> f64 {
    let mut lo = Point3::splat(f64::INFINITY);
    let mut hi = Point3::splat(f64::NEG_INFINITY);
    for object in &world.objects {
        let b = object.bounds();
        if b.min.is_finite() && b.max.is_finite() {
            lo = lo.min(b.min);
            hi = hi.max(b.max);
        }
    }
    if lo.x <= hi.x {
        ((hi - lo).length() / 2.0).max(1e-3)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosahedron;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{point, rotation_x, rotation_y, scaling, translation, Frame, Ray, Transform};
    use crate::scene::Shape;
    use crate::shading::{EmissionSide, Material};
    use std::f64::consts::FRAC_1_PI;
    use std::sync::Arc;

    fn lamp(shape: Shape, matrix: glam::DMat4, side: EmissionSide) -> Object {
        Object::new(shape)
            .with_transform(matrix)
            .with_material(Material {
                emission: Color::WHITE,
                emission_side: side,
                ..Material::DEFAULT
            })
    }

    #[test]
    fn the_three_light_samplers_agree_on_a_points_direct_light() {
        // Forty small lamps facing down over a point facing up (some two-sided, some balls),
        // the light arriving there estimated by next-event estimation alone (no occluders):
        // each sampler is unbiased, so their estimates agree within their standard errors.
        let mut objects = Vec::new();
        for i in 0..40 {
            let (x, z) = ((i % 8) as f64 - 3.5, (i / 8) as f64 - 2.0);
            let place = translation(x, 1.0 + 0.1 * (i % 3) as f64, z);
            let side = [EmissionSide::Front, EmissionSide::Both][i % 2];
            let shape = if i % 5 == 0 {
                Shape::Sphere
            } else {
                Shape::Rectangle
            };
            let mut lamp = lamp(shape, place * rotation_x(PI) * scaling(0.2, 0.2, 0.2), side);
            lamp.material.emission = Color::new(1.0 + (i % 4) as f64, 1.0, 0.5);
            objects.push(lamp);
        }
        let world = World {
            objects,
            ..World::default()
        };
        let (point, normal) = (Point3::new(0.3, 0.0, -0.4), Vec3::Y);
        let estimate = |kind: LightSamplerKind| {
            let emitters = Emitters::with_sampler(&world, kind);
            let mut random = SplitMix64::new(99);
            let n = 40_000;
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let pick = random.next_offset();
                let u = [random.next_offset(), random.next_offset()];
                let value = emitters
                    .sample(&world, point, Some(normal), 0.0, pick, u)
                    .map_or(0.0, |s| {
                        s.radiance.luminance() * s.direction.dot(normal).max(0.0) / s.pdf
                    });
                sum += value;
                sum2 += value * value;
            }
            let mean = sum / n as f64;
            (mean, ((sum2 / n as f64 - mean * mean) / n as f64).sqrt())
        };
        let (power, power_se) = estimate(LightSamplerKind::Power);
        for kind in [LightSamplerKind::Uniform, LightSamplerKind::Bvh] {
            let (mean, se) = estimate(kind);
            let k = (mean - power).abs() / (se * se + power_se * power_se).sqrt();
            assert!(
                k < 4.5,
                "{kind:?}: {mean} ± {se} vs power's {power} ± {power_se}"
            );
        }
        // And the tree, which follows the lamps near the point, is the least noisy.
        assert!(estimate(LightSamplerKind::Bvh).1 < power_se);
    }

    /// Every shape sampled by area, placed by a transform that stretches it.
    fn lamps(side: EmissionSide) -> Vec<Object> {
        let stretch = translation(0.5, -0.2, 0.3) * rotation_y(0.7) * scaling(1.5, 0.6, 1.1);
        vec![
            lamp(Shape::Sphere, stretch, side),
            lamp(Shape::Cube, stretch * rotation_x(0.4), side),
            lamp(Shape::Rectangle, stretch, side),
            lamp(
                Shape::Ring {
                    inner: 0.3,
                    outer: 1.0,
                },
                stretch,
                side,
            ),
            lamp(
                Shape::Triangle(Box::new(crate::geometry::Triangle::new(
                    point(0.0, 1.0, 0.0),
                    point(-1.0, 0.0, 0.0),
                    point(1.0, 0.0, 0.0),
                ))),
                stretch,
                side,
            ),
            lamp(Shape::Mesh(Arc::new(icosahedron())), stretch, side),
            lamp(
                Shape::Cylinder {
                    minimum: -0.5,
                    maximum: 0.5,
                    closed: true,
                },
                stretch,
                side,
            ),
            lamp(
                Shape::Cone {
                    minimum: -0.4,
                    maximum: 0.9,
                    closed: true,
                },
                stretch,
                side,
            ),
            lamp(
                Shape::Torus {
                    major: 1.0,
                    minor: 0.35,
                },
                stretch,
                side,
            ),
            lamp(
                Shape::Torus {
                    major: 0.5,
                    minor: 0.8,
                },
                stretch,
                side,
            ),
            // Turned a right angle: a still box, sampled in world space.
            lamp(
                Shape::Cube,
                translation(0.5, -0.2, 0.3)
                    * rotation_y(std::f64::consts::FRAC_PI_2)
                    * scaling(1.5, 0.6, 1.1),
                side,
            ),
            // Scaled evenly: a ball, sampled in the cone it subtends.
            lamp(Shape::Sphere, ball_placement(), side),
        ]
    }

    /// A ball of radius 0.8 at (0.5, −0.2, 0.3), turned.
    fn ball_placement() -> glam::DMat4 {
        translation(0.5, -0.2, 0.3) * rotation_x(0.4) * rotation_y(0.7) * scaling(0.8, 0.8, 0.8)
    }

    /// The light-sampling density per solid angle at `from` of every point a ray along
    /// `direction` meets on the world's one object, summed: the density of that direction,
    /// however many of its points light sampling can draw.
    fn direction_density(emitters: &Emitters, world: &World, from: Point3, direction: Vec3) -> f64 {
        let object = &world.objects[0];
        let ray = Ray::new(from, direction);
        let mut sum = 0.0;
        object
            .shape
            .intersect_hits(&object.ray_to_object(&ray), |hit| {
                if hit.t > 1e-9 {
                    let at = ray.position(hit.t);
                    sum += emitters.object_pdf(world, 0, from, None, at, direction, &hit);
                }
            });
        sum
    }

    #[test]
    fn every_lamps_density_per_solid_angle_integrates_to_one() {
        // Over the directions from a point, light sampling's density integrates to one: drawn
        // uniformly in the cone of a sphere around each lamp (density q), the mean of the
        // density summed over the points along each direction, over q, is 1 within noise. A
        // ball seen from outside (drawn in its cone: its far side has no density) and from
        // inside (by area), and every shape drawn by area, in both of which a direction may
        // meet several points.
        let mut random = SplitMix64::new(2024);
        let ball_inside = point(0.6, 0.1, 0.2);
        let views = lamps(EmissionSide::Both)
            .into_iter()
            .map(|lamp| (lamp, point(4.0, 3.0, -5.0)))
            .chain([(
                lamp(Shape::Sphere, ball_placement(), EmissionSide::Both),
                ball_inside,
            )]);
        for (object, from) in views {
            let bounds = object.bounds();
            let centre = (bounds.min + bounds.max) / 2.0;
            let radius = (bounds.max - bounds.min).length() / 2.0 * 1.01;
            let world = World {
                objects: vec![object],
                ..World::default()
            };
            let emitters = Emitters::new(&world);
            let around = crate::geometry::sphere::SubtendedCone::seen_from(centre, radius, from);
            let n = 20_000;
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let u = [random.next_offset(), random.next_offset()];
                let (direction, q) = match &around {
                    Some(cone) => ((cone.sample(u).0 - from).normalize(), cone.pdf()),
                    None => (crate::geometry::sphere::sample_area(u).0, 0.25 * FRAC_1_PI),
                };
                let value = direction_density(&emitters, &world, from, direction) / q;
                sum += value;
                sum2 += value * value;
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - 1.0).abs() < 4.0 * se + 1e-9,
                "{:?} from {from}: {mean} ± {se}",
                world.objects[0].shape
            );
        }
    }

    /// The emitters of a world of one ball lamp, radius 0.8 at (0.5, −0.2, 0.3), glowing
    /// outwards, sampled in the cone it subtends where `cones`, else by area.
    fn ball_lamp(cones: bool) -> (World, Emitters) {
        let world = World {
            objects: vec![lamp(Shape::Sphere, ball_placement(), EmissionSide::Front)],
            ..World::default()
        };
        let techniques = Techniques {
            sphere_cones: cones,
            ..Techniques::default()
        };
        let emitters = Emitters::build(&world, LightSamplerKind::Auto, &techniques);
        (world, emitters)
    }

    #[test]
    fn the_render_says_how_many_lights_are_equiangular_anchors() {
        // Three point lights, the brightest in the middle of the list: one anchor is that
        // light alone; three (or the default eight) are all of them, another mixture.
        let light = |x: f64, i: f64| {
            Light::Point(crate::shading::PointLight {
                position: point(x, 1.0, 0.0),
                intensity: Color::new(i, i, i),
                falloff: true,
            })
        };
        let world = World {
            lights: vec![light(-2.0, 1.0), light(0.0, 5.0), light(2.0, 2.0)],
            ..World::default()
        };
        let anchors = |count: u32| {
            let mut options = PathOptions::default();
            options.techniques.equiangular_lights = count;
            *Emitters::for_options(&world, &options).anchors()
        };
        assert_eq!(
            anchors(1),
            Anchors::of_lights([(point(0.0, 1.0, 0.0), 1.0)], 1)
        );
        assert_ne!(anchors(2), anchors(1));
        assert_ne!(anchors(3), anchors(2));
        assert_eq!(anchors(3), anchors(Techniques::DEFAULT_EQUIANGULAR_LIGHTS));
        assert_eq!(anchors(3), *Emitters::new(&world).anchors());
    }

    #[test]
    fn a_ball_lamp_lights_a_point_as_its_analytic_irradiance_says() {
        // A ball of radiance L and radius r seen at distance d, wholly above the point's
        // horizon, gives it the irradiance π L (r/d)² cos β, β the angle between the point's
        // normal and the ball's centre: next-event estimation agrees within its standard
        // error, near and far, with the ball drawn in its cone and by area alike.
        let centre = point(0.5, -0.2, 0.3);
        for cones in [true, false] {
            let (world, emitters) = ball_lamp(cones);
            for (distance, tilt) in [(1.1, 0.3_f64), (3.0, 0.9), (60.0, 1.2)] {
                let axis = Vec3::new(-0.4, 1.0, 0.3).normalize();
                let from = centre - axis * distance;
                let frame = Frame::from_normal(axis);
                let normal = frame.to_world(Vec3::new(tilt.sin(), 0.0, tilt.cos()));
                let sin_max = 0.8 / distance;
                assert!(tilt + sin_max.asin() < PI / 2.0);
                let exact = PI * sin_max * sin_max * tilt.cos();
                let mut random = SplitMix64::new(41);
                let n = 20_000;
                let (mut sum, mut sum2) = (0.0, 0.0);
                for _ in 0..n {
                    let u = [random.next_offset(), random.next_offset()];
                    let value = emitters
                        .sample(&world, from, Some(normal), 0.0, 0.5, u)
                        .map_or(0.0, |s| {
                            s.radiance.luminance() * s.direction.dot(normal).max(0.0) / s.pdf
                        });
                    sum += value;
                    sum2 += value * value;
                }
                let mean = sum / n as f64;
                let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - exact).abs() < 4.0 * se + 1e-9 * exact,
                    "cones {cones}, {distance}: {mean} ± {se} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn the_sphere_cones_switch_chooses_how_a_ball_is_sampled() {
        // Seen from outside, a ball drawn in its cone gives every sample on the cap that
        // faces the point, all of the cone's one density; drawn by area, the far half of its
        // points give no light and the densities vary. Either way, a path that reaches the
        // sampled point is told the density the sample had.
        let from = point(4.0, 3.0, -5.0);
        let d2 = (from - point(0.5, -0.2, 0.3)).length_squared();
        let cone_pdf = 1.0 / (2.0 * PI * (1.0 - (1.0 - 0.64 / d2).sqrt()));
        for cones in [true, false] {
            let (world, emitters) = ball_lamp(cones);
            let mut random = SplitMix64::new(7);
            let (n, mut lit, mut off_cone) = (2_000, 0, 0);
            for _ in 0..n {
                let u = [random.next_offset(), random.next_offset()];
                let Some(s) = emitters.sample(&world, from, None, 0.0, 0.5, u) else {
                    continue;
                };
                lit += 1;
                off_cone += usize::from((s.pdf - cone_pdf).abs() > 1e-9 * cone_pdf);
                let object = &world.objects[0];
                let ray = Ray::new(from, s.direction);
                let hit = (object.shape)
                    .closest_hit(&object.ray_to_object(&ray), 1e-9, f64::INFINITY)
                    .expect("a sampled direction meets the ball");
                assert!((hit.t - s.distance).abs() <= 1e-6 * s.distance, "{cones}");
                let pdf = emitters.object_pdf(
                    &world,
                    0,
                    from,
                    None,
                    ray.position(hit.t),
                    s.direction,
                    &hit,
                );
                assert!(
                    (pdf - s.pdf).abs() <= 1e-6 * s.pdf,
                    "{cones}: {pdf} vs {}",
                    s.pdf
                );
            }
            if cones {
                assert_eq!((lit, off_cone), (n, 0));
            } else {
                // About half the ball faces the point, a little less from a finite distance.
                assert!((n * 2 / 5..n / 2).contains(&lit), "{lit}");
                assert_eq!(off_cone, lit);
            }
        }
    }

    #[test]
    fn a_moving_lamp_is_sampled_where_it_is_at_the_paths_instant() {
        let start = Transform::IDENTITY;
        let end = Transform::new(translation(3.0, 0.0, 0.0));
        let lamp = lamp(Shape::Sphere, glam::DMat4::IDENTITY, EmissionSide::Both)
            .placed_by_moving(&start, &end)
            .unwrap();
        let world = World {
            objects: vec![lamp],
            ..World::default()
        };
        let emitters = Emitters::new(&world);
        let from = point(1.5, 0.0, -6.0);
        let mut rng = SplitMixStream(5);
        for time in [0.0, 0.5, 1.0] {
            let centre = point(3.0 * time, 0.0, 0.0);
            for _ in 0..200 {
                let u = [rng.next(), rng.next()];
                let s = emitters
                    .sample(&world, from, None, time, rng.next(), u)
                    .expect("a sample");
                let at = from + s.direction * s.distance;
                assert!(
                    ((at - centre).length() - 1.0).abs() < 1e-9,
                    "{time}: {at:?}"
                );
                let object = &world.objects[0];
                let ray = Ray::new(from, s.direction).at_time(time);
                let Some(hit) =
                    object
                        .shape
                        .closest_hit(&object.ray_to_object(&ray), 1e-9, f64::INFINITY)
                else {
                    panic!("{time}: a sampled direction misses");
                };
                if (hit.t - s.distance).abs() > 1e-6 * s.distance {
                    continue;
                }
                let pdf = emitters.object_pdf(&world, 0, from, None, at, s.direction, &hit);
                assert!(
                    (pdf - s.pdf).abs() <= 1e-6 * s.pdf,
                    "{time}: {pdf} vs {}",
                    s.pdf
                );
            }
        }
    }

    #[test]
    fn a_sampled_point_has_the_density_a_path_that_hits_it_is_told() {
        let from = point(4.0, 3.0, -5.0);
        for object in lamps(EmissionSide::Both) {
            let world = World {
                objects: vec![object],
                ..World::default()
            };
            let emitters = Emitters::new(&world);
            let mut rng = SplitMixStream(12345);
            let mut checked = 0;
            for _ in 0..500 {
                let u = [rng.next(), rng.next()];
                let Some(s) = emitters.sample(&world, from, None, 0.0, rng.next(), u) else {
                    continue;
                };
                // The first hit along the sampled direction: where a path would arrive.
                let ray = Ray::new(from, s.direction);
                let object = &world.objects[0];
                let Some(hit) =
                    object
                        .shape
                        .closest_hit(&object.ray_to_object(&ray), 1e-9, f64::INFINITY)
                else {
                    panic!("{:?}: a sampled direction misses", object.shape);
                };
                if (hit.t - s.distance).abs() > 1e-6 * s.distance {
                    continue; // the sampled point lies behind another part of the shape
                }
                let at = ray.position(hit.t);
                let pdf = emitters.object_pdf(&world, 0, from, None, at, s.direction, &hit);
                assert!(
                    (pdf - s.pdf).abs() <= 1e-6 * s.pdf,
                    "{:?}: sampled with {} but told {pdf}",
                    object.shape,
                    s.pdf
                );
                checked += 1;
            }
            assert!(checked > 100, "{:?}: {checked}", world.objects[0].shape);
        }
    }

    /// Where the lights say they choose nothing (one lamp sampled as a whole), a light sample
    /// is the same whatever its pick number (the path tracer then leaves it undrawn); where a
    /// sample depends on it (several lamps, a mesh's triangles), they say they choose.
    #[test]
    fn the_pick_number_is_used_only_where_the_lights_choose() {
        let from = point(4.0, 3.0, -5.0);
        let one_each = lamps(EmissionSide::Both).into_iter().map(|o| vec![o]);
        let two = lamps(EmissionSide::Both)[1..3].to_vec();
        let (mut unchosen, mut depending) = (0, 0);
        for objects in one_each.chain([two]) {
            let world = World {
                objects,
                ..World::default()
            };
            let emitters = Emitters::new(&world);
            let mut rng = SplitMixStream(77);
            let mut differs = false;
            for _ in 0..200 {
                let u = [rng.next(), rng.next()];
                let low = emitters.sample(&world, from, None, 0.0, 0.0, u);
                let high = emitters.sample(&world, from, None, 0.0, 0.999, u);
                differs |= low != high;
            }
            assert!(
                !differs || emitters.chooses(),
                "{:?}",
                world.objects[0].shape
            );
            unchosen += usize::from(!emitters.chooses());
            depending += usize::from(differs);
        }
        // The rectangle (a parallelogram) chooses nothing; the mesh, the cube and the pair do.
        assert!(unchosen >= 1 && depending >= 3, "{unchosen}, {depending}");
    }

    #[test]
    fn a_one_sided_lamp_lights_only_the_side_its_hits_see_as_front() {
        // Each flat lamp faces its hits' normal; from a point on that side, light samples
        // arrive, from the other side none.
        for object in lamps(EmissionSide::Front).into_iter().skip(2).take(3) {
            let centre = object.transform.point(Point3::new(0.0, 0.3, 0.0));
            let hit_normal = object.normal_at(object.transform.point(Point3::new(0.0, 0.2, 0.0)));
            let world = World {
                objects: vec![object],
                ..World::default()
            };
            let emitters = Emitters::new(&world);
            let front = centre + hit_normal * 3.0;
            let back = centre - hit_normal * 3.0;
            let count = |at: Point3| {
                (0..64)
                    .filter(|i| {
                        let u = [(i % 8) as f64 / 8.0 + 0.06, (i / 8) as f64 / 8.0 + 0.06];
                        emitters.sample(&world, at, None, 0.0, 0.5, u).is_some()
                    })
                    .count()
            };
            assert!(count(front) > 0, "{:?}", world.objects[0].shape);
            assert_eq!(count(back), 0, "{:?}", world.objects[0].shape);
        }
    }

    /// Numbers in [0, 1) for the tests.
    struct SplitMixStream(u64);
    impl SplitMixStream {
        fn next(&mut self) -> f64 {
            use crate::math::random::{Jitter, SplitMix64};
            let mut g = SplitMix64::new(self.0);
            self.0 = g.next_u64();
            g.next_offset()
        }
    }
}
