//! The bonus chapter "Texture mapping": UV patterns, mappings, cube maps and image textures.
// The book's expected values are kept exactly as printed.
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::color::color;
use rayforge::shading::{
    cylindrical_map, planar_map, spherical_map, CubeFace, Filter, Texture, UvMapping, UvPattern,
};
use rayforge::{point, Color, Pattern, PatternKind, Point3};

const BLACK: Color = color(0.0, 0.0, 0.0);
const WHITE: Color = color(1.0, 1.0, 1.0);

fn checkers(width: f64, height: f64) -> UvPattern {
    UvPattern::Checkers {
        width,
        height,
        a: BLACK,
        b: WHITE,
    }
}

fn checker_2d(u: f64, v: f64, expected: Color) {
    assert_eq!(checkers(2.0, 2.0).uv_pattern_at(u, v), expected);
}

scenario_rows! { checker_2d;
    checker_pattern_in_2d_1: 0.0, 0.0, BLACK;
    checker_pattern_in_2d_2: 0.5, 0.0, WHITE;
    checker_pattern_in_2d_3: 0.0, 0.5, WHITE;
    checker_pattern_in_2d_4: 0.5, 0.5, BLACK;
    checker_pattern_in_2d_5: 1.0, 1.0, BLACK;
}

#[track_caller]
fn assert_uv((u, v): (f64, f64), (eu, ev): (f64, f64)) {
    assert_approx(u, eu);
    assert_approx(v, ev);
}

fn spherical(p: Point3, u: f64, v: f64) {
    assert_uv(spherical_map(p), (u, v));
}

scenario_rows! { spherical;
    using_a_spherical_mapping_on_a_3d_point_1: point(0.0, 0.0, -1.0), 0.0, 0.5;
    using_a_spherical_mapping_on_a_3d_point_2: point(1.0, 0.0, 0.0), 0.25, 0.5;
    using_a_spherical_mapping_on_a_3d_point_3: point(0.0, 0.0, 1.0), 0.5, 0.5;
    using_a_spherical_mapping_on_a_3d_point_4: point(-1.0, 0.0, 0.0), 0.75, 0.5;
    using_a_spherical_mapping_on_a_3d_point_5: point(0.0, 1.0, 0.0), 0.5, 1.0;
    using_a_spherical_mapping_on_a_3d_point_6: point(0.0, -1.0, 0.0), 0.5, 0.0;
    using_a_spherical_mapping_on_a_3d_point_7: point(2f64.sqrt() / 2.0, 2f64.sqrt() / 2.0, 0.0), 0.25, 0.75;
}

fn mapped_sphere(p: Point3, expected: Color) {
    let pattern = Pattern::new(PatternKind::Map {
        mapping: UvMapping::Spherical,
        uv: checkers(16.0, 8.0),
    });
    assert_eq!(pattern.pattern_at(p), expected);
}

scenario_rows! { mapped_sphere;
    using_a_texture_map_pattern_with_a_spherical_map_1: point(0.4315, 0.4670, 0.7719), WHITE;
    using_a_texture_map_pattern_with_a_spherical_map_2: point(-0.9654, 0.2552, -0.0534), BLACK;
    using_a_texture_map_pattern_with_a_spherical_map_3: point(0.1039, 0.7090, 0.6975), WHITE;
    using_a_texture_map_pattern_with_a_spherical_map_4: point(-0.4986, -0.7856, -0.3663), BLACK;
    using_a_texture_map_pattern_with_a_spherical_map_5: point(-0.0317, -0.9395, 0.3411), BLACK;
    using_a_texture_map_pattern_with_a_spherical_map_6: point(0.4809, -0.7721, 0.4154), BLACK;
    using_a_texture_map_pattern_with_a_spherical_map_7: point(0.0285, -0.9612, -0.2745), BLACK;
    using_a_texture_map_pattern_with_a_spherical_map_8: point(-0.5734, -0.2162, -0.7903), WHITE;
    using_a_texture_map_pattern_with_a_spherical_map_9: point(0.7688, -0.1470, 0.6223), BLACK;
    using_a_texture_map_pattern_with_a_spherical_map_10: point(-0.7652, 0.2175, 0.6060), BLACK;
}

fn planar(p: Point3, u: f64, v: f64) {
    assert_uv(planar_map(p), (u, v));
}

