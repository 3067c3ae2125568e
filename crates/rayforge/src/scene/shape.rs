//! [`Shape`]: what an object is, in its own object space: one of the primitive shapes of
//! [`crate::geometry`], a mesh, or a CSG solid made of scene objects (which is why the enum
//! lives here, above both).
//!
//! It is a closed enum (no virtual calls on the hot path); every method is one `match`
//! forwarding to the shape's own module. Rays arrive already in object space; transforms are
//! the business of [`super::Object`].

use super::csg::Csg;
use crate::geometry::{cone, cube, cylinder, plane, rectangle, ring, sphere, torus};
use crate::geometry::{Curves, Heights, LocalHit, Mesh, PartialQuadric, ShapeSampler, Triangle};
use crate::math::{Aabb, Point3, Ray, Vec3};
use crate::shading::SurfacePoint;
use std::sync::Arc;

/// A primitive shape in its own object space.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// The unit sphere at the origin (chapter 5).
    Sphere,
    /// The xz plane through the origin, normal +y (chapter 9).
    Plane,
    /// The axis-aligned cube from -1 to 1 on every axis (chapter 12).
    Cube,
    /// The radius-1 cylinder around y between `minimum` and `maximum` (chapter 13).
    Cylinder {
        /// Lowest y of the side (exclusive); `-∞` for an infinite cylinder.
        minimum: f64,
        /// Highest y of the side (exclusive); `+∞` for an infinite cylinder.
        maximum: f64,
        /// Whether the ends are capped.
        closed: bool,
    },
    /// A triangle, flat or smooth (chapter 15). Boxed: it is far larger than the other shapes.
    Triangle(Box<Triangle>),
    /// A triangle mesh with its own BVH (an OBJ file's faces), shared between instances.
    Mesh(Arc<Mesh>),
    /// A constructive solid geometry solid (chapter 16), shared between instances.
    Csg(Arc<Csg>),
    /// pbrt-v4's curves (hair, fur, grass): segments with their own BVH, shared between
    /// instances. Open bands with no volume; a flat one's normal faces the ray that met it.
    Curves(Arc<Curves>),
    /// The double-napped cone x² + z² = y² between `minimum` and `maximum` (chapter 13).
    Cone {
        /// Lowest y (exclusive); `-∞` for an infinite cone.
        minimum: f64,
        /// Highest y (exclusive); `+∞` for an infinite cone.
        maximum: f64,
        /// Whether the ends are capped.
        closed: bool,
    },
    /// A torus around the y axis: a tube of radius `minor` around a circle of radius `major` in
    /// the xz plane (Fundamentals of Ray Tracing, chapter 13).
    Torus {
        /// Radius of the tube's centre circle (Cross's A).
        major: f64,
        /// Radius of the tube (Cross's B).
        minor: f64,
    },
    /// A flat ring in the xz plane around the y axis, between two radii (Fundamentals of Ray
    /// Tracing's thin ring; with `inner` 0, its thin disc). No thickness, no volume.
    Ring {
        /// Radius of the hole (0 for a disc).
        inner: f64,
        /// Outer radius.
        outer: f64,
    },
    /// The square from -1 to 1 in x and z of the xz plane, normal +y: a bounded plane (the
    /// walls and lights of the path tracer's reference scenes). No thickness, no volume.
    Rectangle,
    /// One of pbrt-v4's quadrics cut by its heights and sweep (a pbrt file's `sphere` with
    /// `zmin`, `zmax` or `phimax`, a `disk` or `cylinder` with `phimax`), in pbrt's own frame.
    /// Boxed: larger than the other shapes. Open: no volume.
    Partial(Box<PartialQuadric>),
}

impl Shape {
    /// The infinite, open cylinder of chapter 13.
    pub const CYLINDER: Shape = Shape::Cylinder {
        minimum: f64::NEG_INFINITY,
        maximum: f64::INFINITY,
        closed: false,
    };

    /// The infinite, open double cone of chapter 13.
    pub const CONE: Shape = Shape::Cone {
        minimum: f64::NEG_INFINITY,
        maximum: f64::INFINITY,
        closed: false,
    };

    /// The book's `local_intersect`: calls `hit(t)` for every intersection of the object-space
    /// `ray` with the shape, in no particular order (negative `t` included: refraction needs the
    /// whole list).
    #[inline]
    pub fn intersect(&self, ray: &Ray, mut hit: impl FnMut(f64)) {
        self.intersect_hits(ray, |h| hit(h.t));
    }

