//! Scene errors and warnings for the terminal: with miette, the message and the offending line
//! of the file with the spot underlined; a plain line when there is no position to show.

use crate::failure::Failure;
use miette::{Diagnostic, MietteHandlerOpts, NamedSource, SourceSpan};
use rayforge_scene::SceneError;

/// Sets miette's report style: messages are not wrapped, so each stays one line that a script
/// or a test can search (a terminal wraps long lines by itself).
pub fn install_handler() {
    // Fails only when a hook is already set, which then stays.
    let _ = miette::set_hook(Box::new(|_| {
        Box::new(MietteHandlerOpts::new().wrap_lines(false).build())
    }));
}

/// A scene error with the source text it points into.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("{error}")]
struct SceneDiagnostic {
    error: SceneError,
    #[source_code]
    source_code: NamedSource<String>,
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
    source_code: NamedSource<String>,
    #[label("{}", label(&self.error))]
    span: SourceSpan,
}

fn label(error: &SceneError) -> String {
    match &error.key {
        Some(key) => format!("here (`{key}`)"),
        None => "here".to_string(),
    }
}

/// The file's text and the span within it, when the error has a position and the file (read
/// again here, only now that there is something to show) still holds it.
fn locate(error: &SceneError) -> Option<(NamedSource<String>, SourceSpan)> {
    let span = error.span?;
    let text = std::fs::read_to_string(&error.path).ok()?;
    if span.offset > text.len() || !text.is_char_boundary(span.offset) {
        return None;
    }
    let mut len = span.len.min(text.len() - span.offset);
    while !text.is_char_boundary(span.offset + len) {
        len -= 1;
    }
    let name = error.path.display().to_string();
    Some((
        NamedSource::new(name, text),
        SourceSpan::new(span.offset.into(), len),
    ))
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