scenario_rows! { planar;
    using_a_planar_mapping_on_a_3d_point_1: point(0.25, 0.0, 0.5), 0.25, 0.5;
    using_a_planar_mapping_on_a_3d_point_2: point(0.25, 0.0, -0.25), 0.25, 0.75;
    using_a_planar_mapping_on_a_3d_point_3: point(0.25, 0.5, -0.25), 0.25, 0.75;
    using_a_planar_mapping_on_a_3d_point_4: point(1.25, 0.0, 0.5), 0.25, 0.5;
    using_a_planar_mapping_on_a_3d_point_5: point(0.25, 0.0, -1.75), 0.25, 0.25;
    using_a_planar_mapping_on_a_3d_point_6: point(1.0, 0.0, -1.0), 0.0, 0.0;
    using_a_planar_mapping_on_a_3d_point_7: point(0.0, 0.0, 0.0), 0.0, 0.0;
}

fn cylindrical(p: Point3, u: f64, v: f64) {
    assert_uv(cylindrical_map(p), (u, v));
}

scenario_rows! { cylindrical;
    using_a_cylindrical_mapping_on_a_3d_point_1: point(0.0, 0.0, -1.0), 0.0, 0.0;
    using_a_cylindrical_mapping_on_a_3d_point_2: point(0.0, 0.5, -1.0), 0.0, 0.5;
    using_a_cylindrical_mapping_on_a_3d_point_3: point(0.0, 1.0, -1.0), 0.0, 0.0;
    using_a_cylindrical_mapping_on_a_3d_point_4: point(0.70711, 0.5, -0.70711), 0.125, 0.5;
    using_a_cylindrical_mapping_on_a_3d_point_5: point(1.0, 0.5, 0.0), 0.25, 0.5;
    using_a_cylindrical_mapping_on_a_3d_point_6: point(0.70711, 0.5, 0.70711), 0.375, 0.5;
    using_a_cylindrical_mapping_on_a_3d_point_7: point(0.0, -0.25, 1.0), 0.5, 0.75;
    using_a_cylindrical_mapping_on_a_3d_point_8: point(-0.70711, 0.5, 0.70711), 0.625, 0.5;
    using_a_cylindrical_mapping_on_a_3d_point_9: point(-1.0, 1.25, 0.0), 0.75, 0.25;
    using_a_cylindrical_mapping_on_a_3d_point_10: point(-0.70711, 0.5, -0.70711), 0.875, 0.5;
}

const MAIN: Color = color(1.0, 1.0, 1.0);
const UL: Color = color(1.0, 0.0, 0.0);
const UR: Color = color(1.0, 1.0, 0.0);
const BL: Color = color(0.0, 1.0, 0.0);
const BR: Color = color(0.0, 1.0, 1.0);

fn align(u: f64, v: f64, expected: Color) {
    let pattern = UvPattern::AlignCheck {
        main: MAIN,
        ul: UL,
        ur: UR,
        bl: BL,
        br: BR,
    };
    assert_eq!(pattern.uv_pattern_at(u, v), expected);
}

scenario_rows! { align;
    layout_of_the_align_check_pattern_1: 0.5, 0.5, MAIN;
    layout_of_the_align_check_pattern_2: 0.1, 0.9, UL;
    layout_of_the_align_check_pattern_3: 0.9, 0.9, UR;
    layout_of_the_align_check_pattern_4: 0.1, 0.1, BL;
    layout_of_the_align_check_pattern_5: 0.9, 0.1, BR;
}

fn face(p: Point3, expected: CubeFace) {
    assert_eq!(CubeFace::from_point(p), expected);
}

scenario_rows! { face;
    identifying_the_face_of_a_cube_from_a_point_1: point(-1.0, 0.5, -0.25), CubeFace::Left;
    identifying_the_face_of_a_cube_from_a_point_2: point(1.1, -0.75, 0.8), CubeFace::Right;
    identifying_the_face_of_a_cube_from_a_point_3: point(0.1, 0.6, 0.9), CubeFace::Front;
    identifying_the_face_of_a_cube_from_a_point_4: point(-0.7, 0.0, -2.0), CubeFace::Back;
    identifying_the_face_of_a_cube_from_a_point_5: point(0.5, 1.0, 0.9), CubeFace::Up;
    identifying_the_face_of_a_cube_from_a_point_6: point(-0.2, -1.3, 1.1), CubeFace::Down;
}

fn face_uv(f: CubeFace, p: Point3, u: f64, v: f64) {
    assert_uv(f.uv(p), (u, v));
}

