//! What the scene-rendering tests share: the repository, rendering a shipped scene with the
//! `rayforge` binary, and a hash to pin a render by.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The repository's root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Renders `scenes/<scene>.yml` at its own size, quietly, and returns its pixels.
pub fn render_scene(scene: &str) -> image::RgbImage {
    // A name of its own for each render: tests run at once, and a render to an output another
    // render holds is refused (its lock).
    static RENDERS: AtomicUsize = AtomicUsize::new(0);
    let n = RENDERS.fetch_add(1, Ordering::Relaxed);
    let out =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{}-{n}.png", scene.replace('/', "-")));
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(repo().join(format!("scenes/{scene}.yml")))
        .arg("-o")
        .arg(&out)
        .arg("--quiet")
        .output()
        .expect("runs rayforge");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    image::open(&out).expect("reads the render").to_rgb8()
}

/// FNV-1a, 64 bits, over the RGB bytes.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
