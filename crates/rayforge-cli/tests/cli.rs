//! The `rayforge` command end to end, in a temporary directory.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A red sphere lit only by ambient light: pure red where it is, black elsewhere.
const RED_SPHERE: &str = "
- add: camera
  width: 9
  height: 9
  field-of-view: 0.8
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: sphere
  material:
    color: [1, 0, 0]
    ambient: 1
    diffuse: 0
    specular: 0
";

struct Dir(tempfile::TempDir);

impl Dir {
    fn new() -> Self {
        Dir(tempfile::tempdir().unwrap())
    }
    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }
}

fn rayforge(args: &[&Path]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args(args)
        .output()
        .expect("runs")
}

fn render(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args: Vec<&Path> = vec![Path::new("render"), scene, Path::new("-o"), out];
    args.extend(extra.iter().map(Path::new));
    rayforge(&args)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn renders_a_ppm_with_the_books_encoding() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("out.ppm");
    let o = render(&scene, &out, &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ppm = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = ppm.lines().collect();
    assert_eq!(&lines[..3], ["P3", "9 9", "255"]);
    let values: Vec<u8> = lines[3..]
        .iter()
        .flat_map(|l| l.split_whitespace().map(|v| v.parse::<u8>().unwrap()))
        .collect();
    assert_eq!(values.len(), 9 * 9 * 3);
    let pixel = |x: usize, y: usize| &values[(y * 9 + x) * 3..][..3];
    assert_eq!(pixel(4, 4), [255, 0, 0]);
    assert_eq!(pixel(0, 0), [0, 0, 0]);
    assert!(o.stderr.is_empty(), "--quiet prints nothing");
}

#[test]
fn renders_a_png_and_prints_a_summary() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("out.png");
    let o = render(&scene, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (9, 9));
    assert_eq!(img.get_pixel(4, 4).0, [255, 0, 0]);
    let summary = stderr(&o);
    assert!(summary.contains("rendered 9×9"), "{summary}");
    assert!(summary.contains("rays/s"), "{summary}");
}

#[test]
fn renders_a_pfm_with_linear_floats_bottom_row_first() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("out.pfm");
    assert!(render(&scene, &out, &["-q"]).status.success());
    let bytes = std::fs::read(&out).unwrap();
    let header = b"PF\n9 9\n-1.0\n";
    assert_eq!(&bytes[..header.len()], header);
    let floats: Vec<f32> = bytes[header.len()..]
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(floats.len(), 9 * 9 * 3);
    assert_eq!(&floats[(4 * 9 + 4) * 3..][..3], [1.0, 0.0, 0.0]);
}

#[test]
fn width_and_height_override_the_camera() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("out.png");
    assert!(
        render(&scene, &out, &["-q", "--width", "20", "--height", "10"])
            .status
            .success()
    );
    assert_eq!(image::open(&out).unwrap().to_rgb8().dimensions(), (20, 10));
    // One side alone keeps the camera's aspect ratio.
    assert!(render(&scene, &out, &["-q", "--width", "18"])
        .status
        .success());
    assert_eq!(image::open(&out).unwrap().to_rgb8().dimensions(), (18, 18));
}

#[test]
fn the_image_is_the_same_for_any_thread_count() {
    let d = Dir::new();
    let scene = d.file(
        "s.yml",
        &RED_SPHERE
            .replace("width: 9", "width: 40")
            .replace("ambient: 1", "ambient: 0.1\n    reflective: 0.5"),
    );
    let (one, four) = (d.path("one.pfm"), d.path("four.pfm"));
    assert!(render(&scene, &one, &["-q", "--threads", "1"])
        .status
        .success());
    assert!(render(&scene, &four, &["-q", "--threads", "4"])
        .status
        .success());
    assert_eq!(std::fs::read(one).unwrap(), std::fs::read(four).unwrap());
}

