//! The GGX (Trowbridge–Reitz) microfacet distribution with Smith shadowing, for rough
//! conductors, rough dielectrics and rough plastic coats.
//!
//! Directions are in the local frame (normal +Z) and the view direction `wo` is in the upper
//! hemisphere (callers mirror it there first). `alpha` is used as given (not squared from a
//! "roughness"). Sampling draws from the distribution of *visible* normals, so that few
//! samples are wasted on microfacets facing away from the viewer.

use crate::math::{sin_cos_turns, Vec3};
use std::f64::consts::PI;

/// An isotropic GGX distribution of microfacet normals with width `alpha`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ggx {
    pub alpha: f64,
}

impl Ggx {
    /// The density of microfacet normals `m` per unit projected area:
    /// `D(m) = 1 / (π α² (m_z² + (m_x² + m_y²)/α²)²)`, the same as
    /// `1 / (π α² cos⁴θ (1 + tan²θ/α²)²)` without dividing by a vanishing cosine.
    pub fn d(&self, m: Vec3) -> f64 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
        let d = 1.0 / (PI * a2 * t * t);
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }

    /// Smith's masking of microfacet `m` seen from `w`: `2 / (1 + √(1 + α² tan²θ))`, and 0 when
    /// `w` sees the back of the microfacet or lies on the other side of the surface.
    pub fn g1(&self, w: Vec3, m: Vec3) -> f64 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        let z2 = w.z * w.z;
        let tan2 = (w.x * w.x + w.y * w.y) / z2;
        let g = 2.0 / (1.0 + (1.0 + self.alpha * self.alpha * tan2).sqrt());
        if g.is_finite() {
            g
        } else {
            0.0
        }
    }

    /// The density of normals visible from `wo` (upper hemisphere):
    /// `D_wo(m) = G1(wo, m) max(0, wo·m) D(m) / wo_z`.
    pub fn visible_pdf(&self, wo: Vec3, m: Vec3) -> f64 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        let p = self.g1(wo, m) * wo.dot(m).max(0.0) * self.d(m) / wo.z;
        if p.is_finite() {
            p
        } else {
            0.0
        }
    }

    /// A normal drawn from [`visible_pdf`](Self::visible_pdf) by the spherical-cap method of
    /// Dupuy & Benyoub 2023: in the space where the distribution is a hemisphere of unit
    /// normals, visible normals are the sum of the stretched view direction and a point drawn
    /// uniformly on the cap of the unit sphere beyond the plane it defines.
    pub fn sample_visible(&self, wo: Vec3, u: [f64; 2]) -> Option<Vec3> {
        if wo.z <= 0.0 {
            return None;
        }
        let stretched = Vec3::new(self.alpha * wo.x, self.alpha * wo.y, wo.z);
        let len = stretched.length();
        if len.is_nan() || len <= 0.0 {
            return None;
        }
        let v = stretched / len;
        let (sin_phi, cos_phi) = sin_cos_turns(u[0]);
        let z = (1.0 - u[1]) * (1.0 + v.z) - v.z;
        let sin_theta = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
        let cap = Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, z);
        let h = cap + v;
        let m = Vec3::new(self.alpha * h.x, self.alpha * h.y, h.z.max(0.0));
        let m_len = m.length();
        if m_len.is_nan() || m_len <= 1e-300 || !m_len.is_finite() {
            return None;
        }
        let m = m / m_len;
        (m.z > 0.0).then_some(m)
    }
}

/// `w` mirrored about microfacet normal `m`.
#[inline]
pub(crate) fn reflect(w: Vec3, m: Vec3) -> Vec3 {
    m * (2.0 * w.dot(m)) - w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use std::f64::consts::TAU;

    /// ∫ D(m) cos θm dω = 1 over the hemisphere: the projected microfacet area is the
    /// macrosurface's. Checked by quadrature in (cos θ, φ) (D is isotropic, so φ integrates to 2π).
    #[test]
    fn projected_microfacet_area_is_one() {
        for alpha in [0.05, 0.2, 0.6, 1.0] {
            let ggx = Ggx { alpha };
            let n = 400_000;
            let mut sum = 0.0;
            for i in 0..n {
                // Substitute cos θ = 1 − s² to resolve the peak near the normal.
                let s = (i as f64 + 0.5) / n as f64;
                let c = 1.0 - s * s;
                let m = Vec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c);
                sum += ggx.d(m) * c * 2.0 * s;
            }
            let integral = TAU * sum / n as f64;
            assert!((integral - 1.0).abs() < 1e-3, "alpha {alpha}: {integral}");
        }
    }

    #[test]
    fn visible_normals_face_the_viewer() {
        let mut rng = SplitMix64::new(3);
        let ggx = Ggx { alpha: 0.7 };
        let wo = Vec3::new(0.9, 0.1, 0.2).normalize();
        for _ in 0..1000 {
            let m = ggx
                .sample_visible(wo, [rng.next_offset(), rng.next_offset()])
                .expect("a normal");
            assert!((m.length() - 1.0).abs() < 1e-12);
            assert!(m.z > 0.0 && wo.dot(m) >= 0.0);
        }
    }
}
