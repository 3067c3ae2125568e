//! Scene errors and warnings as miette diagnostics: the message, and the offending line of the
//! file with the spot underlined.

use miette::{Diagnostic, NamedSource, SourceSpan};
use rayforge_scene::SceneError;

/// A scene error with the source text it points into.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("{error}")]
#[diagnostic(code(rayforge::scene))]
struct SceneDiagnostic {
    error: SceneError,
    #[source_code]
    source_code: Option<NamedSource<String>>,
    #[label("{}", label(&self.error))]
    span: Option<SourceSpan>,
}

/// A problem the reader worked around, shown like an error but not fatal.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("{error}")]
#[diagnostic(code(rayforge::scene), severity(Warning))]
struct SceneWarning {
    error: SceneError,
    #[source_code]
    source_code: Option<NamedSource<String>>,
    #[label("{}", label(&self.error))]
    span: Option<SourceSpan>,
}

fn label(error: &SceneError) -> String {
    match &error.key {
        Some(key) => format!("here (`{key}`)"),
        None => "here".to_string(),
    }
}

/// The file's text and the span within it, read again only when there is something to show.
fn locate(error: &SceneError) -> (Option<NamedSource<String>>, Option<SourceSpan>) {
    let text = error
        .span
        .and_then(|_| std::fs::read_to_string(&error.path).ok());
    let span = match (&text, error.span) {
        (Some(text), Some(span)) if span.offset <= text.len() => {
            let len = span.len.min(text.len() - span.offset);
            Some(SourceSpan::new(span.offset.into(), len))
        }
        _ => None,
    };
    let source_code = match (text, span) {
        (Some(text), Some(_)) => Some(NamedSource::new(error.path.display().to_string(), text)),
        _ => None,
    };
    (source_code, span)
}

/// Turns a scene error into a report.
pub fn scene_report(error: SceneError) -> miette::Report {
    let (source_code, span) = locate(&error);
    miette::Report::new(SceneDiagnostic {
        error,
        source_code,
        span,
    })
}

/// Turns a scene warning into a report.
pub fn scene_warning(error: SceneError) -> miette::Report {
    let (source_code, span) = locate(&error);
    miette::Report::new(SceneWarning {
        error,
        source_code,
        span,
    })
}
