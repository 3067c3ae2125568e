//! Computer Graphics from Scratch's own 2D drawing, to the pixel: `Interpolate`, `PutPixel`,
//! `DrawLine`, `DrawWireframeTriangle`, `DrawFilledTriangle` and `DrawShadedTriangle` as the
//! book's chapters "Lines", "Filled triangles" and "Shaded triangles" write them and its demos
//! (`demos/raster-02.html` … `raster-05.html` in the author's repository) run them. Scenes
//! draw with them through canvas items (`add: canvas-line`, `add: canvas-triangle`, see
//! [`Overlay`](super::overlay::Overlay)), so that the book's figures come out pixel for pixel.
//!
//! Why not the rasterizer's `draw_line` and `draw_filled_triangle`: those serve the 3D
//! pipeline, and are exact where the book approximates: they round lines to the nearest pixel
//! and cover triangles by the top-left rule, so that triangles sharing an edge neither overlap
//! nor leave gaps. The book's scanline triangles do both (each row runs from
//! `x_left` to `x_right` inclusive), its outline does not quite match its fill (the book points
//! this out), and its `Interpolate` adds the slope once per step, so rounding accumulates. To
//! reproduce its figures these functions repeat its arithmetic in its order:
//!
//! - Coordinates are the book's canvas coordinates: the origin at the centre, x to the right,
//!   y up. `PutPixel(x, y)` writes column `⌊Cw/2⌋ + ⌊x⌋`, row `⌊Ch/2⌋ − ⌊y⌋ − 1` (the demos
//!   floor both coordinates) and skips points off the canvas.
//! - Colours are on the book's 0–255 scale (this crate's 1 is 255); a pixel stores each channel
//!   clamped to [0, 255] and rounded to the nearest step, halves up: the book's shaded-triangle
//!   figure ("raster-04") has 77 where `0.3 × 255` is exactly 76.5, at its corner with h = 0.3.
//! - `Interpolate(i0, d0, i1, d1)` yields `d0`, then adds `a = (d1 − d0)/(i1 − i0)` once per
//!   step, for `i = i0, i0 + 1, …` while `i ≤ i1` (`[d0]` alone when `i0 = i1`).
//! - `DrawFilledTriangle` steps x from `x_left` to `x_right` by ones, fractions kept (PutPixel
//!   floors them); `DrawShadedTriangle` truncates both ends to whole numbers first (the demo's
//!   `| 0`) and interpolates `h` between them.
//!
//! Work is bounded by the canvas, not by the coordinates: nothing is stepped beyond the far
//! edge of the canvas, and steps before its near edge are skipped, one addition at a time up to
//! [`EXACT_SKIP`] of them (so the arithmetic stays the book's) and by one multiplication beyond
//! that. A shape however large costs about as much as its visible part.

use crate::canvas::Canvas;
use crate::color::Color;
use glam::DVec2;

/// The most steps of an [`Interpolation`] skipped one addition at a time; more are skipped by
/// one multiplication (`d + k·a`). No shape that starts within a million pixels of the canvas
/// notices; a shape reaching a billion pixels away does not make the drawing take seconds.
pub const EXACT_SKIP: u64 = 1 << 20;

/// The book's `Interpolate(i0, d0, i1, d1)`: `d0`, then the slope added once per step, for
/// `i = i0, i0 + 1, …` while `i ≤ i1`; `d0` alone when `i0 = i1`; nothing when `i1 < i0` (or
/// either is NaN). Lazy: values are computed as they are read, and [`Interpolation::advance`]
/// passes over those that fall off the canvas.
pub fn interpolate(i0: f64, d0: f64, i1: f64, d1: f64) -> Interpolation {
    if i0 == i1 {
        return Interpolation {
            value: d0,
            slope: 0.0,
            left: 1,
        };
    }
    Interpolation {
        value: d0,
        slope: (d1 - d0) / (i1 - i0),
        left: steps(i0, i1),
    }
}

