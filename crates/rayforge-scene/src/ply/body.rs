//! A PLY file's body, value by value: as text (one element to a line, values between spaces)
//! or binary (either byte order), each value read as the type its header declared. Every error
//! says which element (counting from 0) and property it is in, and where: the line and column
//! of a text body, the byte offset of a binary one.

use super::header::{Format, Scalar};
use crate::error::{SceneError, Span};
use crate::stop::StopFlag;
use std::path::Path;

/// What is being read, for errors: the element's name and number, and the property's name.
#[derive(Debug, Clone, Copy)]
pub struct At<'a> {
    pub element: &'a str,
    pub index: u64,
    pub property: &'a str,
}

impl At<'_> {
    fn key(&self) -> String {
        format!("{}.{}", self.element, self.property)
    }
}

/// The body being read.
pub struct Body<'b> {
    bytes: &'b [u8],
    pos: usize,
    format: Format,
    path: &'b Path,
    /// A text body's line being read: its number, where it starts and where it ends (before
    /// its line break).
    line: usize,
    line_start: usize,
    line_end: usize,
    /// Where the value read last starts (it ends where reading is now).
    last: usize,
    /// Looked at as each element begins.
    stop: &'b StopFlag,
}

impl<'b> Body<'b> {
    /// The body of `bytes` (the whole file) from `start`, whose line is number `line` + 1.
    pub fn new(
        bytes: &'b [u8],
        start: usize,
        line: usize,
        format: Format,
        path: &'b Path,
        stop: &'b StopFlag,
    ) -> Self {
        Self {
            stop,
            bytes,
            pos: start,
            format,
            path,
            line,
            line_start: start,
            line_end: start,
            last: start,
        }
    }

    /// Starts an element: in a text body, moves to the next line that holds anything. Stops
    /// here, before the element, once the stop flag is set.
    pub fn begin(&mut self, element: &str, index: u64, count: u64) -> Result<(), SceneError> {
        self.stop
            .check(self.path)
            .map_err(|e| e.at(self.span_at(self.pos, 0)).with_key(element))?;
        if self.format != Format::Ascii {
            return Ok(());
        }
        loop {
            if self.pos >= self.bytes.len() {
                return Err(SceneError::new(
                    self.path,
                    format!(
                        "the file ends before {element} #{index} (the header declares {count}; \
                         counting from 0): it is cut short"
                    ),
                )
                .at(self.end_of_file())
                .with_key(element));
            }
            self.next_line();
            self.skip_blanks();
            if self.pos < self.line_end {
                return Ok(());
            }
            self.pos = (self.line_end + 1).min(self.bytes.len());
        }
    }

    /// Ends an element: in a text body, its line must hold nothing more.
    pub fn end(&mut self, element: &str, index: u64) -> Result<(), SceneError> {
        if self.format != Format::Ascii {
            return Ok(());
        }
        self.skip_blanks();
        if self.pos < self.line_end {
            let len = self.token_len();
            return Err(SceneError::new(
                self.path,
                format!(
                    "{element} #{index} has more values on its line than the header declares \
                     properties for"
                ),
            )
            .at(self.span_at(self.pos, len))
            .with_key(element));
        }
        self.pos = (self.line_end + 1).min(self.bytes.len());
        Ok(())
    }

    /// After the last element: a text body may hold only blank lines more (anything else
    /// means the header's counts are wrong); a binary one may have padding.
    pub fn finish(&mut self) -> Result<(), SceneError> {
        if self.format != Format::Ascii {
            return Ok(());
        }
        while self.pos < self.bytes.len() {
            self.next_line();
            self.skip_blanks();
            if self.pos < self.line_end {
                let len = self.token_len();
                return Err(SceneError::new(
                    self.path,
                    "the file holds more lines than the header declares elements",
                )
                .at(self.span_at(self.pos, len))
                .with_key("end_header"));
            }
            self.pos = (self.line_end + 1).min(self.bytes.len());
        }
        Ok(())
    }

    /// The next value, of type `scalar`, as a number (whole numbers exactly).
    pub fn value(&mut self, scalar: Scalar, at: &At<'_>) -> Result<f64, SceneError> {
        match self.format {
            Format::Ascii => self.text_value(scalar, at),
            Format::LittleEndian | Format::BigEndian => self.binary_value(scalar, at),
        }
    }

