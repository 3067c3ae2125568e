//! Lines (the book's "Lines" chapter): `Interpolate` and `DrawLine`, and wireframe triangles.
//!
//! Coordinates are the canvas's own: pixel `(0, 0)` is the top-left one, y grows downwards (the
//! book centres its canvas and points y up; the algorithm does not care).

use crate::canvas::Canvas;
use crate::color::Color;
use glam::IVec2;

/// The book's `Interpolate(i0, d0, i1, d1)`: the values of the linear function with
/// `f(i0) = d0` and `f(i1) = d1` at `i = i0, i0 + 1, …, i1`, as an iterator (no list is
/// allocated). When `i0 == i1` it yields `d0` once, as the book special-cases.
///
/// Each value is computed from the ends (`d0 + (d1 - d0)·(i - i0)/(i1 - i0)`) rather than by
/// adding the slope repeatedly, so the last value is exactly `d1` and no rounding error
/// accumulates along a long line.
pub fn interpolate(i0: i32, d0: f64, i1: i32, d1: f64) -> Interpolate {
    let count = if i0 == i1 {
        1
    } else {
        (i1 as i64 - i0 as i64 + 1).max(0) as usize
    };
    Interpolate {
        next: 0,
        count,
        span: (i1 as i64 - i0 as i64) as f64,
        d0,
        d1,
    }
}

/// The values of [`interpolate`].
#[derive(Debug, Clone)]
pub struct Interpolate {
    next: usize,
    count: usize,
    span: f64,
    d0: f64,
    d1: f64,
}

impl Iterator for Interpolate {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        if self.next >= self.count {
            return None;
        }
        let k = self.next as f64;
        self.next += 1;
        Some(if self.span == 0.0 {
            self.d0
        } else {
            self.d0 + (self.d1 - self.d0) * (k / self.span)
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.count - self.next;
        (n, Some(n))
    }
}

impl ExactSizeIterator for Interpolate {}

/// The book's `DrawLine(P0, P1, color)`: one pixel per column for lines closer to horizontal,
/// one per row otherwise, the other coordinate interpolated and rounded to the nearest pixel
/// (halves away from zero). The endpoints are put in order first, so drawing `P1 → P0` sets
/// exactly the pixels of `P0 → P1`. Pixels off the canvas are skipped.
pub fn draw_line(canvas: &mut Canvas, p0: IVec2, p1: IVec2, color: Color) {
    let (w, h) = (canvas.width() as i64, canvas.height() as i64);
    // Only the part of the line over the canvas is walked, however far the endpoints lie.
    line_pixels_in(p0, p1, Some((0, 0, w - 1, h - 1)), |x, y| {
        if (0..w).contains(&x) && (0..h).contains(&y) {
            canvas.write_pixel(x as usize, y as usize, color);
        }
    });
}

/// The book's `DrawWireframeTriangle`: the three edges.
pub fn draw_wireframe_triangle(canvas: &mut Canvas, p0: IVec2, p1: IVec2, p2: IVec2, color: Color) {
    draw_line(canvas, p0, p1, color);
    draw_line(canvas, p1, p2, color);
    draw_line(canvas, p2, p0, color);
}

/// The pixels of the line `p0 → p1` whose independent coordinate lies in `span` (when given):
/// the wireframe pass draws only the part of a long line that crosses its tile, computing
/// exactly the pixels the whole line would have there; `draw_line` likewise walks only the
/// canvas.
pub(crate) fn line_pixels_in(
    p0: IVec2,
    p1: IVec2,
    span: Option<(i64, i64, i64, i64)>,
    mut visit: impl FnMut(i64, i64),
) {
    // In 64 bits: the difference of two i32 coordinates may not fit in 32.
    let (p0, p1) = (p0.as_i64vec2(), p1.as_i64vec2());
    let (dx, dy) = ((p1.x - p0.x).abs(), (p1.y - p0.y).abs());
    if dx > dy {
        // Horizontal-ish: x is the independent variable; make sure x0 < x1.
        let (a, b) = if p0.x > p1.x { (p1, p0) } else { (p0, p1) };
        let (lo, hi) = span.map_or((a.x, b.x), |(x0, _, x1, _)| (a.x.max(x0), b.x.min(x1)));
        for x in lo..=hi {
            let t = (x - a.x) as f64 / (b.x - a.x) as f64;
            let y = (a.y as f64 + (b.y - a.y) as f64 * t).round() as i64;
            visit(x, y);
        }
    } else {
        // Vertical-ish (or a single point): y is the independent variable; y0 <= y1.
        let (a, b) = if p0.y > p1.y { (p1, p0) } else { (p0, p1) };
        let (lo, hi) = span.map_or((a.y, b.y), |(_, y0, _, y1)| (a.y.max(y0), b.y.min(y1)));
        for y in lo..=hi {
            let x = if a.y == b.y {
                a.x
            } else {
                let t = (y - a.y) as f64 / (b.y - a.y) as f64;
                (a.x as f64 + (b.x - a.x) as f64 * t).round() as i64
            };
            visit(x, y);
        }
    }
}
