//! `rayforge render scene.pbrt`: the file's sample count and depth followed as pbrt-v4 follows
//! them (`pixelsamples 1` is one sample, `--spp` replaces it), and held to the limits of the
//! renderer the command line picks, the error at the file's own place for them.
#[path = "support/pfm.rs"]
mod pfm;

use pfm::pfm_floats;
use std::path::Path;
use std::process::Command;

/// Runs `rayforge render <scene> <args…>` and gives (success, stderr).
fn render(scene: &Path, args: &[&str]) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .args(args)
        .output()
        .unwrap();
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// A ball under a white sky, seen by a camera of 6 × 4 pixels, after the options `head`.
fn scene(dir: &Path, head: &str) -> std::path::PathBuf {
    let path = dir.join("s.pbrt");
    std::fs::write(
        &path,
        format!(
            "{head}\nFilm \"rgb\" \"integer xresolution\" 6 \"integer yresolution\" 4\n\
             WorldBegin\nLightSource \"infinite\"\nTranslate 0 0 5\nShape \"sphere\"\n"
        ),
    )
    .unwrap();
    path
}

/// Every pixel's sample count, from a render with `--aovs`.
fn samples(scene: &Path, args: &[&str]) -> Vec<f32> {
    let out = scene.with_file_name("out.pfm");
    let mut all = vec![
        "-o",
        out.to_str().unwrap(),
        "--aovs",
        "--sample-allocation",
        "uniform",
    ];
    all.extend_from_slice(args);
    let (ok, stderr) = render(scene, &all);
    assert!(ok, "{stderr}");
    pfm_floats(&scene.with_file_name("out.samples.pfm"))
}

#[test]
fn the_files_sample_count_is_followed_one_included_and_spp_replaces_it() {
    let dir = tempfile::tempdir().unwrap();
    let one = scene(dir.path(), "Sampler \"sobol\" \"integer pixelsamples\" 1");
    assert!(samples(&one, &[]).iter().all(|&n| n == 1.0));
    assert!(samples(&one, &["--spp", "3"]).iter().all(|&n| n == 3.0));
    // No Sampler: pbrt-v4's default sampler's 16; the independent sampler's default is 4.
    let default = scene(dir.path(), "");
    assert!(samples(&default, &[]).iter().all(|&n| n == 16.0));
    let independent = scene(dir.path(), "Sampler \"independent\"");
    assert!(samples(&independent, &[]).iter().all(|&n| n == 4.0));
}

#[test]
fn a_depth_past_the_ray_tracers_limit_is_refused_at_the_included_files_place() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("settings.pbrt"),
        "\nIntegrator \"path\" \"integer maxdepth\" 65\n",
    )
    .unwrap();
    let main = scene(dir.path(), "Include \"settings.pbrt\"");
    let out = dir.path().join("out.png");
    let (ok, stderr) = render(&main, &["-o", out.to_str().unwrap(), "--renderer", "ray"]);
    assert!(!ok);
    assert!(stderr.contains("settings.pbrt:2:19"), "{stderr}");
    assert!(stderr.contains("integer maxdepth"), "{stderr}");
    assert!(stderr.contains("65 bounces is more than 64"), "{stderr}");
    // --max-depth replaces it; the path tracer takes it as it is.
    let (ok, stderr) = render(
        &main,
        &[
            "-o",
            out.to_str().unwrap(),
            "--renderer",
            "ray",
            "--max-depth",
            "5",
        ],
    );
    assert!(ok, "{stderr}");
    let (ok, stderr) = render(&main, &["-o", out.to_str().unwrap(), "--spp", "1"]);
    assert!(ok, "{stderr}");
}
