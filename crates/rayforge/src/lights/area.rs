//! Light given off by surfaces: the book's rectangular area light and every object whose
//! material emits.
//!
//! - The book's area light (the bonus chapter "Rendering soft shadows") keeps the book's
//!   meaning: an invisible rectangle whose points are point lights without fall-off (inverse
//!   square under the optics model), sampled by area; only its light is seen, and it is a delta
//!   light in that scattering never finds it.
//! - An emitting object gives off radiance `emission` from the side its normal faces (or the
//!   other side, or both: [`EmissionSide`]); a glTF material's emissive texture scales it at the
//!   surface's own texture coordinates. What is sampled:
//!   - Through their shape's [`ShapeSampler`] (the shapes' sampling lives with them, in
//!     `geometry`), where they are at the path's instant of the shutter when they move:
//!     spheres seen from outside in the cone of directions they subtend (when their transform
//!     keeps them spheres, and unless the world's `sphere-cones` switch is off), and by area
//!     spheres from inside, cubes, rectangles, rings and
//!     discs, triangles, meshes, finite cylinders and cones, ring tori and spindle tori; a
//!     still rectangle as a parallelogram and a still box face by face in world space.
//!   - Alpha cut-outs (pbrt-v4's `alpha`) on an emitting mesh: a drawn point's light is
//!     weighed by the alpha there, the chance a path meeting it finds the surface.
//!   - Emissive textures, on any of those: sampled as the plain shape, the radiance
//!     read at the sampled point by the same code a path that hits it uses; the emitter's
//!     power (which picks it) uses the texture's mean over 32 × 32 points.
//!   - CSG solids that stand still, of at most [`MAX_SAMPLED_CSG_LEAVES`] primitives: one of
//!     their emitting primitives of the kinds above is picked by area, a point on it by area
//!     (a sphere too: the solid may cut away its side facing the point), and the sample gives
//!     no light where the solid does not keep that surface ([`Csg::keeps_surface_point`]). A
//!     kept point's density is the primitive's probability over its area, which
//!     [`AreaEmitter::pdf_li`] returns for a hit there.
//!   - Infinite planes: a direction cosine-weighted about the normal, over the hemisphere
//!     towards the plane's glowing side (every such direction meets it); picked by the power
//!     it sends through the scene's cross-section.
//!
//!   Other emitting shapes (infinite cylinders and cones, CSG solids that move or have more
//!   primitives, a solid's primitives of other kinds, glTF meshes whose alpha mode cuts holes
//!   in them) are found only by the paths that hit them, which is unbiased but noisier.

use super::emitters::NOT_SAMPLED;
use super::light_bounds::{Cone, LightBounds};
use super::point::{at_point, point_power};
use super::sample::LightSample;
use crate::color::Color;
use crate::geometry::{rectangle, LocalHit, ShapeSampler, SolidAngleSample};
use crate::math::random::{Jitter, SplitMix64};
use crate::math::{cosine_hemisphere, Aabb, Distribution1D, Frame, Point3, Transform, Vec3};
use crate::scene::{Csg, Cuboid, Object, Shape, World};
use crate::shading::{AreaLight, EmissionSide, Material, SurfacePoint};
use std::f64::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

/// The most primitives a CSG solid may have to be light-sampled: whether the solid keeps a
/// sampled point asks every operation above its primitive whether the point is inside the
/// other operand, a cost that grows with the product of primitives and operations.
const MAX_SAMPLED_CSG_LEAVES: usize = 64;

/// A light that is a surface, in the path tracer's light list: what it is, and the power it is
/// picked by (worked out once, when the list is built: an emissive texture's mean, the share
/// of a CSG primitive's surface the solid keeps).
#[derive(Debug, Clone)]
pub struct AreaEmitter {
    kind: Area,
    power: f64,
}

