//! What a density grid gives off where its light is not one colour throughout (pbrt-v4's
//! grid emission): a radiance scaled by a grid of factors (`Lescale`), a grid of colours
//! (an `rgbgrid`'s `Le`), or a blackbody at a grid of temperatures (`temperature`), and the
//! grids of colours an `rgbgrid` keeps its coefficients in. Every grid here is looked up in
//! the medium's unit cube as the density is (trilinear between samples at cell centres).
//! The light a point gives is σa there times this radiance, as for every medium.

use super::grid::DensityGrid;
use super::MediumError;
use crate::color::Color;
use crate::math::Point3;

/// A grid of colours: one density grid per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ColorGrid {
    channels: [DensityGrid; 3],
}

impl ColorGrid {
    /// A grid of `size` holding `values` (x fastest), each channel finite and at least 0.
    pub fn new(size: [usize; 3], values: &[Color]) -> Result<Self, MediumError> {
        let channel = |f: fn(&Color) -> f64| {
            DensityGrid::new(size, values.iter().map(|c| f(c) as f32).collect())
        };
        Ok(Self {
            channels: [
                channel(|c| c.red)?,
                channel(|c| c.green)?,
                channel(|c| c.blue)?,
            ],
        })
    }

    /// The samples along x, y and z.
    pub fn size(&self) -> [usize; 3] {
        self.channels[0].size()
    }

    /// The colour at `p` in the unit cube.
    #[inline]
    pub fn lookup(&self, p: Point3) -> Color {
        let [r, g, b] = &self.channels;
        Color::new(r.lookup(p), g.lookup(p), b.lookup(p))
    }

    /// Per sample, its largest channel: the grid a majorant bounds.
    pub fn max_channels(&self) -> DensityGrid {
        let [r, g, b] = &self.channels;
        let values = (0..r.len())
            .map(|i| r.value(i).max(g.value(i)).max(b.value(i)))
            .collect();
        DensityGrid::new(self.size(), values).expect("the channels' grids are valid")
    }
}

/// The linear sRGB colour of a blackbody from a temperature, tabulated (a medium cannot
/// integrate spectra per sample): a blackbody normalised to 1 at its peak, as pbrt-v4's
/// `BlackbodySpectrum`, seen by an RGB film, at evenly spaced temperatures, interpolated
/// linearly between.
#[derive(Debug, Clone, PartialEq)]
pub struct BlackbodyTable {
    lowest: f64,
    step: f64,
    colors: Vec<Color>,
}

/// The most entries a blackbody table holds.
pub const MAX_BLACKBODY_ENTRIES: usize = 4096;

/// No light below this temperature (pbrt-v4's cut-off, in kelvin).
pub const LOWEST_GLOWING_KELVIN: f64 = 100.0;

impl BlackbodyTable {
    /// The table from [`LOWEST_GLOWING_KELVIN`] to `highest` kelvin, of `entries` (2 to
    /// [`MAX_BLACKBODY_ENTRIES`]) colours that `color_of` gives a temperature.
    pub fn new(highest: f64, entries: usize, color_of: impl Fn(f64) -> Color) -> Self {
        let entries = entries.clamp(2, MAX_BLACKBODY_ENTRIES);
        let highest = if highest.is_finite() {
            highest.max(LOWEST_GLOWING_KELVIN + 1.0)
        } else {
            LOWEST_GLOWING_KELVIN + 1.0
        };
        let step = (highest - LOWEST_GLOWING_KELVIN) / (entries - 1) as f64;
        let colors = (0..entries)
            .map(|i| color_of(LOWEST_GLOWING_KELVIN + step * i as f64))
            .collect();
        Self {
            lowest: LOWEST_GLOWING_KELVIN,
            step,
            colors,
        }
    }

