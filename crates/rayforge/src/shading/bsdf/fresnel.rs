//! The Fresnel equations: how much light a smooth boundary reflects, for dielectrics (real
//! index) and conductors (complex index `η + iκ`), unpolarised (the mean of the s and p
//! reflectances), plus the hemispherical average a coated material needs.
//!
//! Written out rather than approximated (no Schlick): the renders are compared with a reference
//! renderer that uses the exact equations, and metals' colour at grazing angles depends on them.

use crate::color::Color;

/// What a dielectric boundary does to one direction: its reflectance and, unless the light is
/// totally internally reflected, the refracted direction's cosine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DielectricFresnel {
    /// The unpolarised reflectance `F` in `[0, 1]` (1 under total internal reflection).
    pub reflectance: f64,
    /// The cosine of the refracted direction, signed opposite to the incident cosine (it lies
    /// on the other side); 0 under total internal reflection.
    pub cos_t: f64,
    /// The index of the transmitted side over the index of the incident side.
    pub eta_ti: f64,
}

/// Fresnel reflectance of a dielectric boundary for a direction with signed cosine `cos_i`
/// against the normal, where `eta` is the index below the surface (−Z side) over the index
/// above it. `cos_i < 0` means the light arrives from below, so the ratio is inverted.
pub fn dielectric(cos_i: f64, eta: f64) -> DielectricFresnel {
    let (cos_i_abs, eta_ti) = if cos_i >= 0.0 {
        (cos_i.min(1.0), eta)
    } else {
        ((-cos_i).min(1.0), 1.0 / eta)
    };
    if eta_ti.is_nan() || eta_ti <= 0.0 || !eta_ti.is_finite() {
        return DielectricFresnel {
            reflectance: 1.0,
            cos_t: 0.0,
            eta_ti: 1.0,
        };
    }
    let sin2_t = (1.0 - cos_i_abs * cos_i_abs).max(0.0) / (eta_ti * eta_ti);
    if sin2_t >= 1.0 {
        return DielectricFresnel {
            reflectance: 1.0,
            cos_t: 0.0,
            eta_ti,
        };
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs_den = cos_i_abs + eta_ti * cos_t;
    let rp_den = eta_ti * cos_i_abs + cos_t;
    let reflectance = if rs_den > 0.0 && rp_den > 0.0 {
        let rs = (cos_i_abs - eta_ti * cos_t) / rs_den;
        let rp = (eta_ti * cos_i_abs - cos_t) / rp_den;
        (0.5 * (rs * rs + rp * rp)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    DielectricFresnel {
        reflectance,
        cos_t: if cos_i >= 0.0 { -cos_t } else { cos_t },
        eta_ti,
    }
}

/// Unpolarised reflectance of a conductor of complex index `eta + i k` (relative to the outside
/// medium) for a direction at `cos_i` (its absolute value is used) from the normal.
///
/// With `a² + b² = √((η² − κ² − sin²θ)² + 4η²κ²)` and `a = √((a² + b² + η² − κ² − sin²θ)/2)`:
/// `Rs = (a² + b² − 2a cosθ + cos²θ) / (a² + b² + 2a cosθ + cos²θ)` and
/// `Rp = Rs (a² + b² cos²θ − 2a cosθ sin²θ + sin⁴θ) / (a² + b² cos²θ + 2a cosθ sin²θ + sin⁴θ)`;
/// the result is their mean. With κ = 0 it is the dielectric reflectance.
pub fn conductor_channel(cos_i: f64, eta: f64, k: f64) -> f64 {
    let c = cos_i.abs().min(1.0);
    let c2 = c * c;
    let s2 = (1.0 - c2).max(0.0);
    let e2 = eta * eta;
    let k2 = k * k;
    let t0 = e2 - k2 - s2;
    let a2b2 = (t0 * t0 + 4.0 * e2 * k2).sqrt();
    let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
    let rs_num = a2b2 - 2.0 * a * c + c2;
    let rs_den = a2b2 + 2.0 * a * c + c2;
    if rs_den.is_nan() || rs_den <= 0.0 {
        return 1.0;
    }
    let rs = rs_num / rs_den;
    let rp_num = a2b2 * c2 - 2.0 * a * c * s2 + s2 * s2;
    let rp_den = a2b2 * c2 + 2.0 * a * c * s2 + s2 * s2;
    let rp = if rp_den > 0.0 {
        rs * rp_num / rp_den
    } else {
        rs
    };
    let r = 0.5 * (rs + rp);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// [`conductor_channel`] for each colour channel.
pub fn conductor(cos_i: f64, eta: Color, k: Color) -> Color {
    Color::new(
        conductor_channel(cos_i, eta.red, k.red),
        conductor_channel(cos_i, eta.green, k.green),
        conductor_channel(cos_i, eta.blue, k.blue),
    )
}

/// The reflectance of a conductor at normal incidence, `((η − 1)² + κ²) / ((η + 1)² + κ²)` per
/// channel: the colour a metal shows head-on.
pub fn conductor_normal(eta: Color, k: Color) -> Color {
    let f = |n: f64, k: f64| {
        let den = (n + 1.0) * (n + 1.0) + k * k;
        if den > 0.0 {
            (((n - 1.0) * (n - 1.0) + k * k) / den).clamp(0.0, 1.0)
        } else {
            1.0
        }
    };
    Color::new(
        f(eta.red, k.red),
        f(eta.green, k.green),
        f(eta.blue, k.blue),
    )
}

/// The cosine-weighted hemispherical average `2 ∫₀¹ F(μ) μ dμ` of the dielectric reflectance
/// seen from the side above a boundary of relative index `eta` (below over above): the fraction
/// of uniformly diffuse light that the boundary reflects back.
///
/// For `η > 1` the closed form of the integral (as derived e.g. by Stern 1964) is used; for
/// `η < 1` (light inside the denser medium) energy conservation between the two sides gives
/// `1 − F̄(η) = η² (1 − F̄(1/η))`, since the flux that escapes equals the flux that enters.
pub fn diffuse_reflectance(eta: f64) -> f64 {
    if eta.is_nan() || eta <= 0.0 || !eta.is_finite() {
        return 1.0;
    }
    if (eta - 1.0).abs() < 1e-9 {
        return 0.0;
    }
    if eta < 1.0 {
        let outside = diffuse_reflectance_external(1.0 / eta);
        return (1.0 - eta * eta * (1.0 - outside)).clamp(0.0, 1.0);
    }
    diffuse_reflectance_external(eta)
}

/// The closed form for `η > 1`.
fn diffuse_reflectance_external(n: f64) -> f64 {
    let n2 = n * n;
    let n3 = n2 * n;
    let n4 = n2 * n2;
    let r = 0.5
        + (n - 1.0) * (3.0 * n + 1.0) / (6.0 * (n + 1.0) * (n + 1.0))
        + n2 * (n2 - 1.0).powi(2) / (n2 + 1.0).powi(3) * ((n - 1.0) / (n + 1.0)).ln()
        - 2.0 * n3 * (n2 + 2.0 * n - 1.0) / ((n2 + 1.0) * (n4 - 1.0))
        + 8.0 * n4 * (n4 + 1.0) / ((n2 + 1.0) * (n4 - 1.0).powi(2)) * n.ln();
    r.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_reflectance_at_normal_incidence_is_the_squared_ratio() {
        for eta in [1.1_f64, 1.33, 1.5, 2.4, 1.0 / 1.5] {
            let expected = ((eta - 1.0) / (eta + 1.0)).powi(2);
            let f = dielectric(1.0, eta);
            assert!((f.reflectance - expected).abs() < 1e-14, "{eta}");
            assert!((f.cos_t + 1.0).abs() < 1e-14);
            // From below the same boundary reflects as much.
            let g = dielectric(-1.0, eta);
            assert!((g.reflectance - expected).abs() < 1e-14);
        }
    }

    #[test]
    fn light_inside_beyond_the_critical_angle_is_totally_reflected() {
        let eta: f64 = 1.5;
        let critical = (1.0 / eta).asin();
        let below = dielectric(-(critical - 1e-3).cos(), eta);
        assert!(below.reflectance < 1.0 && below.cos_t > 0.0);
        let beyond = dielectric(-(critical + 1e-3).cos(), eta);
        assert_eq!(beyond.reflectance, 1.0);
        assert_eq!(beyond.cos_t, 0.0);
        // Grazing from outside reflects everything too, without NaN.
        assert!((dielectric(0.0, eta).reflectance - 1.0).abs() < 1e-12);
    }

    #[test]
    fn snell_s_law_holds_for_the_refracted_cosine() {
        let eta = 1.5;
        let cos_i: f64 = 0.6;
        let f = dielectric(cos_i, eta);
        let sin_i = (1.0 - cos_i * cos_i).sqrt();
        let sin_t = (1.0 - f.cos_t * f.cos_t).sqrt();
        assert!((sin_i - eta * sin_t).abs() < 1e-14);
    }

    #[test]
    fn a_conductor_without_absorption_reflects_as_a_dielectric() {
        for eta in [1.2, 1.5, 2.0, 3.5] {
            for i in 0..=20 {
                let cos = i as f64 / 20.0;
                let d = dielectric(cos, eta).reflectance;
                let c = conductor_channel(cos, eta, 0.0);
                let c_small = conductor_channel(cos, eta, 1e-7);
                assert!((d - c).abs() < 1e-9, "eta {eta} cos {cos}: {d} vs {c}");
                assert!((d - c_small).abs() < 1e-6, "eta {eta} cos {cos}");
            }
        }
    }

    #[test]
    fn conductor_reflectance_at_normal_incidence_has_its_closed_form() {
        let eta = Color::new(1.6575, 0.880405, 0.521244);
        let k = Color::new(9.22381, 6.2695, 4.837);
        let head_on = conductor(1.0, eta, k);
        let closed = conductor_normal(eta, k);
        assert!((head_on - closed).max_channel().abs() < 1e-12);
        assert!((closed.red - 0.928_045).abs() < 1e-5, "{closed:?}");
        // Grazing reflects everything.
        assert!((conductor(0.0, eta, k) - Color::WHITE).max_channel().abs() < 1e-12);
    }

    #[test]
    fn diffuse_reflectance_matches_a_quadrature_of_the_fresnel_term() {
        for eta in [1.05, 1.33, 1.5, 2.0, 1.0 / 1.5, 1.0 / 1.33] {
            let n = 200_000;
            let mut sum = 0.0;
            for i in 0..n {
                let mu = (i as f64 + 0.5) / n as f64;
                sum += 2.0 * mu * dielectric(mu, eta).reflectance;
            }
            let quad = sum / n as f64;
            let closed = diffuse_reflectance(eta);
            assert!(
                (quad - closed).abs() < 2e-5,
                "eta {eta}: {quad} vs {closed}"
            );
        }
    }
}