#[test]
fn a_scene_error_names_file_line_column_and_key_and_exits_2() {
    let d = Dir::new();
    let scene = d.file(
        "bad.yml",
        &RED_SPHERE.replace("    ambient: 1", "    ambient: lots"),
    );
    let out = d.path("out.png");
    let o = render(&scene, &out, &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("bad.yml:15:14"), "{err}");
    assert!(err.contains("`ambient`"), "{err}");
    assert!(err.contains("expected a number"), "{err}");
    assert!(!out.exists(), "a failed render leaves nothing behind");
}

#[test]
fn a_missing_scene_file_exits_2() {
    let d = Dir::new();
    let o = render(&d.path("nope.yml"), &d.path("out.png"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("nope.yml"), "{}", stderr(&o));
}

#[test]
fn an_unwritable_output_exits_2_and_leaves_nothing() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("missing-dir/out.png");
    let o = render(&scene, &out, &["-q"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot write"), "{}", stderr(&o));
    assert!(!out.exists());
    let leftovers: Vec<_> = std::fs::read_dir(d.0.path()).unwrap().collect();
    assert_eq!(leftovers.len(), 1, "only the scene file remains");
}

#[test]
fn an_unknown_extension_is_refused_before_rendering() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let o = render(&scene, &d.path("out.gif"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(".png, .ppm or .pfm"), "{}", stderr(&o));
}

#[test]
fn an_existing_output_survives_a_failed_render() {
    let d = Dir::new();
    let out = d.file("out.png", "previous image");
    let bad = d.file("bad.yml", "- add: sphere\n  material: nowhere\n");
    assert_eq!(render(&bad, &out, &[]).status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous image");
}

#[test]
fn an_absurd_resolution_is_refused() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let o = render(
        &scene,
        &d.path("o.png"),
        &["--width", "100000", "--height", "100000"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--max-pixels"), "{}", stderr(&o));
}

#[test]
fn zero_threads_is_refused() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let o = render(&scene, &d.path("o.png"), &["--threads", "0"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn help_describes_every_option() {
    let o = rayforge(&[Path::new("render"), Path::new("--help")]);
    let help = String::from_utf8_lossy(&o.stdout);
    for flag in [
        "--output",
        "--width",
        "--height",
        "--threads",
        "--max-depth",
        "--max-pixels",
        "--spp",
        "--adaptive",
        "--quiet",
    ] {
        assert!(help.contains(flag), "{flag} missing from:\n{help}");
    }
}

#[test]
fn supersampled_images_are_the_same_for_any_thread_count() {
    let d = Dir::new();
    let scene = d.file("s.yml", &RED_SPHERE.replace("ambient: 1", "ambient: 0.2"));
    let (one, four) = (d.path("one.pfm"), d.path("four.pfm"));
    assert!(
        render(&scene, &one, &["-q", "--threads", "1", "--spp", "4"])
            .status
            .success()
    );
    assert!(
        render(&scene, &four, &["-q", "--threads", "4", "--spp", "4"])
            .status
            .success()
    );
    assert_eq!(std::fs::read(&one).unwrap(), std::fs::read(&four).unwrap());
    let adaptive = d.path("adaptive.pfm");
    assert!(render(&scene, &adaptive, &["-q", "--adaptive", "0.05"])
        .status
        .success());
}

#[test]
fn the_cameras_samples_key_and_bad_sampling_flags() {
    let d = Dir::new();
    let scene = d.file(
        "s.yml",
        &RED_SPHERE.replace("  up: [0, 1, 0]", "  up: [0, 1, 0]\n  samples: 4"),
    );
    assert!(render(&scene, &d.path("o.png"), &["-q"]).status.success());
    for bad in [
        &["--spp", "0"][..],
        &["--adaptive", "-1"],
        &["--spp", "4", "--adaptive", "0.1"],
    ] {
        let o = render(&scene, &d.path("o.png"), bad);
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
    }
}
