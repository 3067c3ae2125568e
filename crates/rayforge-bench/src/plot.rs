//! The scaling plot: time per primary ray against triangle count (log x axis), one line per
//! tracer, drawn pixel by pixel into a PNG with the bitmap font of `font.rs`.

use super::font::{descends, glyph, ADVANCE, DESCENT, HEIGHT};
use crate::failure::Failure;
use image::{Rgb, RgbImage};

/// One line of the plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// The legend's name for it.
    pub name: String,
    /// Its colour.
    pub color: [u8; 3],
    /// (triangles, nanoseconds per ray), any order.
    pub points: Vec<(f64, f64)>,
}

const WIDTH: u32 = 960;
const HEIGHT_PX: u32 = 600;
/// The plot area inside the margins that hold the title, the ticks' labels and the legend.
const LEFT: i64 = 100;
const RIGHT: i64 = 930;
const TOP: i64 = 110;
const BOTTOM: i64 = 525;
/// Labels are drawn at twice the font's size.
const SCALE: u32 = 2;

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const INK: Rgb<u8> = Rgb([30, 30, 30]);
const GRID: Rgb<u8> = Rgb([225, 225, 225]);

/// Draws the plot as a PNG file's bytes.
pub fn png(title: &str, subtitle: &str, series: &[Series]) -> Result<Vec<u8>, Failure> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    draw(title, subtitle, series)
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| Failure::internal(format!("PNG encoding failed: {e}")))?;
    Ok(bytes.into_inner())
}

/// The plot as an image.
pub fn draw(title: &str, subtitle: &str, series: &[Series]) -> RgbImage {
    let mut img = RgbImage::from_pixel(WIDTH, HEIGHT_PX, WHITE);
    let points = || series.iter().flat_map(|s| s.points.iter().copied());
    let (x_lo, x_hi) = decades(points().map(|p| p.0));
    let (y_max, y_step) = nice_axis(points().map(|p| p.1).fold(0.0, f64::max));
    let px = |t: f64| LEFT as f64 + (t.log10() - x_lo) / (x_hi - x_lo) * (RIGHT - LEFT) as f64;
    let py = |v: f64| BOTTOM as f64 - v / y_max * (BOTTOM - TOP) as f64;

    text(&mut img, LEFT, 14, title, INK);
    text(&mut img, LEFT, 40, subtitle, Rgb([90, 90, 90]));

    // Vertical grid and x ticks at every decade, with minor ticks at 2..9 of each.
    let mut decade = x_lo;
    while decade <= x_hi + 1e-9 {
        let x = px(10f64.powf(decade)).round() as i64;
        line(&mut img, (x, TOP), (x, BOTTOM), GRID, 1);
        line(&mut img, (x, BOTTOM), (x, BOTTOM + 8), INK, 2);
        let label = count_label(10f64.powf(decade));
        let w = text_width(&label) as i64;
        text(&mut img, x - w / 2, BOTTOM + 14, &label, INK);
        if decade < x_hi {
            for m in 2..10 {
                let x = px(10f64.powf(decade) * m as f64).round() as i64;
                line(&mut img, (x, BOTTOM), (x, BOTTOM + 4), INK, 1);
            }
        }
        decade += 1.0;
    }
    // Horizontal grid and y ticks.
    let mut v = 0.0;
    while v <= y_max + y_step * 1e-6 {
        let y = py(v).round() as i64;
        line(&mut img, (LEFT, y), (RIGHT, y), GRID, 1);
        line(&mut img, (LEFT - 8, y), (LEFT, y), INK, 2);
        let label = number_label(v, y_step);
        let w = text_width(&label) as i64;
        text(
            &mut img,
            LEFT - 14 - w,
            y - (HEIGHT * SCALE / 2) as i64,
            &label,
            INK,
        );
        v += y_step;
    }
    // The axes and their names.
    line(&mut img, (LEFT, TOP), (LEFT, BOTTOM), INK, 2);
    line(&mut img, (LEFT, BOTTOM), (RIGHT, BOTTOM), INK, 2);
    let x_name = "triangles (log scale)";
    text(
        &mut img,
        (LEFT + RIGHT) / 2 - text_width(x_name) as i64 / 2,
        BOTTOM + 44,
        x_name,
        INK,
    );
    text(&mut img, 8, TOP - 30, "ns per ray", INK);

    // The series, then the legend in the top right corner.
    for s in series {
        let mut pts = s.points.clone();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let color = Rgb(s.color);
        let to_px = |p: &(f64, f64)| (px(p.0).round() as i64, py(p.1).round() as i64);
        for pair in pts.windows(2) {
            line(&mut img, to_px(&pair[0]), to_px(&pair[1]), color, 3);
        }
        for p in &pts {
            let (x, y) = to_px(p);
            fill_rect(&mut img, x - 5, y - 5, 11, 11, color);
        }
    }
    // The legend goes top left, where the lines start low.
    let mut y = TOP + 12;
    for s in series {
        let x = LEFT + 60;
        fill_rect(&mut img, x - 40, y + 4, 28, 6, Rgb(s.color));
        text(&mut img, x, y, &s.name, INK);
        y += 26;
    }
    img
}

