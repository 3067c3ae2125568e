//! Everything that gives off light, as the path tracer samples it: the book's lights, objects
//! whose material emits, and the sky (an environment map, or the background as a constant sky).
//!
//! Next-event estimation picks one emitter per path vertex, with a probability proportional to
//! an estimate of its power ([`Emitters::sample`]), and a point or direction on it. A path that
//! finds an emitter by scattering asks how likely light sampling would have been to choose that
//! point ([`Emitters::object_pdf`], [`Emitters::sky_radiance_and_pdf`]), so that multiple
//! importance sampling can weigh the two ways of finding it.
//!
//! What each kind of light means physically:
//! - The book's point, spot, directional and area lights keep the book's meaning: no fall-off
//!   with distance, each giving a surface facing it the irradiance `π · intensity · cos θ`, so
//!   a white Lambertian surface is as bright as the book's diffuse term makes it. Under the
//!   optics model, whose lights fall off with the square of the distance, point and spot
//!   lights do too (`π · intensity / d²`). The area light is an invisible rectangle whose
//!   points are such lights, sampled by area: only its light is seen.
//! - An emitting object gives off radiance `emission` from the side its normal faces (or the
//!   other side, or both: [`EmissionSide`](crate::shading::EmissionSide)); a glTF material's
//!   emissive texture scales it at the surface's own texture coordinates. What is sampled:
//!   - Through their shape's [`ShapeSampler`] (the shapes' sampling lives with them, in
//!     `geometry`), where they are at the path's instant of the shutter when they move:
//!     spheres seen from outside in the cone of directions they subtend (when their transform
//!     keeps them spheres), and by area spheres from inside, cubes, rectangles, rings and
//!     discs, triangles, meshes, finite cylinders and cones, ring tori and spindle tori.
//!   - Emissive textures, on any of those: sampled as the plain shape, the radiance
//!     read at the sampled point by the same code a path that hits it uses; the emitter's
//!     power (which picks it) uses the texture's mean over 32 × 32 points.
//!   - CSG solids that stand still, of at most [`MAX_SAMPLED_CSG_LEAVES`] primitives: one of
//!     their emitting primitives of the kinds above is picked by area, a point on it by area
//!     (a sphere too: the solid may cut away its side facing the point), and the sample gives
//!     no light where the solid does not keep that surface ([`Csg::keeps_surface_point`]). A
//!     kept point's density is the primitive's probability over its area, which
//!     [`Emitters::object_pdf`] returns for a hit there.
//!   - Infinite planes: a direction cosine-weighted about the normal, over the hemisphere
//!     towards the plane's glowing side (every such direction meets it); picked by the power
//!     it sends through the scene's cross-section.
//!
//!   Other emitting shapes (infinite cylinders and cones, CSG solids that move or have more
//!   primitives, a solid's primitives of other kinds, glTF meshes whose alpha mode cuts holes
//!   in them) are found only by the paths that hit them, which is unbiased but noisier.
//! - The sky: the world's environment map, importance-sampled by luminance, else the
//!   background as light of constant radiance from every direction (found by the paths that
//!   escape: sampling the BSDF follows a uniform sky as well as light sampling could).
//! - The cgfs model's ambient light has no physical meaning and is left out: the path tracer's
//!   indirect light is what it stood for.

use super::light_bounds::{Cone, LightBounds};
use super::mirror_ball::MirrorBall;
use super::sampler::LightSampler;
use crate::color::Color;
use crate::geometry::{rectangle, LocalHit, ShapeSampler, SolidAngleSample};
use crate::math::random::{Jitter, SplitMix64};
use crate::math::{cosine_hemisphere, Aabb, Distribution1D, Frame, Point3, Transform, Vec3};
use crate::options::LightSamplerKind;
use crate::scene::{Csg, Cuboid, LightingModel, Object, Shape, World};
use crate::shading::{EmissionSide, EnvironmentMap, Light, Material, SkyDraw, SpotLight};
use std::f64::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

/// Marks an object that is not a sampled emitter.
const NOT_SAMPLED: u32 = u32::MAX;

/// The most primitives a CSG solid may have to be light-sampled: whether the solid keeps a
/// sampled point asks every operation above its primitive whether the point is inside the
/// other operand, a cost that grows with the product of primitives and operations.
const MAX_SAMPLED_CSG_LEAVES: usize = 64;

