//! Reading a file a scene names, within a limit and inside the scene's folder: below both the
//! scene file's reader and the asset readers (models, images), so that neither has to import
//! the other for it.

use std::cell::RefCell;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// Reads a whole file of at most `limit` bytes; the error is the reason, for the caller to
/// put in context. Refuses what is not a regular file (a directory, `/dev/zero`, a pipe that
/// would never end) and stops reading past the limit, so neither a huge file nor an endless
/// device can take all memory.
pub(crate) fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err("it is not a regular file".into());
    }
    if meta.len() > limit {
        return Err(format!("it is {} bytes; the limit is {limit}", meta.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    // Taken fallibly: a file near the limit on a machine short of memory is an error, not
    // an abort.
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(meta.len() as usize)
        .map_err(|_| format!("cannot allocate {} bytes to read it", meta.len()))?;
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
                self.named.display()
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
                self.named.display()
            )
        })?;
        if real.starts_with(folder) {
            Ok(())
        } else {
            Err(outside())
        }
    }
}
