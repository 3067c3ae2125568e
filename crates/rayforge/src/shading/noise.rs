//! 3D gradient noise in the manner of Ken Perlin's "improved noise" (2002): a lattice of
//! pseudo-random gradients, blended with the quintic fade curve 6t⁵ − 15t⁴ + 10t³.
//!
//! The permutation is our own, generated at compile time from a fixed seed, so the noise is
//! deterministic across runs and platforms.

use crate::math::Point3;

/// A permutation of 0..=255 from a fixed seed (a Fisher–Yates shuffle driven by splitmix64).
const PERMUTATION: [u8; 256] = {
    let mut p = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        p[i] = i as u8;
        i += 1;
    }
    let mut state: u64 = 0x5241_5946_4f52_4745; // "RAYFORGE"
    let mut i = 255;
    while i > 0 {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let j = (z % (i as u64 + 1)) as usize;
        let tmp = p[i];
        p[i] = p[j];
        p[j] = tmp;
        i -= 1;
    }
    p
};

#[inline]
fn hash(i: i64) -> usize {
    PERMUTATION[(i & 255) as usize] as usize
}

#[inline]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The dot product of the offset with one of the 12 edge-midpoint gradients of a cube.
#[inline]
fn grad(hash: usize, x: f64, y: f64, z: f64) -> f64 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Noise at a point, roughly in [-1, 1], smooth, zero at lattice points.
pub fn perlin_noise(p: Point3) -> f64 {
    if !p.is_finite() {
        return 0.0;
    }
    let cell = p.floor();
    let (xi, yi, zi) = (cell.x as i64, cell.y as i64, cell.z as i64);
    let f = p - cell;
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let corner = |dx: i64, dy: i64, dz: i64| {
        let h = hash(xi + dx + hash(yi + dy + hash(zi + dz) as i64) as i64);
        grad(h, f.x - dx as f64, f.y - dy as f64, f.z - dz as f64)
    };
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    lerp(
        w,
        lerp(
            v,
            lerp(u, corner(0, 0, 0), corner(1, 0, 0)),
            lerp(u, corner(0, 1, 0), corner(1, 1, 0)),
        ),
        lerp(
            v,
            lerp(u, corner(0, 0, 1), corner(1, 0, 1)),
            lerp(u, corner(0, 1, 1), corner(1, 1, 1)),
        ),
    )
}