/// One direction towards light from a point, chosen by [`Emitters::sample`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point towards the light.
    pub direction: Vec3,
    /// How far the light is along it (infinite for the sky and directional lights).
    pub distance: f64,
    /// The radiance arriving along `direction`; for a delta light (a point, a direction), the
    /// irradiance it gives a surface facing it, per unit of `pdf`.
    pub radiance: Color,
    /// The solid-angle density of `direction` times the probability of picking this emitter;
    /// for a delta light, that probability alone.
    pub pdf: f64,
    /// Whether the light is a point or a direction, which scattering can never find.
    pub delta: bool,
}

/// One light source as next-event estimation sees it.
#[derive(Debug, Clone)]
enum Emitter {
    /// A book point light, or a spotlight (its cone in `spot`).
    Point {
        position: Point3,
        intensity: Color,
        falloff: bool,
        spot: Option<SpotLight>,
    },
    /// Parallel light from `towards` (unit).
    Directional { towards: Vec3, irradiance: Color },
    /// The book's area light: a rectangle of no-fall-off points, sampled by area.
    BookArea {
        corner: Point3,
        side_u: Vec3,
        side_v: Vec3,
        intensity: Color,
        falloff: bool,
    },
    /// A rectangle that stands still and glows with a plain colour, worked out in world space
    /// once: under any fixed transform it is a parallelogram, `corner + u·edge_u + v·edge_v`,
    /// of one normal and one density, so a light sample takes a few products where the
    /// general surface's took the transform's (less than half the instructions per light
    /// sample in the Cornell box).
    Parallelogram {
        corner: Point3,
        edge_u: Vec3,
        edge_v: Vec3,
        /// The unit normal of its emitting side (as the object's transform maps +Y).
        normal: Vec3,
        /// The density per unit of world area: one over the area.
        density: f64,
        radiance: Color,
        side: EmissionSide,
    },
    /// A cube that stands still, turned and scaled along its axes, and glows with a plain
    /// colour (see [`Cuboid`]): a face picked by its area, a point on it uniformly, all in
    /// world space, where the general surface took every point and normal through the
    /// transform and back (a closed furnace's light samples and densities were a fifth of
    /// its render).
    Cuboid {
        cuboid: Cuboid,
        /// The faces, in proportion to their areas.
        faces: Distribution1D,
        /// The density per unit of world area: one over the whole surface's area.
        density: f64,
        radiance: Color,
        side: EmissionSide,
    },
    /// The world's object `object`, whose material emits (sampled where the object is at the
    /// path's instant, when it moves).
    Surface { object: u32, surface: ShapeSampler },
    /// A CSG solid that stands still, through its primitives that emit and can be sampled by
    /// area (`parts`, picked by `pick` in proportion to their areas; `by_leaf` gives each
    /// primitive's part, or [`NOT_SAMPLED`]).
    Csg {
        csg: Arc<Csg>,
        parts: Box<[CsgPart]>,
        pick: Distribution1D,
        by_leaf: Box<[u32]>,
    },
    /// The world's object `object`, an infinite plane: directions towards it, cosine-weighted.
    Plane { object: u32 },
    /// The sky.
    Sky,
}

/// A primitive of a CSG solid, sampled by area as an object of its own would be.
#[derive(Debug, Clone)]
struct CsgPart {
    /// Its index among the solid's leaves.
    leaf: u32,
    surface: ShapeSampler,
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
    /// The sky when there is no environment map.
    background: Color,
    environment: Option<Arc<EnvironmentMap>>,
    /// The polished metal balls through which the environment map's light is sampled
    /// (empty without a map that gives light).
    mirror_balls: Vec<MirrorBall>,
    /// Per world object, its index in `mirror_balls`, or [`NOT_SAMPLED`].
    mirror_of_object: Vec<u32>,
}

impl Emitters {
    /// The emitters of `world`, picked as [`LightSamplerKind::Auto`] picks.
    pub fn new(world: &World) -> Self {
        Self::with_sampler(world, LightSamplerKind::Auto)
    }

