//! The light list: everything that gives off light in a world, as the path tracer samples it,
//! each light one of the kinds of this module's files ([`PointEmitter`], [`SpotEmitter`],
//! [`DirectionalEmitter`], [`AreaEmitter`], [`SkyEmitter`], whose docs say what each means
//! physically), held in one enum so a light sample dispatches with a `match` (no `dyn`, no
//! allocation).
//!
//! Next-event estimation picks one emitter per path vertex through the scene's
//! [`LightSampler`] (uniformly, by power, or by a light tree that weighs the vertex's place)
//! ([`Emitters::sample`]), and a point or direction on it. A path that finds an emitter by
//! scattering asks how likely light sampling would have been to choose that point
//! ([`Emitters::object_pdf`], [`Emitters::sky_radiance_and_pdf`]), so that multiple importance
//! sampling can weigh the two ways of finding it.
//!
//! The cgfs model's ambient light has no physical meaning and is left out: the path tracer's
//! indirect light is what it stood for.
//!
//! This file also holds the shapes' sampling by area that emitting objects use (`Surface`,
//! [`sample_surface`], [`surface_density`]).

use super::area::{emitted, AreaEmitter};
use super::directional::DirectionalEmitter;
use super::environment::SkyEmitter;
use super::mirror_ball::MirrorBall;
use super::point::PointEmitter;
use super::sample::LightSample;
use super::sampler::LightSampler;
use super::spot::SpotEmitter;
use crate::color::Color;
use crate::geometry::{rectangle, LocalHit, Mesh};
use crate::math::{sin_cos_turns, Distribution1D, Point3, Transform, Vec3};
use crate::options::LightSamplerKind;
use crate::scene::{LightingModel, Object, Shape, World};
use crate::shading::{EnvironmentMap, Light, SkyDraw};
use std::f64::consts::{PI, SQRT_2};
use std::sync::Arc;

/// Marks an object that is not a sampled emitter.
pub(super) const NOT_SAMPLED: u32 = u32::MAX;

/// Where points are drawn on an emitting shape: uniformly by its own (object-space) area.
#[derive(Debug, Clone)]
pub(super) enum Surface {
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
    /// A spindle torus about the y axis (its tube of radius `minor` wider than `major` > 0):
    /// the whole surface the quartic describes, the outer apple and the inner lemon, which is
    /// what rays meet.
    Spindle {
        major: f64,
        minor: f64,
    },
}

