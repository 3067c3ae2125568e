//! `rayforge bench` runs the separate `rayforge-bench` program found beside `rayforge` (or on
//! PATH), passing every argument through and exiting as it did; without it, a usage error
//! (exit 2) that says how to build it. A copy of `rayforge` in a directory of its own stands in
//! for an installed one.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A copy of the `rayforge` executable alone in a new directory.
fn lone_rayforge() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let name = Path::new(env!("CARGO_BIN_EXE_rayforge"))
        .file_name()
        .unwrap();
    let copy = dir.path().join(name);
    std::fs::copy(env!("CARGO_BIN_EXE_rayforge"), &copy).unwrap();
    (dir, copy)
}

fn bench(rayforge: &Path, args: &[&str]) -> Output {
    // A file just written may be "busy" for a moment: another test's child, forked between
    // its writing and closing, holds it until that child execs. Try again then.
    for _ in 0..50 {
        let run = Command::new(rayforge)
            .arg("bench")
            .args(args)
            // Nothing on PATH either: only what lies beside the copy counts.
            .env("PATH", "")
            .output();
        match run {
            Err(e) if e.kind() == std::io::ErrorKind::ExecutableFileBusy => {
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            run => return run.expect("runs"),
        }
    }
    panic!("{} stayed busy", rayforge.display());
}

#[test]
fn without_rayforge_bench_the_error_says_how_to_build_it() {
    let (_dir, rayforge) = lone_rayforge();
    let o = bench(&rayforge, &["--quick"]);
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("cargo build --release -p rayforge-bench"),
        "{stderr}"
    );
    assert!(stderr.contains("rayforge-bench"), "{stderr}");
    // `--help` goes to the missing program too, and gets the same answer.
    assert_eq!(bench(&rayforge, &["--help"]).status.code(), Some(2));
}

#[test]
fn rayforge_help_still_describes_bench() {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args(["help", "bench"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("rayforge-bench"), "{help}");
}

/// A stand-in `rayforge-bench` (a shell script) beside the copy: it prints its arguments one a
/// line and exits with status 7.
#[cfg(unix)]
#[test]
fn arguments_and_the_exit_status_pass_through() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, rayforge) = lone_rayforge();
    let stand_in = dir.path().join("rayforge-bench");
    std::fs::write(
        &stand_in,
        "#!/bin/sh\nfor a in \"$@\"; do echo \"[$a]\"; done\nexit 7\n",
    )
    .unwrap();
    std::fs::set_permissions(&stand_in, std::fs::Permissions::from_mode(0o755)).unwrap();
    let o = bench(&rayforge, &["scaling", "--help", "--plot", "a b.png", "-q"]);
    assert_eq!(o.status.code(), Some(7));
    assert_eq!(
        String::from_utf8_lossy(&o.stdout),
        "[scaling]\n[--help]\n[--plot]\n[a b.png]\n[-q]\n"
    );
}

/// With the real program built beside `rayforge` (as `cargo test --workspace` leaves it),
/// `rayforge bench --help` is its help.
#[test]
fn rayforge_bench_help_comes_from_rayforge_bench_when_built() {
    let name = format!("rayforge-bench{}", std::env::consts::EXE_SUFFIX);
    let beside = Path::new(env!("CARGO_BIN_EXE_rayforge")).with_file_name(name);
    if !beside.is_file() {
        eprintln!("{} is not built; nothing to compare", beside.display());
        return;
    }
    let o = bench(Path::new(env!("CARGO_BIN_EXE_rayforge")), &["--help"]);
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("Usage: rayforge-bench"), "{help}");
    assert!(help.contains("--scene-repeat"), "{help}");
}

/// The user's way in, end to end: `rayforge bench --quick` runs the benchmark laboratory
/// (every part on tiny inputs, the peers missing and reported as skipped, whole renders by this
/// very `rayforge`), prints its tables and draws its plot. `cargo test --workspace` builds
/// `rayforge-bench` beside `rayforge`; a run of this package alone may not, and says so.
#[test]
fn rayforge_bench_quick_runs_the_laboratory_through_rayforge() {
    let name = format!("rayforge-bench{}", std::env::consts::EXE_SUFFIX);
    let beside = Path::new(env!("CARGO_BIN_EXE_rayforge")).with_file_name(name);
    if !beside.is_file() {
        eprintln!(
            "{} is not built; run cargo test --workspace",
            beside.display()
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (peers, out) = (dir.path().join("peers"), dir.path().join("out"));
    std::fs::create_dir(&peers).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .arg("bench")
        .arg("--quick")
        .arg("--peers")
        .arg(&peers)
        .arg("--out")
        .arg(&out)
        .arg("--models")
        .arg(peers.join("no-models"))
        .env("PATH", "")
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    for title in [
        "### Primary rays against Embree",
        "### BVH build",
        "### Whole renders",
        "### Summary",
    ] {
        assert!(stdout.contains(title), "no `{title}` in:\n{stdout}");
    }
    assert!(
        stdout.contains("| cover"),
        "the whole renders ran: {stdout}"
    );
    let plot = image::open(out.join("scaling.png")).expect("the plot is a PNG");
    assert!(plot.width() > 100 && plot.height() > 100);
}
