//! One render per output: a lock beside the image, `<output>.rayforge-lock`, held from before
//! the scene is read until the render ends.
//!
//! Two renders to the same output would share its checkpoint: the second replaces it, and the
//! first then says its rows are saved in a file that no longer holds them. So a render takes
//! the lock first, and a second render to the same output is refused, naming the lock and the
//! process holding it, before it touches anything.
//!
//! On Unix the lock is `flock` on the file, which the system releases when its process ends
//! however it ends: a killed render leaves at most the file, never a stale lock (the next
//! render takes it over). The file holds the holder's process id, for the message. Elsewhere
//! the file's existence is the lock (created exclusively), which a crash can leave behind.

use crate::failure::Failure;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock of the image written to `output`.
pub fn path_for(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_os_string();
    name.push(".rayforge-lock");
    PathBuf::from(name)
}

/// A held lock on an output; released, and its file removed, when dropped (on every return,
/// errors and interrupts included).
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    // Held open: closing it releases the lock.
    _file: File,
}

impl OutputLock {
    /// Takes the lock of `output`, or explains which process holds it.
    pub fn acquire(output: &Path) -> Result<Self, Failure> {
        let path = path_for(output);
        let mut file = platform::lock(&path, output)?;
        // The lock is ours: say who holds it, for a render refused meanwhile.
        let _ = file.set_len(0);
        let _ = writeln!(file, "{}", std::process::id());
        Ok(Self { path, _file: file })
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still held (the file closes after), so a waiting render cannot take a
        // lock on a file about to vanish; see `platform::lock`.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// The refusal of a render whose output another process is rendering.
fn held_by_another(lock: &Path, output: &Path, holder: &str) -> Failure {
    let holder = match holder.trim() {
        pid if !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) => {
            format!("another rayforge (process {pid})")
        }
        _ => "another rayforge".to_string(),
    };
    Failure::usage(format!(
        "`{}` is being rendered by {holder}, which holds the lock `{}`; wait for it to finish \
         or stop it (its checkpoint is left alone)",
        output.display(),
        lock.display()
    ))
}

fn cannot_lock(lock: &Path, e: &std::io::Error) -> Failure {
    Failure::usage(format!(
        "cannot create the lock `{}`: {}",
        lock.display(),
        crate::atomic_write::reason(e, lock)
    ))
}

/// The refusal of a lock path that holds something rayforge did not make there.
#[cfg(unix)]
fn not_a_lock(lock: &Path, what: &str) -> Failure {
    Failure::usage(format!(
        "cannot take the lock `{}`: {what}, not a lock file rayforge made; nothing was written \
         to it (remove it if it is not needed)",
        lock.display()
    ))
}

#[cfg(unix)]
mod platform {
    use super::{cannot_lock, held_by_another, not_a_lock};
    use crate::failure::Failure;
    use std::fs::{File, OpenOptions};
    use std::io::Read;
    use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
    use std::os::unix::io::AsRawFd;
    use std::path::Path;

    /// Opens (or creates) the lock file and takes an exclusive `flock` on it without waiting.
    /// The holder removes the file before it lets go, so a lock taken on a file that is no
    /// longer the one at `lock` is worthless: then it tries again with the new one.
    ///
    /// The lock is truncated and written, so what is opened must be a file of rayforge's own:
    /// a symbolic link there is not followed (`O_NOFOLLOW`: in a shared scratch folder another
    /// user could plant one pointing at a file of the user's, which writing the lock would
    /// destroy), and a file that is not a regular one, or that has other names (a hard link
    /// to another file), is refused; nothing waits on a named pipe (`O_NONBLOCK`).
    pub fn lock(lock: &Path, output: &Path) -> Result<File, Failure> {
        loop {
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
                .open(lock)
                .map_err(|e| match e.raw_os_error() {
                    Some(libc::ELOOP) => not_a_lock(lock, "it is a symbolic link"),
                    _ => cannot_lock(lock, &e),
                })?;
            let opened = file.metadata().map_err(|e| cannot_lock(lock, &e))?;
            if !opened.is_file() {
                return Err(not_a_lock(lock, "it is not a regular file"));
            }
            if opened.nlink() != 1 {
                return Err(not_a_lock(
                    lock,
                    "it has other names (a hard link to another file)",
                ));
            }
            // SAFETY: flock on a descriptor this function owns; no memory is involved.
            if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } != 0 {
                let e = std::io::Error::last_os_error();
                if e.raw_os_error() == Some(libc::EWOULDBLOCK) {
                    let mut holder = String::new();
                    let _ = file.read_to_string(&mut holder);
                    return Err(held_by_another(lock, output, &holder));
                }
                return Err(cannot_lock(lock, &e));
            }
            let ours = opened;
            match std::fs::symlink_metadata(lock) {
                Ok(now) if (now.dev(), now.ino()) == (ours.dev(), ours.ino()) => return Ok(file),
                _ => continue,
            }
        }
    }
}

