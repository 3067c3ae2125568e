//! The files of a pbrt scene: the top-level file and those it includes or imports, each read
//! as untrusted input (a regular file, its size checked before it is read, gzip's output
//! bounded as it is inflated), and where in them something is, for messages.

use crate::error::{SceneError, Span};
use crate::files::{read_bounded, Folder};
use crate::scene::PbrtLimits;
use crate::stop::StopFlag;
use std::cell::Cell;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// The default of the most bytes one of a scene's files may hold (after inflating, for a
/// `.gz`): a YAML scene's limit (see [`PbrtLimits`]).
pub const MAX_SCENE_BYTES: u64 = PbrtLimits::DEFAULT.file_bytes;

/// The default of how deep `Include` and `Import` may nest (a file that includes itself stops
/// here).
pub const MAX_INCLUDE_DEPTH: usize = PbrtLimits::DEFAULT.include_depth;

/// The default of the most bytes all of a scene's files may hold together, after inflating: a
/// file included many times is read each time.
pub const MAX_TOTAL_BYTES: u64 = PbrtLimits::DEFAULT.total_bytes;

/// The default of the most parameter values all of a scene's files may hold together.
pub const MAX_VALUES: u64 = PbrtLimits::DEFAULT.values;

/// How many parameter values are lexed between two looks at the stop flag: one directive's
/// bracket may hold tens of millions (a `trianglemesh`'s points), seconds of lexing.
const STOP_EVERY: u64 = 1 << 16;

/// What is left of a scene's parameter values ([`PbrtLimits::values`]), spent as each value is
/// lexed, before it is kept; with the flag that stops the reading, looked at every
/// [`STOP_EVERY`] values.
#[derive(Debug)]
pub struct ValueBudget {
    left: Cell<u64>,
    limit: u64,
    stop: StopFlag,
}

impl ValueBudget {
    pub fn new(limit: u64) -> Self {
        Self {
            left: Cell::new(limit),
            limit,
            stop: StopFlag::default(),
        }
    }

    /// The stop flag, when the value just spent is one at which it is looked at.
    pub fn stop_due(&self) -> Option<&StopFlag> {
        ((self.limit - self.left.get()) % STOP_EVERY == 0).then_some(&self.stop)
    }

    /// Spends one value: `false` when none is left.
    pub fn take(&self) -> bool {
        match self.left.get().checked_sub(1) {
            Some(left) => {
                self.left.set(left);
                true
            }
            None => false,
        }
    }

    /// What an error past the budget says.
    pub fn spent(&self) -> String {
        format!(
            "the scene's parameter lists hold more than {} values together \
             (`--max-pbrt-values`)",
            self.limit
        )
    }
}

/// Where something is: which file, and where in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Loc {
    /// The file.
    pub file: Rc<Path>,
    /// The place in it.
    pub span: Span,
}

impl Loc {
    /// An error here, about `key` when given (a directive's or a parameter's name).
    pub fn error(&self, key: Option<&str>, message: impl Into<String>) -> SceneError {
        let error = SceneError::new(&self.file, message).at(self.span);
        match key {
            Some(k) => error.with_key(k),
            None => error,
        }
    }

    /// `Err` here, about `key`, once `stop` is set.
    pub fn stopped(&self, stop: &StopFlag, key: &str) -> Result<(), SceneError> {
        stop.check(&self.file)
            .map_err(|e| e.at(self.span).with_key(key))
    }
}

/// The files read so far, and the folder the names in them are found in.
pub struct Files {
    main: PathBuf,
    folder: Folder,
    /// Bytes read so far, all files together.
    total: u64,
    /// The flag that stops the reading part-way: looked at before each directive and each
    /// shape built.
    stop: StopFlag,
    /// What the files may hold.
    limits: PbrtLimits,
    /// What is left of the parameter values.
    values: ValueBudget,
}

impl Files {
    /// The files of the scene whose top-level file is `main` (the folder the names in every
    /// file resolve in is `main`'s, as pbrt-v4 resolves them); names must stay inside it
    /// unless `allow_outside`.
    pub fn new(main: &Path, allow_outside: bool) -> Self {
        Self {
            main: main.to_path_buf(),
            folder: Folder::of_file(main, allow_outside),
            total: 0,
            stop: StopFlag::default(),
            limits: PbrtLimits::DEFAULT,
            values: ValueBudget::new(PbrtLimits::DEFAULT.values),
        }
    }

    /// The same files, held to `limits`.
    pub fn limited_by(self, limits: PbrtLimits) -> Self {
        Self {
            limits,
            values: ValueBudget {
                stop: self.stop.clone(),
                ..ValueBudget::new(limits.values)
            },
            ..self
        }
    }

