//! Random numbers for rendering: [`SplitMix64`], a small seeded generator, and [`Jitter`], the
//! source of sample offsets within a cell that area lights and the sampler draw from.
//!
//! Renders reseed a generator per pixel (the seed is the pixel's index), so images do not
//! depend on thread count or on the order in which pixels are rendered.

/// Numbers in `[0, 1)` that place samples inside their cells.
pub trait Jitter {
    /// The next offset.
    fn next_offset(&mut self) -> f64;
}

/// SplitMix64: a small, fast generator with good statistics, so each pixel's samples come from
/// its own seed (a pure function of the pixel) and never from a shared generator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator starting from `seed`.
    pub const fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

impl Jitter for SplitMix64 {
    #[inline]
    fn next_offset(&mut self) -> f64 {
        // 53 random bits into [0, 1).
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}
