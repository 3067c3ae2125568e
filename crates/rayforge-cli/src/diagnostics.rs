//! Scene errors and warnings for the terminal: with miette, the message and the offending line
//! of the file with the spot underlined; a plain line when there is no position to show.
//!
//! The display never shows more than a bounded excerpt of the file: the offending line and the
//! line either side, each cut to a window of [`WINDOW`] characters around the error's column.
//! A scene or model may hold lines of any length (a 200 MB OBJ line, a name of 50 MB), and
//! miette pads its underline to the column, which it cannot do past 65 535 (it panicked there);
//! the excerpt keeps both the output and the padding small whatever the input.

use crate::failure::Failure;
use miette::{
    Diagnostic, MietteError, MietteHandlerOpts, MietteSpanContents, SourceCode, SourceSpan,
    SpanContents,
};
use rayforge_scene::{clip, SceneError};

/// How many characters of a line the display shows at most.
pub(crate) const WINDOW: usize = 120;

/// How many characters before the error's column the window starts, when the line is cut.
pub(crate) const LEAD: usize = 40;

/// The file an error points into, read again (only now that there is something to show), and
/// the byte range of the line that holds the error.
pub(crate) struct ErrorLine {
    /// The file's text.
    pub text: String,
    /// Where the error's line starts and ends (before its newline).
    pub line_start: usize,
    pub line_end: usize,
    /// The error's place, within the text.
    pub span: rayforge_scene::Span,
}

impl ErrorLine {
    /// `None` when the error has no position, or the file can no longer be read or no longer
    /// holds the place (it was saved again since).
    pub(crate) fn read(error: &SceneError) -> Option<Self> {
        let span = error.span?;
        // Read as the file was (a regular file, within the largest size a scene reads).
        let bytes =
            rayforge_scene::files::read_bounded(&error.path, rayforge_scene::obj::MAX_MODEL_BYTES)
                .ok()?;
        let text = String::from_utf8(bytes).ok()?;
        if span.offset > text.len() || !text.is_char_boundary(span.offset) {
            return None;
        }
        let breaks = Breaks::of(&text, &span);
        let line_start = breaks.line_start(&text, span.offset);
        let line_end = breaks.line_end(&text, span.offset);
        Some(Self {
            text,
            line_start,
            line_end,
            span,
        })
    }
}

/// How the error's file breaks its lines, as the reader that placed the error counted them:
/// YAML takes a carriage return alone (old Mac files) as a line break, JSON and OBJ only a
/// line feed. Told apart by the error's line: the excerpt must show the line the message
/// names, under the same number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Breaks {
    /// `\n` ends a line (a `\r` before it stays in the line).
    Lf,
    /// `\r\n`, `\r` and `\n` each end a line.
    Any,
}

impl Breaks {
    fn of(text: &str, span: &rayforge_scene::Span) -> Self {
        if text[..span.offset].matches('\n').count() + 1 == span.line {
            Breaks::Lf
        } else {
            Breaks::Any
        }
    }

    fn is_break(self, b: u8) -> bool {
        b == b'\n' || (self == Breaks::Any && b == b'\r')
    }

    /// Where the line holding byte `at` starts.
    fn line_start(self, text: &str, at: usize) -> usize {
        text.as_bytes()[..at]
            .iter()
            .rposition(|&b| self.is_break(b))
            .map_or(0, |i| i + 1)
    }

    /// Where the line holding byte `at` ends, before its break.
    fn line_end(self, text: &str, at: usize) -> usize {
        text.as_bytes()[at..]
            .iter()
            .position(|&b| self.is_break(b))
            .map_or(text.len(), |i| at + i)
    }

    /// The start of the line after the one that ends at `end` (a `\r\n` is one break).
    fn next_start(self, text: &str, end: usize) -> usize {
        if self == Breaks::Any && text[end..].starts_with("\r\n") {
            end + 2
        } else {
            end + 1
        }
    }

    /// The end of the line before the one that starts at `start`.
    fn previous_end(self, text: &str, start: usize) -> usize {
        if self == Breaks::Any && text[..start].ends_with("\r\n") {
            start - 2
        } else {
            start - 1
        }
    }

    /// How many lines come before byte `at` (the start of a line).
    fn lines_before(self, text: &str, at: usize) -> usize {
        let before = &text[..at];
        match self {
            Breaks::Lf => before.matches('\n').count(),
            Breaks::Any => {
                before.matches('\n').count() + before.matches('\r').count()
                    - before.matches("\r\n").count()
            }
        }
    }
}

/// Sets miette's report style: messages are not wrapped, so each stays one line that a script
/// or a test can search (a terminal wraps long lines by itself).
pub fn install_handler() {
    // Fails only when a hook is already set, which then stays.
    let _ = miette::set_hook(Box::new(|_| {
        Box::new(
            MietteHandlerOpts::new()
                .wrap_lines(false)
                .context_lines(1)
                .build(),
        )
    }));
}

/// A scene error with the excerpt of the file it points into.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("{error}")]
struct SceneDiagnostic {
    error: SceneError,
    #[source_code]
    source_code: Excerpt,
    #[label("{}", label(&self.error))]
    span: SourceSpan,
}