    /// What the files may hold.
    pub fn limits(&self) -> &PbrtLimits {
        &self.limits
    }

    /// What is left of the parameter values.
    pub fn values(&self) -> &ValueBudget {
        &self.values
    }

    /// The same files, whose reading and building stop once `stop` is set.
    pub fn stopped_by(self, stop: StopFlag) -> Self {
        Self {
            values: ValueBudget {
                stop: stop.clone(),
                ..self.values
            },
            stop,
            ..self
        }
    }

    /// The flag that stops the reading.
    pub fn stop(&self) -> &StopFlag {
        &self.stop
    }

    /// The top-level file.
    pub fn main_path(&self) -> &Path {
        &self.main
    }

    /// Where the file named `name` in the scene is.
    pub fn resolve(&self, name: &str) -> PathBuf {
        let named = Path::new(name);
        if named.is_absolute() {
            named.to_path_buf()
        } else {
            self.folder.named().join(named)
        }
    }

    /// Whether the file at `path` (named at `loc` by `key`) may be read: inside the scene's
    /// folder unless the options allow the rest.
    pub fn check(&self, path: &Path, loc: &Loc, key: &str) -> Result<(), SceneError> {
        self.folder.check(path).map_err(|e| loc.error(Some(key), e))
    }

    /// Every file the scene read besides the top-level one, each once, in the order first
    /// asked for.
    pub fn read_besides_main(&self) -> Vec<PathBuf> {
        let mut files = self.folder.asked();
        files.retain(|f| f != &self.main);
        files
    }

    /// Reads the top-level file's text.
    pub fn read_main(&mut self) -> Result<String, SceneError> {
        let path = self.main.clone();
        self.read_text(&path)
            .map_err(|e| SceneError::new(&path, format!("cannot read the scene file: {e}")))
    }

    /// Reads the file at `path` named at `loc` (by `Include`, `Import`), checked against the
    /// folder, and gives its text.
    pub fn read_named(&mut self, path: &Path, loc: &Loc, key: &str) -> Result<String, SceneError> {
        self.check(path, loc, key)?;
        self.read_text(path)
            .map_err(|e| loc.error(Some(key), format!("cannot read `{}`: {e}", path.display())))
    }

    /// A file's text: a regular file of at most [`PbrtLimits::file_bytes`], inflated when its
    /// name ends in `.gz` (to at most as many bytes), UTF-8 without NUL bytes; the error is the
    /// reason.
    fn read_text(&mut self, path: &Path) -> Result<String, String> {
        let PbrtLimits {
            file_bytes,
            total_bytes,
            ..
        } = self.limits;
        let raw = read_bounded(path, file_bytes)
            .map_err(|e| format!("{e} (`--max-pbrt-file-bytes`: {file_bytes})"))?;
        let bytes = if is_gzip_name(path) {
            inflate(&raw, file_bytes)?
        } else {
            raw
        };
        self.total = self.total.saturating_add(bytes.len() as u64);
        if self.total > total_bytes {
            return Err(format!(
                "the scene's files hold more than {total_bytes} bytes together (a file \
                 included again is counted again; `--max-pbrt-total-bytes`)"
            ));
        }
        if bytes.contains(&0) {
            return Err("it is binary, not pbrt's text format".into());
        }
        String::from_utf8(bytes).map_err(|_| "it is not UTF-8 text".into())
    }
}

/// Whether `path`'s name ends in `.gz` (any case).
pub fn is_gzip_name(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"))
}

/// `raw` inflated from gzip, refused once it grows past `limit` bytes (a small file can
/// inflate a thousandfold).
fn inflate(raw: &[u8], limit: u64) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(raw)
        .take(limit + 1)
        .read_to_end(&mut out)
        .map_err(|e| format!("it is not a valid gzip file: {e}"))?;
    if out.len() as u64 > limit {
        return Err(format!(
            "it inflates to more than {limit} bytes, the limit of a scene file \
             (`--max-pbrt-file-bytes`)"
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn gzip(bytes: &[u8]) -> Vec<u8> {
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        encoder.write_all(bytes).expect("compress");
        encoder.finish().expect("compress")
    }

    #[test]
    fn gzip_is_inflated_within_its_limit() {
        let packed = gzip(b"WorldBegin\n");
        assert_eq!(inflate(&packed, 100).expect("inflate"), b"WorldBegin\n");
        let bomb = gzip(&vec![b' '; 10_000]);
        assert!(bomb.len() < 200);
        let err = inflate(&bomb, 1000).expect_err("too large");
        assert!(err.contains("more than 1000 bytes"), "{err}");
        assert!(inflate(b"not gzip", 100).is_err());
    }
}
