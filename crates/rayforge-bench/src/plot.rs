//! The scaling plot: time per primary ray against triangle count (log x axis), one line per
//! tracer, drawn by plotters into an RGB buffer and encoded as a PNG.
//!
//! The x axis is the triangle count's base-10 logarithm, so the whole decades are its ticks
//! (labelled `1k`, `10k`, `1M`) and the steps from 2 to 9 of each its light grid lines. The
//! text uses DejaVu Sans, embedded by the `dejavu` crate and registered once with plotters.

use image::RgbImage;
use plotters::prelude::*;
use plotters::style::FontStyle;
use rayforge_cli::failure::Failure;
use std::sync::OnceLock;

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
const HEIGHT: u32 = 600;
/// The band at the top holding the title and the subtitle.
const HEADER: u32 = 80;
/// Where the title and subtitle start: above the plot area's left edge.
const TEXT_LEFT: i32 = 100;

const INK: RGBColor = RGBColor(30, 30, 30);
const SUBTITLE: RGBColor = RGBColor(90, 90, 90);
const GRID: RGBColor = RGBColor(225, 225, 225);
const MINOR_GRID: RGBColor = RGBColor(240, 240, 240);

/// The font family plotters draws every label with (its default, `sans-serif`), registered
/// with the embedded DejaVu Sans before the first plot.
fn register_font() -> Result<(), Failure> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .is_ok()
    });
    match ok {
        true => Ok(()),
        false => Err(Failure::internal(
            "the embedded DejaVu Sans font is invalid",
        )),
    }
}

/// Draws the plot as a PNG file's bytes.
pub fn png(title: &str, subtitle: &str, series: &[Series]) -> Result<Vec<u8>, Failure> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    draw(title, subtitle, series)?
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| Failure::internal(format!("PNG encoding failed: {e}")))?;
    Ok(bytes.into_inner())
}

/// The plot as an image.
pub fn draw(title: &str, subtitle: &str, series: &[Series]) -> Result<RgbImage, Failure> {
    register_font()?;
    let mut buffer = vec![0u8; (WIDTH * HEIGHT * 3) as usize];
    draw_into(&mut buffer, title, subtitle, series)
        .map_err(|e| Failure::internal(format!("drawing the scaling plot failed: {e}")))?;
    Ok(RgbImage::from_raw(WIDTH, HEIGHT, buffer).expect("the buffer is WIDTH × HEIGHT RGB"))
}

/// Draws onto a `WIDTH` × `HEIGHT` RGB buffer.
fn draw_into(
    buffer: &mut [u8],
    title: &str,
    subtitle: &str,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    let points = || series.iter().flat_map(|s| s.points.iter().copied());
    let (x_lo, x_hi) = decades(points().map(|p| p.0));
    let (y_max, y_step) = nice_axis(points().map(|p| p.1).fold(0.0, f64::max));

    let root = BitMapBackend::with_buffer(buffer, (WIDTH, HEIGHT)).into_drawing_area();
    root.fill(&WHITE)?;
    let (header, body) = root.split_vertically(HEADER);
    header.draw(&Text::new(
        title.to_string(),
        (TEXT_LEFT, 14),
        ("sans-serif", 26).into_font().color(&INK),
    ))?;
    header.draw(&Text::new(
        subtitle.to_string(),
        (TEXT_LEFT, 46),
        ("sans-serif", 20).into_font().color(&SUBTITLE),
    ))?;

    let mut chart = ChartBuilder::on(&body)
        .margin_top(10)
        .margin_left(10)
        .margin_right(30)
        .margin_bottom(10)
        .x_label_area_size(60)
        .y_label_area_size(90)
        .build_cartesian_2d(x_lo..x_hi, 0.0..y_max)?;
    let decade_count = (x_hi - x_lo).round() as usize;
    let y_ticks = (y_max / y_step).round() as usize + 1;
    let x_label = |v: &f64| count_label(10f64.powf(*v));
    let y_label = |v: &f64| number_label(*v, y_step);
    chart
        .configure_mesh()
        .x_labels(decade_count + 1)
        .y_labels(y_ticks)
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .max_light_lines(0)
        .bold_line_style(GRID)
        .axis_style(ShapeStyle::from(INK).stroke_width(2))
        .label_style(("sans-serif", 20).into_font().color(&INK))
        .axis_desc_style(("sans-serif", 20).into_font().color(&INK))
        .x_desc("triangles (log scale)")
        .y_desc("ns per ray")
        .draw()?;
    // Light grid lines at 2..9 times each decade: the marks of a log axis.
    for decade in 0..decade_count {
        for m in 2..10 {
            let x = x_lo + decade as f64 + (m as f64).log10();
            chart.draw_series(LineSeries::new([(x, 0.0), (x, y_max)], MINOR_GRID))?;
        }
    }

    for s in series {
        let mut pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|p| p.0 > 0.0)
            .map(|&(t, ns)| (t.log10(), ns))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let color = RGBColor(s.color[0], s.color[1], s.color[2]);
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(3)))?
            .label(s.name.as_str())
            .legend(move |(x, y)| {
                Rectangle::new([(x - 12, y - 3), (x + 16, y + 3)], color.filled())
            });
        chart
            .draw_series(pts.iter().map(|&p| {
                EmptyElement::at(p) + Rectangle::new([(-5, -5), (6, 6)], color.filled())
            }))?;
    }
    // The legend goes top left, where the lines start low.
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .margin(20)
        .label_font(("sans-serif", 20).into_font().color(&INK))
        .background_style(WHITE.mix(0.9))
        .border_style(GRID)
        .draw()?;
    root.present()?;
    Ok(())
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
    fn the_plot_draws_its_series_in_their_colours_and_its_text() {
        let s = Series {
            name: "rayforge".into(),
            color: [200, 40, 40],
            points: vec![(1e3, 100.0), (1e7, 200.0)],
        };
        let img = draw("time per primary ray", "1920×1080 rays", &[s]).unwrap();
        assert_eq!(img.dimensions(), (WIDTH, HEIGHT));
        let red = img.pixels().filter(|p| p.0 == [200, 40, 40]).count();
        assert!(red > 500, "{red}");
        // The title's band holds text: dark pixels where there is no line or grid.
        let header_ink = (0..HEADER)
            .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0.iter().all(|&c| c < 100))
            .count();
        assert!(header_ink > 200, "{header_ink}");
    }

    #[test]
    fn an_empty_plot_still_draws_its_axes() {
        let img = draw("t", "s", &[]).unwrap();
        assert!(img.pixels().any(|p| p.0 == [30, 30, 30]));
    }
}
