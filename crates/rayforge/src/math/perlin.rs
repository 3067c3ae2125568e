//! Perlin's gradient noise as *Physically Based Rendering* (4th edition, section 10.6)
//! defines it: on the integer lattice, with the permutation of Perlin's reference
//! implementation, so that what is built on it looks as it does in pbrt-v4. It lives with the
//! mathematics, below the layers that use it: pbrt-v4's noise textures (`shading`) and its
//! procedural cloud medium (`media`) read the same function.

use super::Point3;

/// Perlin's permutation of 0–255 (the reference implementation's, which pbrt-v4 uses).
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// The permutation, read at any index (the table repeats every 256).
#[inline]
fn perm(i: usize) -> usize {
    usize::from(PERM[i & 255])
}

/// The gradient of lattice point `(x, y, z)` (each in 0–256) dotted with the offset `d`.
#[inline]
fn grad(x: usize, y: usize, z: usize, d: [f64; 3]) -> f64 {
    let h = perm(perm(perm(x) + y) + z) & 15;
    let u = if h < 8 || h == 12 || h == 13 {
        d[0]
    } else {
        d[1]
    };
    let v = if h < 4 || h == 12 || h == 13 {
        d[1]
    } else {
        d[2]
    };
    (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
}

/// The quintic fade `6t⁵ − 15t⁴ + 10t³`.
#[inline]
fn weight(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(t: f64, a: f64, b: f64) -> f64 {
    (1.0 - t) * a + t * b
}

/// pbrt-v4's `Noise(p)`: smooth, zero at the lattice points, within about [−1, 1]; 0 for a
/// point that is not finite.
pub fn noise(p: Point3) -> f64 {
    if !p.is_finite() {
        return 0.0;
    }
    // As pbrt-v4 does, far coordinates are folded so the cell's index fits.
    let fold = |x: f64| x % f64::from(1u32 << 30);
    let (x, y, z) = (fold(p.x), fold(p.y), fold(p.z));
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let (dx, dy, dz) = (x - fx, y - fy, z - fz);
    let cell = |f: f64| (f as i64 & 255) as usize;
    let (ix, iy, iz) = (cell(fx), cell(fy), cell(fz));
    let w = |a: usize, b: usize, c: usize| {
        grad(
            ix + a,
            iy + b,
            iz + c,
            [dx - a as f64, dy - b as f64, dz - c as f64],
        )
    };
    let (wx, wy, wz) = (weight(dx), weight(dy), weight(dz));
    let x00 = lerp(wx, w(0, 0, 0), w(1, 0, 0));
    let x10 = lerp(wx, w(0, 1, 0), w(1, 1, 0));
    let x01 = lerp(wx, w(0, 0, 1), w(1, 0, 1));
    let x11 = lerp(wx, w(0, 1, 1), w(1, 1, 1));
    lerp(wz, lerp(wy, x00, x10), lerp(wy, x01, x11))
}

/// pbrt-v4's `DNoise(p)`: the gradient of [`noise`] by forward differences of 0.01 along
/// each axis (pbrt-v4 takes that step, not the analytic derivative; the cloud medium's
/// wisps are shaped by it, so it is kept).
pub fn noise_gradient(p: Point3) -> Point3 {
    const DELTA: f64 = 0.01;
    let n = noise(p);
    Point3::new(
        noise(p + Point3::X * DELTA) - n,
        noise(p + Point3::Y * DELTA) - n,
        noise(p + Point3::Z * DELTA) - n,
    ) / DELTA
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    #[test]
    fn noise_is_zero_on_the_lattice_smooth_and_bounded() {
        for p in [
            Point3::ZERO,
            Point3::new(3.0, -7.0, 12.0),
            Point3::new(-256.0, 511.0, 1e6),
        ] {
            assert_eq!(noise(p), 0.0, "{p}");
        }
        let mut rng = SplitMix64::new(1);
        let (mut sum, mut sum_sq, n) = (0.0, 0.0, 20_000);
        for _ in 0..n {
            let p = Point3::new(rng.next_offset(), rng.next_offset(), rng.next_offset()) * 50.0
                - Point3::splat(25.0);
            let v = noise(p);
            assert!(v.abs() <= 1.5, "{v} at {p}");
            // Continuous: a small step moves it little (the gradient is bounded).
            let step = noise(p + Point3::splat(1e-6));
            assert!((step - v).abs() < 1e-4, "{v} {step}");
            sum += v;
            sum_sq += v * v;
        }
        let mean = sum / n as f64;
        let rms = (sum_sq / n as f64).sqrt();
        // Centred on zero and not flat.
        assert!(mean.abs() < 0.02, "{mean}");
        assert!(rms > 0.1, "{rms}");
        assert_eq!(noise(Point3::new(f64::NAN, 0.0, 0.0)), 0.0);
    }

    #[test]
    fn a_known_value_of_perlins_noise() {
        // At (0.5, 0.5, 0.5) every corner's offset is (±½, ±½, ±½) and the fades are ½: the
        // mean of the eight corners' gradient dots, each ±½ ± ½ by the table's hashes.
        let expected: f64 = (0..8)
            .map(|k| {
                let (a, b, c) = (k & 1, (k >> 1) & 1, (k >> 2) & 1);
                let d = [0.5 - a as f64, 0.5 - b as f64, 0.5 - c as f64];
                grad(a, b, c, d) / 8.0
            })
            .sum();
        assert!((noise(Point3::splat(0.5)) - expected).abs() < 1e-15);
        // The table is Perlin's, a permutation: perm(0) = 151, perm(151) = 17, perm(17) = 36.
        assert_eq!(perm(perm(perm(0))), 36);
        let mut seen = [false; 256];
        for &v in &PERM {
            seen[usize::from(v)] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn the_gradient_is_the_forward_difference_of_the_noise() {
        let p = Point3::new(0.3, 1.7, -2.2);
        let g = noise_gradient(p);
        assert_eq!(
            g.y,
            (noise(p + Point3::new(0.0, 0.01, 0.0)) - noise(p)) / 0.01
        );
        // Close to the derivative: a central difference of a small step agrees.
        let h = 1e-6;
        let dx =
            (noise(p + Point3::new(h, 0.0, 0.0)) - noise(p - Point3::new(h, 0.0, 0.0))) / (2.0 * h);
        assert!((g.x - dx).abs() < 0.2, "{} {dx}", g.x);
        assert_eq!(
            noise_gradient(Point3::new(f64::NAN, 0.0, 0.0)),
            Point3::ZERO
        );
    }
}