/// A point drawn on a surface, in object space.
#[derive(Debug, Clone, Copy)]
pub(super) struct SurfaceSample {
    pub(super) point: Point3,
    /// The unit normal of the surface there (up to its sign), which the stretch of its area
    /// by the transform needs.
    normal: Vec3,
    /// Where a ray's hit there would be: the face and barycentric `u`, `v` on a mesh (which
    /// its texture coordinates need); nothing elsewhere.
    hit: LocalHit,
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

/// The angle φ around a spindle torus's tube, uniformly by area from `u` in [0, 1): the surface
/// element is `|R + r cos φ|·r dφ dθ` (the lemon, where `R + r cos φ < 0`, is surface too), so
/// φ inverts `G(φ) = ∫₀^φ |R + r cos t| dt`. By symmetry about π, the lower half of `u` covers
/// [0, π] and the upper half mirrors it onto [π, 2π). On [0, π], with `φ₀ = acos(−R/r)` and
/// `f(φ) = R φ + r sin φ`, `G` is `f` up to φ₀ and `2 f(φ₀) − f` beyond: increasing, and
/// inverted by Newton's steps inside a shrinking bracket.
fn spindle_tube_angle(major: f64, minor: f64, u: f64) -> f64 {
    let phi0 = (-major / minor).clamp(-1.0, 1.0).acos();
    let f = |phi: f64| major * phi + minor * phi.sin();
    let at_phi0 = f(phi0);
    let half = 2.0 * at_phi0 - major * PI;
    let (w, mirrored) = if u < 0.5 {
        (2.0 * u, false)
    } else {
        (2.0 - 2.0 * u, true)
    };
    let target = w * half;
    let g = |phi: f64| {
        if phi <= phi0 {
            f(phi)
        } else {
            2.0 * at_phi0 - f(phi)
        }
    };
    let (mut lo, mut hi) = (0.0, PI);
    let mut phi = PI * w;
    for _ in 0..80 {
        let error = g(phi) - target;
        if error.abs() <= 1e-13 * (major + minor) {
            break;
        }
        if error > 0.0 {
            hi = phi;
        } else {
            lo = phi;
        }
        let slope = (major + minor * phi.cos()).abs();
        let next = phi - error / slope;
        phi = if slope > 0.0 && next > lo && next < hi {
            next
        } else {
            (lo + hi) / 2.0
        };
    }
    if mirrored {
        2.0 * PI - phi
    } else {
        phi
    }
}

/// The area of the spindle torus: `2π r ∫₀^{2π} |R + r cos φ| dφ`
/// `= 2π r (4 R φ₀ + 4 r sin φ₀ − 2π R)` with `φ₀ = acos(−R/r)`.
fn spindle_area(major: f64, minor: f64) -> f64 {
    let phi0 = (-major / minor).clamp(-1.0, 1.0).acos();
    2.0 * PI * minor * (4.0 * major * phi0 + 4.0 * minor * phi0.sin() - 2.0 * PI * major)
}

/// The point of the torus at angle `phi` around the tube and `theta` around the axis, and the
/// unit normal of the tube there.
fn torus_point(major: f64, minor: f64, phi: f64, theta: f64) -> (Point3, Vec3) {
    let n = Vec3::new(phi.cos() * theta.cos(), phi.sin(), phi.cos() * theta.sin());
    let centre = Point3::new(major * theta.cos(), 0.0, major * theta.sin());
    (centre + n * minor, n)
}

/// `y·|y|`: the area of the cone x² + z² = y² up to height `y` grows with it (the side's
/// area between two heights is √2·π times its difference), so inverting it samples heights
/// uniformly by area.
fn cone_measure(y: f64) -> f64 {
    y * y.abs()
}

impl Surface {
    /// The sampler of `shape`, if it is one that can be sampled by area.
    pub(super) fn of(shape: &Shape) -> Option<Self> {
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
            Shape::Torus { major, minor } if minor.is_finite() && *major > 0.0 && minor > major => {
                Surface::Spindle {
                    major: *major,
                    minor: *minor,
                }
            }
            _ => return None,
        })
    }

    /// The object-space area.
    pub(super) fn area(&self) -> f64 {
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
            Surface::Spindle { major, minor } => spindle_area(*major, *minor),
        }
    }

    /// A point uniformly by area, from `pick` (which part of the surface) and `u`.
    pub(super) fn sample(&self, pick: f64, u: [f64; 2]) -> SurfaceSample {
        if let Surface::Mesh { mesh, faces } = self {
            let (face, _) = faces.sample_discrete(pick);
            let [a, b, c] = mesh.corners(&mesh.face(face));
            let (b1, b2) = triangle_weights(u[0], u[1]);
            return SurfaceSample {
                point: a + (b - a) * b1 + (c - a) * b2,
                normal: mesh.face_normal(face as u32).normalize_or_zero(),
                hit: LocalHit {
                    u: b1,
                    v: b2,
                    face: face as u32,
                    ..LocalHit::default()
                },
            };
        }
        let (point, normal) = self.sample_point(pick, u);
        SurfaceSample {
            point,
            normal,
            hit: LocalHit::default(),
        }
    }

    /// A point uniformly by area and the unit object-space normal there, from `pick` (which
    /// part of the surface) and `u`.
    fn sample_point(&self, pick: f64, [u, v]: [f64; 2]) -> (Point3, Vec3) {
        match self {
            Surface::Sphere => {
                let z = 1.0 - 2.0 * u;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let (sin, cos) = sin_cos_turns(v);
                let p = Point3::new(r * cos, r * sin, z);
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
                let (sin, cos) = sin_cos_turns(v);
                (Point3::new(r * cos, 0.0, r * sin), Vec3::Y)
            }
            Surface::Triangle { p1, e1, e2 } => triangle_point(*p1, *e1, *e2, u, v),
            Surface::Mesh { mesh, faces } => {
                // (`sample` draws meshes itself, with the face and weights.)
                let (face, _) = faces.sample_discrete(pick);
                let [a, b, c] = mesh.corners(&mesh.face(face));
                let (point, _) = triangle_point(a, b - a, c - a, u, v);
                (point, mesh.face_normal(face as u32).normalize_or_zero())
            }
            Surface::Cylinder {
                minimum,
                maximum,
                closed,
            } => {
                let side = 2.0 * PI * (maximum - minimum);
                let (sin, cos) = sin_cos_turns(v);
                let caps = if *closed { 2.0 * PI } else { 0.0 };
                let at = pick * (side + caps);
                if at < side || !closed {
                    let y = minimum + u * (maximum - minimum);
                    let n = Vec3::new(cos, 0.0, sin);
                    (Point3::new(n.x, y, n.z), n)
                } else {
                    let (y, n) = if at < side + PI {
                        (*minimum, -Vec3::Y)
                    } else {
                        (*maximum, Vec3::Y)
                    };
                    let r = u.sqrt();
                    (Point3::new(r * cos, y, r * sin), n)
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
                let (sin, cos) = sin_cos_turns(v);
                if at < side || !closed {
                    let t = low + u * (high - low);
                    let y = t.signum() * t.abs().sqrt();
                    let p = Point3::new(y.abs() * cos, y, y.abs() * sin);
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
                    (Point3::new(r * cos, y, r * sin), n)
                }
            }
            Surface::Torus { major, minor } => {
                let phi = torus_tube_angle(*major, *minor, u);
                torus_point(*major, *minor, phi, 2.0 * PI * v)
            }
            Surface::Spindle { major, minor } => {
                let phi = spindle_tube_angle(*major, *minor, u);
                let (p, n) = torus_point(*major, *minor, phi, 2.0 * PI * v);
                // On the lemon (`R + r cos φ < 0`) the tube's direction points out of the
                // lemon, into the solid: its outward normal is the other way (see
                // `torus::normal_at`).
                if major + minor * phi.cos() < 0.0 {
                    (p, -n)
                } else {
                    (p, n)
                }
            }
        }
    }

    /// The unit object-space geometric normal at `point` of face `face` (for meshes).
    fn normal_at(&self, shape: &Shape, point: Point3, face: u32) -> Vec3 {
        match self {
            Surface::Triangle { e1, e2, .. } => face_normal(*e1, *e2),
            Surface::Mesh { mesh, .. } => mesh.face_normal(face).normalize_or_zero(),
            _ => shape.normal_at(point).normalize_or_zero(),
        }
    }
}

