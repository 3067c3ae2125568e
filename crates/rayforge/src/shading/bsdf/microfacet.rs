//! The GGX (Trowbridge–Reitz) microfacet distribution with Smith shadowing, for rough
//! conductors, rough dielectrics and rough plastic coats.
//!
//! Directions are in the local frame (normal +Z, first tangent +X) and the view direction `wo`
//! is in the upper hemisphere (callers mirror it there first). The widths are used as given
//! (not squared from a "roughness"): `alpha_x` along the frame's first tangent, `alpha_y` along
//! the second, as pbrt-v4's `TrowbridgeReitzDistribution` has them (its `uroughness` and
//! `vroughness`). Sampling draws from the distribution of *visible* normals, so that few
//! samples are wasted on microfacets facing away from the viewer.
//!
//! Where the two widths are equal every function computes exactly what the isotropic
//! formulas did before anisotropy was added (same operations, same rounding), so renders of
//! isotropic materials keep their bytes.

use crate::math::{sin_cos_turns, Vec3};
use std::f64::consts::PI;

/// A GGX distribution of microfacet normals with widths `alpha_x` (along the first tangent)
/// and `alpha_y` (along the second); isotropic where they are equal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ggx {
    pub alpha_x: f64,
    pub alpha_y: f64,
}

impl Ggx {
    /// The isotropic distribution of width `alpha`.
    pub fn isotropic(alpha: f64) -> Self {
        Self {
            alpha_x: alpha,
            alpha_y: alpha,
        }
    }

    /// The density of microfacet normals `m` per unit projected area:
    /// `D(m) = 1 / (π α_x α_y (m_x²/α_x² + m_y²/α_y² + m_z²)²)`, the same as
    /// `1 / (π α_x α_y cos⁴θ (1 + tan²θ (cos²φ/α_x² + sin²φ/α_y²))²)` without dividing by a
    /// vanishing cosine.
    pub fn d(&self, m: Vec3) -> f64 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (d, t) = if self.alpha_x == self.alpha_y {
            let a2 = self.alpha_x * self.alpha_x;
            (a2, (m.x * m.x + m.y * m.y) / a2 + m.z * m.z)
        } else {
            let (x, y) = (m.x / self.alpha_x, m.y / self.alpha_y);
            (self.alpha_x * self.alpha_y, x * x + y * y + m.z * m.z)
        };
        let d = 1.0 / (PI * d * t * t);
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }

    /// Smith's masking of microfacet `m` seen from `w`: `2 / (1 + √(1 + α² tan²θ))` with
    /// `α² = α_x² cos²φ + α_y² sin²φ` (the width in `w`'s azimuth), and 0 when `w` sees the
    /// back of the microfacet or lies on the other side of the surface.
    pub fn g1(&self, w: Vec3, m: Vec3) -> f64 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        let z2 = w.z * w.z;
        let a2_tan2 = if self.alpha_x == self.alpha_y {
            self.alpha_x * self.alpha_x * ((w.x * w.x + w.y * w.y) / z2)
        } else {
            let (x, y) = (self.alpha_x * w.x, self.alpha_y * w.y);
            (x * x + y * y) / z2
        };
        let g = 2.0 / (1.0 + (1.0 + a2_tan2).sqrt());
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
    /// uniformly on the cap of the unit sphere beyond the plane it defines. The stretch is
    /// by `α_x` and `α_y` along the two tangents, which is what makes it anisotropic.
    pub fn sample_visible(&self, wo: Vec3, u: [f64; 2]) -> Option<Vec3> {
        if wo.z <= 0.0 {
            return None;
        }
        let stretched = Vec3::new(self.alpha_x * wo.x, self.alpha_y * wo.y, wo.z);
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
        let m = Vec3::new(self.alpha_x * h.x, self.alpha_y * h.y, h.z.max(0.0));
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
            let ggx = Ggx::isotropic(alpha);
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
        let wo = Vec3::new(0.9, 0.1, 0.2).normalize();
        for ggx in [
            Ggx::isotropic(0.7),
            Ggx {
                alpha_x: 0.1,
                alpha_y: 0.8,
            },
        ] {
            for _ in 0..1000 {
                let m = ggx
                    .sample_visible(wo, [rng.next_offset(), rng.next_offset()])
                    .expect("a normal");
                assert!((m.length() - 1.0).abs() < 1e-12);
                assert!(m.z > 0.0 && wo.dot(m) >= 0.0);
            }
        }
    }

    /// The anisotropic distribution's projected area is one too, by quadrature over the
    /// whole hemisphere (it depends on φ), and it is wider along the tangent of the wider
    /// width: `D` falls off more slowly tilting towards +X than towards +Y when `α_x > α_y`.
    #[test]
    fn anisotropic_microfacets_cover_the_surface_once_and_stretch_along_their_wider_axis() {
        let ggx = Ggx {
            alpha_x: 0.4,
            alpha_y: 0.1,
        };
        let (n, m) = (2000, 400);
        let mut sum = 0.0;
        for i in 0..n {
            let s = (i as f64 + 0.5) / n as f64;
            let c = 1.0 - s * s;
            let sin = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..m {
                let phi = TAU * (j as f64 + 0.5) / m as f64;
                let w = Vec3::new(sin * phi.cos(), sin * phi.sin(), c);
                sum += ggx.d(w) * c * 2.0 * s;
            }
        }
        let integral = sum * TAU / (n * m) as f64;
        assert!((integral - 1.0).abs() < 2e-3, "{integral}");
        let tilt = |x: f64, y: f64| Vec3::new(x, y, 0.95).normalize();
        assert!(ggx.d(tilt(0.2, 0.0)) > 10.0 * ggx.d(tilt(0.0, 0.2)));
        // Isotropic widths give the isotropic formulas' bits.
        let iso = Ggx::isotropic(0.3);
        let w = Vec3::new(0.3, -0.4, 0.5).normalize();
        let a2 = 0.3 * 0.3;
        let t = (w.x * w.x + w.y * w.y) / a2 + w.z * w.z;
        assert_eq!(iso.d(w), 1.0 / (PI * a2 * t * t));
    }
}
