//! Intersections and hits (chapter 5).

use crate::geometry::LocalHit;
use crate::math::Vec3;
use crate::scene::Object;

/// A ray meeting an object at distance `t`. The object is referenced, so identity (which object,
/// not which values) is available to refraction's container tracking.
#[derive(Debug, Clone, Copy)]
pub struct Intersection<'a> {
    /// Distance along the ray, in units of the ray's direction.
    pub t: f64,
    /// The object that was hit.
    pub object: &'a Object,
    /// Surface coordinate u at the hit (barycentric on triangles, towards `p2`).
    pub u: f64,
    /// Surface coordinate v at the hit (barycentric on triangles, towards `p3`).
    pub v: f64,
    /// The face of a mesh that was hit (0 for other shapes).
    pub face: u32,
    /// The primitive of a CSG solid that was hit (0 for other shapes).
    pub leaf: u32,
    /// When the ray was cast (where a moving object was).
    pub time: f64,
    /// The object-space normal the shape found with the hit, where the ray decides it (see
    /// [`LocalHit::normal`]); zero for most shapes.
    pub normal: Vec3,
}

impl<'a> Intersection<'a> {
    /// The book's `intersection(t, object)`.
    #[inline]
    pub fn new(t: f64, object: &'a Object) -> Self {
        Self::with_uv(t, object, 0.0, 0.0)
    }

    /// The book's `intersection_with_uv(t, object, u, v)`.
    #[inline]
    pub fn with_uv(t: f64, object: &'a Object, u: f64, v: f64) -> Self {
        Self::from_local(
            object,
            LocalHit {
                t,
                u,
                v,
                ..LocalHit::default()
            },
        )
    }

    /// An intersection from a shape's object-space hit.
    #[inline]
    pub fn from_local(object: &'a Object, hit: LocalHit) -> Self {
        Self {
            t: hit.t,
            object,
            u: hit.u,
            v: hit.v,
            face: hit.face,
            leaf: hit.leaf,
            time: hit.time,
            normal: hit.normal,
        }
    }

    /// Where on the surface the hit is, in the shape's terms.
    #[inline]
    pub fn local(&self) -> LocalHit {
        LocalHit {
            t: self.t,
            u: self.u,
            v: self.v,
            face: self.face,
            leaf: self.leaf,
            time: self.time,
            normal: self.normal,
        }
    }

    /// Whether two intersections are the same `t` on the same object (by identity).
    pub fn same_as(&self, other: &Intersection<'_>) -> bool {
        self.t == other.t && std::ptr::eq(self.object, other.object)
    }
}

impl PartialEq for Intersection<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.same_as(other)
    }
}

/// Sorts intersections by `t` (NaN, which no shape should produce, sorts last).
pub fn sort_intersections(xs: &mut [Intersection<'_>]) {
    xs.sort_unstable_by(|a, b| a.t.total_cmp(&b.t));
}

/// The book's `hit(xs)`: the intersection with the lowest non-negative `t`, in any order.
pub fn hit<'a>(xs: &[Intersection<'a>]) -> Option<Intersection<'a>> {
    xs.iter()
        .filter(|i| i.t >= 0.0)
        .min_by(|a, b| a.t.total_cmp(&b.t))
        .copied()
}