/// The whole decades spanning the values, as exponents (at least one decade wide).
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    // A value a few percent off a power of ten (972 triangles, 10.002 M) belongs to that
    // decade's tick, not to a whole decade more of empty axis.
    let (lo, hi) = ((lo.log10() + 0.05).floor(), (hi.log10() - 0.05).ceil());
    (lo, hi.max(lo + 1.0))
}

/// A top for the y axis above `max` and a step of 1, 2 or 5 times a power of ten that gives
/// four to eight ticks.
fn nice_axis(max: f64) -> (f64, f64) {
    let max = if max > 0.0 && max.is_finite() {
        max * 1.1
    } else {
        1.0
    };
    let raw = max / 5.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    ((max / step).ceil() * step, step)
}

/// `1k`, `10k`, `1M`: a triangle count on the x axis.
fn count_label(v: f64) -> String {
    match v {
        v if v >= 1e6 => format!("{}M", (v / 1e6).round()),
        v if v >= 1e3 => format!("{}k", (v / 1e3).round()),
        v => format!("{}", v.round()),
    }
}

/// A tick value with as many decimals as the step needs.
fn number_label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10().floor()) as usize
    };
    format!("{v:.decimals$}")
}

fn text_width(s: &str) -> u32 {
    s.chars().count() as u32 * ADVANCE * SCALE
}

/// Draws `s` with its top-left corner at (x, y); characters the font lacks are left blank.
fn text(img: &mut RgbImage, x: i64, y: i64, s: &str, color: Rgb<u8>) {
    for (i, c) in s.chars().enumerate() {
        let Some(rows) = glyph(c) else { continue };
        let cx = x + (i as u32 * ADVANCE * SCALE) as i64;
        let y = if descends(c) {
            y + (DESCENT * SCALE) as i64
        } else {
            y
        };
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..5 {
                if bits & (1 << (4 - col)) != 0 {
                    fill_rect(
                        img,
                        cx + (col * SCALE) as i64,
                        y + (r as u32 * SCALE) as i64,
                        SCALE,
                        SCALE,
                        color,
                    );
                }
            }
        }
    }
}

fn fill_rect(img: &mut RgbImage, x: i64, y: i64, w: u32, h: u32, color: Rgb<u8>) {
    for yy in y.max(0)..(y + h as i64).min(img.height() as i64) {
        for xx in x.max(0)..(x + w as i64).min(img.width() as i64) {
            img.put_pixel(xx as u32, yy as u32, color);
        }
    }
}

/// A line `thickness` pixels wide (Bresenham's walk, stamping a square at each step).
fn line(img: &mut RgbImage, from: (i64, i64), to: (i64, i64), color: Rgb<u8>, thickness: u32) {
    let (mut x, mut y) = from;
    let (dx, dy) = ((to.0 - x).abs(), -(to.1 - y).abs());
    let (sx, sy) = ((to.0 - x).signum(), (to.1 - y).signum());
    let mut err = dx + dy;
    let half = thickness as i64 / 2;
    loop {
        fill_rect(img, x - half, y - half, thickness, thickness, color);
        if (x, y) == to {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_take_whole_decades_and_round_steps() {
        assert_eq!(decades([1_002.0, 9_990_000.0].into_iter()), (3.0, 7.0));
        assert_eq!(decades([972.0, 10_002_828.0].into_iter()), (3.0, 7.0));
        assert_eq!(decades([500.0].into_iter()), (2.0, 3.0));
        assert_eq!(nice_axis(430.0), (500.0, 100.0));
        assert_eq!(nice_axis(0.0), (1.0, 0.2));
        assert_eq!(count_label(1e7), "10M");
        assert_eq!(number_label(0.4, 0.2), "0.4");
    }

    #[test]
    fn the_plot_draws_its_series_in_their_colours() {
        let s = Series {
            name: "rayforge".into(),
            color: [200, 40, 40],
            points: vec![(1e3, 100.0), (1e7, 200.0)],
        };
        let img = draw("time per primary ray", "1920×1080 rays", &[s]);
        let red = img.pixels().filter(|p| p.0 == [200, 40, 40]).count();
        assert!(red > 500, "{red}");
        assert_eq!(img.dimensions(), (WIDTH, HEIGHT_PX));
    }
}