/// A problem the reader worked around, shown like an error but not fatal.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("{error}")]
#[diagnostic(severity(Warning))]
struct SceneWarning {
    error: SceneError,
    #[source_code]
    source_code: Excerpt,
    #[label("{}", label(&self.error))]
    span: SourceSpan,
}

fn label(error: &SceneError) -> String {
    match &error.key {
        Some(key) => format!("here (`{}`)", rayforge_scene::clip(key)),
        None => "here".to_string(),
    }
}

/// The lines around an error, cut to a window, standing in for the whole file: miette reads
/// spans of it as of a small file, and the line and column it prints are put back to those of
/// the real file.
#[derive(Debug)]
struct Excerpt {
    /// The file's name as the report shows it.
    name: String,
    /// The excerpt's lines, each already cut to the window.
    text: String,
    /// The 0-based line of the file that the excerpt's first line is.
    first_line: usize,
    /// The error's 0-based line and column in the file, for the report's header.
    error_line: usize,
    error_column: usize,
}

impl SourceCode for Excerpt {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let inner = self
            .text
            .read_span(span, context_lines_before, context_lines_after)?;
        let line = inner.line() + self.first_line;
        let column = if line == self.error_line {
            self.error_column
        } else {
            inner.column()
        };
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            inner.data(),
            *inner.span(),
            line,
            column,
            inner.line_count(),
        )))
    }
}

/// The excerpt of the error's file and the span within it, when the error has a position and
/// the file (read again here, only now that there is something to show) still holds it.
fn locate(error: &SceneError) -> Option<(Excerpt, SourceSpan)> {
    let ErrorLine {
        text,
        line_start,
        line_end,
        span,
    } = ErrorLine::read(error)?;
    let breaks = Breaks::of(&text, &span);
    let previous = (line_start > 0).then(|| {
        let end = breaks.previous_end(&text, line_start);
        &text[breaks.line_start(&text, end)..end]
    });
    let next = (line_end < text.len()).then(|| {
        let start = breaks.next_start(&text, line_end);
        &text[start..breaks.line_end(&text, start)]
    });
    let line = &text[line_start..line_end];
    // The window, in characters of the error's line: from a little before the column, so
    // that the underline starts near the left of the window.
    let column_chars = text[line_start..span.offset].chars().count();
    let skip = column_chars.saturating_sub(LEAD);
    let shown = window(line, skip);
    let start_in_shown = usize::from(skip > 0) * '…'.len_utf8()
        + text[line_start..span.offset]
            .chars()
            .skip(skip)
            .map(char::len_utf8)
            .sum::<usize>();
    let end_in_shown = (start_in_shown + span.len.min(line_end - span.offset)).min(shown.len());
    let mut end_in_shown = end_in_shown.max(start_in_shown);
    while !shown.is_char_boundary(end_in_shown) {
        end_in_shown -= 1;
    }

    let mut excerpt = String::new();
    if let Some(previous) = previous {
        excerpt.push_str(&window(previous, skip));
        excerpt.push('\n');
    }
    let offset = excerpt.len() + start_in_shown;
    excerpt.push_str(&shown);
    if let Some(next) = next {
        excerpt.push('\n');
        excerpt.push_str(&window(next, skip));
    }
    let error_line = breaks.lines_before(&text, line_start);
    Some((
        Excerpt {
            name: rayforge_scene::clip(&error.path.display().to_string()).into_owned(),
            text: excerpt,
            first_line: error_line - usize::from(previous.is_some()),
            error_line,
            error_column: column_chars,
        },
        SourceSpan::new(offset.into(), end_in_shown - start_in_shown),
    ))
}

/// The characters of `line` from `skip` on, at most [`WINDOW`] of them, with an ellipsis
/// where the line was cut. A line shorter than `skip` (a context line beside a long one) is
/// shown from its start instead of as nothing.
fn window(line: &str, skip: usize) -> String {
    let skip = if line.chars().nth(skip).is_some() {
        skip
    } else {
        0
    };
    let mut shown = String::new();
    if skip > 0 {
        shown.push('…');
    }
    shown.extend(line.chars().skip(skip).take(WINDOW));
    if line.chars().skip(skip).nth(WINDOW).is_some() {
        shown.push('…');
    }
    shown
}

/// A scene error as a failure (exit 2): a miette report with the offending line when the
/// position is known, otherwise the one-line message (which names the file); a reading
/// stopped by Ctrl-C or a termination signal is the interrupt's failure (exit 130).
pub fn scene_failure(error: SceneError) -> Failure {
    if error.interrupted {
        let at = match error.span {
            Some(span) => format!(" at {}:{}:{}", error.path.display(), span.line, span.column),
            None => format!(" in {}", error.path.display()),
        };
        return Failure::Interrupted(format!(
            "stopped while reading the scene{}; nothing was written",
            clip(&at)
        ));
    }
    match locate(&error) {
        Some((source_code, span)) => Failure::Scene(miette::Report::new(SceneDiagnostic {
            error,
            source_code,
            span,
        })),
        None => Failure::usage(error.to_string()),
    }
}

/// Prints a scene warning on stderr, with the offending line when the position is known.
pub fn print_warning(error: &SceneError) {
    match locate(error) {
        Some((source_code, span)) => {
            let warning = miette::Report::new(SceneWarning {
                error: error.clone(),
                source_code,
                span,
            });
            eprintln!("{warning:?}");
        }
        None => eprintln!("warning: {error}"),
    }
}