    /// The emitters of `world`, picked by a sampler of kind `kind`.
    pub fn with_sampler(world: &World, kind: LightSamplerKind) -> Self {
        let radius = scene_radius(world);
        let falloff = world.lighting == LightingModel::Optics;
        let disc = PI * radius * radius;
        // A book light's power: its irradiance π·I over a sphere (falling off) or, not falling
        // off, over the scene's cross-section.
        let point_power = |intensity: Color, own_falloff: bool| {
            intensity.luminance()
                * PI
                * if falloff || own_falloff {
                    4.0 * PI
                } else {
                    disc
                }
        };
        let mut list = Vec::new();
        let mut power = Vec::new();
        // Each emitter's bounds for the light tree; `None` for light from infinity, or light
        // that does not fall off with distance.
        let mut bounds = Vec::new();
        let at_point = |position: Point3, cone: Cone| LightBounds {
            bounds: Aabb::new(position, position),
            power: 0.0,
            cone,
            two_sided: false,
        };
        for light in &world.lights {
            let placed = match *light {
                Light::Point(l) if falloff || l.falloff => {
                    Some(at_point(l.position, Cone::EVERYWHERE))
                }
                Light::Spot(l) if falloff || l.falloff => {
                    // All its light within the outer cone, none beyond it.
                    let cone = Cone {
                        axis: l.direction.normalize_or_zero(),
                        theta_o: l.cos_outer.clamp(-1.0, 1.0).acos(),
                        theta_e: 0.0,
                    };
                    Some(at_point(l.position, cone))
                }
                Light::Area(l) if falloff => {
                    let mut b = Aabb::new(l.corner, l.corner);
                    b.add_point(l.corner + l.uvec * f64::from(l.usteps));
                    b.add_point(l.corner + l.vvec * f64::from(l.vsteps));
                    b.add_point(
                        l.corner + l.uvec * f64::from(l.usteps) + l.vvec * f64::from(l.vsteps),
                    );
                    Some(LightBounds {
                        bounds: b,
                        ..at_point(l.corner, Cone::EVERYWHERE)
                    })
                }
                _ => None,
            };
            let (emitter, p) = match *light {
                Light::Point(l) => (
                    Emitter::Point {
                        position: l.position,
                        intensity: l.intensity * PI,
                        falloff: falloff || l.falloff,
                        spot: None,
                    },
                    point_power(l.intensity, l.falloff),
                ),
                Light::Spot(l) => (
                    Emitter::Point {
                        position: l.position,
                        intensity: l.intensity * PI,
                        falloff: falloff || l.falloff,
                        spot: Some(l),
                    },
                    point_power(l.intensity, l.falloff),
                ),
                Light::Directional(l) => (
                    Emitter::Directional {
                        towards: l.towards.normalize_or_zero(),
                        irradiance: l.intensity * PI,
                    },
                    l.intensity.luminance() * PI * disc,
                ),
                Light::Area(l) => (
                    Emitter::BookArea {
                        corner: l.corner,
                        side_u: l.uvec * f64::from(l.usteps),
                        side_v: l.vvec * f64::from(l.vsteps),
                        intensity: l.intensity * PI,
                        falloff,
                    },
                    point_power(l.intensity, false),
                ),
                Light::Ambient(_) => continue,
            };
            list.push(emitter);
            power.push(p);
            bounds.push(placed.map(|b| LightBounds { power: p, ..b }));
        }
        let mut by_object = vec![NOT_SAMPLED; world.objects.len()];
        for (i, object) in world.objects.iter().enumerate() {
            let Some((emitter, p)) = object_emitter(object, i as u32, disc) else {
                continue;
            };
            by_object[i] = list.len() as u32;
            bounds.push(object_bounds(&emitter, object, p));
            list.push(emitter);
            power.push(p);
        }
        // A constant sky is not sampled as a light: BSDF sampling follows it as well as any
        // light sampling could (perfectly, for a diffuse surface), and a white furnace then
        // has no variance at all. A map is sampled by its luminance.
        let sky_power = world
            .environment
            .as_ref()
            .map_or(0.0, |map| map.average_radiance().luminance() * PI * disc);
        let sky = (sky_power > 0.0).then(|| {
            list.push(Emitter::Sky);
            power.push(sky_power);
            bounds.push(None);
            (list.len() - 1) as u32
        });
        let pick = LightSampler::new(kind, &power, &bounds);
        let mirror_balls: Vec<MirrorBall> = if sky.is_some() {
            world
                .objects
                .iter()
                .enumerate()
                .filter_map(|(i, object)| MirrorBall::of(object, i as u32))
                .collect()
        } else {
            Vec::new()
        };
        let mut mirror_of_object = vec![NOT_SAMPLED; world.objects.len()];
        for (i, ball) in mirror_balls.iter().enumerate() {
            mirror_of_object[ball.object as usize] = i as u32;
        }
        Self {
            list,
            pick,
            by_object,
            sky,
            background: world.background,
            environment: world.environment.clone(),
            mirror_balls,
            mirror_of_object,
        }
    }