    /// The colour at `kelvin`: black at or below the cut-off, the last entry past the end.
    #[inline]
    pub fn at(&self, kelvin: f64) -> Color {
        if kelvin.is_nan() || kelvin <= self.lowest {
            return Color::BLACK;
        }
        let x = (kelvin - self.lowest) / self.step;
        let last = self.colors.len() - 1;
        let i = (x.floor() as usize).min(last - 1);
        let f = (x - i as f64).min(1.0);
        self.colors[i] * (1.0 - f) + self.colors[i + 1] * f
    }
}

/// Where a grid's light varies (see the [module](self)).
#[derive(Debug, Clone, PartialEq)]
pub enum Glow {
    /// `radiance` times a grid of factors.
    Scaled {
        /// The radiance where the factor is 1.
        radiance: Color,
        /// The factors.
        scale: DensityGrid,
    },
    /// A grid of radiances times `scale`.
    Colors {
        /// The radiances.
        radiance: ColorGrid,
        /// What multiplies them.
        scale: f64,
    },
    /// A blackbody at `(T − offset) × factor` kelvin, `T` the grid's temperature, times the
    /// grid of factors `scale` where there is one (else 1).
    Blackbody {
        /// The temperatures.
        temperature: DensityGrid,
        /// What is taken off them.
        offset: f64,
        /// What then multiplies them.
        factor: f64,
        /// The factors of the light, where given.
        scale: Option<DensityGrid>,
        /// The blackbody's colours.
        table: BlackbodyTable,
    },
}

impl Glow {
    /// The radiance at `p` in the unit cube.
    #[inline]
    pub fn at(&self, p: Point3) -> Color {
        match self {
            Glow::Scaled { radiance, scale } => *radiance * scale.lookup(p),
            Glow::Colors { radiance, scale } => radiance.lookup(p) * *scale,
            Glow::Blackbody {
                temperature,
                offset,
                factor,
                scale,
                table,
            } => {
                let s = scale.as_ref().map_or(1.0, |g| g.lookup(p));
                if s <= 0.0 {
                    return Color::BLACK;
                }
                table.at((temperature.lookup(p) - offset) * factor) * s
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::point;

    #[test]
    fn a_blackbody_table_interpolates_between_its_entries_and_is_dark_below_the_cut_off() {
        let t = BlackbodyTable::new(1100.0, 11, |k| Color::new(k, 2.0 * k, 0.0));
        assert_eq!(t.at(50.0), Color::BLACK);
        assert_eq!(t.at(100.0), Color::BLACK);
        assert!((t.at(150.0).red - 150.0).abs() < 1e-9);
        assert!((t.at(1100.0).green - 2200.0).abs() < 1e-9);
        assert_eq!(t.at(5000.0), t.at(1100.0));
    }

    #[test]
    fn glows_read_their_grids() {
        let scale = DensityGrid::new([2, 1, 1], vec![0.0, 2.0]).unwrap();
        let g = Glow::Scaled {
            radiance: Color::new(1.0, 0.5, 0.25),
            scale,
        };
        assert_eq!(g.at(point(0.75, 0.5, 0.5)), Color::new(2.0, 1.0, 0.5));
        assert_eq!(g.at(point(0.25, 0.5, 0.5)), Color::BLACK);
        let colours =
            ColorGrid::new([1, 2, 1], &[Color::new(1.0, 0.0, 0.0), Color::WHITE]).unwrap();
        assert_eq!(colours.max_channels().lookup(point(0.5, 0.25, 0.5)), 1.0);
        let g = Glow::Colors {
            radiance: colours,
            scale: 3.0,
        };
        assert_eq!(g.at(point(0.5, 0.75, 0.5)), Color::new(3.0, 3.0, 3.0));
        let g = Glow::Blackbody {
            temperature: DensityGrid::new([1, 1, 1], vec![1000.0]).unwrap(),
            offset: 500.0,
            factor: 2.0,
            scale: None,
            table: BlackbodyTable::new(2000.0, 20, |k| Color::new(k, k, k)),
        };
        assert!((g.at(point(0.5, 0.5, 0.5)).red - 1000.0).abs() < 1e-9);
        assert!(ColorGrid::new([1, 1, 1], &[Color::new(-1.0, 0.0, 0.0)]).is_err());
    }
}
