//! Clipping (the book's "Clipping" chapter): planes in view space, whole objects accepted or
//! rejected by their bounding sphere, and triangles that cross a plane split into the one or two
//! triangles that cover their inside part, with every attribute interpolated at the new
//! vertices.

use glam::DVec3;

/// A plane `⟨normal, p⟩ + d = 0` with a unit normal pointing into the visible side, so that
/// `⟨normal, p⟩ + d` is the signed distance of `p` (positive inside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipPlane {
    /// Unit normal, towards the inside.
    pub normal: DVec3,
    /// Offset: minus the distance from the origin along the normal.
    pub d: f64,
}

impl ClipPlane {
    /// The plane `⟨normal, p⟩ + d = 0`, scaled so the normal has unit length.
    pub fn new(normal: DVec3, d: f64) -> Self {
        let length = normal.length();
        Self {
            normal: normal / length,
            d: d / length,
        }
    }

    /// Signed distance of `p` from the plane: positive on the inside.
    #[inline]
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) + self.d
    }

    /// Where a sphere lies relative to the plane (the book's whole-object test).
    pub fn classify_sphere(&self, centre: DVec3, radius: f64) -> SphereSide {
        let distance = self.signed_distance(centre);
        if distance > radius {
            SphereSide::Inside
        } else if distance < -radius {
            SphereSide::Outside
        } else {
            SphereSide::Crossing
        }
    }
}

/// A bounding sphere against a plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SphereSide {
    /// Wholly inside: no triangle of the object needs clipping against this plane.
    Inside,
    /// Wholly outside: the object is not drawn at all.
    Outside,
    /// The plane cuts the sphere: triangles must be tested one by one.
    Crossing,
}

/// A vertex with whatever attributes the renderer carries (colour, normal, texture
/// coordinates, …): clipping needs its position and a way to blend two of them.
pub trait ClipVertex: Copy {
    /// The position in the space of the clipping planes.
    fn position(&self) -> DVec3;
    /// The vertex a fraction `t` of the way from `self` to `other`, every attribute blended
    /// linearly (the book's `α_Q = α_A + t(α_B − α_A)`).
    fn lerp(&self, other: &Self, t: f64) -> Self;
}

impl ClipVertex for DVec3 {
    fn position(&self) -> DVec3 {
        *self
    }
    fn lerp(&self, other: &Self, t: f64) -> Self {
        *self + (*other - *self) * t
    }
}

/// Clipping against five planes splits a triangle into at most 2^5 pieces.
const MAX_PIECES: usize = 32;

/// The triangles left after clipping, in a fixed-size buffer (clipping allocates nothing).
#[derive(Debug, Clone)]
pub struct Clipped<V> {
    triangles: [[V; 3]; MAX_PIECES],
    len: usize,
}

impl<V: ClipVertex> Clipped<V> {
    fn one(triangle: [V; 3]) -> Self {
        Self {
            triangles: [triangle; MAX_PIECES],
            len: 1,
        }
    }

    fn push(&mut self, triangle: [V; 3]) {
        // At most twice as many pieces per plane: with at most five planes this never fills.
        if self.len < MAX_PIECES {
            self.triangles[self.len] = triangle;
            self.len += 1;
        }
    }

    /// The pieces, each wound like the original triangle.
    pub fn triangles(&self) -> &[[V; 3]] {
        &self.triangles[..self.len]
    }
}

/// The point where edge `inside → outside` meets the plane. Always computed from the inside
/// vertex, so the two triangles that share an edge get the very same point.
fn crossing<V: ClipVertex>(plane: &ClipPlane, inside: &V, outside: &V) -> V {
    let (a, b) = (
        plane.signed_distance(inside.position()),
        plane.signed_distance(outside.position()),
    );
    // a >= 0 > b, so the denominator is positive and t lies in (0, 1].
    inside.lerp(outside, a / (a - b))
}

/// Clips one triangle against one plane, calling `emit` with what is inside: the triangle
/// itself, nothing, one triangle (one vertex inside) or two (two inside), in the original
/// winding. Vertices at distance 0 count as inside, as in the book.
pub fn clip_against_plane<V: ClipVertex>(
    plane: &ClipPlane,
    tri: [V; 3],
    mut emit: impl FnMut([V; 3]),
) {
    let inside = tri.map(|v| plane.signed_distance(v.position()) >= 0.0);
    match inside.iter().filter(|&&i| i).count() {
        3 => emit(tri),
        0 => {}
        1 => {
            // Rotate so the inside vertex is A: ABC keeps its winding as A B' C'.
            let k = inside.iter().position(|&i| i).unwrap_or(0);
            let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            emit([a, crossing(plane, &a, &b), crossing(plane, &a, &c)]);
        }
        _ => {
            // Rotate so the outside vertex is C; A' on AC and B' on BC. The inside part is the
            // quadrilateral A B B' A', cut into A B A' and A' B B' (the book's two triangles).
            let k = inside.iter().position(|&i| !i).unwrap_or(2);
            let (c, a, b) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let a2 = crossing(plane, &a, &c);
            let b2 = crossing(plane, &b, &c);
            emit([a, b, a2]);
            emit([a2, b, b2]);
        }
    }
}

/// Clips a triangle against every plane in turn (what survives one plane is clipped against
/// the next: the visible volume is the intersection of their inside half-spaces).
pub fn clip_triangle<V: ClipVertex>(planes: &[ClipPlane], tri: [V; 3]) -> Clipped<V> {
    let mut current = Clipped::one(tri);
    for plane in planes {
        let mut next = Clipped {
            triangles: current.triangles,
            len: 0,
        };
        for &piece in current.triangles() {
            clip_against_plane(plane, piece, |t| next.push(t));
        }
        current = next;
        if current.len == 0 {
            break;
        }
    }
    current
}
