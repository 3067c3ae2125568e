//! The path tracer's random numbers: one stream per (pixel, sample), drawn dimension by
//! dimension, a pure function of the pixel, the sample's index and the render's seed. So the
//! image never depends on the thread count or the order pixels are rendered in, and any range
//! of a pixel's samples can be rendered apart from the others and merged later.
//!
//! Two kinds ([`SamplerKind`]):
//! - independent: each number hashed from (seed, pixel, sample, dimension), the plain Monte
//!   Carlo baseline;
//! - Sobol: Owen-scrambled Sobol points (Burley, "Practical Hash-based Owen Scrambling", 2020,
//!   through the `sobol_burley` crate's parts), padded: each group of four dimensions takes the
//!   sequence's first four dimensions under its own scramble, seeded from the pixel and the
//!   group, so every pixel and every path vertex is stratified within itself and decorrelated
//!   from the others. The sequences hold 2¹⁶ points; later samples continue under another
//!   scramble. Every dimension of a path is drawn this way, however deep: Russian roulette
//!   starts a few bounces in, and its coin, stratified over a pixel's samples, is much of what
//!   stratification gains in a bright closed scene (the closed furnace's error at 64 samples
//!   falls by 30 % against hashing the numbers past the third bounce).
//!
//! The Sobol points are the crate's own `sample_4d` for the first dimension set, with the
//! Sobol matrix product read from two tables of 256 entries (one per byte of the shuffled
//! index) instead of a loop over its sixteen bits: the sampler was a fifth of a Cornell box
//! render. They are the same points to the bit (tested).

use crate::math::random::SplitMix64;
use crate::options::SamplerKind;
use sobol_burley::parts::{hash, hash_int4, owen_scramble_int4_rev, owen_scramble_rev, Int4};
use std::sync::LazyLock;

/// The numbers of one pixel's samples, one sample at a time (see the [module](self)): made
/// once per pixel, and [`start`](Self::start)ed at each sample's index. A pixel's samples
/// share the Sobol scrambles of every group of dimensions (they depend on the pixel and the
/// group, not the sample), so the stream keeps those it has hashed for the samples after: the
/// hashing was half of the sampler's time when done afresh for every sample.
#[derive(Debug, Clone)]
pub struct SampleStream {
    kind: SamplerKind,
    /// A hash of the render's seed and the pixel.
    pixel: u64,
    /// The sample's index within its block of 2¹⁶, bit-reversed (every group's Sobol point
    /// starts from it).
    index_rev: u32,
    /// A hash of `pixel` and the sample's index, which hashed numbers start from.
    sample: u64,
    /// The next dimension to draw.
    dimension: u32,
    /// The Sobol sampler's four numbers of the group of dimensions `group` (a Sobol point's
    /// four dimensions cost one call, computed side by side).
    cached: [f32; 4],
    /// Which group `cached` holds (`u32::MAX`: none yet).
    group: u32,
    /// The block of 2¹⁶ sample indices whose scrambles `scrambles` holds.
    block: u64,
    /// Which of the first [`KEPT_GROUPS`] groups' scrambles `scrambles` holds, a bit each.
    kept: u64,
    /// The scrambles of the first groups of dimensions, for `block`.
    scrambles: [GroupScramble; KEPT_GROUPS],
}

/// How many groups of four dimensions keep their scrambles between a pixel's samples: a path
/// of 31 bounces (deeper vertices hash theirs afresh).
const KEPT_GROUPS: usize = 64;

/// The hashed scrambles of one group of four dimensions of one pixel: the shuffle of the
/// sample index (Burley's nested uniform scramble of the index) and the Owen scramble of each
/// of the four dimensions.
#[derive(Debug, Clone, Copy, Default)]
struct GroupScramble {
    shuffle: u32,
    digits: [u32; 4],
}

impl GroupScramble {
    /// The scrambles `sobol_burley::sample_4d` derives from `seed` for the first dimension set.
    #[inline]
    fn new(seed: u32) -> Self {
        let shuffle = hash(seed ^ 0x79c6_8e4a);
        let seed = seed.wrapping_mul(0x9c8f_2d3b);
        let digits = hash_int4(Int4::from([
            seed ^ 0x912f_69ba,
            seed ^ 0x174f_18ab,
            seed ^ 0x691e_72ca,
            seed ^ 0xb40c_c1b8,
        ]));
        Self {
            shuffle,
            digits: digits.into(),
        }
    }
}

/// The bit-reversed Sobol matrix product of the sequence's first four dimensions for each
/// value of the shuffled index's top byte (`high`) and next byte (`low`): the index's 16 bits
/// take two lookups (8 KiB, which stays in the first-level cache).
struct SobolTables {
    high: [[u32; 4]; 256],
    low: [[u32; 4]; 256],
}

static SOBOL_TABLES: LazyLock<SobolTables> = LazyLock::new(|| {
    // Direction number `m` belongs to bit `31 - m` of the bit-reversed index; the crate's
    // product for an index with that one bit set is it.
    let direction =
        |m: u32| <[u32; 4]>::from(sobol_burley::parts::sobol_int4_rev(1 << (31 - m), 0));
    let table = |first: u32| {
        let mut t = [[0u32; 4]; 256];
        for (byte, entry) in t.iter_mut().enumerate() {
            for bit in 0..8 {
                if byte & (0x80 >> bit) != 0 {
                    let v = direction(first + bit);
                    for lane in 0..4 {
                        entry[lane] ^= v[lane];
                    }
                }
            }
        }
        t
    };
    SobolTables {
        high: table(0),
        low: table(8),
    }
});

