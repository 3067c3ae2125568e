//! The canvas (chapter 2): a grid of linear colours, and the book's PPM (P3) encoding.

use crate::color::Color;
use std::fmt::Write as _;

/// A width × height grid of colours, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Canvas {
    width: usize,
    height: usize,
    pixels: Vec<Color>,
}

/// PPM lines must not exceed 70 characters (the format's rule, which the book enforces).
const PPM_MAX_LINE: usize = 70;

impl Canvas {
    /// A black canvas.
    pub fn new(width: usize, height: usize) -> Self {
        Self::from_pixels(width, height, vec![Color::BLACK; width * height])
    }

    /// A canvas over existing pixels, row-major from the top-left.
    ///
    /// # Panics
    /// When `pixels.len() != width * height`.
    pub fn from_pixels(width: usize, height: usize, pixels: Vec<Color>) -> Self {
        assert_eq!(pixels.len(), width * height, "pixel count must match size");
        Self {
            width,
            height,
            pixels,
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

    /// The book's `pixel_at(canvas, x, y)`.
    pub fn pixel_at(&self, x: usize, y: usize) -> Color {
        self.pixels[y * self.width + x]
    }

    /// The book's `write_pixel(canvas, x, y, color)`.
    pub fn write_pixel(&mut self, x: usize, y: usize, color: Color) {
        self.pixels[y * self.width + x] = color;
    }

    /// All pixels, row-major.
    pub fn pixels(&self) -> &[Color] {
        &self.pixels
    }

    /// Mutable access to all pixels, row-major (the render loop fills rows in parallel).
    pub fn pixels_mut(&mut self) -> &mut [Color] {
        &mut self.pixels
    }

    /// The pixels, row-major, without a copy.
    pub fn into_pixels(self) -> Vec<Color> {
        self.pixels
    }

    /// Pixels as 8-bit RGB, each channel scaled by 255, rounded and clamped (the book's rule).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|c| c.to_array().map(to_byte))
            .collect()
    }

    /// The book's `canvas_to_ppm`: a P3 file with lines of at most 70 characters and a final newline.
    pub fn to_ppm(&self) -> String {
        let mut out = format!("P3\n{} {}\n255\n", self.width, self.height);
        for row in self.pixels.chunks(self.width.max(1)) {
            let mut line = String::new();
            for value in row.iter().flat_map(|c| c.to_array().map(to_byte)) {
                let mut word = String::new();
                let _ = write!(word, "{value}");
                if !line.is_empty() && line.len() + 1 + word.len() > PPM_MAX_LINE {
                    out.push_str(&line);
                    out.push('\n');
                    line.clear();
                }
                if !line.is_empty() {
                    line.push(' ');
                }
                line.push_str(&word);
            }
            out.push_str(&line);
            out.push('\n');
        }
        out
    }
}

/// One channel to a byte: scaled by 255, rounded (halves away from zero), clamped to
/// [0, 255]. NaN becomes 0.
///
/// Rounded by hand: `f64::round` is a library call on the baseline x86-64 target (no
/// `roundsd` before SSE4.1), a tenth of a small rasterized frame. Within [0, 255] the scaled
/// value less its truncation is exact, so this is `round` to the bit.
#[inline]
fn to_byte(channel: f64) -> u8 {
    let scaled = channel * 255.0;
    if scaled.is_nan() || scaled <= 0.0 {
        0
    } else if scaled >= 255.0 {
        255
    } else {
        let whole = scaled as u8;
        whole + u8::from(scaled - f64::from(whole) >= 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::to_byte;

    /// The rule as written before it was rounded by hand: scale, `round`, clamp.
    fn by_round(channel: f64) -> u8 {
        let scaled = (channel * 255.0).round();
        if scaled.is_nan() {
            0
        } else {
            scaled.clamp(0.0, 255.0) as u8
        }
    }

    #[test]
    fn a_channel_rounds_to_its_byte_as_round_does() {
        let mut values = vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -0.0,
            0.0,
            -1.0,
            2.0,
            1.0,
            0.5,
        ];
        // Every step's midpoint and its neighbours a few ulps away on both sides.
        for k in 0..=256 {
            let half = (k as f64 + 0.5) / 255.0;
            let mut below = half;
            let mut above = half;
            for _ in 0..4 {
                below = below.next_down();
                above = above.next_up();
                values.extend([below, above]);
            }
            values.extend([half, k as f64 / 255.0]);
        }
        values.extend((0..100_000).map(|i| i as f64 / 99_999.0 * 1.2 - 0.1));
        for v in values {
            assert_eq!(to_byte(v), by_round(v), "channel {v:e}");
        }
    }
}