    /// Like [`Shape::intersect`], with where on the surface each hit is (barycentric `u`, `v`
    /// on triangles, and the face of a mesh).
    #[inline]
    pub fn intersect_hits(&self, ray: &Ray, mut hit: impl FnMut(LocalHit)) {
        let time = ray.time;
        let mut hit = |h: LocalHit| hit(LocalHit { time, ..h });
        let mut hit_t = |t| hit(LocalHit::at(t));
        match self {
            Shape::Sphere => sphere::intersect(ray, &mut hit_t),
            Shape::Plane => plane::intersect(ray, &mut hit_t),
            Shape::Cube => cube::intersect(ray, &mut hit_t),
            Shape::Triangle(triangle) => triangle.intersect(ray, |t, u, v| {
                hit(LocalHit {
                    t,
                    u,
                    v,
                    ..LocalHit::default()
                })
            }),
            Shape::Mesh(mesh) => mesh.intersect(ray, hit),
            Shape::Curves(curves) => curves.intersect_up_to(ray, f64::INFINITY, hit),
            Shape::Csg(csg) => csg.intersect(ray, &mut hit),
            Shape::Cylinder {
                minimum,
                maximum,
                closed,
            } => cylinder::intersect(ray, *minimum, *maximum, *closed, &mut hit_t),
            Shape::Cone {
                minimum,
                maximum,
                closed,
            } => cone::intersect(ray, *minimum, *maximum, *closed, &mut hit_t),
            Shape::Torus { major, minor } => torus::intersect(ray, *major, *minor, &mut hit_t),
            Shape::Ring { inner, outer } => ring::intersect(ray, *inner, *outer, &mut hit_t),
            Shape::Rectangle => rectangle::intersect(ray, &mut hit_t),
            Shape::Partial(q) => q.intersect(ray, &mut hit_t),
        }
    }