    /// The environment map, when it gives light (what [`mirror_balls`](Self::mirror_balls)
    /// reflect).
    pub fn environment(&self) -> Option<&EnvironmentMap> {
        self.sky.and(self.environment.as_deref())
    }

    /// The polished metal balls through which the path tracer samples the environment map's
    /// light (see [`MirrorBall`]); empty when no map gives light.
    pub fn mirror_balls(&self) -> &[MirrorBall] {
        &self.mirror_balls
    }

    /// The mirror ball that world object `index` is, if it is one.
    #[inline]
    pub fn mirror_ball_of(&self, index: usize) -> Option<&MirrorBall> {
        let at = *self.mirror_of_object.get(index)?;
        self.mirror_balls.get(at as usize)
    }

    /// Whether anything can be sampled.
    pub fn is_empty(&self) -> bool {
        self.pick.is_none()
    }

    /// The radiance of the sky along `direction` (what a path that escapes sees).
    #[inline]
    pub fn sky_radiance(&self, direction: Vec3) -> Color {
        match &self.environment {
            Some(map) => map.radiance(direction),
            None => self.background,
        }
    }

    /// The radiance arriving from the sky along `direction`, as
    /// [`sky_radiance`](Self::sky_radiance), and the density with which
    /// [`sample`](Self::sample) chooses that direction towards the sky (0 where the sky is not
    /// sampled): what a path that escapes weighs its light by.
    pub fn sky_radiance_and_pdf(&self, direction: Vec3) -> (Color, f64) {
        let Some(map) = &self.environment else {
            return (self.background, 0.0);
        };
        let (radiance, pdf) = map.radiance_and_pdf(direction);
        // The sky is apart from any tree: its probability is the same from every point.
        let pick = match (self.sky, &self.pick) {
            (Some(sky), Some(pick)) => pick.probability(Point3::ZERO, None, sky as usize),
            _ => 0.0,
        };
        (radiance, pick * pdf)
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
        let density = match self.list.get(slot as usize) {
            Some(Emitter::Parallelogram {
                normal, density, ..
            }) => flat_density(*normal, *density, from, point, direction),
            Some(Emitter::Cuboid {
                cuboid, density, ..
            }) => flat_density(cuboid.normal_at(point), *density, from, point, direction),
            Some(Emitter::Surface { surface, object }) => {
                let placed = world.objects[*object as usize].transform_at(hit.time);
                surface.pdf_solid_angle(&placed, from, point, direction, hit.face)
            }
            Some(Emitter::Csg {
                csg,
                parts,
                pick: leaves,
                by_leaf,
            }) => {
                let Some(&part) = by_leaf.get(hit.leaf as usize) else {
                    return 0.0;
                };
                let Some(CsgPart { leaf, surface }) = parts.get(part as usize) else {
                    return 0.0;
                };
                if !csg.keeps_surface_point(*leaf as usize, point) {
                    return 0.0;
                }
                let placed = csg.leaves()[*leaf as usize].transform_at(hit.time);
                leaves.probability(part as usize)
                    * surface.pdf_area_seen_from(&placed, from, point, direction, hit.face)
            }
            Some(Emitter::Plane { object }) => {
                let object = &world.objects[*object as usize];
                let (origin, normal) = plane_frame(object, hit.time);
                let above = normal.dot(from - origin);
                if !object.material.emission_side.emits_towards(above) {
                    return 0.0;
                }
                normal.dot(direction).abs() * FRAC_1_PI
            }
            _ => return 0.0,
        };
        pick.probability(from, from_normal, slot as usize) * density
    }

