//! A scratch folder for tests that run `rayforge render` on scenes they write: the folder,
//! the render, and its error output. Included by path (`#[path = "support/scratch.rs"]`) by
//! the tests that use all of it, apart from `support/mod.rs`, which other tests include.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A temporary folder, removed with it.
pub struct Dir(pub tempfile::TempDir);

impl Dir {
    pub fn new() -> Self {
        Dir(tempfile::tempdir().unwrap())
    }

    /// Writes `text` to `name` in the folder.
    pub fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// The path of `name` in the folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }
}

/// `rayforge render SCENE -o OUT EXTRA…`.
pub fn render(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args([Path::new("render"), scene, Path::new("-o"), out])
        .args(extra)
        .output()
        .expect("runs")
}

/// A command's error output, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
