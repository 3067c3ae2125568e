//! What the film records of the light that reaches it: a linear map of the rgb radiance of
//! every sample, before the pixel filter sums it. pbrt-v4's `PixelSensor` is such a map (its
//! imaging ratio, the exposure time × ISO / 100, and its white balance, a 3 × 3 matrix from
//! the sensor's white to the colour space's); the identity records the radiance as it is.
//!
//! A sensor may also cap each sample (pbrt-v4's film `maxcomponentvalue`, its guard against
//! fireflies): a sample whose largest component, measured in the sensor's own space, is
//! above the cap is scaled down to it as a whole, so its hue is kept and only its brightness
//! lost. The cap bounds one sample, before the pixel filter weighs it and sums it with the
//! others, as pbrt-v4's `RGBFilm::AddSample` bounds it; that space need not be the one
//! recorded (pbrt-v4 measures in its sensor's rgb, XYZ for its default sensor, and only then
//! white-balances and converts), hence a matrix of its own.

use crate::color::Color;

/// A linear map of a sample's rgb radiance (rows of a 3 × 3 matrix), and the cap on each
/// sample's largest component, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor {
    rows: [[f64; 3]; 3],
    cap: Option<Cap>,
}

/// A cap on each sample: the largest component of `measure` × radiance at most `max`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cap {
    max: f64,
    measure: [[f64; 3]; 3],
}

/// The matrix `m` applied to `c`.
#[inline]
fn apply(m: &[[f64; 3]; 3], c: Color) -> Color {
    let [r, g, b] = m;
    Color::new(
        r[0] * c.red + r[1] * c.green + r[2] * c.blue,
        g[0] * c.red + g[1] * c.green + g[2] * c.blue,
        b[0] * c.red + b[1] * c.green + b[2] * c.blue,
    )
}

impl Sensor {
    /// The radiance as it is.
    pub const IDENTITY: Self = Self {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        cap: None,
    };

    /// The map whose matrix has rows `rows`, uncapped; `None` unless every entry is finite.
    pub fn from_rows(rows: [[f64; 3]; 3]) -> Option<Self> {
        rows.iter()
            .flatten()
            .all(|v| v.is_finite())
            .then_some(Self { rows, cap: None })
    }

    /// The same sensor with each sample scaled down, as a whole, so that the largest
    /// component of `measure` × its radiance is at most `max` (pbrt-v4's
    /// `maxcomponentvalue`). An infinite `max` caps nothing and leaves the sensor as it is,
    /// so that a render without a cap keeps its bits. `None` unless `max` is above 0 (NaN is
    /// not) and `measure`'s entries are finite.
    pub fn with_max_component(self, max: f64, measure: [[f64; 3]; 3]) -> Option<Self> {
        if max.is_nan() || max <= 0.0 || !measure.iter().flatten().all(|v| v.is_finite()) {
            return None;
        }
        if max == f64::INFINITY {
            return Some(self);
        }
        Some(Self {
            cap: Some(Cap { max, measure }),
            ..self
        })
    }

    /// The cap on each sample's largest component (`None`: no cap).
    pub fn max_component(&self) -> Option<f64> {
        self.cap.map(|c| c.max)
    }

    /// The matrix's rows.
    pub fn rows(&self) -> [[f64; 3]; 3] {
        self.rows
    }

    /// Whether it records the radiance as it is (no map and no cap).
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// What the film records of one sample's radiance `c`: the map of `c`, scaled down as a
    /// whole where the cap's measure of `c` has a component above the cap. A measure of NaN
    /// scales nothing (the sample is not finite, and the path tracer leaves it out).
    #[inline]
    pub fn record(&self, c: Color) -> Color {
        let out = apply(&self.rows, c);
        match self.cap {
            Some(Cap { max, measure }) => {
                let m = apply(&measure, c);
                let largest = m.red.max(m.green).max(m.blue);
                if largest > max {
                    out * (max / largest)
                } else {
                    out
                }
            }
            None => out,
        }
    }
}

impl Default for Sensor {
    fn default() -> Self {
        Self::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sample above the cap is scaled down to it as a whole (its hue kept), measured by the
    /// cap's own matrix; one at or below it, and every sample of an infinite cap, is recorded
    /// as the map alone gives it.
    #[test]
    fn the_cap_scales_a_bright_sample_down_keeping_its_hue() {
        let double =
            Sensor::from_rows([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]]).unwrap();
        // Measured in a space whose first component is the sum of the channels.
        let measure = [[1.0, 1.0, 1.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let capped = double.with_max_component(3.0, measure).unwrap();
        assert_eq!(capped.max_component(), Some(3.0));
        let bright = Color::new(4.0, 1.0, 1.0);
        // Measured 6: scaled by 3 / 6, after the map's doubling.
        assert_eq!(capped.record(bright), Color::new(4.0, 1.0, 1.0));
        let dim = Color::new(1.0, 1.0, 0.5);
        assert_eq!(capped.record(dim), double.record(dim));
        let uncapped = double.with_max_component(f64::INFINITY, measure).unwrap();
        assert_eq!(uncapped, double);
        assert!(Sensor::IDENTITY
            .with_max_component(f64::INFINITY, measure)
            .unwrap()
            .is_identity());
        assert!(!Sensor::IDENTITY
            .with_max_component(1.0, measure)
            .unwrap()
            .is_identity());
        for bad in [0.0, -1.0, f64::NAN] {
            assert_eq!(double.with_max_component(bad, measure), None, "{bad}");
        }
        let mut infinite = measure;
        infinite[1][1] = f64::INFINITY;
        assert_eq!(double.with_max_component(1.0, infinite), None);
    }
}