    /// Whether [`sample`](Self::sample) uses its number `pick`: to choose among several
    /// emitters, or a part of the one surface that emits (a mesh's triangle, a moving or
    /// sheared cube's face, a solid's primitive; a still box takes its face from the point's
    /// numbers). Where it does not (one lamp, one sky), a path tracer need not draw the
    /// number at all.
    pub fn chooses(&self) -> bool {
        self.list.len() > 1
            || matches!(
                self.list.first(),
                Some(Emitter::Surface { .. } | Emitter::Csg { .. })
            )
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
            Emitter::Point {
                position,
                intensity,
                falloff,
                spot,
            } => {
                let to_light = *position - point;
                let distance = to_light.length();
                let direction = to_light / distance;
                let cone = spot.map_or(1.0, |s| s.falloff(-direction));
                let mut radiance = *intensity * cone;
                if *falloff {
                    radiance = radiance * (1.0 / (distance * distance));
                }
                (radiance.max_channel() > 0.0 && distance > 0.0).then_some(LightSample {
                    direction,
                    distance,
                    radiance,
                    pdf: probability,
                    delta: true,
                })
            }
            Emitter::Directional {
                towards,
                irradiance,
            } => Some(LightSample {
                direction: *towards,
                distance: f64::INFINITY,
                radiance: *irradiance,
                pdf: probability,
                delta: true,
            }),
            Emitter::BookArea {
                corner,
                side_u,
                side_v,
                intensity,
                falloff,
            } => {
                let on_light = *corner + *side_u * u[0] + *side_v * u[1];
                let to_light = on_light - point;
                let distance = to_light.length();
                let mut radiance = *intensity;
                if *falloff {
                    radiance = radiance * (1.0 / (distance * distance));
                }
                (distance > 0.0).then(|| LightSample {
                    direction: to_light / distance,
                    distance,
                    radiance,
                    pdf: probability,
                    delta: true,
                })
            }
            Emitter::Parallelogram {
                corner,
                edge_u,
                edge_v,
                normal,
                density,
                radiance,
                side,
            } => {
                let on_light = *corner + *edge_u * u[0] + *edge_v * u[1];
                let density = probability * density;
                flat_light(point, on_light, *normal, *side, *radiance, density)
            }
            Emitter::Cuboid {
                cuboid,
                faces,
                density,
                radiance,
                side,
            } => {
                // The face from the point's first number (what is left of it places the point
                // on the face): the pick's number is then drawn only where there are several
                // lights to choose among.
                let (face, _, across) = faces.sample_discrete_reused(u[0]);
                let (on_light, normal) = cuboid.face_point(face, [across, u[1]]);
                let density = probability * density;
                flat_light(point, on_light, normal, *side, *radiance, density)
            }
            Emitter::Surface { object, surface } => {
                let object = &world.objects[*object as usize];
                let placed = object.transform_at(time);
                let drawn = surface.sample_solid_angle(&placed, point, rest, u)?;
                let light = surface_light(object, drawn, |_| true)?;
                Some(LightSample {
                    pdf: probability * light.pdf,
                    ..light
                })
            }
            Emitter::Csg {
                csg,
                parts,
                pick: leaves,
                ..
            } => {
                let (part, chance, rest) = leaves.sample_discrete_reused(rest);
                let CsgPart { leaf, surface } = &parts[part];
                let object = &csg.leaves()[*leaf as usize];
                let keeps = |at: Point3| csg.keeps_surface_point(*leaf as usize, at);
                // By area, not by what the primitive looks like from the point: the solid may
                // cut away the side facing it and keep the one behind.
                let placed = object.transform_at(time);
                let drawn = surface.sample_area_seen_from(&placed, point, rest, u)?;
                let light = surface_light(object, drawn, keeps)?;
                Some(LightSample {
                    pdf: probability * chance * light.pdf,
                    ..light
                })
            }
            Emitter::Plane { object } => {
                let object = &world.objects[*object as usize];
                let (origin, normal) = plane_frame(object, time);
                let above = normal.dot(point - origin);
                if !object.material.emission_side.emits_towards(above) {
                    return None;
                }
                // Cosine-weighted about the normal towards the plane.
                let towards = if above > 0.0 { -normal } else { normal };
                let local = cosine_hemisphere(u);
                let cos = local.z;
                let direction = Frame::from_normal(towards).to_world(local);
                let distance = above.abs() / cos;
                let radiance = emitted(object, &LocalHit::default());
                (cos > 0.0 && distance.is_finite() && radiance.max_channel() > 0.0).then_some(
                    LightSample {
                        direction,
                        distance,
                        radiance,
                        pdf: probability * cos * FRAC_1_PI,
                        delta: false,
                    },
                )
            }
            Emitter::Sky => {
                let (direction, radiance, pdf) = sky.of(self.environment.as_ref()?)?;
                Some(LightSample {
                    direction,
                    distance: f64::INFINITY,
                    radiance,
                    pdf: probability * pdf,
                    delta: false,
                })
            }
        }
    }
}

