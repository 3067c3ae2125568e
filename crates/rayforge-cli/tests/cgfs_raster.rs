//! Computer Graphics from Scratch, part II: the scenes of `scenes/cgfs/raster-*.yml` choose the
//! rasterizer themselves (`world: {renderer: raster}`).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn run(stage: &str, extra: &[&str]) -> (Output, PathBuf) {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{stage}{}.png", extra.join("")));
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
        "raster-06",
        "raster-08",
        "raster-09",
        "raster-10",
        "raster-11",
        "raster-12",
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
