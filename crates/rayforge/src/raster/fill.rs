//! Filled and shaded triangles on a canvas (the book's "Filled triangles" and "Shaded
//! triangles" chapters), with the exact coverage rule of [`edge`](super::edge) instead of the
//! book's scanlines, so that triangles sharing an edge neither overlap nor leave gaps.
//!
//! Points are in pixel coordinates: pixel `(x, y)` spans `[x, x+1) × [y, y+1)` and is drawn
//! when its centre `(x + 0.5, y + 0.5)` is inside the triangle.

use super::edge::{Coverage, FixedPoint, PixelRect, SUBPIXEL_BITS};
use crate::canvas::Canvas;
use crate::color::Color;
use glam::DVec2;

/// The book's `DrawFilledTriangle(P0, P1, P2, color)`, either winding.
pub fn draw_filled_triangle(canvas: &mut Canvas, p0: DVec2, p1: DVec2, p2: DVec2, color: Color) {
    fill(canvas, [p0, p1, p2], |_| color);
}

/// The book's `DrawShadedTriangle`: `color` scaled by an intensity given at each vertex
/// (`h0`, `h1`, `h2`) and blended linearly across the screen.
pub fn draw_shaded_triangle(
    canvas: &mut Canvas,
    points: [DVec2; 3],
    intensities: [f64; 3],
    color: Color,
) {
    fill(canvas, points, |w| {
        color * (w[0] * intensities[0] + w[1] * intensities[1] + w[2] * intensities[2])
    });
}

/// Writes `shade(weights)` at every covered pixel, `weights` being the pixel centre's
/// barycentric coordinates.
fn fill(canvas: &mut Canvas, points: [DVec2; 3], shade: impl Fn([f64; 3]) -> Color) {
    let v = points.map(|p| FixedPoint::from_pixels(p.x, p.y, SUBPIXEL_BITS));
    let Some(coverage) = Coverage::new(v, SUBPIXEL_BITS) else {
        return;
    };
    let area = coverage.area2() as f64;
    let rect = PixelRect::image(canvas.width(), canvas.height());
    coverage.for_each_pixel(rect, |x, y, w| {
        let weights = w.map(|wi| wi as f64 / area);
        canvas.write_pixel(x as usize, y as usize, shade(weights));
    });
}
