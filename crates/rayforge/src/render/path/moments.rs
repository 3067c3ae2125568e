//! The moments of a pixel's samples (their count, sum and sum of squares), and the spread
//! they give: what both pilot passes, the roulette's and adaptive sampling's, judge a pixel's
//! noise by.

use crate::color::Color;

/// The count, sum and sum of squares of a pixel's finite samples.
#[derive(Debug, Clone, Copy, Default)]
pub struct Moments {
    n: f64,
    sum: Color,
    squares: Color,
}

impl Moments {
    /// Counts `radiance` in.
    #[inline]
    pub fn add(&mut self, radiance: Color) {
        self.n += 1.0;
        self.sum += radiance;
        self.squares += radiance.hadamard(radiance);
    }

    /// The moments of both sets of samples together.
    pub fn merged(&self, other: &Self) -> Self {
        Self {
            n: self.n + other.n,
            sum: self.sum + other.sum,
            squares: self.squares + other.squares,
        }
    }

    /// How many samples were counted.
    pub fn count(&self) -> f64 {
        self.n
    }

    /// Their mean (black from none).
    pub fn mean(&self) -> Color {
        if self.n > 0.0 {
            self.sum * (1.0 / self.n)
        } else {
            Color::BLACK
        }
    }

    /// The unbiased variance, the mean over the channels (0 from fewer than two samples).
    pub fn variance(&self) -> f64 {
        if self.n < 2.0 {
            return 0.0;
        }
        let mean = self.mean();
        let spread = (self.squares - mean.hadamard(self.sum)) * (1.0 / (self.n - 1.0));
        ((spread.red + spread.green + spread.blue) / 3.0).max(0.0)
    }
}