/// The unit normal of the book's triangle with edges `e1` and `e2` from its first corner,
/// oriented as the triangle orients its own (`e2 × e1`), so that the side an emitting face
/// lights is the one its hits see as its front. (A mesh's faces follow the mesh's winding:
/// [`Mesh::face_normal`](crate::geometry::Mesh::face_normal).)
fn face_normal(e1: Vec3, e2: Vec3) -> Vec3 {
    e2.cross(e1).normalize_or_zero()
}

/// Barycentric weights of the second and third corners of a triangle, uniformly by area.
fn triangle_weights(u: f64, v: f64) -> (f64, f64) {
    let su = u.sqrt();
    ((1.0 - v) * su, v * su)
}

/// A point of the triangle `p1`, `p1 + e1`, `p1 + e2`, uniformly by area, and its normal.
fn triangle_point(p1: Point3, e1: Vec3, e2: Vec3, u: f64, v: f64) -> (Point3, Vec3) {
    let (b1, b2) = triangle_weights(u, v);
    (p1 + e1 * b1 + e2 * b2, face_normal(e1, e2))
}

/// One light source as next-event estimation sees it: one of the kinds.
#[derive(Debug, Clone)]
enum Emitter {
    Point(PointEmitter),
    Spot(SpotEmitter),
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
        let mut list = Vec::new();
        let mut power = Vec::new();
        // Each emitter's bounds for the light tree; `None` for light from infinity, or light
        // that does not fall off with distance.
        let mut bounds = Vec::new();
        for light in &world.lights {
            let emitter = match light {
                Light::Point(l) => Emitter::Point(PointEmitter::new(l, falloff, disc)),
                Light::Spot(l) => Emitter::Spot(SpotEmitter::new(l, falloff, disc)),
                Light::Directional(l) => Emitter::Directional(DirectionalEmitter::new(l, disc)),
                Light::Area(l) => Emitter::Area(AreaEmitter::of_book(l, falloff, disc)),
                Light::Ambient(_) => continue,
            };
            let (p, b) = match &emitter {
                Emitter::Point(e) => (e.power(), e.bounds()),
                Emitter::Spot(e) => (e.power(), e.bounds()),
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
            let Some(emitter) = AreaEmitter::of_object(object, i as u32, disc) else {
                continue;
            };
            by_object[i] = list.len() as u32;
            bounds.push(emitter.bounds(world));
            power.push(emitter.power());
            list.push(Emitter::Area(emitter));
        }
        let sky_light = SkyEmitter::new(world.background, world.environment.clone());
        let sky_power = sky_light.power(disc);
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
            sky_light,
            mirror_balls,
            mirror_of_object,
        }
    }

    /// The environment map, when it gives light (what [`mirror_balls`](Self::mirror_balls)
    /// reflect).
    pub fn environment(&self) -> Option<&EnvironmentMap> {
        self.sky.and(self.sky_light.map())
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
        self.sky_light.radiance(direction)
    }

    /// The radiance arriving from the sky along `direction`, as
    /// [`sky_radiance`](Self::sky_radiance), and the density with which
    /// [`sample`](Self::sample) chooses that direction towards the sky (0 where the sky is not
    /// sampled): what a path that escapes weighs its light by.
    pub fn sky_radiance_and_pdf(&self, direction: Vec3) -> (Color, f64) {
        let (radiance, pdf) = self.sky_light.radiance_and_pdf(direction);
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
            Emitter::Directional(light) => Some(light.sample_li(probability)),
            Emitter::Area(light) => light.sample_li(world, point, time, probability, rest, u),
            Emitter::Sky => self.sky_light.sample_li(sky, probability),
        }
    }
}

