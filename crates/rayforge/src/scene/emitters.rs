//! Everything that gives off light, as the path tracer samples it: the book's lights, objects
//! whose material emits, and the sky (an environment map, or the background as a constant sky).
//!
//! Next-event estimation picks one emitter per path vertex, with a probability proportional to
//! an estimate of its power ([`Emitters::sample`]), and a point or direction on it. A path that
//! finds an emitter by scattering asks how likely light sampling would have been to choose that
//! point ([`Emitters::object_pdf`], [`Emitters::sky_pdf`]), so that multiple importance sampling
//! can weigh the two ways of finding it.
//!
//! What each kind of light means physically:
//! - The book's point, spot, directional and area lights keep the book's meaning: no fall-off
//!   with distance, each giving a surface facing it the irradiance `π · intensity · cos θ`, so
//!   a white Lambertian surface is as bright as the book's diffuse term makes it. Under the
//!   optics model, whose lights fall off with the square of the distance, point and spot
//!   lights do too (`π · intensity / d²`). The area light is an invisible rectangle whose
//!   points are such lights, sampled by area: only its light is seen.
//! - An emitting object gives off radiance `emission` from the side its normal faces (or the
//!   other side, or both: [`EmissionSide`]). Spheres, cubes, rectangles, rings and discs,
//!   triangles, meshes, finite cylinders and cones, and ring tori are sampled by area, where
//!   they are at the path's instant of the shutter when they move; other emitting shapes
//!   (unbounded ones, planes, spindle tori, CSG solids, surfaces with an emission texture)
//!   are found only by the paths that hit them, which is unbiased but noisier.
//! - The sky: the world's environment map, importance-sampled by luminance, else the
//!   background as light of constant radiance from every direction (found by the paths that
//!   escape: sampling the BSDF follows a uniform sky as well as light sampling could).
//! - The cgfs model's ambient light has no physical meaning and is left out: the path tracer's
//!   indirect light is what it stood for.

use super::object::Object;
use super::shape::Shape;
use super::world::{LightingModel, World};
use crate::color::Color;
use crate::geometry::{rectangle, LocalHit, Mesh};
use crate::math::{Distribution1D, Point3, Transform, Vec3};
use crate::shading::{EmissionSide, EnvironmentMap, Light, SpotLight};
use std::f64::consts::{PI, SQRT_2};
use std::sync::Arc;

/// Marks an object that is not a sampled emitter.
const NOT_SAMPLED: u32 = u32::MAX;

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

/// Where points are drawn on an emitting shape: uniformly by its own (object-space) area.
#[derive(Debug, Clone)]
enum Surface {
    Sphere,
    Cube,
    Rectangle,
    Ring {
        inner: f64,
        outer: f64,
    },
    Triangle {
        p1: Point3,
        e1: Vec3,
        e2: Vec3,
    },
    Mesh {
        mesh: Arc<Mesh>,
        faces: Distribution1D,
    },
    Cylinder {
        minimum: f64,
        maximum: f64,
        closed: bool,
    },
    /// The double cone x² + z² = y² between two heights, with its end discs when closed.
    Cone {
        minimum: f64,
        maximum: f64,
        closed: bool,
    },
    /// A ring torus about the y axis (its tube of radius `minor` no wider than `major`, so
    /// that the surface does not pass through itself).
    Torus {
        major: f64,
        minor: f64,
    },
}

/// The angle φ around a torus's tube, uniformly by area from `u` in [0, 1): the tube's
/// circumference at φ is proportional to `R + r cos φ`, so φ solves
/// `R φ + r sin φ = 2π R u` (increasing, as r ≤ R). Newton's steps kept inside a shrinking
/// bracket converge in a few steps.
fn torus_tube_angle(major: f64, minor: f64, u: f64) -> f64 {
    let target = 2.0 * PI * major * u;
    let (mut lo, mut hi) = (0.0, 2.0 * PI);
    let mut phi = 2.0 * PI * u;
    for _ in 0..60 {
        let f = major * phi + minor * phi.sin() - target;
        if f.abs() <= 1e-13 * major.max(1.0) {
            break;
        }
        if f > 0.0 {
            hi = phi;
        } else {
            lo = phi;
        }
        let slope = major + minor * phi.cos();
        let next = phi - f / slope;
        phi = if slope > 0.0 && next > lo && next < hi {
            next
        } else {
            (lo + hi) / 2.0
        };
    }
    phi
}

/// `y·|y|`: the area of the cone x² + z² = y² up to height `y` grows with it (the side's
/// area between two heights is √2·π times its difference), so inverting it samples heights
/// uniformly by area.
fn cone_measure(y: f64) -> f64 {
    y * y.abs()
}