scenario_rows! { face_uv;
    uv_mapping_the_front_face_of_a_cube_1: CubeFace::Front, point(-0.5, 0.5, 1.0), 0.25, 0.75;
    uv_mapping_the_front_face_of_a_cube_2: CubeFace::Front, point(0.5, -0.5, 1.0), 0.75, 0.25;
    uv_mapping_the_back_face_of_a_cube_1: CubeFace::Back, point(0.5, 0.5, -1.0), 0.25, 0.75;
    uv_mapping_the_back_face_of_a_cube_2: CubeFace::Back, point(-0.5, -0.5, -1.0), 0.75, 0.25;
    uv_mapping_the_left_face_of_a_cube_1: CubeFace::Left, point(-1.0, 0.5, -0.5), 0.25, 0.75;
    uv_mapping_the_left_face_of_a_cube_2: CubeFace::Left, point(-1.0, -0.5, 0.5), 0.75, 0.25;
    uv_mapping_the_right_face_of_a_cube_1: CubeFace::Right, point(1.0, 0.5, 0.5), 0.25, 0.75;
    uv_mapping_the_right_face_of_a_cube_2: CubeFace::Right, point(1.0, -0.5, -0.5), 0.75, 0.25;
    uv_mapping_the_upper_face_of_a_cube_1: CubeFace::Up, point(-0.5, 1.0, -0.5), 0.25, 0.75;
    uv_mapping_the_upper_face_of_a_cube_2: CubeFace::Up, point(0.5, 1.0, 0.5), 0.75, 0.25;
    uv_mapping_the_lower_face_of_a_cube_1: CubeFace::Down, point(-0.5, -1.0, 0.5), 0.25, 0.75;
    uv_mapping_the_lower_face_of_a_cube_2: CubeFace::Down, point(0.5, -1.0, -0.5), 0.75, 0.25;
}

const RED: Color = color(1.0, 0.0, 0.0);
const YELLOW: Color = color(1.0, 1.0, 0.0);
const BROWN: Color = color(1.0, 0.5, 0.0);
const GREEN: Color = color(0.0, 1.0, 0.0);
const CYAN: Color = color(0.0, 1.0, 1.0);
const BLUE: Color = color(0.0, 0.0, 1.0);
const PURPLE: Color = color(1.0, 0.0, 1.0);

fn book_cube_map() -> Pattern {
    let check = |main, ul, ur, bl, br| UvPattern::AlignCheck {
        main,
        ul,
        ur,
        bl,
        br,
    };
    Pattern::new(PatternKind::CubeMap(Box::new([
        check(YELLOW, CYAN, RED, BLUE, BROWN),
        check(CYAN, RED, YELLOW, BROWN, GREEN),
        check(RED, YELLOW, PURPLE, GREEN, WHITE),
        check(GREEN, PURPLE, CYAN, WHITE, BLUE),
        check(BROWN, CYAN, PURPLE, RED, YELLOW),
        check(PURPLE, BROWN, GREEN, BLUE, WHITE),
    ])))
}

fn mapped_cube(p: Point3, expected: Color) {
    assert_eq!(book_cube_map().pattern_at(p), expected);
}

scenario_rows! { mapped_cube;
    finding_the_colors_on_a_mapped_cube_left_1: point(-1.0, 0.0, 0.0), YELLOW;
    finding_the_colors_on_a_mapped_cube_left_2: point(-1.0, 0.9, -0.9), CYAN;
    finding_the_colors_on_a_mapped_cube_left_3: point(-1.0, 0.9, 0.9), RED;
    finding_the_colors_on_a_mapped_cube_left_4: point(-1.0, -0.9, -0.9), BLUE;
    finding_the_colors_on_a_mapped_cube_left_5: point(-1.0, -0.9, 0.9), BROWN;
    finding_the_colors_on_a_mapped_cube_front_1: point(0.0, 0.0, 1.0), CYAN;
    finding_the_colors_on_a_mapped_cube_front_2: point(-0.9, 0.9, 1.0), RED;
    finding_the_colors_on_a_mapped_cube_front_3: point(0.9, 0.9, 1.0), YELLOW;
    finding_the_colors_on_a_mapped_cube_front_4: point(-0.9, -0.9, 1.0), BROWN;
    finding_the_colors_on_a_mapped_cube_front_5: point(0.9, -0.9, 1.0), GREEN;
    finding_the_colors_on_a_mapped_cube_right_1: point(1.0, 0.0, 0.0), RED;
    finding_the_colors_on_a_mapped_cube_right_2: point(1.0, 0.9, 0.9), YELLOW;
    finding_the_colors_on_a_mapped_cube_right_3: point(1.0, 0.9, -0.9), PURPLE;
    finding_the_colors_on_a_mapped_cube_right_4: point(1.0, -0.9, 0.9), GREEN;
    finding_the_colors_on_a_mapped_cube_right_5: point(1.0, -0.9, -0.9), WHITE;
    finding_the_colors_on_a_mapped_cube_back_1: point(0.0, 0.0, -1.0), GREEN;
    finding_the_colors_on_a_mapped_cube_back_2: point(0.9, 0.9, -1.0), PURPLE;
    finding_the_colors_on_a_mapped_cube_back_3: point(-0.9, 0.9, -1.0), CYAN;
    finding_the_colors_on_a_mapped_cube_back_4: point(0.9, -0.9, -1.0), WHITE;
    finding_the_colors_on_a_mapped_cube_back_5: point(-0.9, -0.9, -1.0), BLUE;
    finding_the_colors_on_a_mapped_cube_up_1: point(0.0, 1.0, 0.0), BROWN;
    finding_the_colors_on_a_mapped_cube_up_2: point(-0.9, 1.0, -0.9), CYAN;
    finding_the_colors_on_a_mapped_cube_up_3: point(0.9, 1.0, -0.9), PURPLE;
    finding_the_colors_on_a_mapped_cube_up_4: point(-0.9, 1.0, 0.9), RED;
    finding_the_colors_on_a_mapped_cube_up_5: point(0.9, 1.0, 0.9), YELLOW;
    finding_the_colors_on_a_mapped_cube_down_1: point(0.0, -1.0, 0.0), PURPLE;
    finding_the_colors_on_a_mapped_cube_down_2: point(-0.9, -1.0, -0.9), BLUE;
    finding_the_colors_on_a_mapped_cube_down_3: point(0.9, -1.0, -0.9), WHITE;
    finding_the_colors_on_a_mapped_cube_down_4: point(-0.9, -1.0, 0.9), BROWN;
    finding_the_colors_on_a_mapped_cube_down_5: point(0.9, -1.0, 0.9), GREEN;
}

