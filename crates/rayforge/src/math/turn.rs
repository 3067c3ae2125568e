//! The sine and cosine of an angle given in turns (`2π · u`), as sampling needs them: every
//! azimuth a sampler draws (diffuse bounces, visible microfacet normals, points on discs and
//! cylinders) is a uniform number times a full turn.
//!
//! Written by hand because the angle comes as a fraction of a turn: reducing it to an eighth of
//! a turn is exact (a subtraction of a multiple of ¼), so two polynomials on
//! `[-π/4, π/4]` give both results to within a few units in the last place. libm's `sincos`
//! must first reduce an arbitrary radian angle by an inexact 2π, and it was a twentieth of a
//! path traced Cornell box.
//!
//! The way back, a direction's angle in turns ([`atan2_turns`]), is what an environment map
//! reads its texels by (a column by the azimuth, a row by the angle from the pole): libm's
//! `atan2` took an eighth of an environment-lit render, twice for every path that reached the
//! sky. Here the ratio of the smaller coordinate to the larger is taken to within 7.5° of a
//! multiple of 15° by the tangent's addition formula, where ten terms of the arctangent's
//! series are exact to rounding.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// `(sin 2πu, cos 2πu)`, within 4·10⁻¹⁶ of libm's answer for any finite `u` (NaN for a
/// non-finite one).
#[inline]
pub fn sin_cos_turns(u: f64) -> (f64, f64) {
    // Adding and taking away 1.5·2⁵² rounds to the nearest integer with two additions (Rust's
    // `round` is a library call on the baseline x86-64 target); far from zero, where that
    // would fail, the library does it.
    const ROUNDER: f64 = 6_755_399_441_055_744.0;
    if u.abs() >= (1u64 << 48) as f64 {
        return (TAU * (u - u.round())).sin_cos();
    }
    // The nearest quarter turn, and the rest: `r` lies in [-1/8, 1/8], exactly.
    let quarter = (4.0 * u + ROUNDER) - ROUNDER;
    let r = u - 0.25 * quarter;
    let theta = TAU * r;
    // Taylor series to θ¹⁵ and θ¹⁶ (on |θ| ≤ π/4 the first term left out is below 5·10⁻¹⁷),
    // in powers of z = θ², evaluated by Estrin's scheme: pairs of terms side by side rather
    // than one long chain of dependent multiply-adds.
    let z = theta * theta;
    let (z2, z4) = (z * z, z * z * (z * z));
    let pair = |a: f64, b: f64| a + b * z;
    let sin = theta
        * (pair(1.0, -1.0 / 6.0)
            + z2 * pair(1.0 / 120.0, -1.0 / 5040.0)
            + z4 * (pair(1.0 / 362_880.0, -1.0 / 39_916_800.0)
                + z2 * pair(1.0 / 6_227_020_800.0, -1.0 / 1_307_674_368_000.0)));
    let cos = pair(1.0, -0.5)
        + z2 * pair(1.0 / 24.0, -1.0 / 720.0)
        + z4 * (pair(1.0 / 40_320.0, -1.0 / 3_628_800.0)
            + z2 * pair(1.0 / 479_001_600.0, -1.0 / 87_178_291_200.0)
            + z4 * (1.0 / 20_922_789_888_000.0));
    // Turned on by `quarter` quarter turns.
    match quarter as i64 & 3 {
        0 => (sin, cos),
        1 => (cos, -sin),
        2 => (-sin, -cos),
        _ => (-cos, sin),
    }
}