impl Surface {
    /// The sampler of `shape`, if it is one that can be sampled by area.
    fn of(shape: &Shape) -> Option<Self> {
        Some(match shape {
            Shape::Sphere => Surface::Sphere,
            Shape::Cube => Surface::Cube,
            Shape::Rectangle => Surface::Rectangle,
            Shape::Ring { inner, outer } => Surface::Ring {
                inner: *inner,
                outer: *outer,
            },
            Shape::Triangle(t) => Surface::Triangle {
                p1: t.p1,
                e1: t.e1,
                e2: t.e2,
            },
            Shape::Mesh(mesh) => {
                let areas: Vec<f64> = mesh
                    .faces()
                    .map(|f| {
                        let [a, b, c] = mesh.corners(&f);
                        (b - a).cross(c - a).length() / 2.0
                    })
                    .collect();
                Surface::Mesh {
                    mesh: Arc::clone(mesh),
                    faces: Distribution1D::new(&areas).ok()?,
                }
            }
            Shape::Cylinder {
                minimum,
                maximum,
                closed,
            } if minimum.is_finite() && maximum.is_finite() && maximum > minimum => {
                Surface::Cylinder {
                    minimum: *minimum,
                    maximum: *maximum,
                    closed: *closed,
                }
            }
            Shape::Cone {
                minimum,
                maximum,
                closed,
            } if minimum.is_finite() && maximum.is_finite() && maximum > minimum => Surface::Cone {
                minimum: *minimum,
                maximum: *maximum,
                closed: *closed,
            },
            Shape::Torus { major, minor }
                if minor.is_finite() && *minor > 0.0 && major.is_finite() && major >= minor =>
            {
                Surface::Torus {
                    major: *major,
                    minor: *minor,
                }
            }
            _ => return None,
        })
    }

    /// The object-space area.
    fn area(&self) -> f64 {
        match self {
            Surface::Sphere => 4.0 * PI,
            Surface::Cube => 24.0,
            Surface::Rectangle => 4.0,
            Surface::Ring { inner, outer } => PI * (outer * outer - inner * inner),
            Surface::Triangle { e1, e2, .. } => e1.cross(*e2).length() / 2.0,
            Surface::Mesh { faces, .. } => faces.integral() * faces.len() as f64,
            Surface::Cylinder {
                minimum,
                maximum,
                closed,
            } => 2.0 * PI * (maximum - minimum) + if *closed { 2.0 * PI } else { 0.0 },
            Surface::Cone {
                minimum,
                maximum,
                closed,
            } => {
                let side = SQRT_2 * PI * (cone_measure(*maximum) - cone_measure(*minimum));
                let caps = if *closed {
                    PI * (minimum * minimum + maximum * maximum)
                } else {
                    0.0
                };
                side + caps
            }
            Surface::Torus { major, minor } => 4.0 * PI * PI * major * minor,
        }
    }

