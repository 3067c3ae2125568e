//! The rasterizer's 2D primitives, part one (the book's "Lines" chapter): `Interpolate` and
//! `DrawLine` at every slope, both directions.

use glam::IVec2;
use rayforge::raster::{draw_line, draw_wireframe_triangle, interpolate};
use rayforge::{Canvas, Color};

const INK: Color = Color::WHITE;

/// The set pixels of a canvas, row by row.
fn lit(canvas: &Canvas) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            if canvas.pixel_at(x, y) == INK {
                out.push((x, y));
            }
        }
    }
    out
}

fn line(x0: i32, y0: i32, x1: i32, y1: i32) -> Vec<(usize, usize)> {
    let mut c = Canvas::new(12, 12);
    draw_line(&mut c, IVec2::new(x0, y0), IVec2::new(x1, y1), INK);
    lit(&c)
}

#[test]
fn interpolate_gives_one_value_per_step_ending_exactly_at_d1() {
    let values: Vec<f64> = interpolate(0, 0.0, 4, 2.0).collect();
    assert_eq!(values, [0.0, 0.5, 1.0, 1.5, 2.0]);
    let values: Vec<f64> = interpolate(3, 10.0, 6, 0.0).collect();
    assert_eq!(values.len(), 4);
    assert_eq!(values[3], 0.0);
    assert!((values[1] - 20.0 / 3.0).abs() < 1e-12);
}

#[test]
fn interpolate_a_single_value() {
    assert_eq!(interpolate(5, 7.0, 5, 9.0).collect::<Vec<_>>(), [7.0]);
    assert_eq!(
        interpolate(6, 7.0, 5, 9.0).count(),
        0,
        "i1 < i0 yields nothing"
    );
}

#[test]
fn a_shallow_line_has_one_pixel_per_column() {
    // y = 0.4·x, rounded: 0, 0.4, 0.8, 1.2, 1.6, 2.0.
    assert_eq!(
        line(0, 0, 5, 2),
        [(0, 0), (1, 0), (2, 1), (3, 1), (4, 2), (5, 2)]
    );
}

#[test]
fn a_steep_line_has_one_pixel_per_row() {
    // x = 2 + (y - 1)/3 for y = 1..=7: 2, 2.33, 2.67, 3, 3.33, 3.67, 4, rounded.
    let pixels = line(2, 1, 4, 7);
    assert_eq!(
        pixels,
        [(2, 1), (2, 2), (3, 3), (3, 4), (3, 5), (4, 6), (4, 7)]
    );
}

#[test]
fn reversing_the_endpoints_draws_the_same_pixels() {
    for (x0, y0, x1, y1) in [
        (0, 0, 5, 2),
        (2, 1, 4, 7),
        (1, 9, 10, 3),
        (7, 0, 0, 11),
        (0, 0, 9, 9),
    ] {
        assert_eq!(
            line(x0, y0, x1, y1),
            line(x1, y1, x0, y0),
            "{x0},{y0} → {x1},{y1}"
        );
    }
}

#[test]
fn lines_at_forty_five_degrees_horizontal_and_vertical() {
    assert_eq!(line(1, 1, 4, 4), [(1, 1), (2, 2), (3, 3), (4, 4)]);
    assert_eq!(line(3, 5, 0, 5), [(0, 5), (1, 5), (2, 5), (3, 5)]);
    assert_eq!(line(2, 3, 2, 0), [(2, 0), (2, 1), (2, 2), (2, 3)]);
    assert_eq!(line(6, 6, 6, 6), [(6, 6)]);
}

#[test]
fn a_line_with_negative_slope_rounds_halves_away_from_zero() {
    // From (0, 4) to (4, 2): y = 4 - x/2 → 4, 3.5, 3, 2.5, 2 → 4, 4, 3, 3, 2 (listed by row).
    assert_eq!(line(0, 4, 4, 2), [(4, 2), (2, 3), (3, 3), (0, 4), (1, 4)]);
}

#[test]
fn lines_leaving_the_canvas_are_cut_off() {
    let pixels = line(-3, 2, 14, 2);
    assert_eq!(pixels.len(), 12);
    assert!(pixels.iter().all(|&(_, y)| y == 2));
}

#[test]
fn a_wireframe_triangle_is_its_three_edges() {
    let mut c = Canvas::new(12, 12);
    let (a, b, d) = (IVec2::new(1, 1), IVec2::new(9, 1), IVec2::new(1, 9));
    draw_wireframe_triangle(&mut c, a, b, d, INK);
    let pixels = lit(&c);
    assert!(pixels.contains(&(5, 1)) && pixels.contains(&(1, 5)) && pixels.contains(&(5, 5)));
    assert!(!pixels.contains(&(3, 3)), "the inside stays empty");
    // Top edge 9 pixels, left edge 9, the diagonal 9, corners shared: 24.
    assert_eq!(pixels.len(), 24);
}

#[test]
fn a_line_with_far_away_endpoints_draws_only_its_visible_part_quickly() {
    let mut c = Canvas::new(12, 12);
    // Two billion columns long, but only twelve of them are on the canvas.
    draw_line(
        &mut c,
        IVec2::new(-1_000_000_000, 5),
        IVec2::new(1_000_000_000, 5),
        INK,
    );
    assert_eq!(lit(&c).len(), 12);
    // The extremes of the coordinate type do not overflow.
    let mut c = Canvas::new(12, 12);
    draw_line(
        &mut c,
        IVec2::new(i32::MIN, 3),
        IVec2::new(i32::MAX, 3),
        INK,
    );
    assert_eq!(lit(&c).len(), 12);
}
