//! Scene errors as miette diagnostics: the message, and the offending line of the file with the
//! spot underlined.

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
    #[label("{}", self.label())]
    span: Option<SourceSpan>,
}

impl SceneDiagnostic {
    fn label(&self) -> String {
        match &self.error.key {
            Some(key) => format!("here (`{key}`)"),
            None => "here".to_string(),
        }
    }
}

/// Turns a scene error into a report, reading the file again for the snippet (only on error).
pub fn scene_report(error: SceneError) -> miette::Report {
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
    miette::Report::new(SceneDiagnostic {
        error,
        source_code,
        span,
    })
}