    /// A point uniformly by area and the unit object-space normal there, from `pick` (which
    /// part of the surface) and `u`.
    fn sample(&self, pick: f64, [u, v]: [f64; 2]) -> (Point3, Vec3) {
        match self {
            Surface::Sphere => {
                let z = 1.0 - 2.0 * u;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * PI * v;
                let p = Point3::new(r * phi.cos(), r * phi.sin(), z);
                (p, p)
            }
            Surface::Cube => {
                let face = ((pick * 6.0) as usize).min(5);
                let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
                let sign = if face % 2 == 0 { 1.0 } else { -1.0 };
                let (p, n) = match face / 2 {
                    0 => (Point3::new(sign, a, b), Vec3::X * sign),
                    1 => (Point3::new(a, sign, b), Vec3::Y * sign),
                    _ => (Point3::new(a, b, sign), Vec3::Z * sign),
                };
                (p, n)
            }
            Surface::Rectangle => (rectangle::point_at(u, v), Vec3::Y),
            Surface::Ring { inner, outer } => {
                let r = (inner * inner + u * (outer * outer - inner * inner)).sqrt();
                let phi = 2.0 * PI * v;
                (Point3::new(r * phi.cos(), 0.0, r * phi.sin()), Vec3::Y)
            }
            Surface::Triangle { p1, e1, e2 } => triangle_point(*p1, *e1, *e2, u, v),
            Surface::Mesh { mesh, faces } => {
                let (face, _) = faces.sample_discrete(pick);
                let [a, b, c] = mesh.corners(&mesh.face(face));
                triangle_point(a, b - a, c - a, u, v)
            }
            Surface::Cylinder {
                minimum,
                maximum,
                closed,
            } => {
                let side = 2.0 * PI * (maximum - minimum);
                let phi = 2.0 * PI * v;
                let caps = if *closed { 2.0 * PI } else { 0.0 };
                let at = pick * (side + caps);
                if at < side || !closed {
                    let y = minimum + u * (maximum - minimum);
                    let n = Vec3::new(phi.cos(), 0.0, phi.sin());
                    (Point3::new(n.x, y, n.z), n)
                } else {
                    let (y, n) = if at < side + PI {
                        (*minimum, -Vec3::Y)
                    } else {
                        (*maximum, Vec3::Y)
                    };
                    let r = u.sqrt();
                    (Point3::new(r * phi.cos(), y, r * phi.sin()), n)
                }
            }
            Surface::Cone {
                minimum,
                maximum,
                closed,
            } => {
                let (low, high) = (cone_measure(*minimum), cone_measure(*maximum));
                let side = SQRT_2 * PI * (high - low);
                let (bottom, top) = (PI * minimum * minimum, PI * maximum * maximum);
                let at = pick * (side + if *closed { bottom + top } else { 0.0 });
                let phi = 2.0 * PI * v;
                if at < side || !closed {
                    let t = low + u * (high - low);
                    let y = t.signum() * t.abs().sqrt();
                    let p = Point3::new(y.abs() * phi.cos(), y, y.abs() * phi.sin());
                    // The book's cone normal, (x, −y, z), normalised.
                    let n = Vec3::new(p.x, -y, p.z).normalize_or_zero();
                    (p, n)
                } else {
                    let (y, n) = if at < side + bottom {
                        (*minimum, -Vec3::Y)
                    } else {
                        (*maximum, Vec3::Y)
                    };
                    let r = y.abs() * u.sqrt();
                    (Point3::new(r * phi.cos(), y, r * phi.sin()), n)
                }
            }
            Surface::Torus { major, minor } => {
                let phi = torus_tube_angle(*major, *minor, u);
                let theta = 2.0 * PI * v;
                let n = Vec3::new(phi.cos() * theta.cos(), phi.sin(), phi.cos() * theta.sin());
                let centre = Point3::new(major * theta.cos(), 0.0, major * theta.sin());
                (centre + n * *minor, n)
            }
        }
    }

    /// The unit object-space geometric normal at `point` of face `face` (for meshes).
    fn normal_at(&self, shape: &Shape, point: Point3, face: u32) -> Vec3 {
        match self {
            Surface::Triangle { e1, e2, .. } => face_normal(*e1, *e2),
            Surface::Mesh { mesh, .. } => {
                let [a, b, c] = mesh.corners(&mesh.face(face as usize));
                face_normal(b - a, c - a)
            }
            _ => shape.normal_at(point).normalize_or_zero(),
        }
    }
}

/// The unit normal of the face with edges `e1` and `e2` from its first corner, oriented as the
/// book's triangles and the meshes orient theirs (`e2 × e1`), so that the side an emitting
/// face lights is the one its hits see as its front.
fn face_normal(e1: Vec3, e2: Vec3) -> Vec3 {
    e2.cross(e1).normalize_or_zero()
}

/// A point of the triangle `p1`, `p1 + e1`, `p1 + e2`, uniformly by area, and its normal.
fn triangle_point(p1: Point3, e1: Vec3, e2: Vec3, u: f64, v: f64) -> (Point3, Vec3) {
    let su = u.sqrt();
    let (b1, b2) = ((1.0 - v) * su, v * su);
    (p1 + e1 * b1 + e2 * b2, face_normal(e1, e2))
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
    /// The world's object `object`, whose material emits `emission` (sampled where the object
    /// is at the path's instant, when it moves).
    Surface {
        object: u32,
        surface: Surface,
        /// The surface's object-space area (scaled by the transform at each sample's instant).
        area: f64,
        emission: Color,
        side: EmissionSide,
    },
    /// The sky.
    Sky,
}

/// The lights of a world as the path tracer samples them (see the [module](self)).
#[derive(Debug, Clone)]
pub struct Emitters {
    list: Vec<Emitter>,
    /// Which emitter to pick, by power; `None` when nothing emits.
    pick: Option<Distribution1D>,
    /// Per world object, its index in `list`, or [`NOT_SAMPLED`].
    by_object: Vec<u32>,
    /// The sky's index in `list`, if the sky gives light.
    sky: Option<u32>,
    /// The sky when there is no environment map.
    background: Color,
    environment: Option<Arc<EnvironmentMap>>,
}