/// The surfaces that give off light, each sampled its own way.
#[derive(Debug, Clone)]
enum Area {
    /// The book's area light: a rectangle of no-fall-off points, sampled by area.
    Book {
        corner: Point3,
        side_u: Vec3,
        side_v: Vec3,
        /// `π · intensity`.
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
        /// The world's object it is.
        object: u32,
        cuboid: Cuboid,
        /// The faces, in proportion to their areas.
        faces: Distribution1D,
        /// The density per unit of world area: one over the whole surface's area.
        density: f64,
        radiance: Color,
        side: EmissionSide,
    },
    /// The world's object `object`, whose material emits (sampled where the object is at the
    /// path's instant, when it moves): as seen from the point lit, the best way the shape has
    /// where `best` (a ball in the cone it subtends), else by area (the sphere cones switched
    /// off, [`Techniques::sphere_cones`](crate::options::Techniques::sphere_cones)).
    Surface {
        object: u32,
        surface: ShapeSampler,
        best: bool,
    },
    /// The world's object `object`, a CSG solid that stands still, through its primitives
    /// that emit and can be sampled by area (`parts`, picked by `pick` in proportion to their
    /// areas; `by_leaf` gives each primitive's part, or [`NOT_SAMPLED`]).
    Csg {
        object: u32,
        csg: Arc<Csg>,
        parts: Box<[CsgPart]>,
        pick: Distribution1D,
        by_leaf: Box<[u32]>,
    },
    /// The world's object `object`, an infinite plane: directions towards it, cosine-weighted.
    Plane { object: u32 },
}

/// A primitive of a CSG solid, sampled by area as an object of its own would be.
#[derive(Debug, Clone)]
struct CsgPart {
    /// Its index among the solid's leaves.
    leaf: u32,
    surface: ShapeSampler,
}

impl AreaEmitter {
    /// The book's area `light` in a world whose lighting model makes lights fall off with
    /// distance when `model_falloff` (`disc`: the scene's cross-section, which a light without
    /// fall-off is weighed by).
    pub(super) fn of_book(light: &AreaLight, model_falloff: bool, disc: f64) -> Self {
        let (side_u, side_v) = light.sides();
        Self {
            kind: Area::Book {
                corner: light.corner,
                side_u,
                side_v,
                intensity: light.intensity * PI,
                falloff: model_falloff,
            },
            power: point_power(light.intensity, model_falloff, disc),
        }
    }

    /// The emitter of world object number `index`, if its material emits and its shape can be
    /// sampled (`disc`: the scene's cross-section; `sphere_cones`: whether a ball is sampled in
    /// the cone it subtends, [`Techniques::sphere_cones`](crate::options::Techniques::sphere_cones)).
    pub(super) fn of_object(
        object: &Object,
        index: u32,
        disc: f64,
        sphere_cones: bool,
    ) -> Option<Self> {
        let (kind, power) = object_emitter(object, index, disc, sphere_cones)?;
        Some(Self { kind, power })
    }

    /// Whether [`sample_li`](Self::sample_li) uses its number `rest`: to choose a part of the
    /// surface (a mesh's triangle, a moving or sheared cube's face, a solid's primitive; a
    /// still box takes its face from the point's numbers).
    pub(super) fn chooses(&self) -> bool {
        matches!(self.kind, Area::Surface { .. } | Area::Csg { .. })
    }

