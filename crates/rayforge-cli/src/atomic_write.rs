//! Writing the image atomically: a temporary file beside the target, renamed over it once
//! complete, so readers see the old file or the whole new one, never a truncated image, and a
//! failure leaves nothing behind.

use crate::failure::Failure;
use std::fs::File;
use std::io::{self, Write};
use std::path::Path;
use tempfile::NamedTempFile;

/// Checks, before any rendering, that `path` can be written: its directory exists and takes
/// new files (by creating and removing a temporary one there), and `path` is not a directory.
pub fn check_writable(path: &Path) -> Result<(), Failure> {
    if path.is_dir() {
        return Err(cannot_write(path, "it is a directory"));
    }
    let dir = directory_of(path);
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Err(cannot_write(
                path,
                &format!("the directory `{}` does not exist", dir.display()),
            ));
        }
        Err(e) => return Err(cannot_write(path, &reason(&e, path))),
        Ok(meta) if !meta.is_dir() => {
            return Err(cannot_write(
                path,
                &format!("`{}` is not a directory", dir.display()),
            ));
        }
        Ok(_) => {}
    }
    temporary_beside(path)
        .map(drop)
        .map_err(|e| cannot_write(path, &reason(&e, path)))
}

/// Refuses to write `output` when it is the file one of `inputs` is read from (each given with
/// what it is, for the message): renaming the new file over it would destroy an input (a part
/// merged into itself, an environment map rendered over). Compared as files, not names: the
/// output path's own entry (a link there would be replaced, not followed) against the file
/// each input's path leads to.
pub fn not_an_input<'a>(
    output: &Path,
    inputs: impl IntoIterator<Item = (&'a Path, &'a str)>,
) -> Result<(), Failure> {
    let Ok(target) = std::fs::symlink_metadata(output) else {
        return Ok(());
    };
    for (input, what) in inputs {
        let Ok(read) = std::fs::metadata(input) else {
            continue;
        };
        if same_file(&target, &read, output, input) {
            return Err(Failure::usage(format!(
                "cannot write `{}`: it is {what} `{}`, an input of this command, which \
                 writing would destroy; write it elsewhere",
                output.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

/// Whether two files' metadata are of one file.
#[cfg(unix)]
fn same_file(a: &std::fs::Metadata, b: &std::fs::Metadata, _: &Path, _: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    (a.dev(), a.ino()) == (b.dev(), b.ino())
}

#[cfg(not(unix))]
fn same_file(_: &std::fs::Metadata, _: &std::fs::Metadata, a: &Path, b: &Path) -> bool {
    std::fs::canonicalize(a).ok() == std::fs::canonicalize(b).ok()
}

/// Writes `bytes` to a temporary file in `path`'s directory, flushes it to disk, then renames
/// it over `path`. On any failure the temporary file is removed and `path` is untouched.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    write_atomically_with(path, |out| out.write_all(bytes))
}

/// [`write_atomically`], the file's bytes written by `write` as it makes them (through a
/// buffer), so that a large file (a slice's part) need not be held in memory whole first.
pub fn write_atomically_with(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), Failure> {
    persist_written(path, write)
        .map(drop)
        .map_err(|why| cannot_write(path, &why))
}

/// [`write_atomically`], keeping the new file open at its end (the checkpoint appends its
/// later rows to it). The error says why, without the file's name.
pub fn write_atomically_and_keep(path: &Path, bytes: &[u8]) -> Result<File, String> {
    persist_written(path, |out| out.write_all(bytes))
}

/// A temporary file beside `path` filled by `write`, flushed to disk and renamed over `path`,
/// still open. The error says why, without the file's name.
fn persist_written(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<File, String> {
    let mut file = temporary_beside(path).map_err(|e| reason(&e, path))?;
    let mut out = io::BufWriter::new(&mut file);
    write(&mut out)
        .and_then(|()| out.flush())
        .map_err(|e| reason(&e, path))?;
    drop(out);
    file.as_file().sync_all().map_err(|e| reason(&e, path))?;
    file.persist(path).map_err(|e| reason(&e.error, path))
}

/// A new temporary file in `path`'s directory (removed when dropped unless persisted).
fn temporary_beside(path: &Path) -> io::Result<NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".rayforge-").suffix(".tmp");
    // Temporary files are private (0600) by default; an image should get the usual
    // permissions, which the umask then trims.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    builder.tempfile_in(directory_of(path))
}

/// The directory a relative or absolute file path lies in (`.` for a bare file name).
fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

fn cannot_write(path: &Path, reason: &str) -> Failure {
    Failure::usage(format!("cannot write `{}`: {reason}", path.display()))
}

/// Why an I/O operation failed, without the name of the temporary file (which tempfile adds
/// to its errors, and which means nothing to the user).
pub fn reason(e: &io::Error, path: &Path) -> String {
    match e.kind() {
        io::ErrorKind::PermissionDenied => "permission denied".into(),
        io::ErrorKind::ReadOnlyFilesystem => "the file system is read-only".into(),
        io::ErrorKind::StorageFull => "no space left on the device".into(),
        // A directory that exists but takes no new files (`/proc`) says "not found" too.
        io::ErrorKind::NotFound if directory_of(path).is_dir() => {
            "the directory takes no new files".into()
        }
        io::ErrorKind::NotFound => "the directory does not exist".into(),
        // A plain OS error carries no path of its own: its message is the best there is.
        _ if e.raw_os_error().is_some() => e.to_string(),
        kind => kind.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_complete_file_replaces_the_old_one_and_no_temporary_file_remains() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("image.ppm");
        std::fs::write(&target, "old").unwrap();
        check_writable(&target).ok().unwrap();
        write_atomically(&target, b"new").ok().unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_file_written_as_it_is_made_that_fails_leaves_the_old_one() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("slice.part");
        std::fs::write(&target, "old").unwrap();
        let failed = write_atomically_with(&target, |out| {
            out.write_all(b"half a part")?;
            Err(io::Error::other("the renderer gave up"))
        });
        let Err(Failure::Input(message)) = failed else {
            panic!("a failed write succeeded");
        };
        assert!(message.contains("cannot write"), "{message}");
        assert_eq!(std::fs::read(&target).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        write_atomically_with(&target, |out| out.write_all(b"a whole part"))
            .ok()
            .unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"a whole part");
    }

    #[test]
    fn a_missing_directory_is_named_without_temporary_paths() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("nowhere/image.png");
        let Err(Failure::Input(message)) = check_writable(&target) else {
            panic!("expected an input failure");
        };
        assert!(message.contains("does not exist"), "{message}");
        assert!(!message.contains(".rayforge-"), "{message}");
        assert!(write_atomically(&target, b"x").is_err());
    }

    #[test]
    fn a_directory_is_not_an_output_file() {
        let dir = tempfile::tempdir().unwrap();
        assert!(check_writable(dir.path()).is_err());
    }
}
