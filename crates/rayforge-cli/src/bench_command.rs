//! `rayforge bench`: runs the `rayforge-bench` program, which holds the benchmarks (its own
//! crate, so that this binary ships none of them), with every argument passed through.

use crate::failure::Failure;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// The file name of the benchmark program on this system.
const BENCH: &str = if cfg!(windows) {
    "rayforge-bench.exe"
} else {
    "rayforge-bench"
};

/// Runs `rayforge-bench ARGS` and returns its exit status; a usage failure (exit 2) saying how
/// to build it when it is not there.
pub fn run(args: &[OsString]) -> Result<ExitCode, Failure> {
    let beside = std::env::current_exe()
        .ok()
        .and_then(|exe| Some(exe.parent()?.to_path_buf()));
    let Some(program) = find(beside.as_deref(), std::env::var_os("PATH")) else {
        return Err(Failure::usage(format!(
            "`rayforge bench` runs the separate program `{BENCH}`, which is neither beside \
             this `rayforge`{} nor on PATH; build it with `cargo build --release -p \
             rayforge-bench` (it lands beside `target/release/rayforge`)",
            beside
                .map(|dir| format!(" (in `{}`)", dir.display()))
                .unwrap_or_default()
        )));
    };
    let status = Command::new(&program)
        .args(args)
        .status()
        .map_err(|e| Failure::internal(format!("cannot run `{}`: {e}", program.display())))?;
    Ok(ExitCode::from(exit_code(status)))
}

/// The benchmark program in `beside` (the directory this executable is in: cargo builds both
/// into the same one), else the first in the directories of `path`.
fn find(beside: Option<&Path>, path: Option<OsString>) -> Option<PathBuf> {
    let on_path: Vec<PathBuf> = path
        .map(|p| std::env::split_paths(&p).collect())
        .unwrap_or_default();
    beside
        .into_iter()
        .map(Path::to_path_buf)
        .chain(on_path)
        .map(|dir| dir.join(BENCH))
        .find(|candidate| candidate.is_file())
}

/// The child's exit status as ours: its code, or on Unix 128 + the signal that stopped it, as
/// shells report it.
fn exit_code(status: std::process::ExitStatus) -> u8 {
    if let Some(code) = status.code() {
        // Exit codes above 255 exist only on Windows; keep their low byte, but never turn a
        // failure into 0.
        return match u8::try_from(code & 0xff) {
            Ok(0) if code != 0 => 1,
            Ok(byte) => byte,
            Err(_) => 1,
        };
    }
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return u8::try_from(128 + signal).unwrap_or(1);
        }
    }
    1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_program_beside_comes_before_the_one_on_path() {
        let beside = tempfile::tempdir().unwrap();
        let on_path = tempfile::tempdir().unwrap();
        let path = std::env::join_paths([on_path.path()]).unwrap();
        assert_eq!(find(Some(beside.path()), Some(path.clone())), None);
        std::fs::write(on_path.path().join(BENCH), "").unwrap();
        assert_eq!(
            find(Some(beside.path()), Some(path.clone())),
            Some(on_path.path().join(BENCH))
        );
        std::fs::write(beside.path().join(BENCH), "").unwrap();
        assert_eq!(
            find(Some(beside.path()), Some(path)),
            Some(beside.path().join(BENCH))
        );
        assert_eq!(find(None, None), None);
    }
}