/// The world-space area density of a point sampled uniformly on a surface of object-space area
/// times volume scale `scaled_area` whose object-space normal is `n_local`, and the unit world
/// normal there.
#[inline]
pub(super) fn area_density(scaled_area: f64, transform: &Transform, n_local: Vec3) -> (f64, Vec3) {
    let normal = transform.normal_unnormalised(n_local);
    let length = normal.length();
    let scale = length * scaled_area;
    if scale > 0.0 && scale.is_finite() {
        // One division for both: `1 / length` is the density times the scaled area.
        let density = 1.0 / scale;
        (density, normal * (density * scaled_area))
    } else {
        (0.0, Vec3::ZERO)
    }
}

/// A point drawn uniformly by area on `surface` (of object-space area `area`) of `object`, where
/// it is at shutter instant `time`, as light arriving at `from`: its density per solid angle at
/// `from`, from this surface alone. `None` when it gives no light there: the back of a
/// one-sided emitter, a point `keep` rejects (one a CSG solid does not keep), no radiance.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn sample_surface(
    object: &Object,
    surface: &Surface,
    area: f64,
    from: Point3,
    time: f64,
    pick: f64,
    u: [f64; 2],
    keep: impl Fn(Point3) -> bool,
) -> Option<LightSample> {
    let transform = object.transform_at(time);
    let sample = surface.sample(pick, u);
    let on_light = transform.point(sample.point);
    let scaled_area = area * transform.volume_scale();
    let (area_pdf, normal) = area_density(scaled_area, &transform, sample.normal);
    let to_light = on_light - from;
    let distance_squared = to_light.length_squared();
    let distance = distance_squared.sqrt();
    if distance <= 0.0 || area_pdf <= 0.0 {
        return None;
    }
    let direction = to_light / distance;
    let cos = -normal.dot(direction);
    if cos == 0.0 || !object.material.emission_side.emits_towards(cos) || !keep(on_light) {
        return None;
    }
    let radiance = emitted(object, &sample.hit);
    (radiance.max_channel() > 0.0).then(|| LightSample {
        direction,
        distance,
        radiance,
        pdf: area_pdf * distance_squared / cos.abs(),
        delta: false,
    })
}