/// A 10×10 gradient image (the book's scenario uses a PPM of this kind): pixel (x, y) has grey
/// level (x + y) / 20, so sampling positions are easy to check by hand.
fn gradient_texture(filter: Filter) -> Texture {
    let pixels = (0..10)
        .flat_map(|y| (0..10).map(move |x| (x + y) as f64 / 20.0))
        .map(|g| color(g, g, g))
        .collect();
    Texture::new(10, 10, pixels, filter).unwrap()
}

#[test]
fn an_image_pattern_reads_the_nearest_pixel_with_v_pointing_up() {
    let t = gradient_texture(Filter::Nearest);
    // (0, 0) is the bottom-left pixel: x = 0, y = 9.
    assert_color_approx(t.sample(0.0, 0.0), color(0.45, 0.45, 0.45));
    // u = 0.3 lands at x = 2.7, rounded to 3; v = 0 at y = 9.
    assert_color_approx(t.sample(0.3, 0.0), color(0.6, 0.6, 0.6));
    // The top-right pixel.
    assert_color_approx(t.sample(1.0, 1.0), color(0.45, 0.45, 0.45));
    // The top-left pixel.
    assert_color_approx(t.sample(0.0, 1.0), color(0.0, 0.0, 0.0));
}

#[test]
fn a_bilinear_image_pattern_blends_the_four_nearest_pixels() {
    let t = gradient_texture(Filter::Bilinear);
    // x = 2.7 between columns 2 and 3, y = 9: 0.55 + 0.7 · 0.05.
    assert_color_approx(t.sample(0.3, 0.0), color(0.585, 0.585, 0.585));
    // Exactly on a pixel centre it is that pixel.
    assert_color_approx(t.sample(0.0, 1.0), color(0.0, 0.0, 0.0));
    // Outside [0, 1] clamps to the edge.
    assert_color_approx(t.sample(-3.0, 7.0), color(0.0, 0.0, 0.0));
}

/// Fundamentals of Ray Tracing's chess board as a UV pattern: eight squares a side inside a
/// border of a sixth of the face, the low corner's square dark.
#[test]
fn a_board_pattern_has_squares_inside_a_border() {
    let (light, dark, edge) = (
        rayforge::Color::new(1.0, 1.0, 1.0),
        rayforge::Color::new(0.0, 0.0, 0.0),
        rayforge::Color::new(0.5, 0.3, 0.1),
    );
    let board = UvPattern::Board {
        squares: 8,
        border: 1.0 / 6.0,
        light,
        dark,
        edge,
    };
    let square = |i: f64, j: f64| {
        let at = |k: f64| 1.0 / 6.0 + (k + 0.5) * (4.0 / 6.0) / 8.0;
        board.uv_pattern_at(at(i), at(j))
    };
    assert_eq!(square(0.0, 0.0), dark);
    assert_eq!(square(1.0, 0.0), light);
    assert_eq!(square(1.0, 1.0), dark);
    assert_eq!(square(7.0, 0.0), light);
    assert_eq!(board.uv_pattern_at(0.05, 0.5), edge);
    assert_eq!(board.uv_pattern_at(0.5, 0.95), edge);
}
