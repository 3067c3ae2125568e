//! The book's fixed `sequence` of sample offsets (the soft-shadows bonus chapter's tests); the
//! seeded generator renders use instead is [`SplitMix64`](crate::math::random::SplitMix64).

use crate::math::random::Jitter;

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
