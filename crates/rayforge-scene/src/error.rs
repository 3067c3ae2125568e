//! Scene errors: which file, where in it, which key, and what is wrong.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in the source file something is (1-based line and column, 0-based byte offset).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// Byte offset of the start in the source text.
    pub offset: usize,
    /// Length in bytes (0 when only the start is known).
    pub len: usize,
}

/// A scene that could not be read: which file, where, which key, and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct SceneError {
    /// The file the error is in (the scene file, or an asset it names).
    pub path: PathBuf,
    /// Where in that file, when known.
    pub span: Option<Span>,
    /// The key being read (e.g. `field-of-view`, `transform`), when there is one.
    pub key: Option<String>,
    /// What is wrong, in a sentence.
    pub message: String,
}

impl SceneError {
    /// An error with no position (a missing file, say).
    pub fn new(path: &Path, message: impl Into<String>) -> Self {
        Self {
            path: path.to_path_buf(),
            span: None,
            key: None,
            message: message.into(),
        }
    }

    /// The same error at a position.
    pub fn at(mut self, span: Span) -> Self {
        self.span = Some(span);
        self
    }

    /// The same error about a key.
    pub fn with_key(mut self, key: impl Into<String>) -> Self {
        self.key = Some(key.into());
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(span) = self.span {
            write!(f, ":{}:{}", span.line, span.column)?;
        }
        write!(f, ": ")?;
        if let Some(key) = &self.key {
            write!(f, "`{key}`: ")?;
        }
        write!(f, "{}", self.message)
    }
}