/// Sample `index` (below 2¹⁶; given bit-reversed, as `index_rev`) of the Owen-scrambled Sobol
/// sequence's first four dimensions under `scramble`: `sobol_burley::sample_4d(index, 0, seed)`
/// for the scramble of `seed`, with the matrix product from [`SOBOL_TABLES`].
#[inline]
fn sobol_4d(index_rev: u32, scramble: &GroupScramble) -> [f32; 4] {
    let shuffled = owen_scramble_rev(index_rev, scramble.shuffle);
    let tables = &*SOBOL_TABLES;
    let (high, low) = (
        tables.high[(shuffled >> 24) as usize],
        tables.low[((shuffled >> 16) & 0xFF) as usize],
    );
    let sobol = Int4::from([
        high[0] ^ low[0],
        high[1] ^ low[1],
        high[2] ^ low[2],
        high[3] ^ low[3],
    ]);
    owen_scramble_int4_rev(sobol, Int4::from(scramble.digits))
        .reverse_bits()
        .to_f32_norm()
}

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
        let mut stream = Self {
            kind,
            pixel,
            index_rev: 0,
            sample: 0,
            dimension: 0,
            cached: [0.0; 4],
            group: u32::MAX,
            block: index >> 16,
            kept: 0,
            scrambles: [GroupScramble::default(); KEPT_GROUPS],
        };
        stream.start(index);
        stream
    }

    /// Starts sample `index` of the same pixel, from its first dimension.
    #[inline]
    pub fn start(&mut self, index: u64) {
        self.index_rev = ((index & 0xFFFF) as u32).reverse_bits();
        self.sample = mix(self.pixel, index);
        self.dimension = 0;
        self.group = u32::MAX;
        if index >> 16 != self.block {
            self.block = index >> 16;
            self.kept = 0;
        }
    }

    /// The scrambles of group `group` of this pixel and block.
    #[inline]
    fn scramble(&mut self, group: u32) -> GroupScramble {
        // Each group of four dimensions, and each block of 2¹⁶ samples, has a scramble of its
        // own.
        let hashed = || {
            let seed = mix(mix(self.pixel, u64::from(group)), self.block);
            GroupScramble::new((seed ^ (seed >> 32)) as u32)
        };
        let Some(slot) = self.scrambles.get_mut(group as usize) else {
            return hashed();
        };
        let bit = 1u64 << group;
        if self.kept & bit == 0 {
            *slot = hashed();
            self.kept |= bit;
        }
        *slot
    }

    /// The next number, in `[0, 1)`.
    #[inline]
    pub fn next_1d(&mut self) -> f64 {
        let d = self.dimension;
        self.dimension = self.dimension.wrapping_add(1);
        if self.kind == SamplerKind::Independent {
            let bits = mix(self.sample, u64::from(d));
            return (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
        }
        let group = d / 4;
        if group != self.group {
            self.draw_group(group);
        }
        f64::from(self.cached[(d % 4) as usize])
    }

    /// Draws the Sobol point of group `group` into `cached`: once per four numbers, so kept
    /// out of line, where the numbers themselves are drawn inline.
    #[inline(never)]
    fn draw_group(&mut self, group: u32) {
        let scramble = self.scramble(group);
        self.cached = sobol_4d(self.index_rev, &scramble);
        self.group = group;
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
    fn the_tabled_sobol_points_are_the_crates_to_the_bit() {
        let mut seeds = SplitMix64::new(5);
        for _ in 0..64 {
            let seed = seeds.next_u64() as u32;
            for index in (0u32..1 << 16).step_by(97).chain([0, 1, 2, 3, 0xFFFF]) {
                assert_eq!(
                    sobol_4d(index.reverse_bits(), &GroupScramble::new(seed)),
                    sobol_burley::sample_4d(index, 0, seed),
                    "index {index}, seed {seed:#x}"
                );
            }
        }
    }

    #[test]
    fn deep_dimensions_are_stratified_over_a_pixels_samples() {
        // Dimension 200 (a vertex 24 bounces in): 64 samples put one number in each
        // sixty-fourth of the unit interval, as Russian roulette's coin needs.
        let mut seen = [0u32; 64];
        for i in 0..64 {
            let mut s = SampleStream::new(SamplerKind::Sobol, 3, 17, 9, i);
            s.seek(200);
            seen[(s.next_1d() * 64.0) as usize] += 1;
        }
        assert!(seen.iter().all(|&c| c == 1), "{seen:?}");
    }

    #[test]
    fn a_restarted_stream_draws_what_a_fresh_one_does() {
        // The kept scrambles must never leak between samples: across a block of 2¹⁶ indices,
        // and past the groups kept (dimension 300 is group 75).
        for kind in [SamplerKind::Independent, SamplerKind::Sobol] {
            let mut reused = SampleStream::new(kind, 9, 5, 6, 0);
            for index in [0, 1, 65_535, 65_536, 65_537, 3, 200_000, 7] {
                reused.start(index);
                let mut fresh = SampleStream::new(kind, 9, 5, 6, index);
                for _ in 0..300 {
                    assert_eq!(reused.next_1d(), fresh.next_1d(), "index {index}");
                }
            }
        }
    }

    #[test]
    fn a_pair_starts_on_an_even_dimension() {
        let mut s = SampleStream::new(SamplerKind::Sobol, 0, 0, 0, 5);
        s.next_1d();
        s.next_2d();
        assert_eq!(s.dimension, 4);
    }
}