/// How many times the book's `for (i = i0; i <= i1; i++)` runs: ⌊i1 − i0⌋ + 1, or 0.
fn steps(i0: f64, i1: f64) -> u64 {
    let span = i1 - i0;
    // Negative, or NaN.
    if span.is_nan() || span < 0.0 {
        return 0;
    }
    // Far more than any canvas has pixels: the walks below stop at the canvas's edge anyway.
    const MAX_STEPS: f64 = (1u64 << 62) as f64;
    span.min(MAX_STEPS).floor() as u64 + 1
}

/// The values of [`interpolate`], in order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interpolation {
    value: f64,
    slope: f64,
    left: u64,
}

impl Interpolation {
    /// Nothing at all (what a list emptied by the book's `remove_last` leaves).
    const EMPTY: Self = Self {
        value: 0.0,
        slope: 0.0,
        left: 0,
    };

    /// Values not yet read.
    pub fn remaining(&self) -> u64 {
        self.left
    }

    /// Passes over the next `k` values (all that remain, if fewer).
    pub fn advance(&mut self, k: u64) {
        let k = k.min(self.left);
        if k <= EXACT_SKIP {
            for _ in 0..k {
                self.value += self.slope;
            }
        } else {
            self.value += self.slope * k as f64;
        }
        self.left -= k;
    }

    /// The same values without the last one (the book's `remove_last`).
    fn without_last(mut self) -> Self {
        self.left = self.left.saturating_sub(1);
        self
    }
}

impl Iterator for Interpolation {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        if self.left == 0 {
            return None;
        }
        let value = self.value;
        self.value += self.slope;
        self.left -= 1;
        Some(value)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = usize::try_from(self.left).unwrap_or(usize::MAX);
        (n, usize::try_from(self.left).ok())
    }
}

/// One side of a triangle for the scanline loop: the long side `x02`, or the short sides
/// `x01` (its last value removed) followed by `x12`, as the book concatenates them.
#[derive(Debug, Clone, Copy)]
struct Side {
    first: Interpolation,
    then: Interpolation,
}

impl Side {
    fn long(values: Interpolation) -> Self {
        Self {
            first: values,
            then: Interpolation::EMPTY,
        }
    }

    fn short(first: Interpolation, then: Interpolation) -> Self {
        Self {
            first: first.without_last(),
            then,
        }
    }

    fn advance(&mut self, k: u64) {
        let in_first = k.min(self.first.left);
        self.first.advance(in_first);
        self.then.advance(k - in_first);
    }

    fn next(&mut self) -> Option<f64> {
        self.first.next().or_else(|| self.then.next())
    }

    /// The value `k` places ahead, if there is one (the book's `list[k]`).
    fn get(mut self, k: u64) -> Option<f64> {
        self.advance(k);
        self.next()
    }
}

/// A canvas addressed as the book addresses it (see the module's notes).
struct BookCanvas<'a> {
    canvas: &'a mut Canvas,
    /// `⌊Cw/2⌋` and `⌊Ch/2⌋`.
    half: (i64, i64),
}

impl<'a> BookCanvas<'a> {
    fn new(canvas: &'a mut Canvas) -> Self {
        let half = ((canvas.width() / 2) as i64, (canvas.height() / 2) as i64);
        Self { canvas, half }
    }

    /// The book's `PutPixel(x, y, color)`, the colour on the 0–255 scale.
    fn put_pixel(&mut self, x: f64, y: f64, color: [f64; 3]) {
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        // Saturating casts: a coordinate beyond i64 is off the canvas either way.
        let column = self.half.0.saturating_add(x.floor() as i64);
        let row = self
            .half
            .1
            .saturating_sub(y.floor() as i64)
            .saturating_sub(1);
        let (w, h) = (self.canvas.width() as i64, self.canvas.height() as i64);
        if (0..w).contains(&column) && (0..h).contains(&row) {
            let [r, g, b] = color.map(stored_channel);
            self.canvas
                .write_pixel(column as usize, row as usize, Color::new(r, g, b));
        }
    }

    /// The x of the canvas's left edge and of the first column past its right edge, in the
    /// book's coordinates: `x` is drawn when `lo ≤ x < hi`.
    fn columns(&self) -> (f64, f64) {
        let w = self.canvas.width() as i64;
        (-self.half.0 as f64, (w - self.half.0) as f64)
    }

