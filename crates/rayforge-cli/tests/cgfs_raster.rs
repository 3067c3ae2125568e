//! Computer Graphics from Scratch, part II: the scenes of `scenes/cgfs/raster-*.yml` choose the
//! rasterizer themselves (`world: {renderer: raster}`).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn run(stage: &str, extra: &[&str]) -> (Output, PathBuf) {
    // A name of its own for each render: tests run at once, and a render to an output another
    // render holds is refused (its lock).
    static RENDERS: AtomicUsize = AtomicUsize::new(0);
    let n = RENDERS.fetch_add(1, Ordering::Relaxed);
    let out =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{stage}{}-{n}.png", extra.join("")));
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(repo().join(format!("scenes/cgfs/{stage}.yml")))
        .arg("-o")
        .arg(&out)
        .args(extra)
        .output()
        .expect("runs rayforge");
    (o, out)
}

fn render(stage: &str) -> (String, image::RgbImage) {
    let (o, out) = run(stage, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let image = image::open(&out).expect("reads the render").to_rgb8();
    (String::from_utf8_lossy(&o.stderr).into_owned(), image)
}

fn lit_pixels(image: &image::RgbImage) -> usize {
    image.pixels().filter(|p| p.0 != [0, 0, 0]).count()
}

#[test]
fn the_stages_are_rasterized_by_their_own_choice() {
    for stage in [
        "raster-01",
        "raster-02",
        "raster-03",
        "raster-04",
        "raster-05",
        "raster-06",
        "raster-07",
        "raster-08",
        "raster-09",
        "raster-10",
        "raster-11",
        "raster-12",
        "raster-13",
    ] {
        let (summary, image) = render(stage);
        assert!(
            summary.starts_with("rasterized 600×600"),
            "{stage}: {summary}"
        );
        assert!(lit_pixels(&image) > 1000, "{stage}");
    }
}

#[test]
fn one_cube_model_makes_one_instance_then_two() {
    // raster-06 draws the cube at (-1.5, 0, 7), on the left of the canvas; raster-07 adds a
    // second instance of the same model at (1.25, 2, 7.5), on the right, and leaves the first
    // as it was.
    let (_, one) = render("raster-06");
    let (_, two) = render("raster-07");
    let lit_in = |image: &image::RgbImage, columns: std::ops::Range<u32>| {
        image
            .enumerate_pixels()
            .filter(|(x, _, p)| columns.contains(x) && p.0 != [0, 0, 0])
            .count()
    };
    assert!(lit_in(&one, 0..300) > 1000);
    assert_eq!(lit_in(&one, 300..600), 0);
    assert!(lit_in(&two, 300..600) > 1000);
    let left = |image: &image::RgbImage| {
        image
            .enumerate_pixels()
            .filter(|(x, _, _)| *x < 300)
            .map(|(_, _, p)| p.0)
            .collect::<Vec<_>>()
    };
    assert!(left(&one) == left(&two));
}

#[test]
fn a_cube_behind_the_camera_is_clipped_away_entirely() {
    // raster-09 is raster-08 with a third cube behind the camera: the images are the same.
    assert_eq!(render("raster-08").1, render("raster-09").1);
}

#[test]
fn wireframes_draw_edges_and_filled_triangles_cover_the_faces() {
    let wire = lit_pixels(&render("raster-08").1);
    let filled = lit_pixels(&render("raster-10").1);
    assert!(filled > 10 * wire, "{filled} vs {wire}");
    // The book's unlit face colours come out exactly.
    let (_, image) = render("raster-10");
    let colours = [
        [255, 0, 0],
        [0, 255, 0],
        [0, 0, 255],
        [255, 255, 0],
        [255, 0, 255],
        [0, 255, 255],
    ];
    let seen = colours
        .iter()
        .filter(|c| image.pixels().any(|p| p.0 == **c))
        .count();
    assert!(seen >= 4, "{seen} of the face colours");
}

#[test]
fn the_shading_stage_is_lit_by_the_books_model() {
    // Under `lighting: cgfs` a face is its colour times the summed intensity: the front of the
    // blue cube (facing the point light) is lit but not the full blue of the unlit stage.
    let (_, lit) = render("raster-11");
    let (_, unlit) = render("raster-10");
    let pure_blue = |image: &image::RgbImage| image.pixels().filter(|p| p.0 == [0, 0, 255]).count();
    assert!(pure_blue(&unlit) > 10_000);
    assert_eq!(pure_blue(&lit), 0);
    let bluish = lit
        .pixels()
        .filter(|p| p.0[2] > 100 && p.0[0] < 20 && p.0[1] < 20)
        .count();
    assert!(bluish > 10_000, "{bluish}");
}

#[test]
fn the_crates_wear_their_texture() {
    let (_, image) = render("raster-12");
    // The texture's browns, not the material's white.
    let brown = image
        .pixels()
        .filter(|p| p.0[0] > p.0[2] + 40 && p.0[1] > p.0[2])
        .count();
    assert!(brown > 50_000, "{brown} brown pixels");
}

#[test]
fn the_command_line_can_ask_for_the_ray_tracer_instead() {
    let (o, _) = run("raster-10", &["--renderer", "ray", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (o, _) = run("raster-10", &["--spp", "4"]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "the rasterizer does not anti-alias"
    );
}

/// The book's canvas point (x, y) as (column, row) of its 600 × 600 canvas.
fn at(x: i32, y: i32) -> (u32, u32) {
    ((300 + x) as u32, (299 - y) as u32)
}

fn pixel(image: &image::RgbImage, (x, y): (i32, i32)) -> [u8; 3] {
    let (column, row) = at(x, y);
    image.get_pixel(column, row).0
}

const BLACK: [u8; 3] = [0, 0, 0];

#[test]
fn the_first_line_has_one_pixel_in_each_column_from_end_to_end() {
    let (_, image) = render("raster-01");
    let inked: Vec<(u32, u32)> = image
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0 == BLACK)
        .map(|(x, y, _)| (x, y))
        .collect();
    assert_eq!(inked.len(), 441, "x from -200 to 240");
    let columns: std::collections::BTreeSet<u32> = inked.iter().map(|q| q.0).collect();
    assert_eq!(columns.len(), 441);
    // Both ends, and the middle: y = -100 + 220·0.5 = 10 at x = 20.
    assert_eq!(pixel(&image, (-200, -100)), BLACK);
    assert_eq!(pixel(&image, (240, 120)), BLACK);
    assert_eq!(pixel(&image, (20, 10)), BLACK);
    assert_eq!(image.get_pixel(0, 0).0, [255, 255, 255], "the white page");
}

#[test]
fn the_steep_line_of_the_second_stage_has_a_pixel_in_every_row() {
    let (_, image) = render("raster-02");
    for y in -200..=240 {
        let row = (299 - y) as u32;
        let inked = (250..=360)
            .filter(|&x| image.get_pixel(x, row).0 == BLACK)
            .count();
        assert!(inked >= 1, "row for y = {y}");
    }
}

#[test]
fn the_filled_triangle_is_green_inside_its_black_outline() {
    let (_, image) = render("raster-03");
    let green = image.pixels().filter(|p| p.0 == [0, 255, 0]).count();
    // The triangle's area is 67 000 square pixels.
    assert!((65_000..69_000).contains(&green), "{green}");
    // The corners, the top one a pixel to the left: both lines reaching it add their slope
    // up to 19.99… there, which PutPixel floors (so does the book's figure).
    for corner in [(-200, -250), (200, 50), (19, 250)] {
        assert_eq!(pixel(&image, corner), BLACK, "{corner:?}");
    }
    assert_eq!(pixel(&image, (7, 17)), [0, 255, 0], "the centroid");
}

#[test]
fn the_shaded_triangle_runs_from_each_corners_intensity() {
    let (_, image) = render("raster-04");
    // h = 0.3, 0.1 and 1.0 times 255, rounded halves up as in the book's figure.
    assert_eq!(pixel(&image, (-200, -250)), [0, 77, 0]);
    assert_eq!(pixel(&image, (200, 50)), [0, 26, 0]);
    // The top row's ends add up to 19.99…, truncated: the corner lands one pixel to the left,
    // as in the book's figure.
    assert_eq!(pixel(&image, (19, 250)), [0, 255, 0]);
    assert_eq!(pixel(&image, (20, 250)), [255, 255, 255]);
}

#[test]
fn the_projected_cube_has_its_faces_and_edges_in_the_books_colours() {
    let (_, image) = render("raster-05");
    // The front face (z = 5) spans x from -240 to -120, the back face (z = 6) -200 to -100.
    assert_eq!(
        pixel(&image, (-240, 0)),
        [0, 0, 255],
        "front face, left side"
    );
    assert_eq!(
        pixel(&image, (-150, 50)),
        [255, 0, 0],
        "back face, top side"
    );
    assert_eq!(
        pixel(&image, (-220, -55)),
        [0, 255, 0],
        "the edge from A back"
    );
    let coloured = image.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    // Twelve lines of 121, 101 and 41 pixels (front, back, between), overlapping at the
    // corners and where a green edge leaves along a face's side: 990 distinct pixels, as a
    // replay of the book's demo code (its DrawLine, outside this repository) counts them.
    assert_eq!(coloured, 990);
}

#[test]
fn canvas_items_look_the_same_through_either_renderer() {
    for stage in [
        "raster-01",
        "raster-02",
        "raster-03",
        "raster-04",
        "raster-05",
    ] {
        let (_, raster) = render(stage);
        let (o, out) = run(stage, &["--renderer", "ray", "--quiet"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let ray = image::open(&out).expect("reads the render").to_rgb8();
        assert!(ray == raster, "{stage}");
    }
}

/// raster-13 drawn with one texture filter.
fn filtered(filter: &str) -> image::RgbImage {
    let (o, out) = run("raster-13", &["--texture-filter", filter, "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    image::open(&out).expect("reads the render").to_rgb8()
}

#[test]
fn the_texture_filters_differ_where_they_should() {
    let (nearest, bilinear, trilinear) = (
        filtered("nearest"),
        filtered("bilinear"),
        filtered("trilinear"),
    );
    // Close to the eye (the bottom 100 rows) a texel spans many pixels. Nearest filtering
    // shows only the tile's own colours, with steps; bilinear blends between texels; trilinear
    // is bilinear there (the finest MIP level), to the byte.
    let near = |image: &image::RgbImage| {
        (500..600)
            .flat_map(|y| (0..600).map(move |x| (x, y)))
            .map(|(x, y)| image.get_pixel(x, y).0)
            .collect::<std::collections::BTreeSet<_>>()
    };
    assert!(near(&nearest).len() <= 3, "{}", near(&nearest).len());
    assert!(near(&bilinear).len() > 100, "{}", near(&bilinear).len());
    let bottom = |image: &image::RgbImage| {
        (450..600)
            .flat_map(|y| (0..600).map(move |x| image.get_pixel(x, y).0))
            .collect::<Vec<_>>()
    };
    assert!(bottom(&bilinear) == bottom(&trilinear));
    // Just below the horizon a pixel spans many tiles: nearest and bilinear pick grout or tile
    // or inlay by where the pixel's centre falls, so each row runs from dark to light; the MIP
    // map's coarsest levels have averaged them to one colour.
    let sky = trilinear.get_pixel(300, 0).0;
    let horizon = (0..600)
        .find(|&y| trilinear.get_pixel(300, y).0 != sky)
        .expect("the floor reaches the horizon");
    let spread = |image: &image::RgbImage, y: u32| {
        let greens: Vec<u8> = (0..600).map(|x| image.get_pixel(x, y).0[1]).collect();
        greens.iter().max().unwrap() - greens.iter().min().unwrap()
    };
    for y in horizon..horizon + 10 {
        assert!(
            spread(&nearest, y) > 150,
            "row {y}: {}",
            spread(&nearest, y)
        );
        assert!(
            spread(&bilinear, y) > 150,
            "row {y}: {}",
            spread(&bilinear, y)
        );
        assert!(
            spread(&trilinear, y) < 10,
            "row {y}: {}",
            spread(&trilinear, y)
        );
    }
}
