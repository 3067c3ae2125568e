//! Pixel filters: how much a sample counts towards each pixel near it.
//!
//! A pixel's value is an estimate of the image around its centre. A sample taken at a point of
//! the image plane is evidence about every pixel whose centre is close to it, not only the one
//! whose square it fell in: a filter wider than a pixel *splats* the sample onto each pixel it
//! covers, weighted by the filter at the distance between the sample and that pixel's centre.
//! The film keeps, per pixel, the sum of weighted colours and the sum of weights, and divides
//! one by the other only when the image is developed, so the result is a weighted average
//! however unevenly the samples fell, and two films of one image merge by plain addition.
//!
//! The box filter (the default) gives each sample to the pixel it lies in, at weight 1: a
//! plain average of the pixel's samples, today's images. A tent or a Gaussian blends
//! neighbouring samples in, trading a little sharpness for less aliasing (jagged edges, moiré)
//! than a box of the same number of samples.

use super::FilmError;

/// The widest filter accepted, in pixels from the centre: a sample then touches at most
/// 17 × 17 pixels.
pub const MAX_FILTER_RADIUS: f64 = 8.0;

/// How a sample is spread over the pixels around it (see the module's documentation).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum PixelFilter {
    /// Each sample counts fully for the pixel it lies in and not at all for the others.
    #[default]
    Box,
    /// A pyramid: weight `(1 − |dx|/r)(1 − |dy|/r)` for a sample `(dx, dy)` from a pixel's
    /// centre, zero from `r` pixels away.
    Tent {
        /// Half the width, in pixels (at most [`MAX_FILTER_RADIUS`]).
        radius: f64,
    },
    /// A Gaussian of standard deviation `r / 2` in each direction, less its value at `r` so it
    /// reaches zero there (a sharp cut would ring): `g(dx)·g(dy)` with
    /// `g(d) = max(0, exp(−d²/(2σ²)) − exp(−r²/(2σ²)))`.
    Gaussian {
        /// Where the weight reaches zero, in pixels (at most [`MAX_FILTER_RADIUS`]).
        radius: f64,
    },
}

impl PixelFilter {
    /// The filter, if its radius is finite, positive and at most [`MAX_FILTER_RADIUS`].
    pub fn checked(self) -> Result<Self, FilmError> {
        match self {
            Self::Box => Ok(self),
            Self::Tent { radius } | Self::Gaussian { radius } => {
                if radius > 0.0 && radius <= MAX_FILTER_RADIUS {
                    Ok(self)
                } else {
                    Err(FilmError::BadFilter(radius))
                }
            }
        }
    }

    /// How far from a pixel's centre a sample still counts for it, in pixels.
    pub fn radius(self) -> f64 {
        match self {
            Self::Box => 0.5,
            Self::Tent { radius } | Self::Gaussian { radius } => radius,
        }
    }

    /// The weight of a sample `(dx, dy)` pixels from a pixel's centre.
    pub fn weight(self, dx: f64, dy: f64) -> f64 {
        match self {
            // Half-open, as the pixel's square is: a sample on a border counts for one pixel.
            Self::Box => {
                if (-0.5..0.5).contains(&dx) && (-0.5..0.5).contains(&dy) {
                    1.0
                } else {
                    0.0
                }
            }
            Self::Tent { radius } => {
                let tent = |d: f64| (1.0 - d.abs() / radius).max(0.0);
                tent(dx) * tent(dy)
            }
            Self::Gaussian { radius } => {
                let sigma = radius / 2.0;
                let g = |d: f64| (-d * d / (2.0 * sigma * sigma)).exp();
                let edge = g(radius);
                let gauss = |d: f64| (g(d) - edge).max(0.0);
                gauss(dx) * gauss(dy)
            }
        }
    }

    /// The filter's code in the film file: 0 box, 1 tent, 2 Gaussian.
    pub(super) fn code(self) -> u8 {
        match self {
            Self::Box => 0,
            Self::Tent { .. } => 1,
            Self::Gaussian { .. } => 2,
        }
    }

    /// The filter a film file names (its code and radius), checked.
    pub(super) fn from_code(code: u8, radius: f64) -> Result<Self, FilmError> {
        match code {
            0 => Ok(Self::Box),
            1 => Self::Tent { radius }.checked(),
            2 => Self::Gaussian { radius }.checked(),
            other => Err(FilmError::UnknownFilter(other)),
        }
    }
}
