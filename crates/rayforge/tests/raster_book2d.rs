//! Computer Graphics from Scratch's own 2D drawing (`raster::book2d`) and the canvas items that
//! use it (`raster::Overlay`): the book's coordinates, its `Interpolate`, `DrawLine`,
//! `DrawFilledTriangle` and `DrawShadedTriangle` to the pixel. The expected pixels are worked
//! out by hand from the book's pseudocode.

use glam::{DVec2, DVec3};
use rayforge::camera::Viewport;
use rayforge::raster::book2d::{
    draw_filled_triangle, draw_line, draw_shaded_triangle, draw_wireframe_triangle, interpolate,
};
use rayforge::raster::{CanvasItem, CanvasPoint, Overlay, TriangleStyle};
use rayforge::{Camera, Canvas, Color};

const INK: Color = Color::WHITE;

fn p(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

/// The inked pixels, as (column, row), row by row.
fn inked(canvas: &Canvas) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            if canvas.pixel_at(x, y) != Color::BLACK {
                out.push((x, y));
            }
        }
    }
    out
}

/// A pixel as the image file stores it.
fn bytes(c: Color) -> [u8; 3] {
    c.to_array().map(|v| (v * 255.0).round() as u8)
}

/// The pixels of the book's `DrawLine(a, b)` on a 10 × 10 canvas (origin at column 5, row 4).
fn line(a: DVec2, b: DVec2) -> Vec<(usize, usize)> {
    let mut c = Canvas::new(10, 10);
    draw_line(&mut c, a, b, INK);
    inked(&c)
}

#[test]
fn interpolate_adds_the_slope_once_per_step_as_the_book_does() {
    let values: Vec<f64> = interpolate(0.0, 0.0, 4.0, 2.0).collect();
    assert_eq!(values, [0.0, 0.5, 1.0, 1.5, 2.0]);
    // Ten additions of 0.1 fall short of 1 by a rounding step: the book's list ends there, not
    // at d1.
    let tenths: Vec<f64> = interpolate(0.0, 0.0, 10.0, 1.0).collect();
    assert_eq!(tenths.len(), 11);
    let mut sum = 0.0;
    for _ in 0..10 {
        sum += 0.1;
    }
    assert_eq!(tenths[10], sum);
    assert_ne!(tenths[10], 1.0);
}

#[test]
fn interpolate_gives_d0_alone_when_i0_equals_i1_and_nothing_when_i1_is_smaller() {
    assert_eq!(interpolate(3.0, 7.0, 3.0, 9.0).collect::<Vec<_>>(), [7.0]);
    assert_eq!(interpolate(4.0, 7.0, 3.0, 9.0).count(), 0);
    assert_eq!(interpolate(f64::NAN, 7.0, 3.0, 9.0).count(), 0);
    // Fractional ends step by ones from i0: ⌊i1 − i0⌋ + 1 values.
    assert_eq!(interpolate(0.5, 0.0, 3.4, 1.0).count(), 3);
}

#[test]
fn put_pixel_puts_the_origin_at_the_centre_with_y_up_and_floors() {
    // One point: DrawLine from a point to itself draws it.
    assert_eq!(line(p(0.0, 0.0), p(0.0, 0.0)), [(5, 4)]);
    assert_eq!(line(p(-5.0, -5.0), p(-5.0, -5.0)), [(0, 9)]);
    assert_eq!(line(p(4.0, 4.0), p(4.0, 4.0)), [(9, 0)]);
    // Floors, not truncation: -0.5 is pixel -1 (one row down, one column left of the origin).
    assert_eq!(line(p(-0.5, -0.5), p(-0.5, -0.5)), [(4, 5)]);
    // Off the canvas: nothing.
    assert!(line(p(5.0, 0.0), p(5.0, 0.0)).is_empty());
    assert!(line(p(0.0, 5.0), p(0.0, 5.0)).is_empty());
}

#[test]
fn a_shallow_line_steps_along_x_and_a_steep_one_along_y() {
    // y = x/2 from (0, 0) to (4, 2): 0, 0.5, 1, 1.5, 2, floored.
    assert_eq!(
        line(p(0.0, 0.0), p(4.0, 2.0)),
        [(9, 2), (7, 3), (8, 3), (5, 4), (6, 4)]
    );
    // x = y/4 from (0, 0) to (1, 4): one pixel in every row.
    assert_eq!(
        line(p(0.0, 0.0), p(1.0, 4.0)),
        [(6, 0), (5, 1), (5, 2), (5, 3), (5, 4)]
    );
}

#[test]
fn a_line_drawn_from_either_end_sets_the_same_pixels() {
    for (a, b) in [
        (p(0.0, 0.0), p(4.0, 2.0)),
        (p(-4.0, -2.0), p(0.0, 0.0)),
        (p(-3.0, 4.0), p(2.0, -5.0)),
        (p(-5.0, -1.0), p(4.0, 3.0)),
    ] {
        assert_eq!(line(a, b), line(b, a), "{a} → {b}");
    }
    // Below the origin, y = -2, -1.5, -1, -0.5, 0 floor to -2, -2, -1, -1, 0 (truncation
    // would give -2, -1, -1, 0, 0).
    assert_eq!(
        line(p(0.0, 0.0), p(-4.0, -2.0)),
        [(5, 4), (3, 5), (4, 5), (1, 6), (2, 6)]
    );
}

