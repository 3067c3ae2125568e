//! Triangle coverage: which pixel centres a triangle covers, decided exactly.
//!
//! The book fills a triangle scanline by scanline with `Interpolate`, which draws the pixels of
//! an edge shared by two triangles twice (and, rounded differently on each side, can leave
//! gaps). Here coverage is decided by three *edge functions* evaluated at pixel centres, on
//! vertices snapped to a grid of `1/2^bits` pixel so that the arithmetic is exact integer
//! arithmetic: two triangles sharing an edge compute the same values with opposite signs. A
//! centre that lies exactly on an edge belongs to the triangle for which that edge is a *top* or
//! *left* edge (Direct3D's rule), so a mesh covers every pixel once: no gaps, no double draws.

/// Subpixel bits used unless the image is too large for them (see [`subpixel_bits`]).
pub const SUBPIXEL_BITS: u32 = 8;

/// The subpixel precision for an image of `width × height`: 8 bits, fewer on images so large
/// that edge-function sums would overflow 64 bits (coordinates stay within ±2^29 grid units,
/// so edge coefficients are below 2^30, products below 2^59 and the sums below 2^61).
pub fn subpixel_bits(width: usize, height: usize) -> u32 {
    let largest = (width.max(height) as u64 + 4)
        .next_power_of_two()
        .trailing_zeros();
    29u32.saturating_sub(largest).clamp(1, SUBPIXEL_BITS)
}

/// A point on the subpixel grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FixedPoint {
    /// x in units of `1/2^bits` pixel.
    pub x: i64,
    /// y in units of `1/2^bits` pixel.
    pub y: i64,
}

impl FixedPoint {
    /// A point in pixel coordinates (pixel `(x, y)` spans `[x, x+1) × [y, y+1)`) snapped to
    /// the grid. Coordinates are clamped to `±2^(29-bits)` pixels, beyond any image (a triangle
    /// reaching further is drawn with its corner moved in).
    pub fn from_pixels(x: f64, y: f64, bits: u32) -> Self {
        let scale = (1u64 << bits) as f64;
        Self {
            x: snap(x * scale),
            y: snap(y * scale),
        }
    }
}

/// Grid units to the nearest grid point, halves away from zero (`f64::round`), clamped to
/// `±2^29`; NaN becomes 0.
///
/// Rounded by hand: `f64::round` is a library call on the baseline x86-64 target (no
/// `roundsd` before SSE4.1), and every vertex of a frame is snapped. Clamping first changes
/// nothing (the limit is whole), and within it the value less its truncation is exact, so this
/// is `round` to the bit (tested).
#[inline]
fn snap(units: f64) -> i64 {
    let limit = (1u64 << 29) as f64;
    // `clamp` keeps NaN, which the cast turns into 0, as every comparison below is false.
    let clamped = units.clamp(-limit, limit);
    let whole = clamped as i64;
    let fraction = clamped - whole as f64;
    whole + i64::from(fraction >= 0.5) - i64::from(fraction <= -0.5)
}

/// Twice the signed area of `a b c` on the grid: positive when `c` lies on the side of `a → b`
/// that the edge function counts as inside.
#[inline]
pub fn orient(a: FixedPoint, b: FixedPoint, c: FixedPoint) -> i64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// An inclusive rectangle of pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelRect {
    /// Leftmost column.
    pub x0: i64,
    /// Top row.
    pub y0: i64,
    /// Rightmost column (inclusive).
    pub x1: i64,
    /// Bottom row (inclusive).
    pub y1: i64,
}

impl PixelRect {
    /// The whole of a `width × height` image.
    pub fn image(width: usize, height: usize) -> Self {
        Self {
            x0: 0,
            y0: 0,
            x1: width as i64 - 1,
            y1: height as i64 - 1,
        }
    }

    /// The overlap of two rectangles (possibly empty).
    pub fn intersect(&self, o: &Self) -> Self {
        Self {
            x0: self.x0.max(o.x0),
            y0: self.y0.max(o.y0),
            x1: self.x1.min(o.x1),
            y1: self.y1.min(o.y1),
        }
    }

    /// Whether no pixel is inside.
    pub fn is_empty(&self) -> bool {
        self.x0 > self.x1 || self.y0 > self.y1
    }
}

/// The pixels whose centres lie in the box `min..=max` on the grid.
pub fn pixel_bounds(min: FixedPoint, max: FixedPoint, bits: u32) -> PixelRect {
    let one = 1i64 << bits;
    let half = one >> 1;
    // Pixel x's centre is at x·one + half: the first centre at or after min, the last at or
    // before max. (Floor division by `one` is the arithmetic shift, which saves a division
    // instruction per bound: this runs for every triangle and again in every tile it touches.)
    PixelRect {
        x0: (min.x - half + one - 1) >> bits,
        y0: (min.y - half + one - 1) >> bits,
        x1: (max.x - half) >> bits,
        y1: (max.y - half) >> bits,
    }
}

/// One edge function `w(p) = a·p.x + b·p.y + c`, with the tie-break bias of the fill rule.
#[derive(Debug, Clone, Copy)]
struct Edge {
    a: i64,
    b: i64,
    c: i64,
    /// 0 on top and left edges (centres on them are inside), -1 on the others.
    bias: i64,
}

impl Edge {
    /// The edge `from → to`, positive on the triangle's side.
    fn new(from: FixedPoint, to: FixedPoint) -> Self {
        let (dx, dy) = (to.x - from.x, to.y - from.y);
        // In y-down screen space with the triangle on the positive side: a top edge is
        // horizontal with the triangle below it; a left edge has the triangle to its right.
        let top_left = (dy == 0 && dx > 0) || dy < 0;
        Self {
            a: -dy,
            b: dx,
            c: dy * from.x - dx * from.y,
            bias: if top_left { 0 } else { -1 },
        }
    }

