//! `rayforge render --renderer path`: the path tracer from the command line: its flags, its
//! outputs (linear PFM, the albedo and normal images), determinism across threads and seeds,
//! and refusals of flags that belong to other renderers.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository's root, where the scenes are.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn rayforge() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
}

/// Runs `rayforge render <scene> -o <out> <args…>` and returns (success, stderr).
fn render(scene: &str, out: &Path, args: &[&str]) -> (bool, String) {
    let output = rayforge()
        .arg("render")
        .arg(repo().join(scene))
        .arg("-o")
        .arg(out)
        .args(args)
        .output()
        .unwrap();
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn temp() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn out(dir: &tempfile::TempDir, name: &str) -> PathBuf {
    dir.path().join(name)
}

/// The PFM's floats after its header.
fn pfm_floats(path: &Path) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    let mut lines = 0;
    let start = bytes
        .iter()
        .position(|&b| {
            lines += usize::from(b == b'\n');
            lines == 3
        })
        .unwrap()
        + 1;
    bytes[start..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

const SMALL: &[&str] = &["--width", "12", "--height", "12", "--spp", "8"];

#[test]
fn a_reference_scene_path_traces_to_a_linear_pfm_with_a_summary() {
    let dir = temp();
    let image = out(&dir, "furnace.pfm");
    let (ok, stderr) = render("scenes/pbr/furnace.yml", &image, SMALL);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("path traced 12×12 at 8 spp"), "{stderr}");
    let floats = pfm_floats(&image);
    assert_eq!(floats.len(), 12 * 12 * 3);
    // The corners see the sky of radiance 1, the middle the sphere of albedo 0.8.
    assert_eq!(floats[0], 1.0);
    let middle = (6 * 12 + 6) * 3;
    assert!((floats[middle] - 0.8).abs() < 1e-6, "{}", floats[middle]);
}

#[test]
fn the_image_depends_on_the_seed_but_not_on_the_threads() {
    let dir = temp();
    let run = |name: &str, extra: &[&str]| {
        let image = out(&dir, name);
        let mut args = SMALL.to_vec();
        args.extend_from_slice(extra);
        let (ok, stderr) = render("scenes/pbr/cornell.yml", &image, &args);
        assert!(ok, "{stderr}");
        std::fs::read(image).unwrap()
    };
    let one = run("a.pfm", &["--threads", "1"]);
    let two = run("b.pfm", &["--threads", "2"]);
    let other_seed = run("c.pfm", &["--threads", "2", "--seed", "7"]);
    assert_eq!(one, two);
    assert_ne!(one, other_seed);
}

#[test]
fn aovs_write_the_first_hits_albedo_and_normal_beside_the_image() {
    let dir = temp();
    let image = out(&dir, "cornell.pfm");
    let mut args = SMALL.to_vec();
    args.push("--aovs");
    let (ok, stderr) = render("scenes/pbr/cornell.yml", &image, &args);
    assert!(ok, "{stderr}");
    let albedo = pfm_floats(&out(&dir, "cornell.albedo.pfm"));
    let normal = pfm_floats(&out(&dir, "cornell.normal.pfm"));
    assert_eq!((albedo.len(), normal.len()), (12 * 12 * 3, 12 * 12 * 3));
    // Pixels that see only the floor have its normal (+y) and its white albedo; those that see
    // only the red wall, +x and red.
    let normal = &normal;
    let pixels = |n: [f32; 3]| {
        (0..144).filter(move |&i| (0..3).all(|c| (normal[3 * i + c] - n[c]).abs() < 1e-6))
    };
    let floor: Vec<usize> = pixels([0.0, 1.0, 0.0]).collect();
    let red: Vec<usize> = pixels([1.0, 0.0, 0.0]).collect();
    assert!(!floor.is_empty() && !red.is_empty());
    for i in floor {
        assert!((albedo[3 * i] - 0.885809).abs() < 1e-5, "{}", albedo[3 * i]);
    }
    for i in red {
        assert!(
            (albedo[3 * i + 1] - 0.0430135).abs() < 1e-5,
            "{}",
            albedo[3 * i + 1]
        );
    }
}

#[test]
fn a_book_scene_path_traces_to_png_with_every_sampler_and_filter() {
    let dir = temp();
    for (i, extra) in [
        &["--renderer", "path", "--sampler", "independent"][..],
        &[
            "--renderer",
            "path",
            "--filter",
            "gaussian",
            "--filter-radius",
            "2",
        ][..],
        &["--renderer", "path", "--filter", "tent"][..],
    ]
    .iter()
    .enumerate()
    {
        let image = out(&dir, &format!("world{i}.png"));
        let mut args = SMALL.to_vec();
        args.extend_from_slice(extra);
        let (ok, stderr) = render("scenes/trtc/ch07-world.yml", &image, &args);
        assert!(ok, "{stderr}");
        assert!(image::open(&image).is_ok());
    }
}

#[test]
fn path_flags_are_refused_with_the_other_renderers_and_with_each_other() {
    let dir = temp();
    let image = out(&dir, "x.png");
    for (args, expected) in [
        (&["--seed", "3"][..], "--seed applies to the path tracer"),
        (&["--aovs"][..], "--aovs applies to the path tracer"),
        (
            &["--renderer", "path", "--filter-radius", "2"][..],
            "--filter-radius needs --filter tent or --filter gaussian",
        ),
        (
            &[
                "--renderer",
                "path",
                "--filter",
                "gaussian",
                "--filter-radius",
                "9",
            ][..],
            "--filter-radius must be above 0 and at most 8",
        ),
        (
            &["--renderer", "path", "--adaptive", "0.1"][..],
            "--adaptive applies to the ray tracer",
        ),
        (
            &["--renderer", "path", "--shading", "flat"][..],
            "--shading applies to the rasterizer",
        ),
    ] {
        let (ok, stderr) = render("scenes/trtc/ch07-world.yml", &image, args);
        assert!(!ok, "{args:?} was accepted");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
    assert!(!image.exists());
}

#[test]
fn an_exr_holds_the_same_linear_floats_as_the_pfm() {
    let dir = temp();
    let (pfm, exr) = (out(&dir, "f.pfm"), out(&dir, "f.exr"));
    for image in [&pfm, &exr] {
        let (ok, stderr) = render("scenes/pbr/spheres-materials.yml", image, SMALL);
        assert!(ok, "{stderr}");
    }
    let floats = pfm_floats(&pfm);
    let read = exr::prelude::read_first_rgba_layer_from_file(
        &exr,
        |size, _| vec![0.0f32; size.width() * size.height() * 3],
        |pixels: &mut Vec<f32>, exr::prelude::Vec2(x, y), (r, g, b, _): (f32, f32, f32, f32)| {
            // PFM rows run bottom to top; put the EXR's in the same order.
            let i = ((11 - y) * 12 + x) * 3;
            pixels[i..i + 3].copy_from_slice(&[r, g, b]);
        },
    )
    .unwrap();
    assert_eq!(read.layer_data.channel_data.pixels, floats);
}
