//! A line of a line-oriented text format (OBJ and MTL, a PLY header) with its place in the
//! file, so that each word's error names the file, line, column and statement.

use crate::error::{SceneError, Span};
use std::path::Path;

/// One line of a file at `path`: its 1-based `number`, the byte `offset` of its start in the
/// file, and its `text` (without the line break).
pub(crate) struct TextLine<'t> {
    pub(crate) path: &'t Path,
    pub(crate) number: usize,
    pub(crate) offset: usize,
    pub(crate) text: &'t str,
}

impl<'t> TextLine<'t> {
    /// The line's words with their byte columns (0-based).
    pub(crate) fn words(&self) -> impl Iterator<Item = (usize, &'t str)> + 't {
        let text = self.text;
        text.split_ascii_whitespace()
            .map(move |w| (w.as_ptr() as usize - text.as_ptr() as usize, w))
    }

    /// The place of `len` bytes at byte `column` (0-based) of the line.
    pub(crate) fn span(&self, column: usize, len: usize) -> Span {
        Span {
            line: self.number,
            column: column + 1,
            offset: self.offset + column,
            len,
        }
    }

    /// An error about statement `key` at byte `column` of the line, `len` bytes long.
    pub(crate) fn error(
        &self,
        column: usize,
        len: usize,
        key: &str,
        message: String,
    ) -> SceneError {
        SceneError::new(self.path, message)
            .at(self.span(column, len))
            .with_key(key)
    }
}
