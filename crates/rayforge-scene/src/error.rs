//! Scene errors: which file, where in it, which key, and what is wrong.

use std::borrow::Cow;
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
    /// Whether the reading was stopped by its [`StopFlag`](crate::StopFlag) (Ctrl-C, a
    /// termination signal, the page's cancel) rather than refused: the file is not at fault.
    pub interrupted: bool,
}

impl SceneError {
    /// An error with no position (a missing file, say).
    pub fn new(path: &Path, message: impl Into<String>) -> Self {
        Self {
            path: path.to_path_buf(),
            span: None,
            key: None,
            message: message.into(),
            interrupted: false,
        }
    }

    /// The error of a reading stopped by its [`StopFlag`](crate::StopFlag), in `path` (each
    /// reader places it where it stopped).
    pub fn interrupted(path: &Path) -> Self {
        Self {
            interrupted: true,
            ..Self::new(path, "reading stopped: interrupted")
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
        write!(f, "{}", clip(&self.path.display().to_string()))?;
        if let Some(span) = self.span {
            write!(f, ":{}:{}", span.line, span.column)?;
        }
        write!(f, ": ")?;
        if let Some(key) = &self.key {
            write!(f, "`{}`: ", clip(key))?;
        }
        write!(f, "{}", clip(&self.message))
    }
}

/// How many characters of a message, key or path an error shows at most.
pub const MAX_SHOWN_CHARS: usize = 400;

/// `text` as an error shows it: whole when it is at most [`MAX_SHOWN_CHARS`] characters,
/// otherwise its beginning and end around a note of how much was left out. Messages quote the
/// user's input (a name, a path, a line), and that input may be megabytes long; the beginning
/// says what went wrong and the end usually why, so both are kept.
pub fn clip(text: &str) -> Cow<'_, str> {
    clip_to(text, MAX_SHOWN_CHARS)
}

/// `text` cut as [`clip`] cuts it, to at most `max_chars` characters (and the note).
pub fn clip_to(text: &str, max_chars: usize) -> Cow<'_, str> {
    // Cheap test first: a short text in bytes is short in characters.
    if text.len() <= max_chars || text.chars().nth(max_chars).is_none() {
        return Cow::Borrowed(text);
    }
    let half = (max_chars / 2).max(1);
    let head_end = text.char_indices().nth(half).map_or(text.len(), |(i, _)| i);
    let tail_start = text
        .char_indices()
        .rev()
        .nth(half - 1)
        .map_or(head_end, |(i, _)| i.max(head_end));
    Cow::Owned(format!(
        "{} … ({} bytes left out) … {}",
        &text[..head_end],
        tail_start - head_end,
        &text[tail_start..]
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_text_is_shown_whole() {
        assert_eq!(clip("unknown key `colr`"), "unknown key `colr`");
        let exactly = "é".repeat(MAX_SHOWN_CHARS);
        assert_eq!(clip(&exactly), exactly.as_str());
    }

    #[test]
    fn long_text_keeps_its_beginning_and_end() {
        let name = format!(
            "unknown name `{}` (define it first)",
            "x".repeat(50_000_000)
        );
        let shown = clip(&name);
        assert!(
            shown.chars().count() < MAX_SHOWN_CHARS + 60,
            "{}",
            shown.len()
        );
        assert!(shown.starts_with("unknown name `xxx"));
        assert!(shown.ends_with("xxx` (define it first)"));
        assert!(shown.contains("bytes left out"));
    }

    #[test]
    fn multibyte_text_is_cut_on_character_boundaries() {
        let text = "ж".repeat(10_000);
        let shown = clip(&text);
        assert!(shown.contains(&format!(
            "({} bytes left out)",
            (10_000 - MAX_SHOWN_CHARS) * 2
        )));
    }
}
