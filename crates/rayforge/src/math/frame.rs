//! An orthonormal basis around a unit normal, so that shading can work in a local frame where
//! the normal is +Z: there `cos θ` is just the z component and every BSDF formula is short.

use crate::math::{sin_cos_turns, Vec3};

/// A direction in a frame's local space drawn proportionally to `cos θ` over the upper
/// hemisphere (+Z), density `cos θ / π` (Malley's method: a uniform point on the unit disk
/// lifted onto the hemisphere). Diffuse reflection samples it, and so does light sampling of
/// an infinite glowing plane.
pub fn cosine_hemisphere(u: [f64; 2]) -> Vec3 {
    let r = u[0].clamp(0.0, 1.0).sqrt();
    let (sin, cos) = sin_cos_turns(u[1]);
    Vec3::new(r * cos, r * sin, (1.0 - u[0]).max(0.0).sqrt())
}

/// Three orthonormal unit vectors: tangent `s`, bitangent `t` and normal `n` (right-handed,
/// `s × t = n`). Built from the normal alone, so any surface point gets a frame without needing
/// tangents from its parameterisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The first tangent.
    pub s: Vec3,
    /// The second tangent.
    pub t: Vec3,
    /// The normal, the frame's local +Z.
    pub n: Vec3,
}

impl Frame {
    /// The frame around unit normal `n`, by the branchless construction of Duff et al. 2017
    /// ("Building an Orthonormal Basis, Revisited"): continuous everywhere except across the
    /// plane `n.z = 0`'s sign flip, and exact for `n = ±Z` (no division by a tiny number).
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0_f64.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    /// The frame around unit normal `n` whose first tangent `s` is `tangent` made
    /// perpendicular to `n` (Gram–Schmidt), for materials whose scattering depends on the
    /// direction along the surface (anisotropic roughness); the frame around `n` alone where
    /// `tangent` is (nearly) parallel to `n` or not finite.
    pub fn from_normal_and_tangent(n: Vec3, tangent: Vec3) -> Self {
        let across = tangent - n * n.dot(tangent);
        if across.length_squared().is_nan()
            || across.length_squared() <= 1e-12 * tangent.length_squared()
        {
            return Self::from_normal(n);
        }
        match across.try_normalize() {
            Some(s) if s.is_finite() => Self {
                s,
                t: n.cross(s),
                n,
            },
            _ => Self::from_normal(n),
        }
    }

    /// World direction `v` in this frame's coordinates (its components along `s`, `t`, `n`).
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local direction `v` back in world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    #[test]
    fn a_frame_along_a_tangent_keeps_its_direction_and_is_orthonormal() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        let f = Frame::from_normal_and_tangent(n, Vec3::new(1.0, 0.5, 0.0));
        assert!((f.s.cross(f.t) - n).length() < 1e-12);
        assert!(f.s.dot(n).abs() < 1e-12 && (f.s.length() - 1.0).abs() < 1e-12);
        assert!(f.s.dot(Vec3::new(1.0, 0.5, 0.0)) > 0.9);
        assert_eq!(
            Frame::from_normal_and_tangent(n, n * 2.0),
            Frame::from_normal(n)
        );
    }

    fn check(n: Vec3) {
        let f = Frame::from_normal(n);
        for (name, v) in [("s", f.s), ("t", f.t), ("n", f.n)] {
            assert!(
                (v.length() - 1.0).abs() < 1e-12,
                "{name} of {n} not unit: {v}"
            );
        }
        assert!(f.s.dot(f.t).abs() < 1e-12, "s·t for {n}");
        assert!(f.s.dot(f.n).abs() < 1e-12, "s·n for {n}");
        assert!(f.t.dot(f.n).abs() < 1e-12, "t·n for {n}");
        assert!(
            (f.s.cross(f.t) - f.n).length() < 1e-12,
            "handedness for {n}"
        );
        let v = Vec3::new(0.3, -0.5, 0.8).normalize();
        assert!((f.to_world(f.to_local(v)) - v).length() < 1e-12);
        assert!((f.to_local(n) - Vec3::Z).length() < 1e-12);
    }

    #[test]
    fn frames_are_orthonormal_and_right_handed_for_many_normals() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
            check(n);
        }
        check(Vec3::new(1e-9, -1e-9, -1.0).normalize());
        check(Vec3::new(0.0, 1e-12, 1.0).normalize());
        let mut rng = SplitMix64::new(7);
        for _ in 0..1000 {
            let z = 2.0 * rng.next_offset() - 1.0;
            let phi = std::f64::consts::TAU * rng.next_offset();
            let r = (1.0 - z * z).max(0.0).sqrt();
            check(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
    }
}