/// The angle of the point `(x, y)` from the +x axis, in turns: `atan2(y, x) / 2π`, in
/// `[-½, ½]`, within four units in the last place of libm's for finite coordinates; 0 at the
/// origin, NaN where either coordinate is.
#[inline]
pub fn atan2_turns(y: f64, x: f64) -> f64 {
    // tan(15° k) and 15° k, k = 0..3, and the bounds between them, tan(7.5° + 15° k).
    const TANGENTS: [f64; 4] = [0.0, 0.267_949_192_431_122_7, 0.577_350_269_189_625_7, 1.0];
    const BOUNDS: [f64; 3] = [
        0.131_652_497_587_395_83,
        0.414_213_562_373_095_03,
        0.767_326_987_978_960_4,
    ];
    let (ax, ay) = (x.abs(), y.abs());
    let (small, large) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if large == 0.0 {
        return 0.0;
    }
    // a in [0, 1]; atan a = 15° k + atan z, with |z| ≤ tan 7.5°.
    let a = small / large;
    let k = usize::from(a > BOUNDS[0]) + usize::from(a > BOUNDS[1]) + usize::from(a > BOUNDS[2]);
    let t = TANGENTS[k];
    let z = (a - t) / (1.0 + a * t);
    // atan z = z (1 − z²/3 + z⁴/5 − …): with z² ≤ 0.0174 the term in z²¹ is below 10⁻¹⁶ z.
    let w = z * z;
    let series = 1.0
        + w * (-1.0 / 3.0
            + w * (1.0 / 5.0
                + w * (-1.0 / 7.0
                    + w * (1.0 / 9.0
                        + w * (-1.0 / 11.0
                            + w * (1.0 / 13.0
                                + w * (-1.0 / 15.0 + w * (1.0 / 17.0 + w * (-1.0 / 19.0)))))))));
    let mut angle = k as f64 * (PI / 12.0) + z * series;
    if ay > ax {
        angle = FRAC_PI_2 - angle;
    }
    if x < 0.0 {
        angle = PI - angle;
    }
    if y < 0.0 {
        angle = -angle;
    }
    angle * (1.0 / TAU)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    #[test]
    fn the_angle_in_turns_agrees_with_the_library_everywhere() {
        let mut rng = SplitMix64::new(3);
        let mut unit = move || rng.next_offset();
        let mut worst: f64 = 0.0;
        for i in 0..400_000 {
            // Points all round the circle, near the axes and the diagonals, far and near.
            let (x, y) = match i % 4 {
                0 => (unit() * 2.0 - 1.0, unit() * 2.0 - 1.0),
                1 => (unit() * 2.0 - 1.0, (unit() - 0.5) * 1e-9),
                2 => {
                    let d = unit() * 2.0 - 1.0;
                    (d, d * (1.0 + (unit() - 0.5) * 1e-6))
                }
                _ => ((unit() - 0.5) * 1e30, (unit() - 0.5) * 1e-20),
            };
            let ours = atan2_turns(y, x);
            let theirs = y.atan2(x) / TAU;
            worst = worst.max((ours - theirs).abs() / (theirs.abs() * f64::EPSILON));
        }
        assert!(
            worst <= 4.0,
            "worst difference {worst} units in the last place"
        );
        // The axes and the origin exactly.
        assert_eq!(atan2_turns(0.0, 1.0), 0.0);
        assert_eq!(atan2_turns(1.0, 0.0), 0.25);
        assert_eq!(atan2_turns(0.0, -1.0), 0.5);
        assert_eq!(atan2_turns(-1.0, 0.0), -0.25);
        assert_eq!(atan2_turns(0.0, 0.0), 0.0);
        assert!(atan2_turns(f64::NAN, 1.0).is_nan() && atan2_turns(1.0, f64::NAN).is_nan());
        // Turned back by the sine and cosine, an angle gives its point.
        for i in 0..1000 {
            let u = i as f64 / 1000.0 - 0.5;
            let (s, c) = sin_cos_turns(u);
            let back = atan2_turns(s, c);
            let d = (back - u).abs();
            let diff = d.min((d - 1.0).abs());
            assert!(diff < 3e-16, "{u} {back}");
        }
    }

    #[test]
    fn agrees_with_the_library_sine_and_cosine_over_the_unit_interval_and_beyond() {
        let mut worst: f64 = 0.0;
        for i in 0..=200_000 {
            let u = i as f64 / 100_000.0 - 0.5;
            let (s, c) = sin_cos_turns(u);
            // Whole turns off first (exactly), so that the rounding of `TAU * u` is at most
            // π·2⁻⁵³, and the library's answer within about 4·10⁻¹⁶ of the exact value.
            let (ls, lc) = (TAU * (u - u.round())).sin_cos();
            worst = worst.max((s - ls).abs()).max((c - lc).abs());
        }
        assert!(worst < 6e-16, "worst difference {worst:e}");
        // The quarter turns are exact, and a turn further lands on the same values.
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, -0.0));
        assert_eq!(sin_cos_turns(0.5), (-0.0, -1.0));
        assert_eq!(sin_cos_turns(0.75), (-1.0, 0.0));
        assert_eq!(sin_cos_turns(0.375), sin_cos_turns(-2.625));
        assert!(sin_cos_turns(f64::NAN).0.is_nan());
        // Far from zero the library takes over; 2⁴⁹ + ⅛ turns is an eighth of a turn.
        let far = sin_cos_turns((1u64 << 49) as f64 + 0.125);
        assert!((far.0 - 0.5f64.sqrt()).abs() < 1e-15 && (far.1 - 0.5f64.sqrt()).abs() < 1e-15);
        assert_eq!(sin_cos_turns(-0.25), (-1.0, 0.0));
    }

    #[test]
    fn a_point_on_the_unit_circle_stays_on_it() {
        for i in 0..10_000 {
            let (s, c) = sin_cos_turns(i as f64 / 10_000.0);
            assert!((s * s + c * c - 1.0).abs() < 5e-16);
        }
    }
}
