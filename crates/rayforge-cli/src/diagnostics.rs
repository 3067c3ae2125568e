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
use rayforge_scene::SceneError;

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
        let text = std::fs::read_to_string(&error.path).ok()?;
        if span.offset > text.len() || !text.is_char_boundary(span.offset) {
            return None;
        }
        let line_start = text[..span.offset].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[span.offset..]
            .find('\n')
            .map_or(text.len(), |i| span.offset + i);
        Some(Self {
            text,
            line_start,
            line_end,
            span,
        })
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
    let previous = (line_start > 0).then(|| {
        let end = line_start - 1;
        let start = text[..end].rfind('\n').map_or(0, |i| i + 1);
        &text[start..end]
    });
    let next = (line_end < text.len()).then(|| {
        let start = line_end + 1;
        let end = text[start..].find('\n').map_or(text.len(), |i| start + i);
        &text[start..end]
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
    let error_line = text[..line_start].matches('\n').count();
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
/// position is known, otherwise the one-line message (which names the file).
pub fn scene_failure(error: SceneError) -> Failure {
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
