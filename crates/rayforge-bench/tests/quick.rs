//! `rayforge-bench --quick` end to end, with no peers: every part runs on tiny meshes and
//! images, prints its table and reports the missing peers as skipped. Nothing is timed here.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `rayforge` executable the whole renders use, when cargo has built it beside this
/// crate's program (`cargo test --workspace` does; `cargo test -p rayforge-bench` alone may
/// not, and then the renders are reported as skipped).
fn rayforge_beside() -> Option<PathBuf> {
    let name = format!("rayforge{}", std::env::consts::EXE_SUFFIX);
    let path = Path::new(env!("CARGO_BIN_EXE_rayforge-bench")).with_file_name(name);
    path.is_file().then_some(path)
}

fn bench(args: &[&str], peers: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge-bench"))
        .current_dir(repo_root())
        .args(args)
        .arg("--peers")
        .arg(peers)
        .arg("--out")
        .arg(out)
        // No models: the dragon comparisons are skipped, as they are where shared/ is absent.
        .arg("--models")
        .arg(peers.join("no-models"))
        // No Mitsuba: the path tracer's comparison is skipped, as it is where Python cannot
        // import mitsuba; tests never depend on it.
        .arg("--python")
        .arg(peers.join("no-python"))
        // No `rayforge` on PATH: only the one beside the program counts.
        .env("PATH", "")
        .output()
        .expect("runs")
}

#[test]
fn a_quick_run_without_peers_prints_every_table_and_skips_the_peers() {
    let dir = tempfile::tempdir().unwrap();
    let peers = dir.path().join("peers");
    std::fs::create_dir(&peers).unwrap();
    let out = dir.path().join("out");
    let o = bench(&["--quick"], &peers, &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    for title in [
        "### Primary rays against Embree",
        "### BVH build",
        "### Time per primary ray against triangle count",
        "### Whole renders",
        "### The path tracer against Mitsuba 3",
        "### The rasterizer against llvmpipe",
        "### The rasterizer orbiting the cover",
        "### Summary",
    ] {
        assert!(stdout.contains(title), "no `{title}` in:\n{stdout}");
    }
    // rayforge's own rows are there, the peers' are skipped with the way to install them.
    assert!(stdout.contains("| bumpy sphere"), "{stdout}");
    assert!(stdout.contains("skipped"), "{stdout}");
    assert!(stdout.contains("bench/peers/setup.sh"), "{stdout}");
    assert!(stdout.contains("not measured"), "{stdout}");
    assert!(
        stdout.contains("Skipped: Mitsuba 3 was not found"),
        "{stdout}"
    );
    assert!(out.join("bench.md").is_file());
    assert!(out.join("scaling.png").is_file());
    if rayforge_beside().is_some() {
        // The whole renders ran `rayforge render` and read its summary line back.
        assert!(stdout.contains("| cover"), "{stdout}");
        assert!(out.join("scenes/cover-rayforge-1spp-depth5.png").is_file());
        let cover = stdout.lines().find(|l| l.starts_with("| cover")).unwrap();
        let rays_per_second = cover.rsplit('|').nth(1).unwrap().trim();
        assert!(rays_per_second.ends_with("/s"), "no rays/s in `{cover}`");
    } else {
        assert!(
            stdout.contains("cargo build --release -p rayforge-cli"),
            "{stdout}"
        );
    }
}

#[test]
fn a_quick_scaling_run_draws_the_plot_where_asked() {
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("plots/scaling.png");
    std::fs::create_dir(dir.path().join("plots")).unwrap();
    let out = dir.path().join("out");
    let o = bench(
        &["scaling", "--quick", "--plot", plot.to_str().unwrap()],
        dir.path(),
        &out,
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}");
    assert!(stdout.contains("### Time per primary ray"), "{stdout}");
    assert!(stdout.contains("Copied to"), "{stdout}");
    assert!(!stdout.contains("### Whole renders"), "{stdout}");
    let img = image::open(&plot).expect("a PNG").to_rgb8();
    assert_eq!(img.dimensions(), (960, 600));
    let first = *img.get_pixel(0, 0);
    let others = img.pixels().filter(|p| **p != first).count();
    // Axes, ticks, labels, the line and the legend: thousands of pixels, not a blank page.
    assert!(
        others > 5_000,
        "only {others} pixels differ from the background"
    );
    // rayforge's series is drawn in its red.
    assert!(img.pixels().any(|p| p.0 == [200, 50, 40]));
    assert_eq!(
        std::fs::read(&plot).unwrap(),
        std::fs::read(out.join("scaling.png")).unwrap()
    );
    // The plot was written whole: no temporary file is left beside it.
    assert_eq!(
        std::fs::read_dir(dir.path().join("plots")).unwrap().count(),
        1
    );
}

#[test]
fn the_pbr_part_without_mitsuba_is_a_note_not_a_failure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = bench(&["pbr"], dir.path(), &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}");
    assert!(
        stdout.contains("### The path tracer against Mitsuba 3"),
        "{stdout}"
    );
    assert!(
        stdout.contains("Skipped: Mitsuba 3 was not found"),
        "{stdout}"
    );
    assert!(stdout.contains("pip install mitsuba"), "{stdout}");
    assert!(!stdout.contains("### Whole renders"), "{stdout}");
}

#[test]
fn bad_bench_arguments_are_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let o = bench(&["build", "--threads", "0"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--threads"));
    let o = bench(&["nonsense"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
    let o = bench(&["--rayforge", "no-such-file"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--rayforge"));
    let o = bench(
        &["cross", "--peer", "cross-raytrace=no-such-file"],
        dir.path(),
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--peer cross-raytrace"));
    let o = bench(&["cross", "--peer", "nobody=x"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
    let o = bench(&["pbr", "--pbr-spp", "0"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--pbr-spp"));
}

#[test]
fn the_help_lists_every_option_and_the_parts() {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge-bench"))
        .arg("--help")
        .output()
        .unwrap();
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    for word in [
        "--threads",
        "--peers",
        "--peer <NAME=FILE>",
        "cross-raytrace",
        "raytracer_rs-dragons",
        "--out",
        "--models",
        "--povray-scenes",
        "--rayforge",
        "--repeat",
        "--scene-repeat",
        "--plot",
        "--quick",
        "primary",
        "build",
        "scaling",
        "scenes",
        "pbr",
        "--pbr-spp",
        "--pbr-repeat",
        "--pbr-reference",
        "--python",
    ] {
        assert!(help.contains(word), "no `{word}` in:\n{help}");
    }
}
