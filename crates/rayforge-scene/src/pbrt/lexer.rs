//! pbrt-v4's tokens: bare words (directive names, numbers, `true`/`false`), quoted strings,
//! and the brackets `[` `]` around value lists; `#` starts a comment to the end of the line.
//!
//! Each token keeps where it starts (line, column and byte offset in its file), so that every
//! error about a directive or a parameter points at it. A string ends on the same line it
//! starts on, as pbrt-v4 requires; its escapes (`\n`, `\t`, `\\`, `\"`, …) are decoded when
//! its text is asked for.

use crate::error::Span;
use std::borrow::Cow;

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A run of characters up to a space, quote or bracket: a directive's name, a number,
    /// `true` or `false`.
    Word,
    /// A quoted string; the token's text is what lies between the quotes, escapes undecoded.
    Str,
    /// `[`.
    Open,
    /// `]`.
    Close,
}

/// One token of a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token<'t> {
    /// What it is.
    pub kind: Kind,
    /// Its text (for a string, without the quotes).
    pub text: &'t str,
    /// Where it starts, and its length in bytes (quotes included).
    pub span: Span,
}

impl<'t> Token<'t> {
    /// A string token's text with its escapes decoded (a word's text as it is).
    pub fn string(&self) -> Cow<'t, str> {
        if self.kind != Kind::Str || !self.text.contains('\\') {
            return Cow::Borrowed(self.text);
        }
        let mut out = String::with_capacity(self.text.len());
        let mut chars = self.text.chars();
        while let Some(c) = chars.next() {
            if c != '\\' {
                out.push(c);
                continue;
            }
            // The lexer made sure a backslash is never last.
            let decoded = match chars.next().unwrap_or('\\') {
                'b' => '\u{8}',
                'f' => '\u{c}',
                'n' => '\n',
                'r' => '\r',
                't' => '\t',
                other => other,
            };
            out.push(decoded);
        }
        Cow::Owned(out)
    }

    /// How the token reads in a message: a string in quotes, anything else as it is.
    pub fn shown(&self) -> String {
        let text = crate::error::clip_to(self.text, 60);
        match self.kind {
            Kind::Str => format!("\"{text}\""),
            _ => text.into_owned(),
        }
    }
}

/// A malformed token: what is wrong and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LexError {
    /// Where the bad token starts.
    pub span: Span,
    /// What is wrong.
    pub message: String,
}

/// The tokens of one file's text, in order.
pub struct Lexer<'t> {
    text: &'t str,
    bytes: &'t [u8],
    pos: usize,
    line: usize,
    /// Byte offset where the current line starts.
    line_start: usize,
}

impl<'t> Lexer<'t> {
    /// A lexer at the start of `text`.
    pub fn new(text: &'t str) -> Self {
        Self {
            text,
            bytes: text.as_bytes(),
            pos: 0,
            line: 1,
            line_start: 0,
        }
    }

    /// Where byte `offset` of the current line is.
    fn span_at(&self, offset: usize, len: usize) -> Span {
        // Columns count characters, not bytes.
        let column = 1 + self.text[self.line_start..offset].chars().count();
        Span {
            line: self.line,
            column,
            offset,
            len,
        }
    }

