//! The one-line summary printed after a render: size, time, ray throughput, output file.

use std::path::Path;
use std::time::Duration;

/// E.g. `rendered 1080×1080 in 2.31 s, 4.1 M rays/s (9.5 M rays) → cover.png`.
pub fn summary_line(
    width: usize,
    height: usize,
    elapsed: Duration,
    rays: u64,
    output: &Path,
) -> String {
    let seconds = elapsed.as_secs_f64();
    // A render too quick to time has no meaningful rate; a nanosecond floor keeps it finite.
    let rate = rays as f64 / seconds.max(1e-9);
    format!(
        "rendered {width}×{height} in {seconds:.2} s, {} rays/s ({} rays) → {}",
        si(rate),
        si(rays as f64),
        output.display()
    )
}

/// E.g. `rasterized 1920×1080 in 0.21 s, 1.0 M triangles (480.2 k drawn) → out.png`.
pub fn raster_summary_line(
    width: usize,
    height: usize,
    elapsed: Duration,
    triangles: u64,
    drawn: u64,
    output: &Path,
) -> String {
    format!(
        "rasterized {width}×{height} in {:.2} s, {} triangles ({} drawn) → {}",
        elapsed.as_secs_f64(),
        si(triangles as f64),
        si(drawn as f64),
        output.display()
    )
}

/// E.g. `path traced 256×256 at 64 spp in 3.104 s, 1.4 M samples/s (21.0 M rays) → out.pfm`.
/// The time is given to the millisecond: a small render takes a tenth of a second, and to
/// hundredths its rate (which `rayforge bench pbr` reads back) would be off by up to 5 %.
pub fn path_summary_line(
    width: usize,
    height: usize,
    spp: u64,
    elapsed: Duration,
    samples: u64,
    rays: u64,
    output: &Path,
) -> String {
    let rate = samples as f64 / elapsed.as_secs_f64().max(1e-9);
    format!(
        "path traced {width}×{height} at {spp} spp in {:.3} s, {} samples/s ({} rays) → {}",
        elapsed.as_secs_f64(),
        si(rate),
        si(rays as f64),
        output.display()
    )
}

/// The warning after a render whose image had pixels that were not finite numbers (see
/// [`crate::finite`]), naming the file they were written to; `None` when there were none.
pub fn non_finite_warning(pixels: usize, output: &Path) -> Option<String> {
    let (count, were) = match pixels {
        0 => return None,
        1 => ("1 pixel".to_string(), "was"),
        n => (format!("{n} pixels"), "were"),
    };
    Some(format!(
        "warning: {count} of `{}` {were} not finite (NaN or infinite) and {were} written as 0",
        output.display()
    ))
}

/// A count with an SI prefix and one decimal: `4.1 M`, `950.0 k`, `12`.
fn si(v: f64) -> String {
    match v {
        v if v >= 1e9 => format!("{:.1} G", v / 1e9),
        v if v >= 1e6 => format!("{:.1} M", v / 1e6),
        v if v >= 1e3 => format!("{:.1} k", v / 1e3),
        v => format!("{v:.0}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_reads_like_the_example() {
        let line = summary_line(
            1080,
            1080,
            Duration::from_millis(2310),
            9_500_000,
            Path::new("cover.png"),
        );
        assert_eq!(
            line,
            "rendered 1080×1080 in 2.31 s, 4.1 M rays/s (9.5 M rays) → cover.png"
        );
    }

    #[test]
    fn the_raster_summary_counts_triangles() {
        let line = raster_summary_line(
            1920,
            1080,
            Duration::from_millis(210),
            1_000_000,
            480_200,
            Path::new("out.png"),
        );
        assert_eq!(
            line,
            "rasterized 1920×1080 in 0.21 s, 1.0 M triangles (480.2 k drawn) → out.png"
        );
    }

    #[test]
    fn non_finite_pixels_are_counted_in_a_warning() {
        assert_eq!(non_finite_warning(0, Path::new("o.pfm")), None);
        assert_eq!(
            non_finite_warning(3, Path::new("o.pfm")).unwrap(),
            "warning: 3 pixels of `o.pfm` were not finite (NaN or infinite) and were written as 0"
        );
        assert_eq!(
            non_finite_warning(1, Path::new("o.png")).unwrap(),
            "warning: 1 pixel of `o.png` was not finite (NaN or infinite) and was written as 0"
        );
    }

    #[test]
    fn counts_take_si_prefixes() {
        assert_eq!(si(12.0), "12");
        assert_eq!(si(950_000.0), "950.0 k");
        assert_eq!(si(2.5e9), "2.5 G");
    }
}