    /// The nearest hit with `t_min <= t < t_max`. Meshes prune their BVH as hits are found;
    /// other shapes pick from their few hits.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<LocalHit> {
        match self {
            Shape::Mesh(mesh) => return mesh.closest_hit(ray, t_min, t_max),
            Shape::Curves(curves) => return curves.closest_hit(ray, t_min, t_max),
            _ => {}
        }
        let mut best = None;
        let mut limit = t_max;
        self.intersect_hits(ray, |h| {
            if h.t >= t_min && h.t < limit {
                limit = h.t;
                best = Some(h);
            }
        });
        best
    }

    /// Every hit with `t <= t_max`, negative ones included (what refraction's containers need);
    /// meshes skip the parts of their BVH beyond `t_max`.
    #[inline]
    pub fn hits_up_to(&self, ray: &Ray, t_max: f64, mut hit: impl FnMut(LocalHit)) {
        match self {
            Shape::Mesh(mesh) => mesh.intersect_up_to(ray, t_max, hit),
            Shape::Curves(curves) => curves.intersect_up_to(ray, t_max, hit),
            _ => self.intersect_hits(ray, |h| {
                if h.t <= t_max {
                    hit(h)
                }
            }),
        }
    }

    /// Whether any hit lies in `t_min <= t < t_max` (shadow rays); meshes stop at the first,
    /// set operations filter their primitives' hits only when one lies in the span.
    #[inline]
    pub fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        match self {
            Shape::Mesh(mesh) => return mesh.any_hit(ray, t_min, t_max),
            Shape::Curves(curves) => return curves.any_hit(ray, t_min, t_max),
            Shape::Csg(csg) => return csg.any_hit(ray, t_min, t_max),
            _ => {}
        }
        let mut found = false;
        self.intersect_hits(ray, |h| found |= h.t >= t_min && h.t < t_max);
        found
    }

    /// [`Shape::closest_hit`] among the hits that `keep` accepts (an alpha texture's holes): a
    /// refused hit lets the search go on to those behind it. Not for CSG solids, whose own
    /// filtering of their primitives' hits this would bypass (they get `closest_hit`).
    #[inline]
    pub fn closest_hit_where(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut keep: impl FnMut(&LocalHit) -> bool,
    ) -> Option<LocalHit> {
        match self {
            Shape::Mesh(mesh) => mesh.closest_hit_where(ray, t_min, t_max, keep),
            Shape::Curves(curves) => curves.closest_hit_where(ray, t_min, t_max, keep),
            Shape::Csg(_) => self.closest_hit(ray, t_min, t_max),
            _ => {
                let mut best = None;
                let mut limit = t_max;
                self.intersect_hits(ray, |h| {
                    if h.t >= t_min && h.t < limit && keep(&h) {
                        limit = h.t;
                        best = Some(h);
                    }
                });
                best
            }
        }
    }

    /// [`Shape::any_hit`] among the hits that `keep` accepts (as
    /// [`closest_hit_where`](Self::closest_hit_where)).
    #[inline]
    pub fn any_hit_where(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut keep: impl FnMut(&LocalHit) -> bool,
    ) -> bool {
        match self {
            Shape::Mesh(mesh) => mesh.any_hit_where(ray, t_min, t_max, keep),
            Shape::Curves(curves) => curves.any_hit_where(ray, t_min, t_max, keep),
            Shape::Csg(_) => self.any_hit(ray, t_min, t_max),
            _ => {
                let mut found = false;
                self.intersect_hits(ray, |h| {
                    found = found || (h.t >= t_min && h.t < t_max && keep(&h));
                });
                found
            }
        }
    }

    /// The book's `local_normal_at`: the object-space normal at an object-space point on the
    /// surface (not normalised for every shape: the caller normalises after the normal
    /// transform). Smooth triangles and meshes need the hit: see [`Shape::normal_at_hit`].
    #[inline]
    pub fn normal_at(&self, point: Point3) -> Vec3 {
        self.normal_at_hit(point, &LocalHit::default())
    }

    /// The object-space normal at a hit (smooth triangles interpolate with its `u`, `v`).
    #[inline]
    pub fn normal_at_hit(&self, point: Point3, hit: &LocalHit) -> Vec3 {
        match self {
            Shape::Triangle(triangle) => triangle.normal_at(hit.u, hit.v),
            Shape::Mesh(mesh) => mesh.normal_at(hit),
            Shape::Curves(curves) => curves.normal_at(hit),
            Shape::Csg(csg) => csg.normal_at(point, hit),
            Shape::Sphere => sphere::normal_at(point),
            Shape::Plane => plane::normal_at(point),
            Shape::Cube => cube::normal_at(point),
            Shape::Cylinder {
                minimum, maximum, ..
            } => cylinder::normal_at(point, *minimum, *maximum),
            Shape::Cone {
                minimum, maximum, ..
            } => cone::normal_at(point, *minimum, *maximum),
            Shape::Torus { major, minor } => torus::normal_at(point, *major, *minor),
            Shape::Ring { .. } => ring::normal_at(point),
            Shape::Rectangle => rectangle::normal_at(point),
            Shape::Partial(q) => q.normal_at(point),
        }
    }

    /// The surface's own texture coordinates and vertex colour at a hit, where it has them
    /// (meshes with `vt`, glTF meshes with `COLOR_0`).
    #[inline]
    pub fn surface_point(&self, hit: &LocalHit) -> SurfacePoint {
        match self {
            Shape::Mesh(mesh) => SurfacePoint {
                uv: mesh.texcoord_at(hit),
                vertex_color: mesh.color_at(hit),
            },
            // pbrt-v4's uv on a curve: u along the segment, v across it.
            Shape::Curves(_) => SurfacePoint {
                uv: Some((hit.u, hit.v)),
                ..SurfacePoint::default()
            },
            _ => SurfacePoint::default(),
        }
    }

    /// The (u, v) pbrt-v4 gives the object-space point `p` of a sphere, ring (pbrt's disk),
    /// open cylinder or cut quadric (its own: see [`PartialQuadric::uv`]), in the frame the pbrt reader places them in (pbrt's z along the ring's
    /// and cylinder's y): `u = φ / 2π` with φ pbrt's angle about its z from its x, and `v` from
    /// the bottom pole to the top (sphere), from the outer edge in (disk), from `minimum` to
    /// `maximum` (cylinder). Other shapes have none: (0, 0).
    pub fn quadric_uv(&self, p: Point3) -> (f64, f64) {
        use std::f64::consts::PI;
        let turn = |y: f64, x: f64| {
            let phi = y.atan2(x);
            (if phi < 0.0 { phi + 2.0 * PI } else { phi }) / (2.0 * PI)
        };
        match *self {
            Shape::Sphere => {
                let r = p.length();
                let cos_theta = if r > 0.0 {
                    (p.z / r).clamp(-1.0, 1.0)
                } else {
                    1.0
                };
                (turn(p.y, p.x), 1.0 - cos_theta.acos() / PI)
            }
            // pbrt's (x, y, z) is the reader's (x, −z, y) for these two.
            Shape::Ring { inner, outer } => {
                let r = (p.x * p.x + p.z * p.z).sqrt();
                let v = if outer > inner {
                    (outer - r) / (outer - inner)
                } else {
                    0.0
                };
                (turn(-p.z, p.x), v)
            }
            Shape::Cylinder {
                minimum, maximum, ..
            } if maximum > minimum && maximum.is_finite() && minimum.is_finite() => {
                (turn(-p.z, p.x), (p.y - minimum) / (maximum - minimum))
            }
            Shape::Partial(ref q) => q.uv(p),
            _ => (0.0, 0.0),
        }
    }

    /// Whether an object-space point is inside the shape, for the shapes whose inside a formula
    /// gives (`None` for the others, which the caller asks by casting a ray). Every formula is
    /// `f(p) < 0` for the implicit surface `f = 0` with `f > 0` far away, so it agrees with the
    /// parity of the surfaces ahead of the point everywhere but within rounding of the surface;
    /// it costs a few products where a ray costs an intersection (a quartic on a torus), and set
    /// operations ask it after every hit.
    #[inline]
    pub fn contains_point(&self, p: Point3) -> Option<bool> {
        match self {
            Shape::Sphere => Some(p.length_squared() < 1.0),
            Shape::Cube => Some(p.abs().max_element() < 1.0),
            Shape::Plane => Some(p.y < 0.0),
            Shape::Cylinder {
                minimum,
                maximum,
                closed: true,
            } => Some(p.x * p.x + p.z * p.z < 1.0 && *minimum < p.y && p.y < *maximum),
            Shape::Torus { major, minor } => Some(torus::contains(p, *major, *minor)),
            _ => None,
        }
    }

    /// The sampler of the shape's surface (see [`ShapeSampler`]), for the shapes with a
    /// finite one: not infinite planes, cylinders or cones, degenerate tori, meshes of no area,
    /// nor CSG solids (whose primitives are sampled instead), nor curves (pbrt-v4 samples none).
    pub fn sampler(&self) -> Option<ShapeSampler> {
        Some(match self {
            Shape::Sphere => ShapeSampler::Sphere,
            Shape::Cube => ShapeSampler::Cube,
            Shape::Rectangle => ShapeSampler::Rectangle,
            Shape::Partial(q) => ShapeSampler::Partial(**q),
            Shape::Ring { inner, outer } => ShapeSampler::Ring {
                inner: *inner,
                outer: *outer,
            },
            Shape::Triangle(t) => ShapeSampler::Triangle(t.clone()),
            Shape::Mesh(mesh) => return ShapeSampler::mesh(mesh),
            Shape::Cylinder {
                minimum,
                maximum,
                closed,
            } => ShapeSampler::Cylinder(Heights::finite(*minimum, *maximum, *closed)?),
            Shape::Cone {
                minimum,
                maximum,
                closed,
            } => ShapeSampler::Cone(Heights::finite(*minimum, *maximum, *closed)?),
            Shape::Torus { major, minor } if torus::is_sampled(*major, *minor) => {
                ShapeSampler::Torus {
                    major: *major,
                    minor: *minor,
                }
            }
            _ => return None,
        })
    }

    /// Whether the shape encloses a volume (surfaces with no thickness, a ring or a lone
    /// triangle, do not: nothing is ever inside them).
    pub fn has_volume(&self) -> bool {
        !matches!(
            self,
            Shape::Ring { .. }
                | Shape::Triangle(_)
                | Shape::Rectangle
                | Shape::Partial(_)
                | Shape::Curves(_)
        )
    }

    /// The book's `bounds_of(shape)`: the object-space box around the shape (infinite along the
    /// axes where the shape is unbounded).
    pub fn bounds(&self) -> Aabb {
        let unit = Aabb::new(Point3::splat(-1.0), Point3::ONE);
        match self {
            Shape::Sphere | Shape::Cube => unit,
            Shape::Plane => Aabb::new(
                Point3::new(f64::NEG_INFINITY, 0.0, f64::NEG_INFINITY),
                Point3::new(f64::INFINITY, 0.0, f64::INFINITY),
            ),
            Shape::Cylinder {
                minimum, maximum, ..
            } => Aabb::new(
                Point3::new(-1.0, *minimum, -1.0),
                Point3::new(1.0, *maximum, 1.0),
            ),
            Shape::Cone {
                minimum, maximum, ..
            } => {
                let r = minimum.abs().max(maximum.abs());
                Aabb::new(Point3::new(-r, *minimum, -r), Point3::new(r, *maximum, r))
            }
            Shape::Torus { major, minor } => {
                let (outer, r) = (major + minor, *minor);
                Aabb::new(
                    Point3::new(-outer, -r, -outer),
                    Point3::new(outer, r, outer),
                )
            }
            Shape::Ring { outer, .. } => Aabb::new(
                Point3::new(-outer, 0.0, -outer),
                Point3::new(*outer, 0.0, *outer),
            ),
            Shape::Rectangle => Aabb::new(Point3::new(-1.0, 0.0, -1.0), Point3::new(1.0, 0.0, 1.0)),
            Shape::Mesh(mesh) => mesh.bounds(),
            Shape::Curves(curves) => curves.bounds(),
            Shape::Csg(csg) => csg.bounds(),
            Shape::Partial(q) => q.bounds(),
            Shape::Triangle(t) => {
                let mut b = Aabb::EMPTY;
                for p in [t.p1, t.p2, t.p3] {
                    b.add_point(p);
                }
                b
            }
        }
    }
}
