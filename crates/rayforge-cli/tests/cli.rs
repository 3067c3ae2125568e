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
    let wide = d.file("wide.yml", &RED_SPHERE.replace("width: 9", "width: 18"));
    assert!(render(&wide, &out, &["-q", "--height", "5"])
        .status
        .success());
    assert_eq!(image::open(&out).unwrap().to_rgb8().dimensions(), (10, 5));
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
    assert!(
        err.contains("ambient: lots"),
        "the offending line is shown: {err}"
    );
    assert!(!out.exists(), "a failed render leaves nothing behind");
}

#[test]
fn a_missing_scene_file_exits_2() {
    let d = Dir::new();
    let o = render(&d.path("nope.yml"), &d.path("out.png"), &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("nope.yml"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
}

#[test]
fn an_unwritable_output_exits_2_and_leaves_nothing() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("missing-dir/out.png");
    let o = render(&scene, &out, &["-q"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("cannot write"), "{err}");
    assert!(err.contains("does not exist"), "{err}");
    assert!(!err.contains(".rayforge-"), "no temporary names: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
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
    assert!(
        stderr(&o).contains(".png, .ppm, .pfm or .exr"),
        "{}",
        stderr(&o)
    );
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
    let err = stderr(&o);
    assert!(err.contains("--width 100000 --height 100000"), "{err}");
    assert!(err.contains("--max-pixels"), "{err}");
    // Raising the limit past what memory can address is refused too, without overflow.
    let o = render(
        &scene,
        &d.path("o.png"),
        &[
            "--width",
            "4294967296",
            "--max-pixels",
            "18446744073709551615",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    // One side alone is checked at the camera's aspect ratio.
    let o = render(&scene, &d.path("o.png"), &["--height", "20000"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("20000×20000"), "{}", stderr(&o));
    assert!(!d.path("o.png").exists());
}

#[test]
fn zero_or_absurd_thread_counts_are_refused() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    for threads in ["0", "100000"] {
        let o = render(&scene, &d.path("o.png"), &["--threads", threads]);
        assert_eq!(o.status.code(), Some(2), "--threads {threads}");
        assert!(stderr(&o).contains("--threads"), "{}", stderr(&o));
    }
    let o = render(&scene, &d.path("o.png"), &["--threads", "many"]);
    assert_eq!(o.status.code(), Some(2), "clap refuses a non-number");
}

#[test]
fn zero_sizes_and_deep_recursion_are_refused_naming_the_flag() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    for (flag, value) in [
        ("--width", "0"),
        ("--height", "0"),
        ("--max-depth", "1000"),
        ("--bailout", "2"),
        ("--bailout", "NaN"),
    ] {
        let o = render(&scene, &d.path("o.png"), &[flag, value]);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}");
        assert!(stderr(&o).contains(flag), "{}", stderr(&o));
    }
}

#[test]
fn an_output_that_is_a_directory_exits_2() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("taken.png");
    std::fs::create_dir(&out).unwrap();
    let o = render(&scene, &out, &["-q"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
    assert!(out.is_dir());
}

#[test]
fn pfm_rows_are_the_ppm_rows_bottom_to_top() {
    let d = Dir::new();
    // The sphere sits in the upper half, so the rows are not symmetric.
    let scene = d.file(
        "s.yml",
        &format!(
            "{RED_SPHERE}  transform:\n    - [scale, 0.5, 0.5, 0.5]\n    - [translate, 0, 1, 0]\n"
        ),
    );
    let (ppm, pfm) = (d.path("o.ppm"), d.path("o.pfm"));
    assert!(render(&scene, &ppm, &["-q"]).status.success());
    assert!(render(&scene, &pfm, &["-q"]).status.success());
    let ppm = std::fs::read_to_string(&ppm).unwrap();
    let bytes: Vec<u8> = ppm
        .lines()
        .skip(3)
        .flat_map(|l| l.split_whitespace().map(|v| v.parse::<u8>().unwrap()))
        .collect();
    let pfm = std::fs::read(&pfm).unwrap();
    let header = b"PF\n9 9\n-1.0\n";
    assert_eq!(&pfm[..header.len()], header);
    let floats: Vec<f32> = pfm[header.len()..]
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let lit_rows: Vec<usize> = (0..9)
        .filter(|y| bytes[y * 9 * 3..][..9 * 3].iter().any(|&v| v > 0))
        .collect();
    assert!(
        !lit_rows.is_empty() && lit_rows.iter().all(|&y| y < 4),
        "the sphere is in the upper half only: {lit_rows:?}"
    );
    for y in 0..9 {
        let ppm_row = &bytes[y * 9 * 3..][..9 * 3];
        let pfm_row = &floats[(8 - y) * 9 * 3..][..9 * 3];
        let as_bytes: Vec<u8> = pfm_row
            .iter()
            .map(|v| (v * 255.0).round().clamp(0.0, 255.0) as u8)
            .collect();
        assert_eq!(ppm_row, &as_bytes[..], "row {y}");
    }
}

#[test]
fn help_describes_every_option() {
    let render_help = rayforge(&[Path::new("render"), Path::new("--help")]);
    let top_help = rayforge(&[Path::new("--help")]);
    assert!(render_help.status.success() && top_help.status.success());
    let render_help = String::from_utf8_lossy(&render_help.stdout);
    let top_help = String::from_utf8_lossy(&top_help.stdout);
    for flag in [
        "--output",
        "--width",
        "--height",
        "--threads",
        "--max-depth",
        "--max-pixels",
        "--spp",
        "--adaptive-aa",
        "--max-triangles",
        "--resume",
        "--quiet",
        "--renderer",
        "--shading",
        "--sphere-divisions",
        "--texture-filter",
        "--wireframe",
        "--slice",
        "--slice-by",
    ] {
        for help in [&render_help, &top_help] {
            assert!(help.contains(flag), "{flag} missing from:\n{help}");
        }
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
    assert!(render(&scene, &adaptive, &["-q", "--adaptive-aa", "0.05"])
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
        &["--adaptive-aa", "-1"],
        &["--spp", "4", "--adaptive-aa", "0.1"],
    ] {
        let o = render(&scene, &d.path("o.png"), bad);
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
    }
}

/// A scene with reflection, refraction and 64 samples a pixel, so that resuming exercises
/// every kind of ray.
const SLOW_SCENE: &str = "
- add: camera
  width: 200
  height: 150
  field-of-view: 0.9
  from: [0, 1.5, -5]
  to: [0, 0.5, 0]
  up: [0, 1, 0]
  samples: 64
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: plane
  material:
    pattern:
      type: checkers
      colors: [[1, 1, 1], [0.2, 0.2, 0.2]]
    reflective: 0.3
- add: sphere
  transform:
    - [translate, -0.8, 1, 0]
  material:
    color: [0.1, 0.1, 0.1]
    transparency: 0.9
    refractive-index: 1.5
    reflective: 0.9
- add: sphere
  transform:
    - [translate, 1.2, 1, 1]
  material:
    color: [1, 0.2, 0.2]
    reflective: 0.5
";

/// The checkpoint's header, and one row's record, in bytes (see `checkpoint.rs`).
const CHECKPOINT_HEADER: u64 = 22 + 32;
const SLOW_ROW_RECORD: u64 = 16 + 200 * 24;

fn checkpoint_of(output: &Path) -> PathBuf {
    PathBuf::from(format!("{}.rayforge-checkpoint", output.display()))
}

/// Ctrl-C for real: the binary is interrupted once its checkpoint holds a row, exits 130 with
/// the rows saved, refuses to resume with other settings, and `--resume` then finishes the
/// image with exactly the bytes of an uninterrupted render. `--pause-after-rows 1` holds the
/// render after its first row until the interrupt comes, so the test does not depend on how
/// fast the machine renders.
#[cfg(unix)]
#[test]
fn an_interrupted_render_resumes_to_the_same_bytes() {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let reference = d.path("reference.pfm");
    let o = render(&scene, &reference, &["-q", "--threads", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !checkpoint_of(&reference).exists(),
        "a finished render leaves no checkpoint"
    );

    let out = d.path("out.pfm");
    let checkpoint = checkpoint_of(&out);
    let mut child = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args([Path::new("render"), &scene, Path::new("-o"), &out])
        .args(["--threads", "1", "--pause-after-rows", "1"])
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let size = |p: &Path| std::fs::metadata(p).map_or(0, |m| m.len());
    // A guard against a hang, not a measure of speed: the paused render waits for us.
    let deadline = Instant::now() + Duration::from_secs(300);
    while size(&checkpoint) < CHECKPOINT_HEADER + SLOW_ROW_RECORD {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the paused render ended before it was interrupted"
        );
        assert!(Instant::now() < deadline, "no row was checkpointed");
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        child.try_wait().unwrap().is_none(),
        "the paused render ended before it was interrupted"
    );
    let kill = Command::new("kill")
        .args(["-s", "INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let interrupted = child.wait_with_output().unwrap();
    let err = stderr(&interrupted);
    assert_eq!(interrupted.status.code(), Some(130), "{err}");
    assert!(err.contains("--resume"), "{err}");
    assert!(!out.exists(), "no partial image is written");
    let saved = (size(&checkpoint) - CHECKPOINT_HEADER) / SLOW_ROW_RECORD;
    assert_eq!(saved, 1, "one thread paused after its first row: {err}");
    assert!(err.contains(&format!("{saved} of 150 rows")), "{err}");

    // Other settings are another image: refused, and the checkpoint is kept.
    let o = render(&scene, &out, &["-q", "--resume", "--spp", "4"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("other settings"), "{}", stderr(&o));
    assert!(checkpoint.exists());

    let o = render(&scene, &out, &["--resume", "--threads", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&format!("resuming: {saved} of 150 rows")),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(&reference).unwrap()
    );
    assert!(
        !checkpoint.exists(),
        "the finished render removes its checkpoint"
    );

    // Nothing left to resume.
    let o = render(&scene, &out, &["-q", "--resume"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no checkpoint"), "{}", stderr(&o));
}

#[test]
fn a_mesh_over_the_triangle_limit_is_refused_naming_the_flag() {
    let d = Dir::new();
    d.file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 3 2\n");
    let scene = d.file(
        "s.yml",
        &format!("{RED_SPHERE}- add: obj\n  file: quad.obj\n"),
    );
    let o = render(&scene, &d.path("o.png"), &["-q", "--max-triangles", "1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("more than 1 triangles"), "{err}");
    assert!(err.contains("quad.obj:5:1"), "{err}");
    assert!(err.contains("--max-triangles"), "{err}");
    assert!(err.contains("quad.obj"), "{err}");
    assert!(
        render(&scene, &d.path("o.png"), &["-q", "--max-triangles", "2"])
            .status
            .success()
    );
    let o = render(&scene, &d.path("o.png"), &["-q", "--max-triangles", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--max-triangles"), "{}", stderr(&o));
}

/// A scene whose camera asks for 10 gigapixels (about 240 GB of colours) is refused before
/// anything is allocated, naming the camera and the flag.
#[test]
fn a_ten_gigapixel_scene_camera_is_refused_before_rendering() {
    let d = Dir::new();
    let scene = d.file(
        "huge.yml",
        &RED_SPHERE
            .replace("width: 9", "width: 100000")
            .replace("height: 9", "height: 100000"),
    );
    let started = std::time::Instant::now();
    let o = render(&scene, &d.path("o.png"), &["-q"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("the scene's camera"), "{err}");
    assert!(err.contains("100000×100000"), "{err}");
    assert!(err.contains("--max-pixels"), "{err}");
    assert!(started.elapsed() < std::time::Duration::from_secs(30));
    assert!(!d.path("o.png").exists());
    assert!(!d.path("o.png.rayforge-checkpoint").exists());
}

#[test]
fn the_rasterizer_renders_the_scene() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("out.png");
    let o = render(&scene, &out, &["--renderer", "raster"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (9, 9));
    assert_eq!(img.get_pixel(4, 4).0, [255, 0, 0]);
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0]);
    let summary = stderr(&o);
    assert!(summary.contains("rasterized 9×9"), "{summary}");
    assert!(summary.contains("triangles"), "{summary}");
}

#[test]
fn the_rasterizer_and_the_ray_tracer_agree_on_a_matte_sphere() {
    let d = Dir::new();
    let scene = d.file(
        "s.yml",
        &RED_SPHERE.replace("width: 9\n  height: 9", "width: 40\n  height: 40"),
    );
    let (ray, raster) = (d.path("ray.pfm"), d.path("raster.pfm"));
    assert!(render(&scene, &ray, &["-q"]).status.success());
    let o = render(
        &scene,
        &raster,
        &["-q", "--renderer", "raster", "--sphere-divisions", "96"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (std::fs::read(ray).unwrap(), std::fs::read(raster).unwrap());
    assert_eq!(a.len(), b.len());
    let differ = a
        .chunks(12)
        .zip(b.chunks(12))
        .filter(|(p, q)| p != q)
        .count();
    // Only pixels along the silhouette of the tessellated sphere may differ.
    assert!(differ < 40, "{differ} pixels differ");
}

#[test]
fn raster_options_change_the_image_and_any_thread_count_gives_the_same_bytes() {
    let d = Dir::new();
    let scene = d.file(
        "s.yml",
        &RED_SPHERE.replace("width: 9", "width: 60").replace(
            "ambient: 1\n    diffuse: 0\n    specular: 0",
            "ambient: 0.1",
        ),
    );
    let run = |name: &str, extra: &[&str]| {
        let out = d.path(name);
        let mut args = vec!["-q", "--renderer", "raster"];
        args.extend_from_slice(extra);
        let o = render(&scene, &out, &args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let one = run("one.pfm", &["--threads", "1", "--shading", "gouraud"]);
    let four = run("four.pfm", &["--threads", "4", "--shading", "gouraud"]);
    assert_eq!(one, four);
    let flat = run(
        "flat.pfm",
        &["--shading", "flat", "--sphere-divisions", "8"],
    );
    let phong = run(
        "phong.pfm",
        &["--shading", "phong", "--texture-filter", "nearest"],
    );
    let wire = run("wire.pfm", &["--wireframe"]);
    assert_ne!(flat, phong);
    assert_ne!(phong, wire);
}

#[test]
fn raster_flags_need_the_rasterizer_and_sampling_flags_the_ray_tracer() {
    let d = Dir::new();
    let scene = d.file("s.yml", RED_SPHERE);
    let out = d.path("o.png");
    for extra in [
        &["--shading", "flat"][..],
        &["--wireframe"],
        &["--sphere-divisions", "10"],
        &["--texture-filter", "nearest"],
    ] {
        let o = render(&scene, &out, extra);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(stderr(&o).contains(extra[0]), "{}", stderr(&o));
        assert!(stderr(&o).contains("--renderer raster"), "{}", stderr(&o));
    }
    for extra in [&["--spp", "4"][..], &["--adaptive-aa", "0.1"]] {
        let mut args = vec!["--renderer", "raster"];
        args.extend_from_slice(extra);
        let o = render(&scene, &out, &args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(stderr(&o).contains(extra[0]), "{}", stderr(&o));
    }
    for divisions in ["2", "5000"] {
        let o = render(
            &scene,
            &out,
            &["--renderer", "raster", "--sphere-divisions", divisions],
        );
        assert_eq!(o.status.code(), Some(2), "{divisions}");
        assert!(stderr(&o).contains("--sphere-divisions"), "{}", stderr(&o));
    }
    let o = render(&scene, &out, &["--renderer", "gpu"]);
    assert_eq!(o.status.code(), Some(2), "clap refuses an unknown renderer");
    assert!(!out.exists());
}

/// A sphere that moves one unit right per frame.
const SLIDING: &str = "
- add: camera
  width: 16
  height: 8
  field-of-view: 1.2
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: sphere
  transform:
    - [scale, 0.5, 0.5, 0.5]
    - [translate, -1, 0, 0]
  per-frame:
    - [translate, 1, 0, 0]
";

#[test]
fn frames_are_written_numbered_and_skipped_when_present() {
    let d = Dir::new();
    let scene = d.file("s.yml", SLIDING);
    let pattern = d.path("frame-%03d.png");
    let o = render(&scene, &pattern, &["--frames", "0..2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let frames: Vec<_> = (0..3)
        .map(|f| {
            image::open(d.path(&format!("frame-{f:03}.png")))
                .unwrap()
                .to_rgb8()
        })
        .collect();
    // The sphere moves: each frame differs from the one before.
    assert_ne!(frames[0], frames[1]);
    assert_ne!(frames[1], frames[2]);
    // Frame 1 has the sphere at the origin: the same image as a still with it there.
    let still = d.file(
        "still.yml",
        &SLIDING.replace("[translate, -1, 0, 0]", "[translate, 0, 0, 0]"),
    );
    let o = render(&still, &d.path("still.png"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        frames[1],
        image::open(d.path("still.png")).unwrap().to_rgb8()
    );
    // Run again with one frame removed: only that one is rendered.
    std::fs::remove_file(d.path("frame-001.png")).unwrap();
    let o = render(&scene, &pattern, &["--frames", "0..2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("frame 0") && err.contains("already there"),
        "{err}"
    );
    assert!(d.path("frame-001.png").exists());
}

#[test]
fn frames_need_a_number_in_the_output_name() {
    let d = Dir::new();
    let scene = d.file("s.yml", SLIDING);
    let o = render(&scene, &d.path("out.png"), &["--frames", "0..2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("%04d"), "{}", stderr(&o));
    let o = render(&scene, &d.path("f%d.png"), &["--frames", "3..1"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn trace_pixel_prints_the_rays_of_one_pixel_under_every_lighting_model() {
    let d = Dir::new();
    for (model, extra) in [("phong", ""), ("cgfs", ""), ("optics", ""), ("flat", "")] {
        let scene = d.file(
            &format!("{model}.yml"),
            &format!(
                "- world:\n    lighting: {model}\n{}{extra}",
                SLIDING.replace("[translate, -1, 0, 0]", "[translate, 0, 0, 0]")
            ),
        );
        let o = render(
            &scene,
            &d.path(&format!("{model}.png")),
            &["--trace-pixel", "8,4", "--quiet"],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("pixel (8, 4)"), "{model}: {out}");
        assert!(out.contains("ray from"), "{model}: {out}");
        assert!(out.contains("hit object #0 (sphere)"), "{model}: {out}");
        assert!(out.contains("pixel colour"), "{model}: {out}");
        assert!(
            d.path(&format!("{model}.png")).exists(),
            "the image is written too"
        );
    }
    let scene = d.file("s.yml", SLIDING);
    let o = render(&scene, &d.path("o.png"), &["--trace-pixel", "99,4"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("outside"), "{}", stderr(&o));
}