/// The light arriving at `point` from `on_light`, a point of a flat lamp of unit normal
/// `normal` (its front) drawn with density `density` per unit of area, that glows with
/// `radiance` on `side`: `None` from behind, or from the point itself.
#[inline]
fn flat_light(
    point: Point3,
    on_light: Point3,
    normal: Vec3,
    side: EmissionSide,
    radiance: Color,
    density: f64,
) -> Option<LightSample> {
    let to_light = on_light - point;
    let distance_squared = to_light.length_squared();
    let distance = distance_squared.sqrt();
    if distance <= 0.0 {
        return None;
    }
    let direction = to_light / distance;
    let cos = -normal.dot(direction);
    (cos != 0.0 && side.emits_towards(cos)).then(|| LightSample {
        direction,
        distance,
        radiance,
        pdf: density * distance_squared / cos.abs(),
        delta: false,
    })
}

/// The density per solid angle at `from` of the point `point` of a flat lamp of unit normal
/// `normal`, seen along unit `direction`, drawn with `density` per unit of area (what
/// [`flat_light`] reports for it).
#[inline]
fn flat_density(normal: Vec3, density: f64, from: Point3, point: Point3, direction: Vec3) -> f64 {
    let cos = normal.dot(direction).abs();
    if cos <= 0.0 {
        return 0.0;
    }
    density * (point - from).length_squared() / cos
}

/// The light `object` sends to the viewer of `drawn`, a point drawn on its surface: `None` when
/// it gives none there (the back of a one-sided emitter, a point `keep` rejects, one a CSG
/// solid does not keep, no radiance).
#[inline]
fn surface_light(
    object: &Object,
    drawn: SolidAngleSample,
    keep: impl Fn(Point3) -> bool,
) -> Option<LightSample> {
    let cos = -drawn.normal.dot(drawn.direction);
    if !object.material.emission_side.emits_towards(cos) || !keep(drawn.point) {
        return None;
    }
    let radiance = emitted(object, &drawn.hit);
    (radiance.max_channel() > 0.0).then_some(LightSample {
        direction: drawn.direction,
        distance: drawn.distance,
        radiance,
        pdf: drawn.pdf,
        delta: false,
    })
}

/// The radiance `object` gives off at the object-space hit `hit`: the same reading of its
/// material as the path integrator makes where a path meets it (a glTF material's emissive
/// factor times its emissive texture at the surface's texture coordinates).
#[inline]
fn emitted(object: &Object, hit: &LocalHit) -> Color {
    let material = &object.material;
    match &material.metal_rough {
        Some(m) => m.emission_at(&object.shape.surface_point(hit)),
        None => material.emission,
    }
}

/// The emission factor of a material (before any texture): zero when it does not emit.
fn emission_factor(material: &Material) -> Color {
    match &material.metal_rough {
        Some(m) => m.emissive,
        None => material.emission,
    }
}