    /// Whether `count` values of type `scalar` can still follow (a binary body's list is
    /// checked so before it is read; a text body's values end where its line does).
    pub fn has_room(&self, count: u64, scalar: Scalar) -> bool {
        self.format == Format::Ascii
            || count
                .checked_mul(scalar.size() as u64)
                .is_some_and(|n| n <= (self.bytes.len() - self.pos) as u64)
    }

    /// The error for the value just read.
    pub fn error_here(&self, at: &At<'_>, message: String) -> SceneError {
        let (start, len) = (self.last, self.pos - self.last);
        match self.format {
            Format::Ascii => SceneError::new(
                self.path,
                format!("{} #{}: {message}", at.element, at.index),
            )
            .at(self.span_at(start, len))
            .with_key(at.key()),
            _ => SceneError::new(
                self.path,
                format!("at byte {start}, {} #{}: {message}", at.element, at.index),
            )
            .with_key(at.key()),
        }
    }

    fn binary_value(&mut self, scalar: Scalar, at: &At<'_>) -> Result<f64, SceneError> {
        let size = scalar.size();
        let Some(raw) = self.bytes.get(self.pos..self.pos + size) else {
            return Err(SceneError::new(
                self.path,
                format!(
                    "the file ends at byte {}, inside {} #{} (property `{}`): it is cut short",
                    self.bytes.len(),
                    at.element,
                    at.index,
                    at.property
                ),
            )
            .with_key(at.key()));
        };
        self.last = self.pos;
        self.pos += size;
        let big = self.format == Format::BigEndian;
        let word = |n: usize| -> [u8; 8] {
            let mut out = [0; 8];
            out[..n].copy_from_slice(raw);
            if big {
                out[..n].reverse();
            }
            out
        };
        let b = word(size);
        Ok(match scalar {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    fn text_value(&mut self, scalar: Scalar, at: &At<'_>) -> Result<f64, SceneError> {
        self.skip_blanks();
        if self.pos >= self.line_end {
            return Err(SceneError::new(
                self.path,
                format!(
                    "{} #{}: its line ends before property `{}`",
                    at.element, at.index, at.property
                ),
            )
            .at(self.span_at(self.line_end, 0))
            .with_key(at.key()));
        }
        let len = self.token_len();
        let token = &self.bytes[self.pos..self.pos + len];
        self.last = self.pos;
        self.pos += len;
        let word = std::str::from_utf8(token).unwrap_or("");
        let bad = |what: &str| {
            self.error_here(
                at,
                format!(
                    "expected {what} for `{}`, found `{}`",
                    at.property,
                    String::from_utf8_lossy(token)
                ),
            )
        };
        if scalar.is_integer() {
            let n: i64 = word.parse().map_err(|_| bad("a whole number"))?;
            let (lo, hi) = scalar.range();
            if n < lo || n > hi {
                return Err(self.error_here(
                    at,
                    format!("{n} is outside the range of its type ({lo} to {hi})"),
                ));
            }
            Ok(n as f64)
        } else {
            let x: f64 = word.parse().map_err(|_| bad("a number"))?;
            Ok(if scalar == Scalar::F32 {
                f64::from(x as f32)
            } else {
                x
            })
        }
    }

    /// Moves to the line that starts where reading is now.
    fn next_line(&mut self) {
        self.line += 1;
        self.line_start = self.pos;
        let rest = &self.bytes[self.pos..];
        self.line_end = self.pos + rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
    }

    fn skip_blanks(&mut self) {
        while self.pos < self.line_end && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn token_len(&self) -> usize {
        self.bytes[self.pos..self.line_end]
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(self.line_end - self.pos)
    }

    /// The place of the file's end: past the last line's break, the start of a line of its
    /// own (so that the line number is the one a text editor shows there).
    fn end_of_file(&self) -> Span {
        let len = self.bytes.len();
        if self.bytes.last() == Some(&b'\n') {
            Span {
                line: self.line + 1,
                column: 1,
                offset: len,
                len: 0,
            }
        } else {
            self.span_at(len, 0)
        }
    }

    /// The place of byte `offset` on the current line.
    fn span_at(&self, offset: usize, len: usize) -> Span {
        Span {
            line: self.line.max(1),
            column: offset.saturating_sub(self.line_start) + 1,
            offset,
            len,
        }
    }
}
