//! Sources of sample offsets within a cell: the book's fixed `sequence` (for tests), and a
//! seeded generator for renders, reseeded per pixel so images do not depend on thread count.

/// Numbers in `[0, 1)` that place samples inside their cells.
pub trait Jitter {
    /// The next offset.
    fn next_offset(&mut self) -> f64;
}

/// The book's `sequence(a, b, …)`: the given numbers, over and over.
#[derive(Debug, Clone, PartialEq)]
pub struct Sequence {
    values: Vec<f64>,
    at: usize,
}

impl Sequence {
    /// A sequence of the given numbers (at least one).
    pub fn new(values: &[f64]) -> Self {
        Self {
            values: if values.is_empty() {
                vec![0.5]
            } else {
                values.to_vec()
            },
            at: 0,
        }
    }
}

impl Jitter for Sequence {
    fn next_offset(&mut self) -> f64 {
        let v = self.values[self.at % self.values.len()];
        self.at += 1;
        v
    }
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
