//! The film: what a renderer's samples accumulate into before they become an image.
//!
//! Per pixel the film keeps a sum of weighted linear colours and a sum of weights (64-bit
//! floats), and divides one by the other only when it is developed ([`develop`]). Keeping the
//! two sums apart is what the renderers to come need:
//!
//! - samples can arrive in any number and any weight (progressive passes of a path tracer,
//!   a [`PixelFilter`] wider than a pixel splatting one sample onto several);
//! - two films of the same image (disjoint slices of rows rendered on different machines, or
//!   two sets of passes) [`merge`](Film::merge) by adding sums and weights;
//! - a film can be [written and read back](Film::write_to) bit for bit, to be merged or
//!   developed later;
//! - a [`SharedFilm`] takes finished rows or tiles from render workers and hands out a
//!   [`snapshot`](SharedFilm::snapshot) at any moment, for a preview of a render in progress;
//!   it may hold only some of the image's rows ([`SharedFilm::with_rows`]), so that a slice
//!   of a render cut by rows needs memory for its rows alone.
//!
//! Sums start at −0.0, the exact identity of floating-point addition (`−0 + x` is `x` for every
//! `x`, a negative zero included, where `+0 + −0` is `+0`): a pixel given one sample of weight 1
//! holds that sample's colour to the bit, and a pixel merged with one that had no samples is
//! unchanged.

mod develop;
pub mod file;
mod filter;
mod shared;

pub use develop::{develop, develop_in_place, Exposure};
pub use file::{FILM_MAGIC, FILM_VERSION, MAX_FILM_PIXELS};
pub use filter::{PixelFilter, MAX_FILTER_RADIUS};
pub use shared::SharedFilm;

use crate::canvas::Canvas;
use crate::color::Color;

/// Why films could not be made, merged, read or written.
#[derive(Debug, thiserror::Error)]
pub enum FilmError {
    /// Merging films of two sizes.
    #[error("cannot merge a {0}×{1} film into a {2}×{3} one: the sizes differ")]
    SizeMismatch(usize, usize, usize, usize),
    /// Merging films made with two pixel filters: their weights do not mean the same.
    #[error("cannot merge a film made with the {0:?} filter into one made with the {1:?} filter")]
    FilterMismatch(PixelFilter, PixelFilter),
    /// Rows that do not fit in the film they are added to.
    #[error("{rows} rows from row {first} do not fit in a film {height} rows high")]
    RowsOutside {
        /// The first row added.
        first: usize,
        /// How many rows.
        rows: usize,
        /// The film's height.
        height: usize,
    },
    /// A row the film does not hold (see [`SharedFilm::with_rows`]).
    #[error("row {0} is not one of the rows this film holds")]
    RowNotHeld(usize),
    /// A tent or Gaussian radius that is not finite, positive and at most
    /// [`MAX_FILTER_RADIUS`].
    #[error("a pixel filter's radius must be more than 0 and at most {MAX_FILTER_RADIUS} pixels, found {0}")]
    BadFilter(f64),
    /// A film file naming a filter this version does not know.
    #[error("unknown pixel filter code {0} (0 box, 1 tent, 2 Gaussian)")]
    UnknownFilter(u8),
    /// Not a film file.
    #[error("not a rayforge film (wrong magic bytes)")]
    BadMagic,
    /// A film file of a format version this build cannot read.
    #[error("film format version {0} is not supported (this build reads version {FILM_VERSION})")]
    UnsupportedVersion(u32),
    /// A film file that ends early.
    #[error("the film file is truncated")]
    Truncated,
    /// A film file with bytes after its checksum.
    #[error("the film file has {0} bytes after its end")]
    TrailingBytes(usize),
    /// A film whose size would need more memory than [`MAX_FILM_PIXELS`] allows.
    #[error("a {0}×{1} film is larger than the limit of {MAX_FILM_PIXELS} pixels")]
    TooLarge(u64, u64),
    /// A film file whose checksum does not match its contents.
    #[error("the film file is damaged: CRC-32 {found:#010x} where {expected:#010x} was recorded")]
    BadChecksum {
        /// The checksum in the file.
        expected: u32,
        /// The checksum of what was read.
        found: u32,
    },
    /// Reading or writing failed.
    #[error("film input/output failed: {0}")]
    Io(#[from] std::io::Error),
}

/// Linear-light accumulation of weighted samples: per pixel a sum of weighted colours and a
/// sum of weights (see the module's documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    width: usize,
    height: usize,
    filter: PixelFilter,
    sums: Vec<Color>,
    weights: Vec<f64>,
    brightest: f64,
}