#[test]
fn the_books_steep_line_has_exactly_one_pixel_in_every_row() {
    // The second line of the book's figure "raster-02", on its 600 × 600 canvas.
    let mut c = Canvas::new(600, 600);
    draw_line(&mut c, p(-50.0, -200.0), p(60.0, 240.0), INK);
    let pixels = inked(&c);
    assert_eq!(pixels.len(), 441);
    for (row, pair) in (59..=499).zip(pixels.windows(2)) {
        assert_eq!(pair[0].1, row);
        assert!(pair[1].0.abs_diff(pair[0].0) <= 1, "{pair:?}");
    }
    assert_eq!(pixels[0], (360, 59), "the top end, (60, 240)");
    assert_eq!(pixels[440], (250, 499), "the bottom end, (-50, -200)");
}

#[test]
fn a_filled_triangle_covers_each_row_from_its_left_side_to_its_right_inclusive() {
    // Corners (0, 0), (4, 0), (0, 4): the short sides give x = 4, 3, 2, 1, 0 on rows 0 to 4, the
    // long side x = 0: rows of 5, 4, 3, 2 and 1 pixels, the diagonal side included.
    let mut c = Canvas::new(10, 10);
    draw_filled_triangle(&mut c, [p(0.0, 0.0), p(4.0, 0.0), p(0.0, 4.0)], INK);
    let pixels = inked(&c);
    assert_eq!(pixels.len(), 15);
    let row_lengths: Vec<usize> = (0..5)
        .map(|y| pixels.iter().filter(|q| q.1 == 4 - y).count())
        .collect();
    assert_eq!(row_lengths, [5, 4, 3, 2, 1]);
    assert!(pixels.iter().all(|&(x, y)| x >= 5 && y <= 4));
}

#[test]
fn the_books_triangles_sharing_a_side_both_draw_it() {
    // Unlike the exact coverage of the 3D pipeline, the book's scanlines include both ends:
    // two triangles making a square draw their shared diagonal twice (here, in two colours,
    // the second wins).
    let mut c = Canvas::new(10, 10);
    let red = Color::new(1.0, 0.0, 0.0);
    let blue = Color::new(0.0, 0.0, 1.0);
    draw_filled_triangle(&mut c, [p(0.0, 0.0), p(4.0, 0.0), p(0.0, 4.0)], red);
    let first = inked(&c);
    draw_filled_triangle(&mut c, [p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)], blue);
    let both = inked(&c);
    assert_eq!(both.len(), 25, "the 5 × 5 square");
    let redrawn = first
        .iter()
        .filter(|&&(x, y)| c.pixel_at(x, y) == blue)
        .count();
    assert_eq!(redrawn, 5, "the diagonal x + y = 4");
}

#[test]
fn a_wireframe_triangle_is_its_three_sides() {
    let corners = [p(-4.0, -4.0), p(3.0, -4.0), p(-4.0, 3.0)];
    let mut c = Canvas::new(10, 10);
    draw_wireframe_triangle(&mut c, corners, INK);
    let mut sides = Canvas::new(10, 10);
    draw_line(&mut sides, corners[0], corners[1], INK);
    draw_line(&mut sides, corners[1], corners[2], INK);
    draw_line(&mut sides, corners[2], corners[0], INK);
    assert_eq!(inked(&c), inked(&sides));
    // Two legs of 8 pixels and a diagonal of 8, sharing the three corners.
    assert_eq!(inked(&c).len(), 21);
}

#[test]
fn a_shaded_triangle_blends_h_down_its_sides_and_across_each_row() {
    // Corners (0, 0) with h = 0, (4, 0) with h = 1, (0, 4) with h = 0: on the bottom row h runs
    // 0, 0.25, 0.5, 0.75, 1 from left to right; times 255 and rounded: 0, 64, 128, 191, 255.
    let mut c = Canvas::new(10, 10);
    draw_shaded_triangle(
        &mut c,
        [p(0.0, 0.0), p(4.0, 0.0), p(0.0, 4.0)],
        [0.0, 1.0, 0.0],
        Color::new(0.0, 1.0, 0.0),
    );
    let bottom: Vec<u8> = (5..10).map(|x| bytes(c.pixel_at(x, 4))[1]).collect();
    assert_eq!(bottom, [0, 64, 128, 191, 255]);
    // The row y = 1 runs from x = 0 (h 0) to x = 3 (h 0.75): x = 1 has h 0.25.
    assert_eq!(bytes(c.pixel_at(6, 3)), [0, 64, 0]);
}

