//! Four triangles tested against a ray at once, with the watertight test of Woop, Benthin and
//! Wald ("Watertight Ray/Triangle Intersection", JCGT 2013).
//!
//! The test moves the triangle into a frame where the ray starts at the origin and runs along
//! +z (a translation, an axis permutation and a shear, all set up once per ray in
//! [`TriangleRay`]), then asks on which side of each edge the origin lies. The edge functions of
//! two triangles sharing an edge are computed from the same two corners in the same way, so a
//! ray through a shared edge is never missed by both: a mesh has no cracks for rays to slip
//! through. Möller–Trumbore, used for the book's lone triangles, computes from precomputed
//! edges and can miss both.

use crate::accel::{Isa, Lanes4, RayQuery};

/// What the watertight test needs of a ray, set up once per ray, in every lane of the set's
/// vectors.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TriangleRay<I: Isa> {
    /// The axis order: the direction's dominant axis last.
    axes: [usize; 3],
    /// The shear constants.
    shear: [I::F4; 3],
    /// The ray's origin (in the order of the hierarchy's axes, not `axes`).
    origin: [I::F4; 3],
}

impl<I: Isa> TriangleRay<I> {
    /// The test's set-up for a ray prepared for the BVH walk.
    #[inline(always)]
    pub(crate) fn new(isa: I, q: &RayQuery) -> Self {
        let d = q.direction;
        // Look down the dominant axis (z after the permutation); swapping x and y when that
        // axis points backwards keeps the triangles' winding.
        let abs = d.map(f32::abs);
        let kz = if abs[0] > abs[1] {
            if abs[0] > abs[2] {
                0
            } else {
                2
            }
        } else if abs[1] > abs[2] {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let inv = q.inv_direction[kz];
        let shear = if abs[kz] > 0.0 && abs[kz].is_finite() {
            [d[kx] * inv, d[ky] * inv, inv]
        } else {
            // A zero (or unusable) direction meets no triangle; NaN shears make every test
            // fail instead of inventing a hit.
            [f32::NAN; 3]
        };
        Self {
            axes: [kx, ky, kz],
            shear: shear.map(|x| isa.splat4(x)),
            origin: q.origin.map(|x| isa.splat4(x)),
        }
    }
}

/// Four triangles' corners in the hierarchy's `f32` frame, lane by lane; unused lanes hold
/// NaN, which no test accepts.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(16))]
pub(crate) struct TrianglePacket {
    /// `corners[k][axis][lane]`: corner `k` of triangle `lane`.
    corners: [[[f32; 4]; 3]; 3],
    /// Which face each lane holds (beside its corners, so a hit costs no further memory
    /// access to name it).
    pub(crate) faces: [u32; 4],
}

impl TrianglePacket {
    /// A packet with no triangles.
    pub(crate) const EMPTY: Self = Self {
        corners: [[[f32::NAN; 4]; 3]; 3],
        faces: [u32::MAX; 4],
    };

    /// Puts a face (corners relative to the frame's base) in `lane`.
    pub(crate) fn set(&mut self, lane: usize, face: u32, corners: [[f32; 3]; 3]) {
        self.faces[lane] = face;
        for (k, corner) in corners.iter().enumerate() {
            for (axis, &coordinate) in corner.iter().enumerate() {
                self.corners[k][axis][lane] = coordinate;
            }
        }
    }

    /// Which lanes the ray hits with `t_min <= t < t_max` (bit per lane), and their `t`.
    #[inline(always)]
    pub(crate) fn intersect<I: Isa>(
        &self,
        isa: I,
        ray: &TriangleRay<I>,
        t_min: f32,
        t_max: f32,
    ) -> (u32, I::F4) {
        let [kx, ky, kz] = ray.axes;
        let [sx, sy, sz] = ray.shear;
        let o = &ray.origin;
        // Corner k relative to the ray's origin, sheared so the ray runs along +z (each
        // corner is transformed alone, identically in every triangle that shares it).
        let corner = |k: usize| {
            let c = &self.corners[k];
            let z = isa.load4(&c[kz]) - o[kz];
            let x = sx.mul_neg_add(z, isa.load4(&c[kx]) - o[kx]);
            let y = sy.mul_neg_add(z, isa.load4(&c[ky]) - o[ky]);
            (x, y, z)
        };
        let (ax, ay, az) = corner(0);
        let (bx, by, bz) = corner(1);
        let (cx, cy, cz) = corner(2);
        // Twice the signed areas of the triangles the origin makes with each edge. (Plain
        // products, not fused: the two triangles sharing an edge must compute its function
        // with exactly opposite signs.)
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = isa.splat4(0.0);
        let some_negative = u.lt(zero) | v.lt(zero) | w.lt(zero);
        let some_positive = u.gt(zero) | v.gt(zero) | w.gt(zero);
        let det = u + v + w;
        let inside = det.ne(zero).and_not(some_negative & some_positive);
        if inside.bits() == 0 {
            // Most packets a ray reaches are missed: no distance to divide out.
            return (0, zero);
        }
        let t = (u * az + v * bz + w * cz) * sz / det;
        let in_range = t.ge(isa.splat4(t_min)) & t.lt(isa.splat4(t_max));
        ((inside & in_range).bits(), t)
    }
}
