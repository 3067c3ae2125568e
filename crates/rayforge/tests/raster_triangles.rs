//! The rasterizer's 2D primitives, part two (the book's "Filled triangles" and "Shaded
//! triangles"): coverage by pixel centres with the top-left rule, so that triangles sharing
//! edges cover every pixel once.

use glam::DVec2;
use rayforge::raster::edge::{Coverage, FixedPoint, PixelRect, SUBPIXEL_BITS};
use rayforge::raster::{draw_filled_triangle, draw_shaded_triangle};
use rayforge::{Canvas, Color};

const SIZE: usize = 64;

/// How many times each pixel of a `SIZE × SIZE` image is covered by the triangles.
fn coverage_counts(triangles: &[[DVec2; 3]]) -> Vec<u32> {
    let mut counts = vec![0u32; SIZE * SIZE];
    for t in triangles {
        let v = t.map(|p| FixedPoint::from_pixels(p.x, p.y, SUBPIXEL_BITS));
        if let Some(c) = Coverage::new(v, SUBPIXEL_BITS) {
            c.for_each_pixel(PixelRect::image(SIZE, SIZE), |x, y, _| {
                counts[y as usize * SIZE + x as usize] += 1;
            });
        }
    }
    counts
}

/// A grid of `n × n` quads over [lo, hi]², each cut into two triangles along alternating
/// diagonals and with alternating windings; `jitter` moves the inner vertices.
fn grid(n: usize, lo: f64, hi: f64, jitter: impl Fn(usize, usize) -> DVec2) -> Vec<[DVec2; 3]> {
    let step = (hi - lo) / n as f64;
    let at = |i: usize, j: usize| {
        let base = DVec2::new(lo + i as f64 * step, lo + j as f64 * step);
        if i == 0 || j == 0 || i == n || j == n {
            base
        } else {
            base + jitter(i, j)
        }
    };
    let mut out = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            let (t1, t2) = if (i + j) % 2 == 0 {
                ([a, b, c], [a, c, d])
            } else {
                ([a, b, d], [b, c, d])
            };
            out.push(t1);
            // Reverse every other triangle's winding: coverage must not depend on it.
            out.push(if i % 3 == 0 {
                [t2[0], t2[2], t2[1]]
            } else {
                t2
            });
        }
    }
    out
}

/// Pixels whose centres lie inside [lo, hi]² are covered once; those outside never.
fn assert_covered_once(counts: &[u32], lo: f64, hi: f64) {
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
            let inside = cx > lo && cx < hi && cy > lo && cy < hi;
            let on_border = cx == lo || cx == hi || cy == lo || cy == hi;
            let n = counts[y * SIZE + x];
            if inside {
                assert_eq!(n, 1, "pixel ({x}, {y}) covered {n} times");
            } else if !on_border {
                assert_eq!(n, 0, "pixel ({x}, {y}) outside covered {n} times");
            }
        }
    }
}

#[test]
fn a_grid_with_vertices_on_pixel_centres_covers_each_pixel_once() {
    // Edges run exactly through pixel centres: every tie goes to exactly one triangle.
    let tris = grid(12, 2.5, 62.5, |_, _| DVec2::ZERO);
    let counts = coverage_counts(&tris);
    assert_covered_once(&counts, 2.5, 62.5);
    // Centres on the outer border: the top and left borders are drawn, the others not.
    assert_eq!(counts[2 * SIZE + 10], 1, "top border belongs to the mesh");
    assert_eq!(counts[10 * SIZE + 2], 1, "left border belongs to the mesh");
    assert_eq!(counts[62 * SIZE + 10], 0, "bottom border does not");
    assert_eq!(counts[10 * SIZE + 62], 0, "right border does not");
}

#[test]
fn a_jittered_grid_leaves_no_gaps_and_no_double_draws() {
    let tris = grid(9, 3.0, 60.0, |i, j| {
        // Deterministic, irregular offsets of up to ±2.3 pixels.
        let h = (i * 7919 + j * 104_729) as f64;
        DVec2::new((h * 0.618).sin() * 2.3, (h * 0.377).cos() * 2.3)
    });
    assert_covered_once(&coverage_counts(&tris), 3.0, 60.0);
}