/// The mean radiance a material gives off, for the power an emitter is picked by: its emission,
/// times the mean of its emissive texture (read at 32 × 32 points) where it has one.
fn mean_emission(material: &Material) -> Color {
    let factor = emission_factor(material);
    let Some(slot) = (material.metal_rough.as_ref()).and_then(|m| m.emissive_texture.as_ref())
    else {
        return factor;
    };
    // Read at 32 × 32 points of the unit square (the same texture may cover a thousand
    // surfaces: reading every texel for each would cost more than the render).
    let n = 32;
    let mut sum = Color::BLACK;
    for i in 0..n {
        for j in 0..n {
            let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            sum += slot.sample(u, v);
        }
    }
    let mean = factor.hadamard(sum * (1.0 / (n * n) as f64));
    // A texture dark at every point read may still glow between them: keep it pickable.
    if mean.max_channel() > 0.0 {
        mean
    } else {
        factor * (1.0 / (n * n) as f64)
    }
}

/// A point of the (infinite) plane `object` at `time` and its unit normal, the side its hits
/// see as their front.
#[inline]
fn plane_frame(object: &Object, time: f64) -> (Point3, Vec3) {
    let transform = object.transform_at(time);
    (transform.point(Point3::ZERO), transform.normal(Vec3::Y))
}

/// The emitter of world object number `index`, and the power it is picked by, if its material
/// emits and its shape can be sampled (`disc`: the scene's cross-section).
fn object_emitter(object: &Object, index: u32, disc: f64) -> Option<(Emitter, f64)> {
    let power = || mean_emission(&object.material).luminance() * PI;
    match &object.shape {
        // Its primitives' materials shine, not its own.
        Shape::Csg(csg) => csg_emitter(object, csg),
        _ if emission_factor(&object.material).max_channel() <= 0.0 => None,
        // What an infinite plane sends through the scene's cross-section.
        Shape::Plane => Some((Emitter::Plane { object: index }, power() * disc)),
        // A glTF mesh whose alpha cuts holes: a point sampled in a hole would give light that
        // paths pass through.
        Shape::Mesh(_) if (object.material.metal_rough.as_ref()).is_some_and(|m| m.has_holes()) => {
            None
        }
        Shape::Rectangle if object.motion.is_none() && object.material.metal_rough.is_none() => {
            let t = &object.transform;
            let corner = t.point(rectangle::point_at(0.0, 0.0));
            let edge_u = t.point(rectangle::point_at(1.0, 0.0)) - corner;
            let edge_v = t.point(rectangle::point_at(0.0, 1.0)) - corner;
            let (density, normal) = ShapeSampler::Rectangle.area_density(t, Vec3::Y);
            let emitter = Emitter::Parallelogram {
                corner,
                edge_u,
                edge_v,
                normal,
                density,
                radiance: emitted(object, &LocalHit::default()),
                side: object.material.emission_side,
            };
            let area = rectangle::AREA;
            (density > 0.0).then(|| (emitter, power() * rough_world_area(area, t)))
        }
        Shape::Cube if object.material.metal_rough.is_none() && Cuboid::of(object).is_some() => {
            let cuboid = Cuboid::of(object)?;
            let areas = cuboid.face_areas();
            let area: f64 = areas.iter().sum();
            let faces = Distribution1D::new(&areas).ok()?;
            let emitter = Emitter::Cuboid {
                cuboid,
                faces,
                density: 1.0 / area,
                radiance: emitted(object, &LocalHit::default()),
                side: object.material.emission_side,
            };
            (area > 0.0 && area.is_finite()).then(|| (emitter, power() * area))
        }
        shape => {
            let surface = shape.sampler()?;
            let world_area = rough_world_area(surface.area(), &object.transform);
            let emitter = Emitter::Surface {
                object: index,
                surface,
            };
            Some((emitter, power() * world_area))
        }
    }
}

/// The light tree's bounds of `emitter`, world object `object`'s, of power `power`: a flat
/// lamp's parallelogram and the side it faces; for any other shape, its box and every
/// direction (a closed shape faces every way); `None` for an infinite plane, whose light comes
/// from infinity.
fn object_bounds(emitter: &Emitter, object: &Object, power: f64) -> Option<LightBounds> {
    let bounds = match emitter {
        Emitter::Plane { .. } => return None,
        Emitter::Parallelogram {
            corner,
            edge_u,
            edge_v,
            normal,
            side,
            ..
        } => {
            let mut b = Aabb::new(*corner, *corner);
            for p in [*edge_u, *edge_v, *edge_u + *edge_v] {
                b.add_point(*corner + p);
            }
            let axis = match side {
                EmissionSide::Back => -*normal,
                EmissionSide::Front | EmissionSide::Both => *normal,
            };
            let cone = Cone {
                axis,
                theta_o: 0.0,
                theta_e: std::f64::consts::FRAC_PI_2,
            };
            return Some(LightBounds {
                bounds: b,
                power,
                cone,
                two_sided: *side == EmissionSide::Both,
            });
        }
        Emitter::Cuboid { .. } => object.bounds(),
        _ => object.bounds(),
    };
    let finite = bounds.min.is_finite() && bounds.max.is_finite() && !bounds.is_empty();
    finite.then_some(LightBounds {
        bounds,
        power,
        cone: Cone::EVERYWHERE,
        two_sided: false,
    })
}

