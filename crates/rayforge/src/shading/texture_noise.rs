//! The noise textures of pbrt-v4 (`fbm`, `wrinkled`, `windy`, `marble`, `dots`), as
//! *Physically Based Rendering* (4th edition, section 10.6) defines them over Perlin's noise
//! ([`crate::math::perlin`], which the cloud medium reads too): its sums of octaves
//! (fractional Brownian motion and turbulence), and the marble's colour spline.
//!
//! pbrt-v4 picks the number of octaves from the ray's footprint so that noise finer than a
//! pixel is left out; the path tracer traces no footprints, so every octave is summed (what
//! pbrt-v4 does for a footprint of zero), and each pixel's samples average the finest ones.
//! This differs from rayforge's own pattern noise ([`super::perlin_noise`]), which has its
//! own permutation.

use crate::color::Color;
use crate::math::perlin::noise;
use crate::math::Point3;

/// The most octaves a noise texture may sum: each costs a noise evaluation at every hit.
pub const MAX_OCTAVES: u32 = 32;

/// pbrt-v4's `FBm` with every octave: `Σ ωⁱ noise(λⁱ p)`, `λ = 1.99`, `i < octaves`.
pub fn fbm(p: Point3, omega: f64, octaves: u32) -> f64 {
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..octaves.min(MAX_OCTAVES) {
        sum += o * noise(p * lambda);
        lambda *= 1.99;
        o *= omega;
    }
    sum
}

/// pbrt-v4's `Turbulence` with every octave: `Σ ωⁱ |noise(λⁱ p)|`, and the `0.2 ω^octaves`
/// it adds for the octave beyond (with a footprint of zero).
pub fn turbulence(p: Point3, omega: f64, octaves: u32) -> f64 {
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..octaves.min(MAX_OCTAVES) {
        sum += o * noise(p * lambda).abs();
        lambda *= 1.99;
        o *= omega;
    }
    sum + o * 0.2
}

/// pbrt-v4's `windy` texture at the texture-space point `p`: waves whose height is noise,
/// scaled by a slower noise standing for the wind's strength.
pub fn windy(p: Point3) -> f64 {
    let strength = fbm(p * 0.1, 0.5, 3);
    let height = fbm(p, 0.5, 6);
    strength.abs() * height
}

/// pbrt-v4's `marble` texture at the texture-space point `p` (already times its `scale`):
/// bands along y disturbed by `variation` × fBm, coloured by pbrt-v4's spline of greys.
pub fn marble(p: Point3, omega: f64, octaves: u32, variation: f64) -> Color {
    const COLORS: [[f64; 3]; 9] = [
        [0.58, 0.58, 0.6],
        [0.58, 0.58, 0.6],
        [0.58, 0.58, 0.6],
        [0.5, 0.5, 0.5],
        [0.6, 0.59, 0.58],
        [0.58, 0.58, 0.6],
        [0.58, 0.58, 0.6],
        [0.2, 0.2, 0.33],
        [0.58, 0.58, 0.6],
    ];
    let m = p.y + variation * fbm(p, omega, octaves);
    let t = 0.5 + 0.5 * m.sin();
    let segments = COLORS.len() - 3;
    let first = ((t * segments as f64).floor().max(0.0) as usize).min(segments - 1);
    let t = t * segments as f64 - first as f64;
    // The cubic Bézier of the four control colours from `first`, by de Casteljau.
    let c = |k: usize| Color::new(COLORS[k][0], COLORS[k][1], COLORS[k][2]);
    let (a, b, c2, d) = (c(first), c(first + 1), c(first + 2), c(first + 3));
    let (ab, bc, cd) = (a.lerp(b, t), b.lerp(c2, t), c2.lerp(d, t));
    let rgb = ab.lerp(bc, t).lerp(bc.lerp(cd, t), t) * 1.5;
    Color::new(
        rgb.red.clamp(0.0, 1.0),
        rgb.green.clamp(0.0, 1.0),
        rgb.blue.clamp(0.0, 1.0),
    )
}

/// pbrt-v4's polka dots: whether `(s, t)` lies in the dot of its cell (cells of side 1 around
/// whole numbers; a dot of radius 0.35, nudged by noise, in about half of them).
pub fn inside_polka_dot(s: f64, t: f64) -> bool {
    if !(s.is_finite() && t.is_finite()) {
        return false;
    }
    let (s_cell, t_cell) = ((s + 0.5).floor(), (t + 0.5).floor());
    let n = |x: f64, y: f64| noise(Point3::new(x, y, 0.5));
    if n(s_cell + 0.5, t_cell + 0.5) <= 0.0 {
        return false;
    }
    let radius = 0.35;
    let shift = 0.5 - radius;
    let sc = s_cell + shift * n(s_cell + 1.5, t_cell + 2.8);
    let tc = t_cell + shift * n(s_cell + 4.5, t_cell + 9.8);
    let (ds, dt) = (s - sc, t - tc);
    ds * ds + dt * dt < radius * radius
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    #[test]
    fn octave_sums_and_the_textures_built_on_them() {
        let p = Point3::new(0.3, 1.7, -2.2);
        // One octave is the noise itself; turbulence adds the 0.2 ω^octaves of the rest.
        assert_eq!(fbm(p, 0.5, 1), noise(p));
        let expected = noise(p).abs() + 0.5 * noise(p * 1.99).abs() + 0.25 * 0.2;
        assert!((turbulence(p, 0.5, 2) - expected).abs() < 1e-15);
        assert_eq!(windy(p), fbm(p * 0.1, 0.5, 3).abs() * fbm(p, 0.5, 6));
        // Marble stays within its spline's greys (times 1.5, at most 1).
        let mut rng = SplitMix64::new(4);
        for _ in 0..1000 {
            let q = Point3::new(rng.next_offset(), rng.next_offset(), rng.next_offset()) * 10.0;
            let c = marble(q, 0.5, 8, 0.2);
            assert!(c.red >= 0.2 * 1.5 - 1e-9 && c.red <= 0.9 + 1e-9, "{c:?}");
        }
        // Polka dots cover some of the plane, never all: a dot's area is π 0.35² of its cell.
        let mut inside = 0;
        let n = 40_000;
        for _ in 0..n {
            if inside_polka_dot(rng.next_offset() * 40.0, rng.next_offset() * 40.0) {
                inside += 1;
            }
        }
        let share = inside as f64 / n as f64;
        assert!(share > 0.1 && share < 0.385, "{share}");
    }
}
