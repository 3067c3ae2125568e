//! The optics model's finishing (Fundamentals of Ray Tracing): pixels whose rays met ties are
//! filled from their neighbours, then the image is exposed automatically.

use crate::{Canvas, Color};

/// Fills each listed pixel (sorted indices) with the average of its 3 × 3 neighbours that are
/// not listed themselves (black when all are), as the book "airbrushes" ambiguous pixels.
pub fn repair_ambiguous(canvas: &mut Canvas, ambiguous: &[usize]) {
    let (width, height) = (canvas.width(), canvas.height());
    let is_ambiguous = |i: usize| ambiguous.binary_search(&i).is_ok();
    for &i in ambiguous {
        let (x, y) = (i % width, i / width);
        let mut sum = Color::BLACK;
        let mut found = 0.0;
        for ny in y.saturating_sub(1)..=(y + 1).min(height - 1) {
            for nx in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                if !is_ambiguous(ny * width + nx) {
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
pub fn expose(canvas: &mut Canvas, brightest: f64) {
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
