//! The path tracer's random numbers: one stream per (pixel, sample), drawn dimension by
//! dimension, a pure function of the pixel, the sample's index and the render's seed. So the
//! image never depends on the thread count or the order pixels are rendered in, and any range
//! of a pixel's samples can be rendered apart from the others and merged later.
//!
//! Two kinds ([`SamplerKind`]):
//! - independent: each number hashed from (seed, pixel, sample, dimension), the plain Monte
//!   Carlo baseline;
//! - Sobol: Owen-scrambled Sobol points from the `sobol_burley` crate (Burley, "Practical
//!   Hash-based Owen Scrambling", 2020), padded: each group of four dimensions takes the
//!   sequence's first four dimensions under its own scramble, seeded from the pixel and the
//!   group, so every pixel and every path vertex is stratified within itself and decorrelated
//!   from the others. The crate's sequences hold 2¹⁶ points; later samples continue under
//!   another scramble. Past the first [`SOBOL_DIMENSIONS`] (the camera and the first three
//!   bounces) the numbers are hashed like the independent sampler's: so deep in a path the
//!   light has been scattered so much that stratifying its choices no longer lowers the
//!   error, and a Sobol point costs several times a hash.

use crate::math::random::SplitMix64;
use crate::options::SamplerKind;

/// The numbers of one sample of one pixel (see the [module](self)).
#[derive(Debug, Clone, Copy)]
pub struct SampleStream {
    kind: SamplerKind,
    /// A hash of the render's seed and the pixel.
    pixel: u64,
    /// The sample's index within the pixel.
    index: u64,
    /// A hash of `pixel` and `index`, which hashed numbers start from.
    sample: u64,
    /// The next dimension to draw.
    dimension: u32,
    /// The Sobol sampler's four numbers of the group of dimensions `group` (a Sobol point's
    /// four dimensions cost one call, computed side by side).
    cached: [f32; 4],
    /// Which group `cached` holds (`u32::MAX`: none yet).
    group: u32,
}

/// Dimensions drawn from Sobol points by the Sobol sampler; later ones are hashed.
pub const SOBOL_DIMENSIONS: u32 = 32;

/// Mixes `a` and `b` into 64 well-spread bits (SplitMix64's finaliser on their combination).
#[inline]
fn mix(a: u64, b: u64) -> u64 {
    SplitMix64::new(a ^ b.wrapping_mul(0x9E37_79B9_7F4A_7C15)).next_u64()
}

impl SampleStream {
    /// The stream of sample `index` of pixel (`x`, `y`) in a render seeded with `seed`.
    #[inline]
    pub fn new(kind: SamplerKind, seed: u64, x: u32, y: u32, index: u64) -> Self {
        let pixel = mix(
            mix(seed, u64::from(x)),
            u64::from(y) ^ 0x5DEE_CE66_D1CE_4E5B,
        );
        Self {
            kind,
            pixel,
            index,
            sample: mix(pixel, index),
            dimension: 0,
            cached: [0.0; 4],
            group: u32::MAX,
        }
    }

    /// The next number, in `[0, 1)`.
    #[inline]
    pub fn next_1d(&mut self) -> f64 {
        let d = self.dimension;
        self.dimension = self.dimension.wrapping_add(1);
        if self.kind == SamplerKind::Independent || d >= SOBOL_DIMENSIONS {
            let bits = mix(self.sample, u64::from(d));
            return (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
        }
        let group = d / 4;
        if group != self.group {
            // Each group of four dimensions, and each block of 2¹⁶ samples, has a scramble of
            // its own.
            let block = self.index >> 16;
            let scramble = mix(mix(self.pixel, u64::from(group)), block);
            self.cached = sobol_burley::sample_4d(
                (self.index & 0xFFFF) as u32,
                0,
                (scramble ^ (scramble >> 32)) as u32,
            );
            self.group = group;
        }
        f64::from(self.cached[(d % 4) as usize])
    }

    /// Goes on from dimension `dimension` (each path vertex starts its numbers at a fixed one).
    #[inline]
    pub fn seek(&mut self, dimension: u32) {
        self.dimension = dimension;
    }

    /// The next two numbers, from one pair of dimensions (so a Sobol pair is stratified in 2D).
    #[inline]
    pub fn next_2d(&mut self) -> [f64; 2] {
        if self.dimension % 2 == 1 {
            self.dimension += 1;
        }
        [self.next_1d(), self.next_1d()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_lie_in_the_unit_interval_and_depend_only_on_pixel_sample_and_seed() {
        for kind in [SamplerKind::Independent, SamplerKind::Sobol] {
            let mut a = SampleStream::new(kind, 7, 3, 4, 70_000);
            let mut b = SampleStream::new(kind, 7, 3, 4, 70_000);
            let mut c = SampleStream::new(kind, 8, 3, 4, 70_000);
            let mut differs = false;
            for _ in 0..300 {
                let (x, y, z) = (a.next_1d(), b.next_1d(), c.next_1d());
                assert!((0.0..1.0).contains(&x));
                assert_eq!(x, y);
                differs |= x != z;
            }
            assert!(differs, "another seed gives other numbers");
        }
    }

    /// Counts of `n` samples' first pair in a `k × k` grid.
    fn grid_counts(kind: SamplerKind, n: u64, k: usize) -> Vec<u64> {
        let mut counts = vec![0; k * k];
        for i in 0..n {
            let [u, v] = SampleStream::new(kind, 1, 10, 20, i).next_2d();
            counts[(v * k as f64) as usize * k + (u * k as f64) as usize] += 1;
        }
        counts
    }

    #[test]
    fn sobol_points_are_stratified_in_every_elementary_square() {
        // 256 points of a (0, 2)-sequence in base 2 put exactly one point in each cell of a
        // 16 × 16 grid; independent points almost never do.
        assert!(grid_counts(SamplerKind::Sobol, 256, 16)
            .iter()
            .all(|&c| c == 1));
        assert!(grid_counts(SamplerKind::Independent, 256, 16)
            .iter()
            .any(|&c| c != 1));
    }

    #[test]
    fn independent_numbers_are_uniform_by_a_chi_square_test() {
        let k = 10;
        let n = 20_000u64;
        let counts = grid_counts(SamplerKind::Independent, n, k);
        let expected = n as f64 / (k * k) as f64;
        let chi2: f64 = counts
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        // 99 degrees of freedom: the 0.1 % and 99.9 % points are about 58 and 149.
        assert!((58.0..149.0).contains(&chi2), "chi² = {chi2}");
    }

    #[test]
    fn a_pair_starts_on_an_even_dimension() {
        let mut s = SampleStream::new(SamplerKind::Sobol, 0, 0, 0, 5);
        s.next_1d();
        s.next_2d();
        assert_eq!(s.dimension, 4);
    }
}