#[test]
fn shaded_channels_round_halves_up_as_the_books_figure_does() {
    // 0.3 × 255 is exactly 76.5 in binary floating point; the book's figure "raster-04" has 77
    // at the corner with h = 0.3.
    let mut c = Canvas::new(4, 4);
    draw_shaded_triangle(
        &mut c,
        [p(-2.0, -2.0), p(-2.0, -2.0), p(-2.0, -2.0)],
        [0.3, 0.3, 0.3],
        Color::new(0.0, 1.0, 0.0),
    );
    assert_eq!(bytes(c.pixel_at(0, 3)), [0, 77, 0]);
}

#[test]
fn shapes_reaching_far_beyond_the_canvas_draw_only_their_visible_part() {
    // A billion pixels either way: the drawing stops at the canvas, and skips what lies before
    // it, instead of stepping through every pixel.
    let mut c = Canvas::new(10, 10);
    draw_line(&mut c, p(-1e15, 0.0), p(1e15, 0.0), INK);
    assert_eq!(inked(&c).len(), 10, "row 4, across");
    let mut c = Canvas::new(10, 10);
    draw_filled_triangle(&mut c, [p(-1e12, -1e12), p(1e12, -1e12), p(0.0, 1e12)], INK);
    assert_eq!(inked(&c).len(), 100, "the whole canvas");
    let mut c = Canvas::new(10, 10);
    draw_shaded_triangle(
        &mut c,
        [p(-1e12, -1e12), p(1e12, -1e12), p(0.0, 1e12)],
        [1.0; 3],
        INK,
    );
    assert_eq!(inked(&c).len(), 100);
    // Not-a-number draws nothing rather than anything odd.
    let mut c = Canvas::new(10, 10);
    draw_line(&mut c, p(f64::NAN, 0.0), p(3.0, 1.0), INK);
    draw_filled_triangle(&mut c, [p(f64::NAN, 0.0), p(3.0, 1.0), p(0.0, 4.0)], INK);
    assert!(inked(&c).len() <= 5, "at most the finite corner's rows");
}

/// The book's camera: a 600 × 600 canvas on a 1 × 1 viewport at distance 1.
fn book_camera(size: usize) -> Camera {
    Camera::viewport(size, size, Viewport::BOOK).expect("the book's viewport")
}

#[test]
fn a_projected_point_lands_where_the_books_project_vertex_puts_it() {
    // (-2, -0.5, 5) projects to (-2/5 · 600, -0.5/5 · 600) = (-240, -60): column 60, row 359.
    let point = CanvasPoint::Projected(DVec3::new(-2.0, -0.5, 5.0));
    let overlay = Overlay::new(
        vec![CanvasItem::Line {
            from: point,
            to: point,
            color: INK,
        }],
        600,
        600,
    );
    let mut c = Canvas::new(600, 600);
    overlay.draw(&mut c, &book_camera(600));
    assert_eq!(inked(&c), [(60, 359)]);
}

#[test]
fn canvas_coordinates_scale_with_the_image_and_projected_points_follow_the_camera() {
    let items = vec![
        CanvasItem::Triangle {
            points: [
                CanvasPoint::Canvas(DVec2::new(-200.0, -200.0)),
                CanvasPoint::Canvas(DVec2::new(200.0, -200.0)),
                CanvasPoint::Canvas(DVec2::new(0.0, 200.0)),
            ],
            color: INK,
            style: TriangleStyle::Filled,
        },
        CanvasItem::Line {
            from: CanvasPoint::Projected(DVec3::new(0.25, 0.0, 1.0)),
            to: CanvasPoint::Projected(DVec3::new(0.25, 0.0, 1.0)),
            color: Color::new(1.0, 0.0, 0.0),
        },
    ];
    let overlay = Overlay::new(items, 600, 600);
    // At a third of the size the triangle spans a third as many rows and the point lands a
    // third as far from the centre: (50, 0), column 150, row 99.
    let mut c = Canvas::new(200, 200);
    overlay.draw(&mut c, &book_camera(200));
    let rows: std::collections::BTreeSet<usize> = inked(&c).iter().map(|q| q.1).collect();
    assert_eq!(rows.len(), 134, "rows -66.7 to 66.7, the ends floored");
    assert_eq!(c.pixel_at(150, 99), Color::new(1.0, 0.0, 0.0));
}

#[test]
fn points_projected_to_infinity_draw_without_hanging_or_panicking() {
    // A point a hair in front of the eye projects beyond any f64: the line towards it is
    // drawn as far as the arithmetic goes, and returns at once.
    let far = CanvasPoint::Projected(DVec3::new(1e10, 1e10, 1e-300));
    let near = CanvasPoint::Projected(DVec3::new(0.0, 0.0, 1.0));
    let items = vec![
        CanvasItem::Line {
            from: far,
            to: near,
            color: INK,
        },
        CanvasItem::Triangle {
            points: [far, near, CanvasPoint::Canvas(DVec2::new(-1e300, 1e300))],
            color: INK,
            style: TriangleStyle::Shaded([1.0, 0.5, 0.0]),
        },
    ];
    let mut c = Canvas::new(60, 60);
    Overlay::new(items, 60, 60).draw(&mut c, &book_camera(60));
    assert!(c
        .pixels()
        .iter()
        .all(|p| p.to_array().iter().all(|v| v.is_finite())));
}
