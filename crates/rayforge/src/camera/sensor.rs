//! What the film records of the light that reaches it: a linear map of the rgb radiance of
//! every sample, before the pixel filter sums it. pbrt-v4's `PixelSensor` is such a map (its
//! imaging ratio, the exposure time × ISO / 100, and its white balance, a 3 × 3 matrix from
//! the sensor's white to the colour space's); the identity records the radiance as it is.

use crate::color::Color;

/// A linear map of a sample's rgb radiance (rows of a 3 × 3 matrix).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor {
    rows: [[f64; 3]; 3],
}

impl Sensor {
    /// The radiance as it is.
    pub const IDENTITY: Self = Self {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// The map whose matrix has rows `rows`; `None` unless every entry is finite.
    pub fn from_rows(rows: [[f64; 3]; 3]) -> Option<Self> {
        rows.iter()
            .flatten()
            .all(|v| v.is_finite())
            .then_some(Self { rows })
    }

    /// The matrix's rows.
    pub fn rows(&self) -> [[f64; 3]; 3] {
        self.rows
    }

    /// Whether it records the radiance as it is.
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// What the film records of radiance `c`.
    #[inline]
    pub fn record(&self, c: Color) -> Color {
        let [r, g, b] = self.rows;
        Color::new(
            r[0] * c.red + r[1] * c.green + r[2] * c.blue,
            g[0] * c.red + g[1] * c.green + g[2] * c.blue,
            b[0] * c.red + b[1] * c.green + b[2] * c.blue,
        )
    }
}

impl Default for Sensor {
    fn default() -> Self {
        Self::IDENTITY
    }
}