/// The world-space area of a surface of object-space area `area` placed by `transform`,
/// roughly (exact for a uniform scale): what an emitter's power is weighed by.
fn rough_world_area(area: f64, transform: &Transform) -> f64 {
    area * transform.volume_scale().powf(2.0 / 3.0)
}

/// The emitter of a CSG solid that stands still (identity transform, no primitive moving: the
/// solid's test of which surface it keeps places its primitives where they are when the shutter
/// opens) and has at most [`MAX_SAMPLED_CSG_LEAVES`] primitives, through its primitives that
/// emit and can be sampled by area. Its power is theirs, each scaled by the share of its
/// surface the solid keeps (estimated from 64 points, and at least 1/64).
fn csg_emitter(object: &Object, csg: &Arc<Csg>) -> Option<(Emitter, f64)> {
    if object.motion.is_some() || object.transform != Transform::IDENTITY {
        return None;
    }
    if csg.leaves().len() > MAX_SAMPLED_CSG_LEAVES {
        return None;
    }
    if csg.leaves().iter().any(|leaf| leaf.motion.is_some()) {
        return None;
    }
    let mut parts = Vec::new();
    let mut areas = Vec::new();
    let mut by_leaf = vec![NOT_SAMPLED; csg.leaves().len()];
    let mut power = 0.0;
    for (k, leaf) in csg.leaves().iter().enumerate() {
        if emission_factor(&leaf.material).max_channel() <= 0.0 {
            continue;
        }
        let Some(surface) = leaf.shape.sampler() else {
            continue;
        };
        let world_area = rough_world_area(surface.area(), &leaf.transform);
        if !(world_area > 0.0 && world_area.is_finite()) {
            continue;
        }
        let mut random = SplitMix64::new(0x05ee_dc59 + k as u64);
        let kept = (0..64)
            .filter(|_| {
                let pick = random.next_offset();
                let u = [random.next_offset(), random.next_offset()];
                let at = leaf.transform.point(surface.sample_area(pick, u).point);
                csg.keeps_surface_point(k, at)
            })
            .count();
        power += mean_emission(&leaf.material).luminance()
            * PI
            * world_area
            * (kept.max(1) as f64 / 64.0);
        by_leaf[k] = parts.len() as u32;
        parts.push(CsgPart {
            leaf: k as u32,
            surface,
        });
        areas.push(world_area);
    }
    let pick = Distribution1D::new(&areas)
        .ok()
        .filter(|d| d.integral() > 0.0)?;
    let emitter = Emitter::Csg {
        csg: Arc::clone(csg),
        parts: parts.into_boxed_slice(),
        pick,
        by_leaf: by_leaf.into_boxed_slice(),
    };
    Some((emitter, power))
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
    use crate::math::{point, rotation_x, rotation_y, scaling, translation, Ray};
    use crate::shading::{EmissionSide, Material};

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

    #[test]
    fn a_ball_lamp_lights_a_point_as_its_analytic_irradiance_says() {
        // A ball of radiance L and radius r seen at distance d, wholly above the point's
        // horizon, gives it the irradiance π L (r/d)² cos β, β the angle between the point's
        // normal and the ball's centre: next-event estimation (the ball drawn in its cone)
        // agrees within its standard error, near and far.
        let world = World {
            objects: vec![lamp(Shape::Sphere, ball_placement(), EmissionSide::Front)],
            ..World::default()
        };
        let emitters = Emitters::new(&world);
        let centre = point(0.5, -0.2, 0.3);
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
                "{distance}: {mean} ± {se} vs {exact}"
            );
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