impl Emitters {
    /// The emitters of `world`.
    pub fn new(world: &World) -> Self {
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
        for light in &world.lights {
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
        }
        let mut by_object = vec![NOT_SAMPLED; world.objects.len()];
        for (i, object) in world.objects.iter().enumerate() {
            let emission = object.material.emission;
            // A textured emission (glTF's emissiveTexture) varies over the surface, which
            // sampling by area at one radiance cannot follow: such a surface is found by BSDF
            // sampling alone (its light then counts in full, unweighted).
            let textured = (object.material.metal_rough.as_ref())
                .is_some_and(|m| m.emissive_texture.is_some());
            if emission.max_channel() <= 0.0 || textured {
                continue;
            }
            let Some(surface) = Surface::of(&object.shape) else {
                continue;
            };
            let area = surface.area();
            // The world-space area, roughly (exact for a uniform scale), for the power estimate.
            let world_area = area * object.transform.volume_scale().powf(2.0 / 3.0);
            by_object[i] = list.len() as u32;
            list.push(Emitter::Surface {
                object: i as u32,
                area,
                surface,
                emission,
                side: object.material.emission_side,
            });
            power.push(emission.luminance() * PI * world_area);
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
            (list.len() - 1) as u32
        });
        let pick = Distribution1D::new(&power)
            .ok()
            .filter(|d| d.integral() > 0.0);
        Self {
            list,
            pick,
            by_object,
            sky,
            background: world.background,
            environment: world.environment.clone(),
        }
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

    /// The density with which [`sample`](Self::sample) chooses `direction` towards the sky.
    pub fn sky_pdf(&self, direction: Vec3) -> f64 {
        let (Some(sky), Some(pick)) = (self.sky, &self.pick) else {
            return 0.0;
        };
        match &self.environment {
            Some(map) => pick.probability(sky as usize) * map.pdf(direction),
            None => 0.0,
        }
    }

    /// The density (per solid angle at `from`) with which [`sample`](Self::sample) chooses the
    /// point `point` of world object `index`, seen along unit `direction` from `from`, where
    /// the object-space hit `hit` was (its face, for meshes, and its instant, for objects that
    /// move); 0 for objects not sampled.
    pub fn object_pdf(
        &self,
        world: &World,
        index: usize,
        from: Point3,
        point: Point3,
        direction: Vec3,
        hit: &LocalHit,
    ) -> f64 {
        let (Some(&slot), Some(pick)) = (self.by_object.get(index), &self.pick) else {
            return 0.0;
        };
        let Some(Emitter::Surface {
            surface,
            object,
            area,
            ..
        }) = self.list.get(slot as usize)
        else {
            return 0.0;
        };
        let object = &world.objects[*object as usize];
        let transform = object.transform_at(hit.time);
        let local = transform.inverse_point(point);
        let n_local = surface.normal_at(&object.shape, local, hit.face);
        let scaled_area = area * transform.volume_scale();
        let (area_pdf, normal) = area_density(scaled_area, &transform, n_local);
        let cos = normal.dot(direction).abs();
        if cos <= 0.0 {
            return 0.0;
        }
        pick.probability(slot as usize) * area_pdf * (point - from).length_squared() / cos
    }

