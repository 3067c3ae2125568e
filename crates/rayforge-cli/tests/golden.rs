//! Golden images: the gallery's chapter scenes rendered small by the `rayforge` binary and
//! compared with stored references.
//!
//! Each scene `scenes/trtc/<name>.yml` is rendered with `rayforge render --width 64` (the
//! height follows the camera's aspect ratio; the scene's own `samples` apply, as for a user)
//! and compared with `tests/golden/<name>.png` (`next-steps/x` is stored as `next-steps-x`).
//!
//! Tolerance: each channel may differ by [`CHANNEL_TOLERANCE`] = 2/255. The renderer is
//! deterministic, so on one machine the bytes are identical; the slack is for other CPUs and
//! compilers, where `sin`, `cos`, `powf` and fused multiply-adds may differ in the last bits of
//! an f64, which moves a channel across a rounding boundary by 1/255 (2/255 when it also shifts
//! a specular highlight's exponent). In addition at most [`OUTLIER_FRACTION`] (0.5 %) of the
//! pixels may differ by more: a ray that grazes an edge can hit the other surface when its
//! last bit changes. Any real change to the renderer's output moves far more pixels than that
//! and fails, naming the first differing pixel; the rendered image is kept under
//! `target/tmp/golden/` for a look.
//!
//! To accept new output deliberately (and review the PNG diff before committing):
//! `RAYFORGE_BLESS=1 cargo test -p rayforge-cli --test golden`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Width of every golden image, in pixels: big enough to show each scene's features, small
/// enough that eleven scenes render in well under a second.
const WIDTH: u32 = 64;
/// Largest difference allowed in one 8-bit channel (see the module comment).
const CHANNEL_TOLERANCE: u8 = 2;
/// Fraction of pixels allowed to exceed [`CHANNEL_TOLERANCE`] (see the module comment).
const OUTLIER_FRACTION: f64 = 0.005;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Renders a gallery scene at the golden width with the `rayforge` binary into `out`.
fn render_small(scene: &str, out: &Path) {
    let path = repo().join("scenes/trtc").join(format!("{scene}.yml"));
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(&path)
        .arg("-o")
        .arg(out)
        .args(["--width", &WIDTH.to_string(), "--quiet"])
        .output()
        .expect("runs rayforge");
    assert!(
        o.status.success(),
        "{scene}: rayforge failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The first pixel that differs beyond the tolerance, and how many do.
struct Difference {
    first: Option<(u32, u32, [u8; 3], [u8; 3])>,
    count: usize,
    largest: u8,
}

fn compare(actual: &image::RgbImage, expected: &image::RgbImage) -> Difference {
    let mut d = Difference {
        first: None,
        count: 0,
        largest: 0,
    };
    for (x, y, a) in actual.enumerate_pixels() {
        let e = expected.get_pixel(x, y);
        let diff = a.0.iter().zip(e.0).map(|(a, e)| a.abs_diff(e)).max();
        let diff = diff.unwrap_or(0);
        d.largest = d.largest.max(diff);
        if diff > CHANNEL_TOLERANCE {
            d.count += 1;
            d.first.get_or_insert((x, y, a.0, e.0));
        }
    }
    d
}

fn check(scene: &str) {
    let file_name = format!("{}.png", scene.replace('/', "-"));
    let golden = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(&file_name);
    if std::env::var_os("RAYFORGE_BLESS").is_some() {
        render_small(scene, &golden);
        return;
    }
    let kept = Path::new(env!("CARGO_TARGET_TMPDIR")).join("golden");
    std::fs::create_dir_all(&kept).expect("creates target/tmp/golden");
    let rendered = kept.join(&file_name);
    render_small(scene, &rendered);
    let actual = image::open(&rendered).expect("reads the render").to_rgb8();
    let expected = image::open(&golden)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e} (create it with RAYFORGE_BLESS=1 cargo test -p rayforge-cli --test golden)",
                golden.display()
            )
        })
        .to_rgb8();
    assert_eq!(
        actual.dimensions(),
        expected.dimensions(),
        "{scene}: size of the render vs the golden image"
    );
    let d = compare(&actual, &expected);
    let (w, h) = actual.dimensions();
    let allowed = (OUTLIER_FRACTION * (w * h) as f64).floor() as usize;
    if let Some((x, y, a, e)) = d.first {
        assert!(
            d.count <= allowed,
            "{scene}: {} pixels differ by more than {CHANNEL_TOLERANCE}/255 (allowed {allowed}, \
             largest difference {}/255); first at ({x}, {y}): rendered {a:?}, golden {e:?}; \
             render kept at {}",
            d.count,
            d.largest,
            rendered.display()
        );
    }
}

#[test]
fn the_comparison_names_the_first_differing_pixel() {
    let expected = image::RgbImage::from_pixel(4, 3, image::Rgb([10, 20, 30]));
    let mut actual = expected.clone();
    actual.put_pixel(1, 1, image::Rgb([12, 20, 30])); // within tolerance
    actual.put_pixel(2, 1, image::Rgb([10, 24, 30]));
    actual.put_pixel(0, 2, image::Rgb([0, 0, 0]));
    let d = compare(&actual, &expected);
    assert_eq!(d.count, 2);
    assert_eq!(d.largest, 30);
    assert_eq!(d.first, Some((2, 1, [10, 24, 30], [10, 20, 30])));
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
fn golden_ch08_shadows() {
    check("ch08-shadows");
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
fn golden_ch13_cylinders() {
    check("ch13-cylinders");
}

#[test]
fn golden_ch14_groups() {
    check("ch14-groups");
}

#[test]
fn golden_ch15_triangles() {
    check("ch15-triangles");
}

#[test]
fn golden_ch16_csg() {
    check("ch16-csg");
}

// Chapter 17's next steps and the bonus chapters. Jittered samples, area lights, lens and
// shutter samples are all seeded per pixel, so these images are as reproducible as the others.

/// Focal blur, soft shadows, a spotlight and the camera's 36 samples per pixel.
#[test]
fn golden_next_steps_focal_blur() {
    check("next-steps/focal-blur");
}

#[test]
fn golden_next_steps_soft_shadows() {
    check("next-steps/soft-shadows");
}

#[test]
fn golden_next_steps_spotlights() {
    check("next-steps/spotlights");
}

#[test]
fn golden_next_steps_motion_blur() {
    check("next-steps/motion-blur");
}

#[test]
fn golden_next_steps_anti_aliasing() {
    check("next-steps/anti-aliasing");
}

#[test]
fn golden_next_steps_texture_mapping() {
    check("next-steps/texture-mapping");
}

#[test]
fn golden_next_steps_skybox() {
    check("next-steps/skybox");
}

#[test]
fn golden_next_steps_bump_mapping() {
    check("next-steps/bump-mapping");
}

#[test]
fn golden_next_steps_torus() {
    check("next-steps/torus");
}