    /// The same for y: `y` is drawn when `lo ≤ y < hi`.
    fn rows(&self) -> (f64, f64) {
        let h = self.canvas.height() as i64;
        ((self.half.1 - h) as f64, self.half.1 as f64)
    }
}

/// A channel as the canvas stores it, on this crate's 0–1 scale: the book's 0–255 value
/// clamped and rounded to a whole step (halves up, as the book's figures). NaN stores 0.
fn stored_channel(v: f64) -> f64 {
    if v.is_nan() {
        return 0.0;
    }
    v.clamp(0.0, 255.0).round() / 255.0
}

/// A colour on the book's 0–255 scale.
fn book_color(color: Color) -> [f64; 3] {
    [color.red * 255.0, color.green * 255.0, color.blue * 255.0]
}

/// The steps `k` of a loop `for (i = start; i <= end; i++)` (`count` of them) whose `i` lies in
/// `[lo, hi)`: the first such step and the first step past them.
fn visible_steps(start: f64, count: u64, (lo, hi): (f64, f64)) -> (u64, u64) {
    // Steps needed to reach `bound` from `start` (0 if already there), at most `count`.
    let reach = |bound: f64| -> u64 {
        let k = (bound - start).ceil();
        if k > 0.0 {
            (k.min(count as f64)) as u64
        } else {
            0
        }
    };
    let first = reach(lo);
    (first, reach(hi).max(first))
}

/// The book's `DrawLine(P0, P1, color)`: for a line closer to horizontal, one pixel per step of
/// x from the left end to the right, y interpolated; otherwise one per step of y from the bottom
/// end up, x interpolated. Both ends are drawn.
pub fn draw_line(canvas: &mut Canvas, p0: DVec2, p1: DVec2, color: Color) {
    let mut canvas = BookCanvas::new(canvas);
    let color = book_color(color);
    let (dx, dy) = (p1.x - p0.x, p1.y - p0.y);
    if dx.abs() > dy.abs() {
        // Horizontal-ish: left to right.
        let (a, b) = if dx < 0.0 { (p1, p0) } else { (p0, p1) };
        let mut ys = interpolate(a.x, a.y, b.x, b.y);
        let (first, end) = visible_steps(a.x, ys.remaining(), canvas.columns());
        ys.advance(first);
        for (k, y) in (first..end).zip(ys) {
            canvas.put_pixel(a.x + k as f64, y, color);
        }
    } else {
        // Vertical-ish (or a single point): bottom to top.
        let (a, b) = if dy < 0.0 { (p1, p0) } else { (p0, p1) };
        let mut xs = interpolate(a.y, a.x, b.y, b.x);
        let (first, end) = visible_steps(a.y, xs.remaining(), canvas.rows());
        xs.advance(first);
        for (k, x) in (first..end).zip(xs) {
            canvas.put_pixel(x, a.y + k as f64, color);
        }
    }
}

/// The book's `DrawWireframeTriangle`: its three sides, as the demo draws them (P0–P1, P1–P2,
/// P0–P2).
pub fn draw_wireframe_triangle(canvas: &mut Canvas, points: [DVec2; 3], color: Color) {
    let [p0, p1, p2] = points;
    draw_line(canvas, p0, p1, color);
    draw_line(canvas, p1, p2, color);
    draw_line(canvas, p0, p2, color);
}

/// The triangle's corners sorted from bottom to top by the book's three swaps, each carrying
/// its intensity.
fn sorted(points: [DVec2; 3], h: [f64; 3]) -> [(DVec2, f64); 3] {
    let mut p = [(points[0], h[0]), (points[1], h[1]), (points[2], h[2])];
    if p[1].0.y < p[0].0.y {
        p.swap(0, 1);
    }
    if p[2].0.y < p[0].0.y {
        p.swap(0, 2);
    }
    if p[2].0.y < p[1].0.y {
        p.swap(1, 2);
    }
    p
}

/// A triangle's rows as the book walks them: the left and right sides' `x` (and `h`) from the
/// bottom row `y0` up.
struct Scanlines {
    y0: f64,
    rows: u64,
    x_left: Side,
    x_right: Side,
    h_left: Side,
    h_right: Side,
}

