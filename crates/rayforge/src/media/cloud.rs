//! pbrt-v4's procedural cloud (`CloudMedium`): a density made of Perlin noise, in a box of
//! the medium's own space placed in the world by a transform, with no grid to store. The
//! density at a point `p` of the medium's space is pbrt-v4's: the point is scaled by the
//! `frequency`, pushed along the noise's gradient twice (finer and weaker the second time) by
//! an amount in proportion to `wispiness`, which draws the noise out into wisps; five octaves
//! of noise are summed there; the sum fades with height (times `(1 − y)·4.5·density`,
//! clamped to 0–1), a base is added below `y = ½` (`2·max(0, ½ − y)`), and the whole is
//! clamped to 0–1. Outside the box the density is 0.
//!
//! Because the density never exceeds 1, σa + σs bounds the extinction everywhere in the box:
//! the majorant is that one value over the ray's stretch inside the box, as in pbrt-v4.

use super::phase::HenyeyGreenstein;
use super::MediumError;
use crate::color::Color;
use crate::math::perlin::{noise, noise_gradient};
use crate::math::{Aabb, Point3, Transform, Vec3};

/// A procedural cloud.
#[derive(Debug, Clone, PartialEq)]
pub struct CloudMedium {
    /// σa where the density is 1.
    pub sigma_a: Color,
    /// σs where the density is 1.
    pub sigma_s: Color,
    /// How it scatters.
    pub phase: HenyeyGreenstein,
    /// How dense the noise's peaks are (pbrt-v4's `density`: it multiplies the octave sum
    /// before the clamp, so large values make a solid cloud with sharp edges).
    pub density: f64,
    /// How far the noise's gradient pushes the lookup point (0: no wisps).
    pub wispiness: f64,
    /// How many noise features fit in a unit of the medium's space.
    pub frequency: f64,
    /// The cloud's box in the medium's space.
    pub bounds: Aabb,
    /// World from the medium's space.
    pub transform: Transform,
}

