//! `prepare_computations` (chapters 7, 8 and 11): everything shading needs about a hit, computed
//! once, and Schlick's approximation of the Fresnel effect.

use crate::math::{reflect, Point3, Ray, Vec3, EPSILON};
use crate::scene::{Intersection, Object};
use crate::shading::SurfacePoint;

/// The state of an intersection, ready for shading.
///
/// `point`, `over_point` and `under_point` are separate fields on purpose (the validation
/// notebook's trap): lighting and shadows start above the surface, refraction below it, and the
/// exact point is still needed for patterns and tests.
#[derive(Debug, Clone, Copy)]
pub struct Computations<'a> {
    /// Distance along the ray.
    pub t: f64,
    /// The object hit (for a CSG solid, the solid: refraction tracks containers by it).
    pub object: &'a Object,
    /// The object whose surface was hit, which shades it: the object itself, or the primitive
    /// of a CSG solid.
    pub surface: &'a Object,
    /// The hit point on the surface.
    pub point: Point3,
    /// The hit point nudged along the normal, so shadow and reflection rays do not re-hit the
    /// surface they leave (acne).
    pub over_point: Point3,
    /// The hit point nudged against the normal, where refracted rays start.
    pub under_point: Point3,
    /// Unit vector towards the eye.
    pub eyev: Vec3,
    /// Unit surface normal, flipped to face the eye.
    pub normalv: Vec3,
    /// Whether the ray hit the surface from inside the object.
    pub inside: bool,
    /// The ray's direction mirrored about the normal.
    pub reflectv: Vec3,
    /// The surface's own texture coordinates at the hit, where it has them.
    pub surface_point: SurfacePoint,
    /// Refractive index of the medium the ray leaves.
    pub n1: f64,
    /// Refractive index of the medium the ray enters.
    pub n2: f64,
    /// When the ray was cast: rays leaving the hit (shadows, reflections, refractions) are
    /// cast at the same instant, and moving patterns are read where the object was then.
    pub time: f64,
}

/// The book's `prepare_computations(hit, ray, xs)`.
///
/// `xs` must be sorted by `t` and contain `hit`; it is only read to find the refractive indices
/// on either side of the hit. Allocates a containers list; the Whitted integrator uses
/// [`prepare_computations_with`] and a reused one.
pub fn prepare_computations<'a>(
    hit: Intersection<'a>,
    ray: &Ray,
    xs: &[Intersection<'a>],
) -> Computations<'a> {
    prepare_computations_with(hit, ray, xs, &mut Vec::new())
}

/// `prepare_computations` with caller-owned scratch space for the containers list.
pub fn prepare_computations_with<'a>(
    hit: Intersection<'a>,
    ray: &Ray,
    xs: &[Intersection<'a>],
    containers: &mut Vec<(&'a Object, f64)>,
) -> Computations<'a> {
    let point = ray.position(hit.t);
    let eyev = -ray.direction.normalize();
    let mut geometric = hit.object.normal_at_hit(point, &hit);
    let inside = geometric.dot(eyev) < 0.0;
    if inside {
        geometric = -geometric;
    }
    // Bumps tilt the normal used for shading; the points nudged off the surface keep to the
    // true normal, so bumps never push a shadow or refraction ray through the surface.
    let surface = hit.object.surface(hit.leaf);
    let normalv = match &surface.material.bump {
        Some(bump) => {
            let transform = surface.transform_at(hit.time);
            bump.perturb(geometric, transform.inverse_point(point), &transform)
        }
        None => geometric,
    };
    let (n1, n2) = refractive_indices(hit, xs, containers);
    let offset = geometric * surface_offset(point);
    Computations {
        t: hit.t,
        object: hit.object,
        surface,
        surface_point: surface.shape.surface_point(&hit.local()),
        point,
        over_point: point + offset,
        under_point: point - offset,
        eyev,
        normalv,
        inside,
        reflectv: reflect(ray.direction, normalv),
        n1,
        n2,
        time: ray.time,
    }
}

/// How far hit points are nudged off their surface: the book's `EPSILON`, or more far from the
/// origin, where coordinates themselves are coarser. A double resolves about 2.2e-16 of a
/// coordinate's size, and a hit point computed from a ray carries a few dozen such steps of
/// error; past about 1e9 from the origin that error outgrows `EPSILON` and surfaces would
/// shadow themselves (acne), so the offset grows with the point's largest coordinate, staying
/// some 45 steps of the coordinates' resolution. Nearer scenes keep exactly `EPSILON`.
pub fn surface_offset(point: Point3) -> f64 {
    EPSILON.max(point.abs().max_element() * 1e-14)
}

/// The chapter 11 algorithm: walk the sorted intersections, keeping the list of objects the ray
/// is inside (by identity, so two equal spheres stay distinct); at the hit, n1 is the index of the
/// innermost container before it and n2 the innermost after it. Empty space has index 1.
///
/// Each container is kept with the refractive index of the surface the ray entered through (the
/// primitive of a CSG solid carries the material, the solid the identity).
fn refractive_indices<'a>(
    hit: Intersection<'a>,
    xs: &[Intersection<'a>],
    containers: &mut Vec<(&'a Object, f64)>,
) -> (f64, f64) {
    let index_of = |c: &[(&Object, f64)]| c.last().map_or(1.0, |(_, index)| *index);
    containers.clear();
    let mut n1 = 1.0;
    for i in xs {
        let is_hit = i.same_as(&hit);
        if is_hit {
            n1 = index_of(containers);
        }
        match containers
            .iter()
            .position(|(o, _)| std::ptr::eq(*o, i.object))
        {
            Some(at) => {
                containers.remove(at);
            }
            None => containers.push((i.object, i.object.surface(i.leaf).material.refractive_index)),
        }
        if is_hit {
            return (n1, index_of(containers));
        }
    }
    (n1, index_of(containers))
}

/// The book's `schlick(comps)`: the fraction of light reflected at the hit (Schlick's
/// approximation to Fresnel), 1 under total internal reflection.
pub fn schlick(comps: &Computations<'_>) -> f64 {
    let mut cos = comps.eyev.dot(comps.normalv);
    if comps.n1 > comps.n2 {
        let n = comps.n1 / comps.n2;
        let sin2_t = n * n * (1.0 - cos * cos);
        if sin2_t > 1.0 {
            return 1.0;
        }
        cos = (1.0 - sin2_t).sqrt();
    }
    let r0 = ((comps.n1 - comps.n2) / (comps.n1 + comps.n2)).powi(2);
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}