#[cfg(not(unix))]
mod platform {
    use super::{cannot_lock, held_by_another};
    use crate::failure::Failure;
    use std::fs::{File, OpenOptions};
    use std::path::Path;

    /// Creates the lock file, failing when it exists.
    pub fn lock(lock: &Path, output: &Path) -> Result<File, Failure> {
        match OpenOptions::new().write(true).create_new(true).open(lock) {
            Ok(file) => Ok(file),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let holder = std::fs::read_to_string(lock).unwrap_or_default();
                Err(held_by_another(lock, output, &holder))
            }
            Err(e) => Err(cannot_lock(lock, &e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lock_sits_beside_the_output() {
        assert_eq!(
            path_for(Path::new("out/cover.png")),
            Path::new("out/cover.png.rayforge-lock")
        );
    }

    #[test]
    fn a_second_lock_is_refused_until_the_first_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join("o.png");
        let first = OutputLock::acquire(&output).unwrap();
        let pid = std::process::id().to_string();
        assert_eq!(
            std::fs::read_to_string(path_for(&output)).unwrap().trim(),
            pid
        );
        let Err(Failure::Input(message)) = OutputLock::acquire(&output) else {
            panic!("a second lock was granted");
        };
        assert!(message.contains(&format!("process {pid}")), "{message}");
        assert!(message.contains("o.png.rayforge-lock"), "{message}");
        drop(first);
        assert!(!path_for(&output).exists(), "the lock file is removed");
        drop(OutputLock::acquire(&output).unwrap());
    }

    #[cfg(unix)]
    #[test]
    fn a_lock_file_left_by_a_killed_process_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join("o.png");
        std::fs::write(path_for(&output), "4000000\n").unwrap();
        let lock = OutputLock::acquire(&output).unwrap();
        assert_eq!(
            std::fs::read_to_string(path_for(&output)).unwrap().trim(),
            std::process::id().to_string()
        );
        drop(lock);
    }

    /// A link, a named pipe or a hard link planted where the lock goes is refused at once:
    /// nothing is written through it, and nothing waits on the pipe.
    #[cfg(unix)]
    #[test]
    fn a_link_or_a_pipe_planted_at_the_lock_is_refused_and_its_target_kept() {
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join("o.png");
        let victim = dir.path().join("thesis.tex");
        std::fs::write(&victim, "years of work").unwrap();
        let refused = |what: &str| {
            let Err(Failure::Input(m)) = OutputLock::acquire(&output) else {
                panic!("a lock was taken through {what}");
            };
            assert!(m.contains("not a lock file rayforge made"), "{m}");
            assert!(m.contains("o.png.rayforge-lock"), "{m}");
            m
        };
        std::os::unix::fs::symlink(&victim, path_for(&output)).unwrap();
        assert!(refused("a symbolic link").contains("symbolic link"));
        std::fs::remove_file(path_for(&output)).unwrap();
        std::fs::hard_link(&victim, path_for(&output)).unwrap();
        assert!(refused("a hard link").contains("other names"));
        std::fs::remove_file(path_for(&output)).unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "years of work");
        let fifo = std::ffi::CString::new(path_for(&output).to_str().unwrap()).unwrap();
        // SAFETY: a NUL-terminated path that outlives the call.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
        assert!(refused("a named pipe").contains("not a regular file"));
    }
}
