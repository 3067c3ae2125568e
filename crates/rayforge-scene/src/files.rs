//! Reading a file a scene names, within a limit and inside the scene's folder: below both the
//! scene file's reader and the asset readers (models, images), so that neither has to import
//! the other for it.
//!
//! [`open_regular`] and [`read_bounded`] are also how the command opens every other file it
//! reads from outside (part files, checkpoints, the scene read again for a part's
//! fingerprint or a merge's canvas items), so that each file from outside is opened one way:
//! a regular file only, refused before a byte is read (and before anything blocks) when it is
//! a directory, a device or a named pipe, and its size checked before it is read.

use std::cell::RefCell;
use std::fs::File;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// Opens the existing file at `path` for reading, as input from outside, and returns it with
/// its length; the error is the reason, for the caller to put in context.
///
/// Refuses what is not a regular file: a directory, a device (`/dev/zero` never ends) or a
/// named pipe (whose opening waits for a writer that may never come). The file is asked about
/// by name first, so that such a file is not even opened, then opened without waiting
/// (`O_NONBLOCK`, which changes nothing for a regular file's reads) and asked again through
/// the open descriptor, so that a file swapped for a pipe between the two is refused too.
pub fn open_regular(path: &Path) -> Result<(File, u64), String> {
    let named = std::fs::metadata(path).map_err(|e| e.to_string())?;
    not_special(&named)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    let file = options.open(path).map_err(|e| e.to_string())?;
    let opened = file.metadata().map_err(|e| e.to_string())?;
    not_special(&opened)?;
    Ok((file, opened.len()))
}

/// Opens the existing regular file at `path` to read and write it in place (a checkpoint
/// continued), as [`open_regular`] does, except that a symbolic link is not followed: a link
/// planted where the program keeps its own file must not make it write wherever it points.
pub fn open_regular_to_update(path: &Path) -> Result<File, String> {
    let named = std::fs::symlink_metadata(path).map_err(|e| e.to_string())?;
    if named.file_type().is_symlink() {
        return Err("it is a symbolic link, not the file rayforge wrote".into());
    }
    not_special(&named)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true).write(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(
        &mut options,
        libc::O_NONBLOCK | libc::O_NOFOLLOW,
    );
    let file = options.open(path).map_err(|e| e.to_string())?;
    not_special(&file.metadata().map_err(|e| e.to_string())?)?;
    Ok(file)
}

/// Refuses a file that is not a regular one, naming what it is.
fn not_special(meta: &std::fs::Metadata) -> Result<(), String> {
    if meta.is_file() {
        return Ok(());
    }
    let kind = meta.file_type();
    let what = if kind.is_dir() {
        "a directory"
    } else {
        special_kind(&kind)
    };
    Err(format!("it is not a regular file (it is {what})"))
}

#[cfg(unix)]
fn special_kind(kind: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        "a named pipe"
    } else if kind.is_char_device() || kind.is_block_device() {
        "a device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "not a file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "not a file"
}

/// Reads a whole file of at most `limit` bytes, opened by [`open_regular`]; the error is the
/// reason, for the caller to put in context. The size is checked before reading, and reading
/// stops past the limit (a file that grows meanwhile), so a huge file cannot take all memory.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let (file, len) = open_regular(path)?;
    if len > limit {
        return Err(format!("it is {len} bytes; the limit is {limit}"));
    }
    // Taken fallibly: a file near the limit on a machine short of memory is an error, not
    // an abort.
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(len as usize)
        .map_err(|_| format!("cannot allocate {len} bytes to read it"))?;
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!("it grew past the limit of {limit} bytes"));
    }
    Ok(bytes)
}

/// The folder the files a scene names must be in: the folder of the top-level scene file, as
/// its path names it. Models, material libraries, images and environment maps, and whatever
/// they name in turn, are read only from inside it, so that a scene from elsewhere cannot make
/// the renderer read (and its errors quote) `/etc/passwd` or a key beside the scene's folder.
#[derive(Debug)]
pub(crate) struct Folder {
    /// The folder as the scene's path names it; names are joined to it.
    named: PathBuf,
    /// Where it really is (links resolved), or why that is unknown: the check for a name that
    /// reaches outside through a symbolic link.
    real: Result<PathBuf, String>,
    /// Whether names may reach outside it after all (`LoadOptions::allow_outside`).
    allow_outside: bool,
    /// Every file asked about, in order: what a scene read besides itself (a render's
    /// fingerprint covers them, and the live page watches them).
    asked: RefCell<Vec<PathBuf>>,
}

impl Folder {
    /// The folder of the file at `path`; `allow_outside` lifts the confinement.
    pub(crate) fn of_file(path: &Path, allow_outside: bool) -> Self {
        let named = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let here = if named.as_os_str().is_empty() {
            Path::new(".")
        } else {
            named.as_path()
        };
        let real = std::fs::canonicalize(here).map_err(|e| e.to_string());
        Self {
            named,
            real,
            allow_outside,
            asked: RefCell::new(Vec::new()),
        }
    }

    /// The files [`Folder::check`] was asked about, each once, in the order first asked.
    pub(crate) fn asked(&self) -> Vec<PathBuf> {
        let mut seen = std::collections::HashSet::new();
        self.asked
            .borrow()
            .iter()
            .filter(|p| seen.insert(p.to_path_buf()))
            .cloned()
            .collect()
    }

    /// The folder as the scene's path names it.
    pub(crate) fn named(&self) -> &Path {
        &self.named
    }

    /// The folder as messages name it: `.` for a scene named without a folder (whose folder
    /// the path names as nothing at all).
    fn shown(&self) -> std::path::Display<'_> {
        if self.named.as_os_str().is_empty() {
            Path::new(".").display()
        } else {
            self.named.display()
        }
    }

    /// Whether the file at `path` (a name joined to this folder, or to the folder of a file
    /// inside it) may be read; the error is the reason, naming the way to allow it.
    ///
    /// Checked twice: by the name, so that an absolute path or a `..` that climbs above the
    /// folder is refused without even asking whether the file exists (which would tell a
    /// scene about files outside), and by where the file really is, so that a symbolic link
    /// inside the folder cannot lead out of it. A missing file passes: reading it says so.
    pub(crate) fn check(&self, path: &Path) -> Result<(), String> {
        self.asked.borrow_mut().push(path.to_path_buf());
        if self.allow_outside {
            return Ok(());
        }
        let outside = || {
            format!(
                "`{}` is outside the scene's folder (`{}`): a scene may only name files inside \
                 the folder it is in, unless `--allow-outside` (on the command line) or \
                 `LoadOptions::allow_outside` (in the library) allows the rest",
                path.display(),
                self.shown()
            )
        };
        let rest = path.strip_prefix(&self.named).map_err(|_| outside())?;
        let mut depth = 0usize;
        for part in rest.components() {
            match part {
                Component::Normal(_) => depth += 1,
                Component::CurDir => {}
                Component::ParentDir => depth = depth.checked_sub(1).ok_or_else(outside)?,
                Component::RootDir | Component::Prefix(_) => return Err(outside()),
            }
        }
        let Ok(real) = std::fs::canonicalize(path) else {
            return Ok(());
        };
        let folder = self.real.as_ref().map_err(|e| {
            format!(
                "cannot tell whether `{}` is inside the scene's folder (`{}`): {e}",
                path.display(),
                self.shown()
            )
        })?;
        if real.starts_with(folder) {
            Ok(())
        } else {
            Err(outside())
        }
    }
}