    #[inline]
    fn at(&self, x: i64, y: i64) -> i64 {
        self.a * x + self.b * y + self.c
    }
}

/// A triangle ready for coverage: its edges, oriented so that the inside is positive.
#[derive(Debug, Clone, Copy)]
pub struct Coverage {
    /// Edge opposite each vertex, in the caller's vertex order.
    edges: [Edge; 3],
    /// Twice the area, positive.
    area2: i64,
    /// Bounding box on the grid.
    min: FixedPoint,
    max: FixedPoint,
    bits: u32,
}

impl Coverage {
    /// Sets up `v0 v1 v2` (either winding); `None` when the area is zero (nothing is covered).
    pub fn new(v: [FixedPoint; 3], bits: u32) -> Option<Self> {
        let area2 = orient(v[0], v[1], v[2]);
        if area2 == 0 {
            return None;
        }
        // The edge opposite vertex i runs from i+1 to i+2; reversing the winding reverses
        // every edge so that the inside stays positive.
        let edge = |i: usize| {
            let (from, to) = (v[(i + 1) % 3], v[(i + 2) % 3]);
            if area2 > 0 {
                Edge::new(from, to)
            } else {
                Edge::new(to, from)
            }
        };
        Some(Self {
            edges: [edge(0), edge(1), edge(2)],
            area2: area2.abs(),
            min: FixedPoint {
                x: v[0].x.min(v[1].x).min(v[2].x),
                y: v[0].y.min(v[1].y).min(v[2].y),
            },
            max: FixedPoint {
                x: v[0].x.max(v[1].x).max(v[2].x),
                y: v[0].y.max(v[1].y).max(v[2].y),
            },
            bits,
        })
    }

    /// Twice the triangle's area in grid units squared.
    pub fn area2(&self) -> i64 {
        self.area2
    }

    /// The pixels whose centres could be covered: those inside the bounding box.
    pub fn bounds(&self) -> PixelRect {
        pixel_bounds(self.min, self.max, self.bits)
    }

    /// Calls `visit(x, y, w)` for every covered pixel inside `rect`, row by row, where `w` are
    /// the edge functions at the pixel's centre in the caller's vertex order: `w[i] / area2`
    /// is the pixel's barycentric weight of vertex `i` on the screen.
    #[inline]
    pub fn for_each_pixel(&self, rect: PixelRect, mut visit: impl FnMut(i64, i64, [i64; 3])) {
        let r = self.bounds().intersect(&rect);
        if r.is_empty() {
            return;
        }
        let one = 1i64 << self.bits;
        let half = one >> 1;
        let (cx, cy) = (r.x0 * one + half, r.y0 * one + half);
        let mut row = self.edges.map(|e| e.at(cx, cy));
        let step_x = self.edges.map(|e| e.a * one);
        let step_y = self.edges.map(|e| e.b * one);
        let bias = self.edges.map(|e| e.bias);
        // Half-open ranges: an inclusive range's iterator checks an extra flag at every step,
        // and this loop runs for every pixel of every triangle's box (`r` lies in that box, on
        // a grid of at most 2^29 units, so `x1 + 1` cannot overflow).
        for y in r.y0..r.y1 + 1 {
            let mut w = row;
            for x in r.x0..r.x1 + 1 {
                if (w[0] + bias[0]) | (w[1] + bias[1]) | (w[2] + bias[2]) >= 0 {
                    visit(x, y, w);
                }
                for i in 0..3 {
                    w[i] += step_x[i];
                }
            }
            for i in 0..3 {
                row[i] += step_y[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{pixel_bounds, snap, FixedPoint};

    #[test]
    fn pixel_bounds_shift_is_floor_division() {
        for bits in 1..=8u32 {
            let one = 1i64 << bits;
            let half = one >> 1;
            for v in -3 * one..3 * one {
                let p = FixedPoint { x: v, y: -v };
                let r = pixel_bounds(p, p, bits);
                assert_eq!(r.x0, (v - half + one - 1).div_euclid(one));
                assert_eq!(r.y0, (-v - half + one - 1).div_euclid(one));
                assert_eq!(r.x1, (v - half).div_euclid(one));
                assert_eq!(r.y1, (-v - half).div_euclid(one));
            }
        }
    }

    /// The rule as written before it was rounded by hand: `round`, then clamp.
    fn by_round(units: f64) -> i64 {
        let limit = (1u64 << 29) as f64;
        let s = units.round();
        if s.is_nan() {
            0
        } else {
            s.clamp(-limit, limit) as i64
        }
    }

    #[test]
    fn snapping_by_hand_is_round_to_the_bit() {
        let limit = (1u64 << 29) as f64;
        let mut values = vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            limit,
            -limit,
            limit + 0.5,
            -limit - 0.5,
            limit - 0.5,
            -limit + 0.5,
            1e300,
            -1e300,
        ];
        // Every half step and its neighbours on either side, over a range of magnitudes.
        for whole in (-2000i64..2000).chain([1 << 20, -(1 << 20), 123_456_789, -123_456_789]) {
            for v in [whole as f64, whole as f64 + 0.5, whole as f64 - 0.5] {
                values.extend([v, v.next_up(), v.next_down()]);
            }
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            values.push(((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 4.0 * limit);
        }
        for v in values {
            assert_eq!(snap(v), by_round(v), "{v:e}");
        }
    }
}