    /// The next token, `None` at the end of the text.
    pub fn next_token(&mut self) -> Result<Option<Token<'t>>, LexError> {
        loop {
            let Some(&b) = self.bytes.get(self.pos) else {
                return Ok(None);
            };
            match b {
                b'\n' => {
                    self.pos += 1;
                    self.line += 1;
                    self.line_start = self.pos;
                }
                b' ' | b'\t' | b'\r' => self.pos += 1,
                b'#' => {
                    while let Some(&c) = self.bytes.get(self.pos) {
                        if c == b'\n' {
                            break;
                        }
                        self.pos += 1;
                    }
                }
                b'[' | b']' => {
                    let span = self.span_at(self.pos, 1);
                    self.pos += 1;
                    let kind = if b == b'[' { Kind::Open } else { Kind::Close };
                    return Ok(Some(Token {
                        kind,
                        text: &self.text[span.offset..span.offset + 1],
                        span,
                    }));
                }
                b'"' => return self.string().map(Some),
                _ => {
                    let start = self.pos;
                    while let Some(&c) = self.bytes.get(self.pos) {
                        if matches!(c, b' ' | b'\n' | b'\t' | b'\r' | b'"' | b'[' | b']') {
                            break;
                        }
                        self.pos += 1;
                    }
                    return Ok(Some(Token {
                        kind: Kind::Word,
                        text: &self.text[start..self.pos],
                        span: self.span_at(start, self.pos - start),
                    }));
                }
            }
        }
    }

    /// A quoted string, the lexer at its opening quote.
    fn string(&mut self) -> Result<Token<'t>, LexError> {
        let start = self.pos;
        self.pos += 1;
        loop {
            match self.bytes.get(self.pos) {
                None | Some(b'\n') => {
                    return Err(LexError {
                        span: self.span_at(start, 1),
                        message: "this string has no closing quote on its line".into(),
                    })
                }
                Some(b'"') => break,
                Some(b'\\') => {
                    if matches!(self.bytes.get(self.pos + 1), None | Some(b'\n')) {
                        return Err(LexError {
                            span: self.span_at(start, 1),
                            message: "this string has no closing quote on its line".into(),
                        });
                    }
                    // The escaped character may be more than one byte long.
                    let next = self.text[self.pos + 1..]
                        .chars()
                        .next()
                        .map_or(1, char::len_utf8);
                    self.pos += 1 + next;
                }
                Some(_) => self.pos += 1,
            }
        }
        self.pos += 1;
        Ok(Token {
            kind: Kind::Str,
            text: &self.text[start + 1..self.pos - 1],
            span: self.span_at(start, self.pos - start),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens(text: &str) -> Vec<(Kind, String, usize, usize)> {
        let mut lexer = Lexer::new(text);
        let mut out = Vec::new();
        while let Some(t) = lexer.next_token().expect("tokens") {
            out.push((t.kind, t.string().into_owned(), t.span.line, t.span.column));
        }
        out
    }

    #[test]
    fn words_strings_brackets_and_comments_with_their_places() {
        let got = tokens("Shape \"sphere\" # a ball\n  \"float radius\" [2.5]\n");
        assert_eq!(
            got,
            vec![
                (Kind::Word, "Shape".into(), 1, 1),
                (Kind::Str, "sphere".into(), 1, 7),
                (Kind::Str, "float radius".into(), 2, 3),
                (Kind::Open, "[".into(), 2, 18),
                (Kind::Word, "2.5".into(), 2, 19),
                (Kind::Close, "]".into(), 2, 22),
            ]
        );
    }

    #[test]
    fn columns_count_characters_and_escapes_are_decoded() {
        let got = tokens("\"é\" \"a\\\"b\\n\"");
        assert_eq!(got[0], (Kind::Str, "é".into(), 1, 1));
        assert_eq!(got[1], (Kind::Str, "a\"b\n".into(), 1, 5));
    }

    #[test]
    fn a_string_must_close_on_its_line() {
        let mut lexer = Lexer::new("Shape\n  \"sphere\n\"");
        assert!(lexer.next_token().is_ok());
        let err = lexer.next_token().expect_err("unterminated");
        assert_eq!((err.span.line, err.span.column), (2, 3));
        let mut lexer = Lexer::new("\"ends with a backslash\\");
        assert!(lexer.next_token().is_err());
    }

    #[test]
    fn a_comment_may_end_the_file_and_crlf_is_a_line_end() {
        let got = tokens("WorldBegin\r\n# last\r\nAttributeBegin # x");
        assert_eq!(got.len(), 2);
        assert_eq!(got[1], (Kind::Word, "AttributeBegin".into(), 3, 1));
    }
}
