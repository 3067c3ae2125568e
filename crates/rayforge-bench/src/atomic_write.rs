//! Writing a report or a plot atomically: a temporary file beside the target, renamed over it
//! once complete, so readers see the old file or the whole new one, never a truncated one.

use crate::failure::Failure;
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to a temporary file in `path`'s directory, flushes it to disk, then renames
/// it over `path`. On any failure the temporary file is removed and `path` is untouched.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    let cannot = |e: &std::io::Error| {
        Failure::usage(format!("cannot write `{}`: {}", path.display(), e.kind()))
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".rayforge-bench-").suffix(".tmp");
    // Temporary files are private (0600) by default; a report should get the usual
    // permissions, which the umask then trims.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let mut file = builder.tempfile_in(dir).map_err(|e| cannot(&e))?;
    file.write_all(bytes).map_err(|e| cannot(&e))?;
    file.as_file().sync_all().map_err(|e| cannot(&e))?;
    file.persist(path).map_err(|e| cannot(&e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_complete_file_replaces_the_old_one_and_no_temporary_file_remains() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("bench.md");
        std::fs::write(&target, "old").unwrap();
        write_atomically(&target, b"new").ok().unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        assert!(write_atomically(&dir.path().join("nowhere/x.png"), b"x").is_err());
    }
}