    /// A point of the surface (or, for a plane, a direction towards it) for lighting `point`
    /// of `world` at shutter instant `time`, drawn with `u` and, where a part of the surface
    /// is chosen, `rest`; the emitter was picked with probability `probability`, which the
    /// sample's density includes. `None` when the choice gives no light: the back of a
    /// one-sided emitter, a point a CSG solid does not keep, no radiance.
    #[inline]
    #[allow(clippy::too_many_arguments)] // the shading point, the numbers and the pick
    pub fn sample_li(
        &self,
        world: &World,
        point: Point3,
        time: f64,
        probability: f64,
        rest: f64,
        u: [f64; 2],
    ) -> Option<LightSample> {
        match &self.kind {
            Area::Book {
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
            Area::Parallelogram {
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
            Area::Cuboid {
                cuboid,
                faces,
                density,
                radiance,
                side,
                ..
            } => {
                // The face from the point's first number (what is left of it places the point
                // on the face): the pick's number is then drawn only where there are several
                // lights to choose among.
                let (face, _, across) = faces.sample_discrete_reused(u[0]);
                let (on_light, normal) = cuboid.face_point(face, [across, u[1]]);
                let density = probability * density;
                flat_light(point, on_light, normal, *side, *radiance, density)
            }
            Area::Surface {
                object,
                surface,
                best,
            } => {
                let object = &world.objects[*object as usize];
                let placed = object.transform_at(time);
                let drawn = if *best {
                    surface.sample_solid_angle(&placed, point, rest, u)
                } else {
                    surface.sample_area_seen_from(&placed, point, rest, u)
                }?;
                let light = surface_light(object, drawn, |_| true)?;
                Some(LightSample {
                    pdf: probability * light.pdf,
                    ..light
                })
            }
            Area::Csg {
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
            Area::Plane { object } => {
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
        }
    }

    /// The density (per solid angle at `from`) with which [`sample_li`](Self::sample_li)
    /// draws the point `point` of the surface, seen along unit `direction` from `from`, where
    /// the object-space hit `hit` was (its face, for meshes, its primitive, for CSG solids,
    /// and its instant, for objects that move), before the emitter's own pick; 0 where light
    /// sampling gives no light (a point a CSG solid does not keep, the dark side of a plane,
    /// the book's light, which scattering never meets).
    pub fn pdf_li(
        &self,
        world: &World,
        from: Point3,
        point: Point3,
        direction: Vec3,
        hit: &LocalHit,
    ) -> f64 {
        match &self.kind {
            Area::Book { .. } => 0.0,
            Area::Parallelogram {
                normal, density, ..
            } => flat_density(*normal, *density, from, point, direction),
            Area::Cuboid {
                cuboid, density, ..
            } => flat_density(cuboid.normal_at(point), *density, from, point, direction),
            Area::Surface {
                surface,
                object,
                best,
            } => {
                let placed = world.objects[*object as usize].transform_at(hit.time);
                if *best {
                    surface.pdf_solid_angle(&placed, from, point, direction, hit.face)
                } else {
                    surface.pdf_area_seen_from(&placed, from, point, direction, hit.face)
                }
            }
            Area::Csg {
                csg,
                parts,
                pick: leaves,
                by_leaf,
                ..
            } => {
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
            Area::Plane { object } => {
                let object = &world.objects[*object as usize];
                let (origin, normal) = plane_frame(object, hit.time);
                let above = normal.dot(from - origin);
                if !object.material.emission_side.emits_towards(above) {
                    return 0.0;
                }
                normal.dot(direction).abs() * FRAC_1_PI
            }
        }
    }

    /// What a path that meets an emitting surface sees: the radiance `surface` (the object
    /// met, or the primitive of a CSG solid) gives off at `at`, towards a direction back along
    /// the path that makes the cosine `cos_out` with its geometric normal (the sign says which
    /// side the path is on); `None` where it gives nothing that way. The same for every
    /// emitting surface, sampled or not (an infinite cylinder, a CSG solid of many primitives
    /// are found by scattering alone), and the same reading of the material as the light
    /// samples' ([`emitted`]); the book's area light, invisible, is never met.
    #[inline]
    pub fn radiance(surface: &Object, at: &SurfacePoint, cos_out: f64) -> Option<Color> {
        let material = &surface.material;
        let emission = emission_of(material, || *at);
        (emission.max_channel() > 0.0 && material.emission_side.emits_towards(cos_out))
            .then_some(emission)
    }

    /// What the light samplers pick it by: its mean radiance times π over its (rough) world
    /// area; a plane's through the scene's cross-section; the book's light as a point light.
    pub fn power(&self) -> f64 {
        self.power
    }

    /// Its bounds for the light tree (an emitting object's: see [`object_bounds`]); the book's light's rectangle,
    /// shining every way, where it falls off; `None` where its light comes as from infinity.
    pub(super) fn bounds(&self, world: &World) -> Option<LightBounds> {
        match &self.kind {
            Area::Book {
                corner,
                side_u,
                side_v,
                falloff,
                ..
            } => falloff.then(|| {
                let mut b = Aabb::new(*corner, *corner);
                b.add_point(*corner + *side_u);
                b.add_point(*corner + *side_v);
                b.add_point(*corner + *side_u + *side_v);
                LightBounds {
                    bounds: b,
                    ..at_point(*corner, Cone::EVERYWHERE, self.power)
                }
            }),
            _ => object_bounds(&self.kind, world, self.power),
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
    let radiance = emitted(object, &drawn.hit) * coverage(object, &drawn);
    (radiance.max_channel() > 0.0).then_some(LightSample {
        direction: drawn.direction,
        distance: drawn.distance,
        radiance,
        pdf: drawn.pdf,
        delta: false,
    })
}

/// How much of the surface is there at the drawn point: its alpha (pbrt-v4's cut-outs), 1
/// where it has none. A path meets a cut-out surface with that probability (the stochastic
/// test at each hit), so light sampling weighs what it draws there by it: both estimate the
/// same light, and their weighing against each other is unchanged.
#[inline]
fn coverage(object: &Object, drawn: &SolidAngleSample) -> f64 {
    let Some(textures) = object.material.textures.as_deref() else {
        return 1.0;
    };
    if textures.alpha.is_none() {
        return 1.0;
    }
    let at = object.shape.surface_point(&drawn.hit);
    let ctx = object.texture_context(drawn.point, &at, &drawn.hit, drawn.normal);
    textures.coverage(&ctx)
}

/// The radiance `object` gives off at the object-space hit `hit`: the same reading of its
/// material as the path integrator makes where a path meets it (a glTF material's emissive
/// factor times its emissive texture at the surface's texture coordinates).
#[inline]
fn emitted(object: &Object, hit: &LocalHit) -> Color {
    emission_of(&object.material, || object.shape.surface_point(hit))
}

/// The radiance `material` gives off at the surface point `at` (asked only of a glTF
/// material, whose emissive texture reads it: a light sample has no surface point until then).
#[inline]
fn emission_of(material: &Material, at: impl FnOnce() -> SurfacePoint) -> Color {
    match &material.metal_rough {
        Some(m) => m.emission_at(&at()),
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
/// emits and its shape can be sampled (see [`AreaEmitter::of_object`]).
fn object_emitter(
    object: &Object,
    index: u32,
    disc: f64,
    sphere_cones: bool,
) -> Option<(Area, f64)> {
    let power = || mean_emission(&object.material).luminance() * PI;
    match &object.shape {
        // Its primitives' materials shine, not its own.
        Shape::Csg(csg) => csg_emitter(object, index, csg),
        _ if emission_factor(&object.material).max_channel() <= 0.0 => None,
        // What an infinite plane sends through the scene's cross-section.
        Shape::Plane => Some((Area::Plane { object: index }, power() * disc)),
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
            let emitter = Area::Parallelogram {
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
            let emitter = Area::Cuboid {
                object: index,
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
            let emitter = Area::Surface {
                object: index,
                surface,
                best: sphere_cones,
            };
            Some((emitter, power() * world_area))
        }
    }
}

/// The light tree's bounds of the emitting object `area` of `world`, of power `power`: a flat
/// lamp's parallelogram and the side it faces; for any other shape, its box and every
/// direction (a closed shape faces every way); `None` for an infinite plane, whose light comes
/// from infinity.
fn object_bounds(area: &Area, world: &World, power: f64) -> Option<LightBounds> {
    let object = match area {
        Area::Book { .. } | Area::Plane { .. } => return None,
        Area::Parallelogram {
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
        Area::Cuboid { object, .. } | Area::Surface { object, .. } | Area::Csg { object, .. } => {
            *object
        }
    };
    let bounds = world.objects.get(object as usize)?.bounds();
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
fn csg_emitter(object: &Object, index: u32, csg: &Arc<Csg>) -> Option<(Area, f64)> {
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
    let emitter = Area::Csg {
        object: index,
        csg: Arc::clone(csg),
        parts: parts.into_boxed_slice(),
        pick,
        by_leaf: by_leaf.into_boxed_slice(),
    };
    Some((emitter, power))
}