#[test]
fn a_fan_around_one_vertex_covers_its_disc_once() {
    let centre = DVec2::new(32.0, 32.0);
    let n = 37;
    let tris: Vec<[DVec2; 3]> = (0..n)
        .map(|k| {
            let angle = |k: usize| std::f64::consts::TAU * k as f64 / n as f64;
            let rim = |k: usize| centre + DVec2::new(angle(k).cos(), angle(k).sin()) * 25.0;
            [centre, rim(k), rim((k + 1) % n)]
        })
        .collect();
    let counts = coverage_counts(&tris);
    assert!(counts.iter().all(|&c| c <= 1), "no pixel covered twice");
    for r in 0..20 {
        let (x, y) = (32 + r, 32);
        assert_eq!(counts[y * SIZE + x], 1, "gap at ({x}, {y})");
    }
}

#[test]
fn a_filled_square_of_two_triangles_covers_exactly_its_pixels() {
    for reverse in [false, true] {
        let mut c = Canvas::new(16, 16);
        let (a, b, d, e) = (
            DVec2::new(2.0, 3.0),
            DVec2::new(10.0, 3.0),
            DVec2::new(10.0, 11.0),
            DVec2::new(2.0, 11.0),
        );
        let red = Color::new(1.0, 0.0, 0.0);
        if reverse {
            draw_filled_triangle(&mut c, a, d, b, red);
            draw_filled_triangle(&mut c, a, e, d, red);
        } else {
            draw_filled_triangle(&mut c, a, b, d, red);
            draw_filled_triangle(&mut c, a, d, e, red);
        }
        let n = c.pixels().iter().filter(|&&p| p == red).count();
        assert_eq!(n, 64, "an 8×8 square");
        assert_eq!(c.pixel_at(2, 3), red);
        assert_eq!(c.pixel_at(9, 10), red);
        assert_eq!(c.pixel_at(10, 10), Color::BLACK);
        assert_eq!(c.pixel_at(1, 3), Color::BLACK);
    }
}

#[test]
fn a_degenerate_triangle_draws_nothing() {
    let mut c = Canvas::new(8, 8);
    let p = DVec2::new(1.0, 1.0);
    draw_filled_triangle(
        &mut c,
        p,
        DVec2::new(5.0, 5.0),
        DVec2::new(3.0, 3.0),
        Color::WHITE,
    );
    draw_filled_triangle(&mut c, p, p, p, Color::WHITE);
    assert!(c.pixels().iter().all(|&px| px == Color::BLACK));
}

#[test]
fn a_shaded_triangle_blends_the_vertex_intensities() {
    let mut c = Canvas::new(101, 101);
    let points = [
        DVec2::new(0.0, 0.0),
        DVec2::new(101.0, 0.0),
        DVec2::new(0.0, 101.0),
    ];
    draw_shaded_triangle(&mut c, points, [1.0, 0.0, 0.5], Color::new(0.0, 1.0, 0.0));
    // Pixel centre (0.5, 0.5) is nearly the first vertex; intensities blend linearly.
    let g = |x, y| c.pixel_at(x, y).green;
    assert!((g(0, 0) - (1.0 - 0.5 / 101.0 - 0.25 / 101.0)).abs() < 1e-3);
    let expected = |x: f64, y: f64| {
        let (u, v) = ((x + 0.5) / 101.0, (y + 0.5) / 101.0);
        (1.0 - u - v) * 1.0 + u * 0.0 + v * 0.5
    };
    for (x, y) in [(10, 20), (50, 30), (0, 90), (70, 5)] {
        assert!(
            (g(x, y) - expected(x as f64, y as f64)).abs() < 1e-3,
            "({x}, {y})"
        );
    }
    assert_eq!(c.pixel_at(60, 60), Color::BLACK, "outside the hypotenuse");
}

#[test]
fn a_triangle_reaching_far_beyond_the_canvas_covers_it_without_overflow() {
    let mut c = Canvas::new(8, 8);
    let far = 1e12;
    draw_filled_triangle(
        &mut c,
        DVec2::new(-far, -far),
        DVec2::new(far, -far),
        DVec2::new(0.0, far),
        Color::WHITE,
    );
    assert!(c.pixels().iter().all(|&p| p == Color::WHITE));
}