/// The density per solid angle at `from` with which [`sample_surface`] draws `point` of
/// `object` (seen along unit `direction`, at the object-space hit `hit`).
#[inline]
pub(super) fn surface_density(
    object: &Object,
    surface: &Surface,
    area: f64,
    from: Point3,
    point: Point3,
    direction: Vec3,
    hit: &LocalHit,
) -> f64 {
    let transform = object.transform_at(hit.time);
    let local = transform.inverse_point(point);
    let n_local = surface.normal_at(&object.shape, local, hit.face);
    let scaled_area = area * transform.volume_scale();
    let (area_pdf, normal) = area_density(scaled_area, &transform, n_local);
    let cos = normal.dot(direction).abs();
    if cos <= 0.0 {
        return 0.0;
    }
    area_pdf * (point - from).length_squared() / cos
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
        ]
    }

    #[test]
    fn a_spindle_torus_is_sampled_uniformly_by_area() {
        // Uniform by area, the tube angle φ has density ∝ |R + r cos φ| (the lemon, where
        // R + r cos φ < 0, included): the mean of cos φ and the area against a fine midpoint
        // quadrature, and every point on the quartic.
        let (major, minor) = (0.5, 0.8);
        let n = 100_000;
        let (mut weight, mut moment) = (0.0, 0.0);
        for i in 0..n {
            let phi = 2.0 * PI * (i as f64 + 0.5) / n as f64;
            let w = (major + minor * phi.cos()).abs();
            weight += w;
            moment += w * phi.cos();
        }
        let expected = moment / weight;
        let area = 2.0 * PI * minor * weight * 2.0 * PI / n as f64;
        let spindle = Surface::Spindle { major, minor };
        assert!(
            (spindle.area() - area).abs() < 1e-6 * area,
            "{} vs {area}",
            spindle.area()
        );
        let mut rng = SplitMixStream(31);
        let mut sum = 0.0;
        for _ in 0..n {
            let phi = spindle_tube_angle(major, minor, rng.next());
            assert!((0.0..=2.0 * PI).contains(&phi), "{phi}");
            sum += phi.cos();
            let s = spindle.sample(rng.next(), [rng.next(), rng.next()]);
            let p = s.point;
            let e = p.length_squared() + major * major - minor * minor;
            let f = e * e - 4.0 * major * major * (p.x * p.x + p.z * p.z);
            assert!(f.abs() < 1e-9, "{p:?}: {f}");
            // The sampled normal is the quartic's gradient's direction.
            let g = spindle.normal_at(&Shape::Torus { major, minor }, p, 0);
            assert!(g.cross(s.normal).length() < 1e-6, "{g:?} {:?}", s.normal);
        }
        // cos φ lies in [−1, 1]: four standard errors of the mean are under 0.013.
        let mean = sum / n as f64;
        assert!((mean - expected).abs() < 0.013, "{mean} vs {expected}");
        // The inversion is exact at the ends, the middle and the lemon's edge.
        assert_eq!(spindle_tube_angle(major, minor, 0.0), 0.0);
        assert!((spindle_tube_angle(major, minor, 0.5) - PI).abs() < 1e-9);
        assert!((spindle_tube_angle(major, minor, 0.999_999_999) - 2.0 * PI).abs() < 1e-6);
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
            let SurfaceSample {
                point: p, normal, ..
            } = torus.sample(rng.next(), [rng.next(), rng.next()]);
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
                .map(|_| cone.sample(rng.next(), [rng.next(), rng.next()]).point.y)
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
