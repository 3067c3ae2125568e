//! Chapter 2: the canvas and its PPM encoding.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
use rayforge::color::color;
use rayforge::Canvas;

#[test]
fn creating_a_canvas() {
    let c = Canvas::new(10, 20);
    assert_eq!((c.width(), c.height()), (10, 20));
    assert!(c.pixels().iter().all(|p| *p == color(0.0, 0.0, 0.0)));
}

#[test]
fn writing_pixels_to_a_canvas() {
    let mut c = Canvas::new(10, 20);
    let red = color(1.0, 0.0, 0.0);
    c.write_pixel(2, 3, red);
    assert_eq!(c.pixel_at(2, 3), red);
}

#[test]
fn constructing_the_ppm_header() {
    let ppm = Canvas::new(5, 3).to_ppm();
    let lines: Vec<&str> = ppm.lines().take(3).collect();
    assert_eq!(lines, ["P3", "5 3", "255"]);
}

/// SEED-NOTES.md erratum 2: the seed prints 16 or 17 numbers per row; a 5-pixel row has 15.
#[test]
fn constructing_the_ppm_pixel_data() {
    let mut c = Canvas::new(5, 3);
    c.write_pixel(0, 0, color(1.5, 0.0, 0.0));
    c.write_pixel(2, 1, color(0.0, 0.5, 0.0));
    c.write_pixel(4, 2, color(-0.5, 0.0, 1.0));
    let ppm = c.to_ppm();
    let lines: Vec<&str> = ppm.lines().skip(3).take(3).collect();
    assert_eq!(
        lines,
        [
            "255 0 0 0 0 0 0 0 0 0 0 0 0 0 0",
            "0 0 0 0 0 0 0 128 0 0 0 0 0 0 0",
            "0 0 0 0 0 0 0 0 0 0 0 0 0 0 255",
        ]
    );
}

/// SEED-NOTES.md erratum 3: each 30-number row splits 17 + 13 (the seed's line breaks are off).
#[test]
fn splitting_long_lines_in_ppm_files() {
    let mut c = Canvas::new(10, 2);
    for p in c.pixels_mut() {
        *p = color(1.0, 0.8, 0.6);
    }
    let ppm = c.to_ppm();
    let lines: Vec<&str> = ppm.lines().skip(3).take(4).collect();
    let first = "255 204 153 255 204 153 255 204 153 255 204 153 255 204 153 255 204";
    let second = "153 255 204 153 255 204 153 255 204 153 255 204 153";
    assert_eq!(lines, [first, second, first, second]);
    assert!(ppm.lines().all(|l| l.len() <= 70));
}

#[test]
fn ppm_files_are_terminated_by_a_newline_character() {
    assert!(Canvas::new(5, 3).to_ppm().ends_with('\n'));
}
