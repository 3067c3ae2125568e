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
//!   - By area, where they are at the path's instant of the shutter when they move: spheres,
//!     cubes, rectangles, rings and discs, triangles, meshes, finite cylinders and cones, ring
//!     tori and spindle tori (tube wider than the ring: the whole surface the quartic
//!     describes, the inner lemon included, uniformly by the area element `|R + r cos φ|·r`).
//!   - Emissive textures, on any of those: sampled by area as the plain shape, the radiance
//!     read at the sampled point by the same code a path that hits it uses; the emitter's
//!     power (which picks it) uses the texture's mean over 32 × 32 points.
//!   - CSG solids that stand still, of at most [`MAX_SAMPLED_CSG_LEAVES`] primitives: one of
//!     their emitting primitives of the kinds above is picked by area, a point on it by area,
//!     and the sample gives no light where the solid does not keep that surface
//!     ([`Csg::keeps_surface_point`]). A kept point's density is the primitive's probability
//!     over its area, which [`Emitters::object_pdf`] returns for a hit there.
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
use crate::geometry::{rectangle, LocalHit, Mesh};
use crate::math::random::{Jitter, SplitMix64};
use crate::math::{
    cosine_hemisphere, sin_cos_turns, Aabb, Distribution1D, Frame, Point3, Transform, Vec3,
};
use crate::options::LightSamplerKind;
use crate::scene::{Csg, Cuboid, LightingModel, Object, Shape, World};
use crate::shading::{EmissionSide, EnvironmentMap, Light, Material, SkyDraw, SpotLight};
use std::f64::consts::{FRAC_1_PI, PI, SQRT_2};
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
struct SurfaceSample {
    point: Point3,
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
            Surface::Spindle { major, minor } => spindle_area(*major, *minor),
        }
    }

    /// A point uniformly by area, from `pick` (which part of the surface) and `u`.
    fn sample(&self, pick: f64, u: [f64; 2]) -> SurfaceSample {
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
    Surface {
        object: u32,
        surface: Surface,
        /// The surface's object-space area (scaled by the transform at each sample's instant).
        area: f64,
    },
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
    surface: Surface,
    /// The object-space area.
    area: f64,
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
            Some(Emitter::Surface {
                surface,
                object,
                area,
            }) => {
                let object = &world.objects[*object as usize];
                surface_density(object, surface, *area, from, point, direction, hit)
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
                let Some(CsgPart {
                    leaf,
                    surface,
                    area,
                }) = parts.get(part as usize)
                else {
                    return 0.0;
                };
                if !csg.keeps_surface_point(*leaf as usize, point) {
                    return 0.0;
                }
                let object = &csg.leaves()[*leaf as usize];
                leaves.probability(part as usize)
                    * surface_density(object, surface, *area, from, point, direction, hit)
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
            Emitter::Surface {
                object,
                surface,
                area,
            } => {
                let object = &world.objects[*object as usize];
                let light = sample_surface(object, surface, *area, point, time, rest, u, |_| true)?;
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
                let CsgPart {
                    leaf,
                    surface,
                    area,
                } = &parts[part];
                let object = &csg.leaves()[*leaf as usize];
                let keeps = |at: Point3| csg.keeps_surface_point(*leaf as usize, at);
                let light = sample_surface(object, surface, *area, point, time, rest, u, keeps)?;
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

/// The world-space area density of a point sampled uniformly on a surface of object-space area
/// times volume scale `scaled_area` whose object-space normal is `n_local`, and the unit world
/// normal there.
#[inline]
fn area_density(scaled_area: f64, transform: &Transform, n_local: Vec3) -> (f64, Vec3) {
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
fn sample_surface(
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
fn surface_density(
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
            let area = Surface::Rectangle.area();
            let (density, normal) = area_density(area * t.volume_scale(), t, Vec3::Y);
            let emitter = Emitter::Parallelogram {
                corner,
                edge_u,
                edge_v,
                normal,
                density,
                radiance: emitted(object, &LocalHit::default()),
                side: object.material.emission_side,
            };
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
            let surface = Surface::of(shape)?;
            let area = surface.area();
            let world_area = rough_world_area(area, &object.transform);
            let emitter = Emitter::Surface {
                object: index,
                surface,
                area,
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
        let Some(surface) = Surface::of(&leaf.shape) else {
            continue;
        };
        let area = surface.area();
        let world_area = rough_world_area(area, &leaf.transform);
        if !(world_area > 0.0 && world_area.is_finite()) {
            continue;
        }
        let mut random = SplitMix64::new(0x05ee_dc59 + k as u64);
        let kept = (0..64)
            .filter(|_| {
                let pick = random.next_offset();
                let u = [random.next_offset(), random.next_offset()];
                let at = leaf.transform.point(surface.sample(pick, u).point);
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
            area,
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
