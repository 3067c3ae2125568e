//! Triangles and smooth triangles (chapter 15), intersected by the Möller–Trumbore algorithm.

use crate::math::{Point3, Ray, Vec3};

/// A triangle with its edges and face normal precomputed, and optionally one normal per vertex
/// (a smooth triangle, whose shading normal is interpolated across the face).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    /// First vertex.
    pub p1: Point3,
    /// Second vertex.
    pub p2: Point3,
    /// Third vertex.
    pub p3: Point3,
    /// `p2 - p1`.
    pub e1: Vec3,
    /// `p3 - p1`.
    pub e2: Vec3,
    /// The face normal, `normalize(e2 × e1)`.
    pub normal: Vec3,
    /// Vertex normals `n1, n2, n3` for a smooth triangle.
    pub vertex_normals: Option<[Vec3; 3]>,
}

impl Triangle {
    /// The book's `triangle(p1, p2, p3)`.
    pub fn new(p1: Point3, p2: Point3, p3: Point3) -> Self {
        let e1 = p2 - p1;
        let e2 = p3 - p1;
        Self {
            p1,
            p2,
            p3,
            e1,
            e2,
            // A degenerate (zero-area) triangle gets a zero normal rather than NaN; rays can
            // never hit it anyway because its determinant is zero.
            normal: e2.cross(e1).normalize_or_zero(),
            vertex_normals: None,
        }
    }

    /// The book's `smooth_triangle(p1, p2, p3, n1, n2, n3)`.
    pub fn smooth(p1: Point3, p2: Point3, p3: Point3, n1: Vec3, n2: Vec3, n3: Vec3) -> Self {
        Self {
            vertex_normals: Some([n1, n2, n3]),
            ..Self::new(p1, p2, p3)
        }
    }

    /// Möller–Trumbore: one hit with its barycentric `u` (towards `p2`) and `v` (towards `p3`).
    #[inline]
    pub fn intersect(&self, ray: &Ray, mut hit: impl FnMut(f64, f64, f64)) {
        if let Some((t, u, v)) = moller_trumbore(ray, self.p1, self.e1, self.e2) {
            hit(t, u, v);
        }
    }

    /// The face normal, or for a smooth triangle the vertex normals blended by `u` and `v`.
    #[inline]
    pub fn normal_at(&self, u: f64, v: f64) -> Vec3 {
        match self.vertex_normals {
            Some([n1, n2, n3]) => n2 * u + n3 * v + n1 * (1.0 - u - v),
            None => self.normal,
        }
    }
}

/// Barycentric weights of the second and third corners of a triangle, uniformly by area from
/// `u`, `v` in [0, 1): the square folded onto the triangle by `√u` (the area up to a line
/// parallel to the far edge grows with its distance squared).
#[inline]
pub fn uniform_weights(u: f64, v: f64) -> (f64, f64) {
    let su = u.sqrt();
    ((1.0 - v) * su, v * su)
}

/// The Möller–Trumbore test against the triangle `p1`, `p1 + e1`, `p1 + e2`: the hit's `t` and
/// barycentric `u`, `v`, or `None`. Shared by standalone triangles and mesh faces.
#[inline]
pub(super) fn moller_trumbore(
    ray: &Ray,
    p1: Point3,
    e1: Vec3,
    e2: Vec3,
) -> Option<(f64, f64, f64)> {
    plane_crossing(ray, p1, e1, e2).filter(|&(_, u, v)| inside(u, v))
}

/// Whether barycentric `u`, `v` lie on the triangle (edges included).
#[inline]
pub(super) fn inside(u: f64, v: f64) -> bool {
    (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0
}

/// Where the ray crosses the plane of the triangle `p1`, `p1 + e1`, `p1 + e2`: its `t` and
/// the barycentric `u`, `v` of the crossing, inside the triangle or not; `None` for a ray
/// parallel to the plane.
#[inline]
pub(super) fn plane_crossing(ray: &Ray, p1: Point3, e1: Vec3, e2: Vec3) -> Option<(f64, f64, f64)> {
    let dir_cross_e2 = ray.direction.cross(e2);
    let det = e1.dot(dir_cross_e2);
    if det == 0.0 || !det.is_finite() {
        // The ray is parallel to the triangle's plane. (The book tests |det| < EPSILON, but
        // det scales with the triangle's area: that would reject every hit on the tiny
        // triangles of a detailed mesh. Near-parallel rays fail the u/v tests.)
        return None;
    }
    let f = 1.0 / det;
    let p1_to_origin = ray.origin - p1;
    let u = f * p1_to_origin.dot(dir_cross_e2);
    let origin_cross_e1 = p1_to_origin.cross(e1);
    let v = f * ray.direction.dot(origin_cross_e1);
    Some((f * e2.dot(origin_cross_e1), u, v))
}