    /// Picks an emitter with `pick` and a point or direction on it with `u`, for lighting
    /// `point` in `world` at shutter instant `time`; `None` when nothing emits or the choice
    /// gives no light (the back of a one-sided emitter, a point outside a spotlight's cone).
    pub fn sample(
        &self,
        world: &World,
        point: Point3,
        time: f64,
        pick: f64,
        u: [f64; 2],
    ) -> Option<LightSample> {
        let distribution = self.pick.as_ref()?;
        let (slot, probability, rest) = distribution.sample_discrete_reused(pick);
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
            Emitter::Surface {
                object,
                surface,
                area,
                emission,
                side,
            } => {
                let object: &Object = &world.objects[*object as usize];
                let transform = object.transform_at(time);
                let (local, n_local) = surface.sample(rest, u);
                let on_light = transform.point(local);
                let scaled_area = area * transform.volume_scale();
                let (area_pdf, normal) = area_density(scaled_area, &transform, n_local);
                let to_light = on_light - point;
                let distance_squared = to_light.length_squared();
                let distance = distance_squared.sqrt();
                if distance <= 0.0 || area_pdf <= 0.0 {
                    return None;
                }
                let direction = to_light / distance;
                let cos = -normal.dot(direction);
                if !side.emits_towards(cos) {
                    return None;
                }
                let cos = cos.abs();
                Some(LightSample {
                    direction,
                    distance,
                    radiance: *emission,
                    pdf: probability * area_pdf * distance_squared / cos,
                    delta: false,
                })
            }
            Emitter::Sky => {
                let (direction, radiance, pdf) = self.environment.as_ref()?.sample(u)?;
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

/// The world-space area density of a point sampled uniformly on a surface of object-space area
/// times volume scale `scaled_area` whose object-space normal is `n_local`, and the unit world
/// normal there.
#[inline]
fn area_density(scaled_area: f64, transform: &Transform, n_local: Vec3) -> (f64, Vec3) {
    let normal = transform.normal_unnormalised(n_local);
    let length = normal.length();
    let scale = length * scaled_area;
    if scale > 0.0 && scale.is_finite() {
        (1.0 / scale, normal / length)
    } else {
        (0.0, Vec3::ZERO)
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
    use crate::math::{point, rotation_x, rotation_y, scaling, translation, Ray};
    use crate::shading::Material;

    fn lamp(shape: Shape, matrix: glam::DMat4, side: EmissionSide) -> Object {
        Object::new(shape)
            .with_transform(matrix)
            .with_material(Material {
                emission: Color::WHITE,
                emission_side: side,
                ..Material::DEFAULT
            })
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
        ]
    }

    #[test]
    fn a_torus_is_sampled_uniformly_by_area() {
        // Uniform by area, the distance from the axis ρ = R + r cos φ has density ∝ ρ, so its
        // mean is (R² + r²/2) / R; every point lies on the tube.
        let (major, minor) = (1.0, 0.4);
        let torus = Surface::Torus { major, minor };
        let mut rng = SplitMixStream(99);
        let n = 200_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let (p, normal) = torus.sample(rng.next(), [rng.next(), rng.next()]);
            let rho = p.x.hypot(p.z);
            assert!(((rho - major).hypot(p.y) - minor).abs() < 1e-9, "{p:?}");
            assert!((normal.length() - 1.0).abs() < 1e-12);
            sum += rho;
        }
        let expected = (major * major + minor * minor / 2.0) / major;
        // ρ spreads over ±0.4: four standard errors are under 0.003.
        assert!(
            (sum / n as f64 - expected).abs() < 0.003,
            "{}",
            sum / n as f64
        );
        assert!((torus.area() - 4.0 * PI * PI * major * minor).abs() < 1e-12);
        // The tube angle inverts its distribution at the ends and the middle.
        assert_eq!(torus_tube_angle(major, minor, 0.0), 0.0);
        assert!((torus_tube_angle(major, minor, 0.5) - PI).abs() < 1e-9);
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
                    .sample(&world, from, time, rng.next(), u)
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
                let pdf = emitters.object_pdf(&world, 0, from, at, s.direction, &hit);
                assert!(
                    (pdf - s.pdf).abs() <= 1e-6 * s.pdf,
                    "{time}: {pdf} vs {}",
                    s.pdf
                );
            }
        }
    }

    #[test]
    fn a_cone_is_sampled_uniformly_by_area() {
        // Over the side of x² + z² = y² from 0.2 to 1, the mean height by area is
        // ∫ y·y dy / ∫ y dy = (1 − 0.008)/3 / ((1 − 0.04)/2) = 0.68889; with its end discs
        // (areas π·0.04 and π, at 0.2 and 1) the mean moves to the weighted mean of the three.
        let mut rng = SplitMixStream(7);
        for closed in [false, true] {
            let cone = Surface::Cone {
                minimum: 0.2,
                maximum: 1.0,
                closed,
            };
            let n = 200_000;
            let mean = (0..n)
                .map(|_| cone.sample(rng.next(), [rng.next(), rng.next()]).0.y)
                .sum::<f64>()
                / n as f64;
            let side = SQRT_2 * PI * (1.0 - 0.04);
            let side_mean = (1.0 - 0.008) / 3.0 / ((1.0 - 0.04) / 2.0);
            let expected = if closed {
                let (bottom, top) = (PI * 0.04, PI);
                (side * side_mean + bottom * 0.2 + top * 1.0) / (side + bottom + top)
            } else {
                side_mean
            };
            // The heights' spread is under 0.3: four standard errors are 0.003.
            assert!(
                (mean - expected).abs() < 0.003,
                "{closed}: {mean} vs {expected}"
            );
            assert!((cone.area() - (side + if closed { PI * 1.04 } else { 0.0 })).abs() < 1e-12);
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
                let Some(s) = emitters.sample(&world, from, 0.0, rng.next(), u) else {
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
                let pdf = emitters.object_pdf(&world, 0, from, at, s.direction, &hit);
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
                        emitters.sample(&world, at, 0.0, 0.5, u).is_some()
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