/// The sum of no colours: −0.0 in every channel, the identity of addition.
const EMPTY: Color = Color::new(-0.0, -0.0, -0.0);

impl Film {
    /// A `width` × `height` film with no samples and the box filter.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            filter: PixelFilter::Box,
            sums: vec![EMPTY; width * height],
            weights: vec![0.0; width * height],
            brightest: 0.0,
        }
    }

    /// A film with no samples that splats samples through `filter` (refused when its radius is
    /// out of range, see [`PixelFilter::checked`]).
    pub fn with_filter(
        width: usize,
        height: usize,
        filter: PixelFilter,
    ) -> Result<Self, FilmError> {
        Ok(Self {
            filter: filter.checked()?,
            ..Self::new(width, height)
        })
    }

    /// A box-filtered film holding each pixel of `canvas` as one sample of weight 1: what a
    /// renderer that computes one finished colour per pixel (the rasterizer) produces.
    /// The canvas's pixels become the sums as they are, without a copy.
    pub fn from_canvas(canvas: Canvas) -> Self {
        let (width, height) = (canvas.width(), canvas.height());
        Self {
            width,
            height,
            filter: PixelFilter::Box,
            sums: canvas.into_pixels(),
            weights: vec![1.0; width * height],
            brightest: 0.0,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The pixel filter samples are splatted through.
    pub fn filter(&self) -> PixelFilter {
        self.filter
    }

    /// Pixel (`x`, `y`)'s sum of weighted colours.
    pub fn sum(&self, x: usize, y: usize) -> Color {
        self.sums[y * self.width + x]
    }

    /// Pixel (`x`, `y`)'s sum of weights (0: no usable sample).
    pub fn weight(&self, x: usize, y: usize) -> f64 {
        self.weights[y * self.width + x]
    }

    /// All sums of weighted colours, row-major from the top-left.
    pub fn sums(&self) -> &[Color] {
        &self.sums
    }

    /// All sums of weights, row-major from the top-left.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Row `y`'s sums of weighted colours.
    pub fn row_sums(&self, y: usize) -> &[Color] {
        &self.sums[y * self.width..(y + 1) * self.width]
    }

    /// Row `y`'s sums of weights.
    pub fn row_weights(&self, y: usize) -> &[f64] {
        &self.weights[y * self.width..(y + 1) * self.width]
    }

    /// The brightest channel of any single sample the renderer noted
    /// ([`note_brightest`](Self::note_brightest)); the optics model's exposure divides by it.
    pub fn brightest(&self) -> f64 {
        self.brightest
    }

    /// Notes the brightest channel of samples that went into the film (a sample can be brighter
    /// than any averaged pixel). Brightness is not negative; values are compared by their bit
    /// patterns, which order like the numbers for non-negative floats, so that a
    /// [`SharedFilm`] keeps the maximum with one atomic operation and both agree to the bit.
    pub fn note_brightest(&mut self, brightest: f64) {
        self.brightest = brighter(self.brightest, brightest);
    }

    /// Adds `color` at `weight` to pixel (`x`, `y`) as it is, without the filter: for a
    /// renderer that estimates each pixel itself (today's ray tracer averages a pixel's samples
    /// before the film sees them).
    pub fn add_pixel(&mut self, x: usize, y: usize, color: Color, weight: f64) {
        let i = y * self.width + x;
        self.sums[i] += color * weight;
        self.weights[i] += weight;
    }

    /// Adds to pixel (`x`, `y`) a sum of weighted colours `weighted_sum` whose weights sum to
    /// `weight`, without the filter: for a renderer that gathers each pixel's samples itself
    /// and adds them at once (the path tracer, whose samples each belong to one pixel).
    pub fn add_pixel_sum(&mut self, x: usize, y: usize, weighted_sum: Color, weight: f64) {
        let i = y * self.width + x;
        self.sums[i] += weighted_sum;
        self.weights[i] += weight;
    }

    /// Sets pixel (`x`, `y`)'s sum of weighted colours and of weights (a renderer that went on
    /// from the pixel's earlier sums: see [`SharedFilm::row`]).
    pub fn set_pixel_sum(&mut self, x: usize, y: usize, weighted_sum: Color, weight: f64) {
        let i = y * self.width + x;
        self.sums[i] = weighted_sum;
        self.weights[i] = weight;
    }

    /// Replaces row `y` with `pixels`, each one sample of weight 1 (a row read back from the
    /// command line's checkpoint, which saves pixel estimates).
    pub(crate) fn replace_row(&mut self, y: usize, pixels: &[Color]) {
        let row = y * self.width..(y + 1) * self.width;
        for (sum, &pixel) in self.sums[row.clone()].iter_mut().zip(pixels) {
            *sum = EMPTY + pixel;
        }
        self.weights[row].fill(1.0);
    }

    /// Splats a sample of `color` at `weight` taken at image point (`px`, `py`) onto every
    /// pixel the filter covers there, each at `weight` times the filter's weight at the
    /// distance from its centre. Pixel (`x`, `y`) spans `[x, x+1) × [y, y+1)`; its centre is
    /// at `(x + 0.5, y + 0.5)`. Pixels off the film are skipped.
    pub fn add_sample(&mut self, px: f64, py: f64, color: Color, weight: f64) {
        if !(px.is_finite() && py.is_finite()) {
            return;
        }
        let r = self.filter.radius();
        let span = |p: f64, size: usize| {
            let lo = (p - 0.5 - r).ceil().max(0.0);
            let hi = (p - 0.5 + r).floor().min(size as f64 - 1.0);
            (lo as usize, hi)
        };
        let ((x0, x1), (y0, y1)) = (span(px, self.width), span(py, self.height));
        let mut y = y0;
        while (y as f64) <= y1 {
            let mut x = x0;
            while (x as f64) <= x1 {
                let dx = px - (x as f64 + 0.5);
                let dy = py - (y as f64 + 0.5);
                let w = self.filter.weight(dx, dy);
                if w != 0.0 {
                    self.add_pixel(x, y, color, weight * w);
                }
                x += 1;
            }
            y += 1;
        }
    }

    /// Adds `other`'s samples to this film: sums and weights pixel by pixel, the brighter of
    /// the two brightest samples. Refused (and nothing changes) when the sizes or the filters
    /// differ.
    ///
    /// Merging is exact, bit for bit the film of all the samples rendered at once, whenever
    /// each pixel's samples all lie in one of the two films (an empty pixel's sums are the
    /// identity): disjoint slices of rows under the box filter, the renderers' case. With a
    /// wider filter, samples near a seam between slices reach pixels on both sides, whose sums
    /// are then added in another order than one render would have: equal to within rounding.
    pub fn merge(&mut self, other: &Film) -> Result<(), FilmError> {
        if (other.width, other.height) != (self.width, self.height) {
            return Err(FilmError::SizeMismatch(
                other.width,
                other.height,
                self.width,
                self.height,
            ));
        }
        if other.filter != self.filter {
            return Err(FilmError::FilterMismatch(other.filter, self.filter));
        }
        for (sum, o) in self.sums.iter_mut().zip(&other.sums) {
            *sum += *o;
        }
        for (weight, o) in self.weights.iter_mut().zip(&other.weights) {
            *weight += o;
        }
        self.note_brightest(other.brightest);
        Ok(())
    }
}

/// The brighter of two brightness values by their bit patterns (see [`Film::note_brightest`]).
fn brighter(a: f64, b: f64) -> f64 {
    f64::from_bits(a.to_bits().max(b.to_bits()))
}
