//! The canvas (chapter 2): a grid of linear colours, and the book's PPM (P3) encoding.

use crate::color::Color;
use std::fmt::Write as _;

/// A width × height grid of colours, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
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

/// One channel to a byte: scaled by 255, rounded, clamped to [0, 255]. NaN becomes 0.
fn to_byte(channel: f64) -> u8 {
    let scaled = (channel * 255.0).round();
    if scaled.is_nan() {
        0
    } else {
        scaled.clamp(0.0, 255.0) as u8
    }
}
