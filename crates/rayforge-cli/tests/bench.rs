//! `rayforge bench --quick` end to end, with no peers: every part runs on tiny meshes and
//! images, prints its table and reports the missing peers as skipped. Nothing is timed here.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn bench(args: &[&str], peers: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .current_dir(repo_root())
        .arg("bench")
        .args(args)
        .arg("--peers")
        .arg(peers)
        .arg("--out")
        .arg(out)
        // No models: the dragon comparisons are skipped, as they are where shared/ is absent.
        .arg("--models")
        .arg(peers.join("no-models"))
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
        "### Summary",
    ] {
        assert!(stdout.contains(title), "no `{title}` in:\n{stdout}");
    }
    // rayforge's own rows are there, the peers' are skipped with the way to install them.
    assert!(stdout.contains("| bumpy sphere"), "{stdout}");
    assert!(stdout.contains("| cover"), "{stdout}");
    assert!(stdout.contains("skipped"), "{stdout}");
    assert!(stdout.contains("bench/peers/setup.sh"), "{stdout}");
    assert!(stdout.contains("not measured"), "{stdout}");
    assert!(out.join("bench.md").is_file());
    assert!(out.join("scaling.png").is_file());
    assert!(out.join("scenes/cover-rayforge-1spp-depth5.png").is_file());
}

#[test]
fn bad_bench_arguments_are_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let o = bench(&["build", "--threads", "0"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--threads"));
    let o = bench(&["nonsense"], dir.path(), dir.path());
    assert_eq!(o.status.code(), Some(2));
}