impl Scanlines {
    fn new(points: [DVec2; 3], h: [f64; 3]) -> Self {
        let [(p0, h0), (p1, h1), (p2, h2)] = sorted(points, h);
        let x02 = Side::long(interpolate(p0.y, p0.x, p2.y, p2.x));
        let h02 = Side::long(interpolate(p0.y, h0, p2.y, h2));
        let x012 = Side::short(
            interpolate(p0.y, p0.x, p1.y, p1.x),
            interpolate(p1.y, p1.x, p2.y, p2.x),
        );
        let h012 = Side::short(
            interpolate(p0.y, h0, p1.y, h1),
            interpolate(p1.y, h1, p2.y, h2),
        );
        // Which is left and which is right, judged in the middle row: `m = x02.length / 2`. A
        // value missing from one list (the demo's `undefined`) compares false.
        let m = steps(p0.y, p2.y) / 2;
        let long_is_left = matches!((x02.get(m), x012.get(m)), (Some(a), Some(b)) if a < b);
        let (x_left, x_right, h_left, h_right) = if long_is_left {
            (x02, x012, h02, h012)
        } else {
            (x012, x02, h012, h02)
        };
        Self {
            y0: p0.y,
            rows: steps(p0.y, p2.y),
            x_left,
            x_right,
            h_left,
            h_right,
        }
    }

    /// Calls `row(y, x_left, x_right, h_left, h_right)` for every row on the canvas, bottom up.
    /// A row where a side has no value (sides of different lengths, from fractional
    /// coordinates) is skipped, as the demo's loop over `undefined` draws nothing.
    fn for_each_visible(mut self, rows: (f64, f64), mut row: impl FnMut(f64, f64, f64, f64, f64)) {
        let (first, end) = visible_steps(self.y0, self.rows, rows);
        for side in [
            &mut self.x_left,
            &mut self.x_right,
            &mut self.h_left,
            &mut self.h_right,
        ] {
            side.advance(first);
        }
        for k in first..end {
            let values = (
                self.x_left.next(),
                self.x_right.next(),
                self.h_left.next(),
                self.h_right.next(),
            );
            if let (Some(xl), Some(xr), Some(hl), Some(hr)) = values {
                row(self.y0 + k as f64, xl, xr, hl, hr);
            }
        }
    }
}

/// The book's `DrawFilledTriangle(P0, P1, P2, color)`: for each row from the lowest corner to
/// the highest, x from the left side to the right side in steps of one.
pub fn draw_filled_triangle(canvas: &mut Canvas, points: [DVec2; 3], color: Color) {
    let mut canvas = BookCanvas::new(canvas);
    let color = book_color(color);
    let (columns, rows) = (canvas.columns(), canvas.rows());
    Scanlines::new(points, [0.0; 3]).for_each_visible(rows, |y, x_left, x_right, _, _| {
        let (first, end) = visible_steps(x_left, steps(x_left, x_right), columns);
        for k in first..end {
            canvas.put_pixel(x_left + k as f64, y, color);
        }
    });
}

/// The book's `DrawShadedTriangle(P0, P1, P2, color)`: `color` times an intensity `h` given at
/// each corner, interpolated along the sides and then along each row, whose ends are truncated
/// to whole numbers first.
pub fn draw_shaded_triangle(canvas: &mut Canvas, points: [DVec2; 3], h: [f64; 3], color: Color) {
    let mut canvas = BookCanvas::new(canvas);
    let color = book_color(color);
    let (columns, rows) = (canvas.columns(), canvas.rows());
    Scanlines::new(points, h).for_each_visible(rows, |y, x_left, x_right, h_left, h_right| {
        // The demo's `x | 0`: towards zero.
        let (xl, xr) = (x_left.trunc(), x_right.trunc());
        let mut h_segment = interpolate(xl, h_left, xr, h_right);
        let (first, end) = visible_steps(xl, h_segment.remaining(), columns);
        h_segment.advance(first);
        for (k, h) in (first..end).zip(h_segment) {
            canvas.put_pixel(xl + k as f64, y, color.map(|c| h * c));
        }
    });
}