impl CloudMedium {
    /// A cloud; `density`, `wispiness` and `frequency` must be finite and at least 0, the
    /// coefficients too, and `bounds` of positive, finite extent.
    #[allow(clippy::too_many_arguments)] // pbrt-v4's parameters, one each
    pub fn new(
        sigma_a: Color,
        sigma_s: Color,
        phase: HenyeyGreenstein,
        density: f64,
        wispiness: f64,
        frequency: f64,
        bounds: Aabb,
        transform: Transform,
    ) -> Result<Self, MediumError> {
        let sigma_a = super::coefficient("sigma_a", sigma_a)?;
        let sigma_s = super::coefficient("sigma_s", sigma_s)?;
        for (name, value) in [
            ("density", density),
            ("wispiness", wispiness),
            ("frequency", frequency),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(MediumError::Parameter { name, value });
            }
        }
        let e = bounds.extent();
        if !(e.min_element() > 0.0 && e.is_finite() && bounds.min.is_finite()) {
            return Err(MediumError::Bounds);
        }
        Ok(Self {
            sigma_a,
            sigma_s,
            phase,
            density,
            wispiness,
            frequency,
            bounds,
            transform,
        })
    }

    /// The density at `p` in the medium's space: pbrt-v4's (see the module's documentation)
    /// inside the box, 0 outside; always within 0–1.
    pub fn density_at(&self, p: Point3) -> f64 {
        let inside = p.cmpge(self.bounds.min).all() && p.cmple(self.bounds.max).all();
        if !inside {
            return 0.0;
        }
        let mut pp = p * self.frequency;
        if self.wispiness > 0.0 {
            let (mut omega, mut lambda) = (0.05 * self.wispiness, 10.0);
            for _ in 0..2 {
                pp += noise_gradient(pp * lambda) * omega;
                omega *= 0.5;
                lambda *= 1.99;
            }
        }
        let (mut sum, mut omega, mut lambda) = (0.0, 0.5, 1.0);
        for _ in 0..5 {
            sum += omega * noise(pp * lambda);
            omega *= 0.5;
            lambda *= 1.99;
        }
        let d = ((1.0 - p.y) * 4.5 * self.density * sum).clamp(0.0, 1.0);
        (d + 2.0 * (0.5 - p.y).max(0.0)).clamp(0.0, 1.0)
    }

    /// σa and σs at the world point `p`.
    #[inline]
    pub fn coefficients_at(&self, p: Point3) -> (Color, Color) {
        let d = self.density_at(self.transform.inverse_point(p));
        (self.sigma_a * d, self.sigma_s * d)
    }

    /// The majorant: the extinction where the density is 1, its largest.
    #[inline]
    pub fn sigma_maj(&self) -> Color {
        self.sigma_a + self.sigma_s
    }

    /// Where the ray `origin + t·direction` (world space) is inside the box, within
    /// `[0, t_max]`; `t` stays the world's (the direction is carried into the medium's
    /// space unnormalised).
    pub fn span(&self, origin: Point3, direction: Vec3, t_max: f64) -> Option<(f64, f64)> {
        let o = self.transform.inverse_point(origin);
        let d = self.transform.inverse_vector(direction);
        let (mut near, mut far) = (0.0f64, t_max);
        for axis in 0..3 {
            let (lo, hi) = (self.bounds.min[axis], self.bounds.max[axis]);
            if d[axis] == 0.0 {
                if !(lo..=hi).contains(&o[axis]) {
                    return None;
                }
                continue;
            }
            let (a, b) = ((lo - o[axis]) / d[axis], (hi - o[axis]) / d[axis]);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        (near < far).then_some((near, far))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{point, vector};

    fn cloud(density: f64, wispiness: f64) -> CloudMedium {
        CloudMedium::new(
            Color::new(0.5, 0.5, 0.5),
            Color::new(1.0, 2.0, 3.0),
            HenyeyGreenstein::ISOTROPIC,
            density,
            wispiness,
            5.0,
            Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0)),
            Transform::IDENTITY,
        )
        .expect("cloud")
    }

    #[test]
    fn the_density_follows_pbrts_formula_at_known_points() {
        let c = cloud(1.0, 0.0);
        // The noise is 0 on its lattice, so every octave is 0 at the origin: the base
        // alone, 2·(½ − 0) = 1.
        assert_eq!(c.density_at(Point3::ZERO), 1.0);
        // At the bottom the base alone is 1 (the sum is then clamped): fully dense.
        assert_eq!(c.density_at(point(0.37, 0.0, 0.81)), 1.0);
        // At the top the height factor (1 − y) is 0 and there is no base.
        assert_eq!(c.density_at(point(0.3, 1.0, 0.6)), 0.0);
        // In between, the octave sum by hand: Σ ½ⁱ⁺¹ noise(1.99ⁱ · 5p).
        let p = point(0.33, 0.7, 0.41);
        let sum: f64 = (0..5)
            .map(|i| 0.5f64.powi(i + 1) * noise(p * 5.0 * 1.99f64.powi(i)))
            .sum();
        let expected = ((1.0 - 0.7) * 4.5 * sum).clamp(0.0, 1.0);
        assert!((c.density_at(p) - expected).abs() < 1e-12, "{expected}");
        // Wisps move the lookup point by the gradient: the first push by hand.
        let w = cloud(1.0, 1.0);
        let pp = p * 5.0 + noise_gradient(p * 50.0) * 0.05;
        let pp = pp + noise_gradient(pp * 19.9) * 0.025;
        let sum: f64 = (0..5)
            .map(|i| 0.5f64.powi(i + 1) * noise(pp * 1.99f64.powi(i)))
            .sum();
        let expected = ((1.0 - 0.7) * 4.5 * sum).clamp(0.0, 1.0);
        assert!((w.density_at(p) - expected).abs() < 1e-12, "{expected}");
    }

    #[test]
    fn the_density_lies_within_the_majorant_and_is_zero_outside_the_box() {
        let c = cloud(3.0, 1.0);
        let mut rng = SplitMix64::new(9);
        let (mut zero, mut one, mut between) = (0, 0, 0);
        for _ in 0..20_000 {
            let p = point(rng.next_offset(), rng.next_offset(), rng.next_offset());
            let d = c.density_at(p);
            assert!((0.0..=1.0).contains(&d), "{d} at {p}");
            let (a, s) = c.coefficients_at(p);
            assert!((a + s).max_channel() <= c.sigma_maj().max_channel() + 1e-12);
            match d {
                0.0 => zero += 1,
                1.0 => one += 1,
                _ => between += 1,
            }
            // Outside the box, along every axis.
            for axis in 0..3 {
                let mut q = p;
                q[axis] += if rng.next_offset() < 0.5 {
                    1.0 + 1e-9
                } else {
                    -1.0 - 1e-9
                };
                assert_eq!(c.density_at(q), 0.0, "{q}");
            }
        }
        // A cloud, not a block: empty, full and partial regions all occur.
        assert!(
            zero > 500 && one > 500 && between > 500,
            "{zero} {one} {between}"
        );
    }

    #[test]
    fn the_span_is_the_box_in_world_t() {
        let t = Transform::try_new(
            crate::math::translation(2.0, 0.0, 0.0) * crate::math::scaling(2.0, 2.0, 2.0),
        )
        .expect("invertible");
        let c = CloudMedium::new(
            Color::WHITE,
            Color::WHITE,
            HenyeyGreenstein::ISOTROPIC,
            1.0,
            1.0,
            5.0,
            Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0)),
            t,
        )
        .expect("cloud");
        // The world box is [2, 4] × [0, 2] × [0, 2].
        let (t0, t1) = c
            .span(point(0.0, 1.0, 1.0), vector(1.0, 0.0, 0.0), 10.0)
            .expect("crosses");
        assert!(
            (t0 - 2.0).abs() < 1e-12 && (t1 - 4.0).abs() < 1e-12,
            "{t0} {t1}"
        );
        assert_eq!(
            c.span(point(0.0, 3.0, 1.0), vector(1.0, 0.0, 0.0), 10.0),
            None
        );
        assert_eq!(
            c.span(point(0.0, 1.0, 1.0), vector(1.0, 0.0, 0.0), 1.5),
            None
        );
    }

    #[test]
    fn bad_parameters_are_refused() {
        let b = Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0));
        let make = |d: f64, w: f64, f: f64, b: Aabb| {
            CloudMedium::new(
                Color::WHITE,
                Color::WHITE,
                HenyeyGreenstein::ISOTROPIC,
                d,
                w,
                f,
                b,
                Transform::IDENTITY,
            )
        };
        assert!(make(-1.0, 1.0, 5.0, b).is_err());
        assert!(make(1.0, f64::NAN, 5.0, b).is_err());
        assert!(make(1.0, 1.0, f64::INFINITY, b).is_err());
        let flat = Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 0.0, 1.0));
        assert!(make(1.0, 1.0, 5.0, flat).is_err());
        assert!(make(1.0, 1.0, 5.0, b).is_ok());
    }
}
