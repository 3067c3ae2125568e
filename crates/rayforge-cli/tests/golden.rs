//! Golden images: the chapter scenes rendered small and compared with stored references.
//!
//! Each scene in `scenes/trtc/` is rendered at 64 pixels wide and compared with
//! `tests/golden/<name>.png`. Tolerance: each channel may differ by 2/255 (rounding of the last
//! float bits across platforms), and at most 0.5 % of the pixels may differ by more (a ray that
//! grazes an edge can pick the other surface on another CPU). A change to the renderer's output
//! beyond that fails the test and names the first differing pixel.
//!
//! To accept new output deliberately: `RAYFORGE_BLESS=1 cargo test -p rayforge-cli --test golden`.

use rayforge::render::{render, RenderOptions};
use std::path::{Path, PathBuf};

const WIDTH: usize = 64;
const CHANNEL_TOLERANCE: u8 = 2;
const OUTLIER_FRACTION: f64 = 0.005;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Renders a scene at the golden width, as 8-bit RGB.
fn render_small(scene: &str) -> (usize, usize, Vec<u8>) {
    let path = repo().join("scenes/trtc").join(format!("{scene}.yml"));
    let scene = rayforge_scene::load_file(&path).expect("scene loads");
    let c = &scene.camera;
    let height = ((WIDTH * c.vsize()) as f64 / c.hsize() as f64)
        .round()
        .max(1.0) as usize;
    let camera = c.resized(WIDTH, height);
    let (canvas, _) = render(&camera, &scene.world, &RenderOptions::default());
    (canvas.width(), canvas.height(), canvas.to_rgb8())
}

fn check(scene: &str) {
    let (w, h, actual) = render_small(scene);
    let golden = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{scene}.png"));
    if std::env::var_os("RAYFORGE_BLESS").is_some() {
        image::save_buffer(&golden, &actual, w as u32, h as u32, image::ColorType::Rgb8)
            .expect("write golden image");
        return;
    }
    let expected = image::open(&golden)
        .unwrap_or_else(|e| panic!("{}: {e} (bless with RAYFORGE_BLESS=1)", golden.display()))
        .to_rgb8();
    assert_eq!(
        (expected.width() as usize, expected.height() as usize),
        (w, h),
        "golden image size"
    );
    let mut outliers = 0;
    let mut first = None;
    for (i, (a, e)) in actual
        .chunks(3)
        .zip(expected.as_raw().chunks(3))
        .enumerate()
    {
        if a.iter()
            .zip(e)
            .any(|(a, e)| a.abs_diff(*e) > CHANNEL_TOLERANCE)
        {
            outliers += 1;
            first.get_or_insert((i % w, i / w, a.to_vec(), e.to_vec()));
        }
    }
    let allowed = (OUTLIER_FRACTION * (w * h) as f64).floor() as usize;
    if let Some((x, y, a, e)) = first {
        assert!(
            outliers <= allowed,
            "{scene}: {outliers} pixels differ (allowed {allowed}); first at ({x}, {y}): \
             rendered {a:?}, golden {e:?}"
        );
    }
}

#[test]
fn golden_cover() {
    check("cover");
}

#[test]
fn golden_ch07_world() {
    check("ch07-world");
}

#[test]
fn golden_ch09_planes() {
    check("ch09-planes");
}

#[test]
fn golden_ch10_patterns() {
    check("ch10-patterns");
}

#[test]
fn golden_ch11_reflection_refraction() {
    check("ch11-reflection-refraction");
}

#[test]
fn golden_ch12_cubes() {
    check("ch12-cubes");
}

#[test]
fn golden_ch14_groups() {
    check("ch14-groups");
}

#[test]
fn golden_ch16_csg() {
    check("ch16-csg");
}

#[test]
fn golden_ch13_cylinders() {
    check("ch13-cylinders");
}

#[test]
fn golden_ch15_triangles() {
    check("ch15-triangles");
}

/// Focal blur, soft shadows, a spotlight and 36 jittered samples per pixel: all seeded per
/// pixel, so the image is as reproducible as the others.
#[test]
fn golden_ch17_focal_blur() {
    check("ch17-focal-blur");
}
