//! Developing: the steps from a film to the [`Canvas`] the image encoders take, all here.
//!
//! 1. Resolve: each pixel's sum of weighted colours divided by its sum of weights; a pixel
//!    with no weight (no usable sample) is black.
//! 2. With [`Exposure::Automatic`], the optics model's finishing (Fundamentals of Ray Tracing):
//!    pixels with no usable sample (their rays met ties between two surfaces) are filled from
//!    their neighbours, then the image is exposed by its brightest channel and quantised to the
//!    255 steps of an 8-bit image.
//!
//! The canvas keeps linear, unclamped colours: clamping to bytes is each encoder's last step
//! ([`Canvas::to_rgb8`], [`Canvas::to_ppm`]), and a float format (PFM) takes the colours as
//! they are.

use super::Film;
use crate::canvas::Canvas;
use crate::color::Color;

/// How a developed image is exposed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Exposure {
    /// The colours as the renderer computed them (the book's lighting models).
    #[default]
    Fixed,
    /// The optics model's: pixels with no usable sample repaired from their neighbours, then
    /// every channel divided by the brightest one (of any sample, or of any pixel if larger).
    Automatic,
}

/// The film's image: resolved, then exposed as asked (see the module's documentation).
pub fn develop(film: &Film, exposure: Exposure) -> Canvas {
    let mut canvas = film.resolve();
    if exposure == Exposure::Automatic {
        repair_empty(&mut canvas, film);
        expose(&mut canvas, film.brightest());
    }
    canvas
}

/// Develops, in place, a canvas whose every pixel is one sample of weight 1 and whose film
/// noted no brighter sample (what the rasterizer draws): the same colours, to the bit, as
/// [`develop`] of [`Film::from_canvas`] of it, without the film's two copies of the image.
pub fn develop_in_place(canvas: &mut Canvas, exposure: Exposure) {
    if exposure == Exposure::Automatic {
        // No pixel lacks weight, so there is nothing to repair.
        expose(canvas, 0.0);
    }
}

impl Film {
    /// Each pixel's sum of weighted colours divided by its sum of weights (black where the
    /// weight is 0). A pixel of one sample at weight 1 is that sample's colour, to the bit.
    pub fn resolve(&self) -> Canvas {
        let pixels = self
            .sums
            .iter()
            .zip(&self.weights)
            .map(|(&sum, &weight)| {
                if weight == 0.0 {
                    Color::BLACK
                } else {
                    sum / weight
                }
            })
            .collect();
        Canvas::from_pixels(self.width, self.height, pixels)
    }
}

/// Fills each pixel with no weight with the average of its 3 × 3 neighbours that have weight
/// (black when none has), as the book "airbrushes" ambiguous pixels.
fn repair_empty(canvas: &mut Canvas, film: &Film) {
    let (width, height) = (canvas.width(), canvas.height());
    let is_empty = |i: usize| film.weights[i] == 0.0;
    for i in (0..width * height).filter(|&i| is_empty(i)) {
        let (x, y) = (i % width, i / width);
        let mut sum = Color::BLACK;
        let mut found = 0.0;
        for ny in y.saturating_sub(1)..=(y + 1).min(height - 1) {
            for nx in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                if !is_empty(ny * width + nx) {
                    sum += canvas.pixel_at(nx, ny);
                    found += 1.0;
                }
            }
        }
        if found > 0.0 {
            canvas.write_pixel(x, y, sum / found);
        }
    }
}

/// Divides every channel by the brightest one, `brightest` (of all the samples taken, which
/// can exceed any averaged pixel) or the brightest pixel if that is larger, then truncates to
/// the 255 steps of an 8-bit image, as the book's `ConvertPixelValue` does. An all-black image
/// stays black.
fn expose(canvas: &mut Canvas, brightest: f64) {
    let brightest_pixel = canvas
        .pixels()
        .iter()
        .map(|c| c.red.max(c.green).max(c.blue))
        .fold(0.0, f64::max);
    let max = brightest.max(brightest_pixel);
    if !(max > 0.0 && max.is_finite()) {
        return;
    }
    let step = |v: f64| ((255.0 * v / max) as i64).clamp(0, 255) as f64 / 255.0;
    for c in canvas.pixels_mut() {
        *c = Color::new(step(c.red), step(c.green), step(c.blue));
    }
}
