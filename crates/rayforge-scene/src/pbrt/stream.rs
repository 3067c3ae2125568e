//! One file's tokens as the directive reader takes them: one token of lookahead, each token's
//! place as a [`Loc`], and the arguments directives take (a quoted string, a number).

use super::input::Loc;
use super::lexer::{Kind, Lexer, Token};
use crate::error::SceneError;
use std::path::Path;
use std::rc::Rc;

/// The tokens of one file.
pub struct Stream<'t> {
    lexer: Lexer<'t>,
    file: Rc<Path>,
    peeked: Option<Token<'t>>,
    /// Where the last token taken was, for an error at the end of the file.
    last: Loc,
}

impl<'t> Stream<'t> {
    /// The tokens of `text`, the file at `file`.
    pub fn new(text: &'t str, file: Rc<Path>) -> Self {
        let last = Loc {
            file: file.clone(),
            span: crate::error::Span {
                line: 1,
                column: 1,
                offset: 0,
                len: 0,
            },
        };
        Self {
            lexer: Lexer::new(text),
            file,
            peeked: None,
            last,
        }
    }

    /// Where `token` is.
    pub fn loc(&self, token: &Token<'_>) -> Loc {
        Loc {
            file: self.file.clone(),
            span: token.span,
        }
    }

    /// The next token without taking it.
    pub fn peek(&mut self) -> Result<Option<Token<'t>>, SceneError> {
        if self.peeked.is_none() {
            self.peeked = self.lexer.next_token().map_err(|e| {
                Loc {
                    file: self.file.clone(),
                    span: e.span,
                }
                .error(None, e.message)
            })?;
        }
        Ok(self.peeked)
    }

    /// The next token, `None` at the end of the file.
    pub fn next(&mut self) -> Result<Option<Token<'t>>, SceneError> {
        let token = self.peek()?;
        self.peeked = None;
        if let Some(t) = &token {
            self.last = self.loc(t);
        }
        Ok(token)
    }

    /// The next token, which `what` (naming the directive and what it needs) must find.
    pub fn required(&mut self, directive: &str, what: &str) -> Result<Token<'t>, SceneError> {
        match self.next()? {
            Some(t) => Ok(t),
            None => Err(self.last.error(
                Some(directive),
                format!("the file ends where `{directive}` needs {what}"),
            )),
        }
    }

    /// A quoted string argument of `directive` (its `what`).
    pub fn string(&mut self, directive: &str, what: &str) -> Result<(String, Loc), SceneError> {
        let token = self.required(directive, what)?;
        if token.kind != Kind::Str {
            return Err(self.loc(&token).error(
                Some(directive),
                format!(
                    "`{directive}` needs {what} in quotes here, found {}",
                    token.shown()
                ),
            ));
        }
        Ok((token.string().into_owned(), self.loc(&token)))
    }

    /// `n` numbers, the arguments of `directive` (such as `Translate`'s three).
    pub fn numbers<const N: usize>(&mut self, directive: &str) -> Result<[f64; N], SceneError> {
        let mut out = [0.0; N];
        for (i, slot) in out.iter_mut().enumerate() {
            let what = format!("{N} numbers (number {} is missing)", i + 1);
            let token = self.required(directive, &what)?;
            *slot = number(&token).ok_or_else(|| {
                self.loc(&token).error(
                    Some(directive),
                    format!(
                        "`{directive}` takes {N} numbers; number {} is {}, not a number",
                        i + 1,
                        token.shown()
                    ),
                )
            })?;
        }
        Ok(out)
    }

    /// `[ 16 numbers ]`, the matrix of `Transform` and `ConcatTransform`.
    pub fn matrix(&mut self, directive: &str) -> Result<[f64; 16], SceneError> {
        let open = self.required(directive, "16 numbers in brackets")?;
        if open.kind != Kind::Open {
            return Err(self.loc(&open).error(
                Some(directive),
                format!(
                    "`{directive}` takes 16 numbers in brackets, found {}",
                    open.shown()
                ),
            ));
        }
        let m = self.numbers::<16>(directive)?;
        let close = self.required(directive, "the `]` after its 16 numbers")?;
        if close.kind != Kind::Close {
            return Err(self.loc(&close).error(
                Some(directive),
                format!(
                    "`{directive}` takes exactly 16 numbers, then `]`; found {}",
                    close.shown()
                ),
            ));
        }
        Ok(m)
    }
}

/// A word token's number: finite, in the forms pbrt-v4 writes and reads (`1`, `-2.5`,
/// `3e-7`, `.5`); `None` for anything else.
pub fn number(token: &Token<'_>) -> Option<f64> {
    if token.kind != Kind::Word {
        return None;
    }
    let text = token.text;
    // Rust's parser also takes `inf`, `NaN` and `infinity`: pbrt's does not, nor does a
    // renderer want them.
    if !text
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'))
    {
        return None;
    }
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}
