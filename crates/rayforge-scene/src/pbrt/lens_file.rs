//! A realistic camera's lens description file (`lensfile`), read as untrusted input: a
//! regular file inside the scene's folder, its size checked against
//! [`PbrtLimits::file_bytes`](crate::pbrt::PbrtLimits::file_bytes) before a byte is read,
//! UTF-8 text, at most [`PbrtLimits::lens_rows`](crate::pbrt::PbrtLimits::lens_rows) rows.
//!
//! The format is pbrt-v4's float file: numbers separated by white space, `#` starting a
//! comment to the end of its line, read four at a time as rows of curvature radius,
//! thickness, index of refraction and aperture diameter (millimetres; a radius of 0 is the
//! aperture stop), from the scene's side to the film's. pbrt-v4 does not tie a row to a
//! line; neither does this reader, but every error names the line and column of the value
//! (or of the first value of the row) it is about, in the lens file.

use super::input::Files;
use super::params::Param;
use crate::error::{SceneError, Span};
use rayforge::camera::LensInterface;
use std::path::{Path, PathBuf};

/// A lens file's rows, each with where its first value is.
pub struct LensFile {
    /// The file read.
    pub path: PathBuf,
    /// Its rows, from the scene's side.
    pub rows: Vec<LensInterface>,
    /// Where each row starts.
    pub spans: Vec<Span>,
}

impl LensFile {
    /// An error about row `row` (from 0) of this file, at its first value.
    pub fn error_at_row(&self, row: usize, message: impl Into<String>) -> SceneError {
        let error = SceneError::new(&self.path, message).with_key("lensfile");
        match self.spans.get(row) {
            Some(&span) => error.at(span),
            None => error,
        }
    }
}

/// Reads the lens file `name`, given by the `lensfile` parameter `p`, of at most `max_rows`
/// rows: an error it cannot be read for is at `p`, one about what it holds at its place in
/// the lens file.
pub fn read(name: &str, p: &Param, files: &Files, max_rows: usize) -> Result<LensFile, SceneError> {
    let path = files.resolve(name);
    files.check(&path, &p.loc, "lensfile")?;
    let limit = files.limits().file_bytes;
    let bytes = crate::files::read_bounded(&path, limit).map_err(|e| {
        p.error(format!(
            "cannot read the lens file `{}`: {e} (`--max-pbrt-file-bytes`: {limit})",
            path.display()
        ))
    })?;
    let text = text_of(&path, bytes)?;
    let (rows, spans) = parse(&path, &text, max_rows)?;
    Ok(LensFile { path, rows, spans })
}

/// The text of a lens file's `bytes`: UTF-8 without NUL bytes, an error at the first byte
/// that is not.
fn text_of(path: &Path, bytes: Vec<u8>) -> Result<String, SceneError> {
    let bad = match std::str::from_utf8(&bytes) {
        Ok(text) => text.find('\0'),
        Err(e) => Some(e.valid_up_to()),
    };
    if let Some(offset) = bad {
        // The text up to the bad byte is valid UTF-8 whichever the reason.
        let before = std::str::from_utf8(&bytes[..offset]).unwrap_or("");
        return Err(SceneError::new(
            path,
            "a lens file is text (UTF-8, no NUL bytes): this one is binary here",
        )
        .with_key("lensfile")
        .at(span_of(before, offset)));
    }
    String::from_utf8(bytes).map_err(|_| SceneError::new(path, "a lens file is UTF-8 text"))
}

/// The place of byte `offset`, the end of `before` (the text up to it).
fn span_of(before: &str, offset: usize) -> Span {
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Span {
        line: 1 + before.matches('\n').count(),
        column: 1 + before[line_start..].chars().count(),
        offset,
        len: 0,
    }
}

/// The rows of the lens file `text` (at `path`), at most `max_rows` of them, and where each
/// starts.
pub fn parse(
    path: &Path,
    text: &str,
    max_rows: usize,
) -> Result<(Vec<LensInterface>, Vec<Span>), SceneError> {
    let mut values: Vec<f64> = Vec::new();
    let mut spans: Vec<Span> = Vec::new();
    let mut last = None;
    let mut offset = 0;
    for (line_index, line) in text.split_inclusive('\n').enumerate() {
        let content = line.split('#').next().unwrap_or("");
        let mut column = 1;
        let mut chars = content.char_indices().peekable();
        while let Some((start, c)) = chars.next() {
            if c.is_whitespace() {
                column += 1;
                continue;
            }
            let mut end = start + c.len_utf8();
            let mut width = 1;
            while let Some(&(i, c)) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                end = i + c.len_utf8();
                width += 1;
                chars.next();
            }
            let word = &content[start..end];
            let span = Span {
                line: line_index + 1,
                column,
                offset: offset + start,
                len: end - start,
            };
            column += width;
            let at = |message: String| SceneError::new(path, message).with_key("lensfile").at(span);
            let value: f64 = match word.parse() {
                Ok(v) if f64::is_finite(v) => v,
                _ => {
                    return Err(at(format!(
                        "`{}` is not a finite number: a lens file holds numbers only, four to \
                         a row (curvature radius, thickness, index of refraction, aperture \
                         diameter), and `#` comments",
                        crate::error::clip_to(word, 40)
                    )))
                }
            };
            if values.len() % 4 == 0 {
                if spans.len() == max_rows {
                    return Err(at(format!(
                        "the lens file has more than {max_rows} rows \
                         (`--max-pbrt-lens-rows`)"
                    )));
                }
                spans.push(span);
            }
            values.push(value);
            last = Some(span);
        }
        offset += line.len();
    }
    let Some(last) = last else {
        return Err(SceneError::new(
            path,
            "the lens file holds no rows (four numbers each: curvature radius, thickness, \
             index of refraction, aperture diameter)",
        )
        .with_key("lensfile"));
    };
    if values.len() % 4 != 0 {
        return Err(SceneError::new(
            path,
            format!(
                "the lens file holds {} numbers, not a multiple of four: its last row is {} \
                 of the four (curvature radius, thickness, index of refraction, aperture \
                 diameter)",
                values.len(),
                values.len() % 4
            ),
        )
        .with_key("lensfile")
        .at(last));
    }
    let rows = values
        .chunks_exact(4)
        .map(|r| LensInterface {
            curvature_radius: r[0],
            thickness: r[1],
            eta: r[2],
            aperture_diameter: r[3],
        })
        .collect();
    Ok((rows, spans))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(text: &str, max_rows: usize) -> Result<Vec<LensInterface>, SceneError> {
        parse(Path::new("lens.dat"), text, max_rows).map(|(rows, _)| rows)
    }

    #[test]
    fn rows_are_four_numbers_wherever_the_lines_break() {
        let rows = parsed("# a lens\n 50 5 1.5 20 # front\n-50\n 40 0 20\n", 8).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1].curvature_radius, -50.0);
        assert_eq!(rows[1].aperture_diameter, 20.0);
    }

    #[test]
    fn a_bad_number_is_named_at_its_line_and_column() {
        let e = parsed("50 5 1.5 20\n-50 4x0 0 20\n", 8).unwrap_err();
        let span = e.span.expect("a place");
        assert_eq!((span.line, span.column), (2, 5), "{e}");
        assert!(e.message.contains("`4x0`"), "{e}");
        let e = parsed("50 5 1.5 inf\n", 8).unwrap_err();
        assert_eq!(e.span.map(|s| (s.line, s.column)), Some((1, 10)), "{e}");
    }

    #[test]
    fn a_short_last_row_and_too_many_rows_are_refused_where_they_are() {
        let e = parsed("50 5 1.5 20\n  -50 40\n", 8).unwrap_err();
        assert_eq!(e.span.map(|s| (s.line, s.column)), Some((2, 7)), "{e}");
        assert!(e.message.contains("6 numbers"), "{e}");
        let e = parsed("1 1 1 1\n2 2 2 2\n3 3 3 3\n", 2).unwrap_err();
        assert_eq!(e.span.map(|s| (s.line, s.column)), Some((3, 1)), "{e}");
        assert!(e.message.contains("--max-pbrt-lens-rows"), "{e}");
        assert!(parsed("1 1 1 1\n2 2 2 2\n", 2).is_ok());
        assert!(parsed("# nothing\n", 2).is_err());
    }

    #[test]
    fn binary_bytes_are_refused_at_the_first() {
        let e = text_of(Path::new("lens.dat"), b"50 5\n1.\xff5 20".to_vec()).unwrap_err();
        assert_eq!(e.span.map(|s| (s.line, s.column)), Some((2, 3)), "{e}");
    }
}
