//! What the page and the server say to each other over the WebSocket.
//!
//! The page sends one kind of message, a render request, as JSON text:
//! `{"type": "render", "renderer": "ray", "lighting": "phong", "samples": 4, "width": 320,
//! "height": 180, "yaw": 30, "pitch": -10, "preview": false, "denoise": false}`, every field
//! but `type` optional (left out or `null`: the scene's own choice; no orbit; not a preview;
//! not denoised; `denoise` applies to the path tracer, the other renderers ignore it). A
//! message that is not such a request is answered with an `error` message and changes nothing.
//!
//! The server sends JSON text (`started`, `progress`, `frame`, `done`, `error`; each names the
//! request it belongs to by `job`, so the page can drop what a newer request made stale), and
//! after each `frame` the image itself as a binary message: a PNG, developed as `rayforge
//! render` writes it. With `denoise` (the path tracer's `--denoise`), passes are denoised beside
//! the render (see [`crate::live_denoise`]): their frames come with `"denoised": true` after
//! the raw passes' (`"denoised": false`), and the last frame is the denoised image `rayforge
//! render --denoise` writes, in place of the raw last pass.

use crate::args::Renderer;
use crate::diagnostics::{ErrorLine, LEAD, WINDOW};
use rayforge::LightingModel;
use rayforge_scene::{clip, SceneError};
use serde_json::{json, Map, Value};

/// The longest message accepted from the page, in bytes: a request is well under 1 KiB; the
/// WebSocket closes on a longer one before it is read.
pub const MAX_MESSAGE_BYTES: usize = 64 * 1024;

/// A render request from the page, checked for its form; the values are checked as `rayforge
/// render` checks its flags when the request is run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Request {
    /// The renderer; `None`: the scene's.
    pub renderer: Option<Renderer>,
    /// The lighting model; `None`: the scene's `world: lighting:`.
    pub lighting: Option<LightingModel>,
    /// Samples per pixel (`--spp`); `None`: the camera's.
    pub samples: Option<u64>,
    /// Image width (`--width`); `None`: the camera's.
    pub width: Option<u64>,
    /// Image height (`--height`); `None`: the camera's.
    pub height: Option<u64>,
    /// Degrees the eye turns about the scene's up (see [`super::orbit`]).
    pub yaw: f64,
    /// Degrees the eye rises toward the up.
    pub pitch: f64,
    /// A quick, small image while the camera is being dragged, not the refined one.
    pub preview: bool,
    /// Denoised when the path tracer renders (its `--denoise`); the other renderers ignore it.
    pub denoise: bool,
}

/// The fields a request may have.
const FIELDS: &[&str] = &[
    "type", "renderer", "lighting", "samples", "width", "height", "yaw", "pitch", "preview",
    "denoise",
];

/// Reads a message from the page; the error says what is wrong, for the page to show.
pub fn parse_request(text: &str) -> Result<Request, String> {
    if text.len() > MAX_MESSAGE_BYTES {
        return Err(format!(
            "a message may be at most {MAX_MESSAGE_BYTES} bytes, this one is {}",
            text.len()
        ));
    }
    let value: Value =
        serde_json::from_str(text).map_err(|e| format!("the message is not JSON: {e}"))?;
    let Value::Object(fields) = value else {
        return Err("the message must be a JSON object such as {\"type\": \"render\"}".into());
    };
    match fields.get("type") {
        Some(Value::String(kind)) if kind == "render" => {}
        Some(Value::String(kind)) => {
            return Err(format!(
                "unknown message type `{}`; the only one is `render`",
                clip(kind)
            ))
        }
        _ => return Err("the message needs \"type\": \"render\"".into()),
    }
    if let Some(unknown) = fields.keys().find(|k| !FIELDS.contains(&k.as_str())) {
        return Err(format!(
            "unknown field `{}`; a request has {}",
            clip(unknown),
            FIELDS.join(", ")
        ));
    }
    Ok(Request {
        renderer: choice(&fields, "renderer", renderer)?,
        lighting: choice(&fields, "lighting", lighting)?,
        samples: whole(&fields, "samples")?,
        width: whole(&fields, "width")?,
        height: whole(&fields, "height")?,
        yaw: angle(&fields, "yaw")?,
        pitch: angle(&fields, "pitch")?,
        preview: switch(&fields, "preview")?,
        denoise: switch(&fields, "denoise")?,
    })
}

/// A field holding true or false; false when left out.
fn switch(fields: &Map<String, Value>, name: &str) -> Result<bool, String> {
    match fields.get(name) {
        None | Some(Value::Null) => Ok(false),
        Some(Value::Bool(b)) => Ok(*b),
        Some(_) => Err(format!("`{name}` must be true or false")),
    }
}

/// A field naming one of a set of choices, read by `named` (which lists them when it fails).
fn choice<T>(
    fields: &Map<String, Value>,
    name: &str,
    named: fn(&str) -> Result<T, &'static str>,
) -> Result<Option<T>, String> {
    match fields.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => named(s).map(Some).map_err(|choices| {
            format!(
                "unknown {name} `{}`; expected {choices}, or null for the scene's",
                clip(s)
            )
        }),
        Some(_) => Err(format!("`{name}` must be a string or null")),
    }
}

/// The renderer a request names.
fn renderer(name: &str) -> Result<Renderer, &'static str> {
    match name {
        "ray" => Ok(Renderer::Ray),
        "raster" => Ok(Renderer::Raster),
        "path" => Ok(Renderer::Path),
        _ => Err("ray, raster or path"),
    }
}

/// The lighting model a request names: the scene format's names for `world: lighting:`.
fn lighting(name: &str) -> Result<LightingModel, &'static str> {
    match name {
        "phong" => Ok(LightingModel::Phong),
        "flat" => Ok(LightingModel::Flat),
        "cgfs" => Ok(LightingModel::Cgfs),
        "optics" => Ok(LightingModel::Optics),
        _ => Err("phong, flat, cgfs or optics"),
    }
}

/// A field holding a whole number of at least 1, or nothing.
fn whole(fields: &Map<String, Value>, name: &str) -> Result<Option<u64>, String> {
    match fields.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => match v.as_u64() {
            Some(n) if n >= 1 => Ok(Some(n)),
            _ => Err(format!(
                "`{name}` must be a whole number of at least 1, or null for the scene's; found {}",
                clip(&v.to_string())
            )),
        },
    }
}

/// A field holding an angle in degrees, finite; 0 when left out.
fn angle(fields: &Map<String, Value>, name: &str) -> Result<f64, String> {
    match fields.get(name) {
        None | Some(Value::Null) => Ok(0.0),
        Some(v) => match v.as_f64() {
            Some(a) if a.is_finite() => Ok(a),
            _ => Err(format!(
                "`{name}` must be a number of degrees; found {}",
                clip(&v.to_string())
            )),
        },
    }
}

/// The name of a renderer in messages, as requests name it.
pub fn renderer_name(renderer: Renderer) -> &'static str {
    match renderer {
        Renderer::Ray => "ray",
        Renderer::Raster => "raster",
        Renderer::Path => "path",
    }
}

/// The name of a lighting model in messages, as requests name it.
pub fn lighting_name(lighting: LightingModel) -> &'static str {
    match lighting {
        LightingModel::Phong => "phong",
        LightingModel::Flat => "flat",
        LightingModel::Cgfs => "cgfs",
        LightingModel::Optics => "optics",
    }
}

/// What a job renders, as resolved from the request and the scene.
pub struct Started {
    /// The renderer.
    pub renderer: Renderer,
    /// The lighting model.
    pub lighting: LightingModel,
    /// The image's width and height.
    pub size: (usize, usize),
    /// Samples per pixel of the final pass.
    pub samples: u64,
    /// Whether the camera can orbit: about the book's camera's `to`, or about what another
    /// camera's image centre sees (none for an image less than 2 pixels high).
    pub orbits: bool,
    /// Whether the frames are denoised (asked for, and the path tracer renders).
    pub denoise: bool,
    /// The scene's warnings (what it read but will not use as written), as the terminal
    /// shows them: at most [`MAX_WARNINGS`].
    pub warnings: Vec<String>,
}

/// The most warnings a `started` message carries (a scene can have thousands).
pub const MAX_WARNINGS: usize = 20;

/// A scene's warnings as `started` carries them: each one line (file, place, key and message,
/// clipped), the first [`MAX_WARNINGS`], then how many more there were.
pub fn warning_lines(warnings: &[SceneError]) -> Vec<String> {
    let mut lines: Vec<String> = warnings
        .iter()
        .take(MAX_WARNINGS)
        .map(|w| clip(&w.to_string()).into_owned())
        .collect();
    if warnings.len() > MAX_WARNINGS {
        lines.push(format!("… and {} more", warnings.len() - MAX_WARNINGS));
    }
    lines
}

/// `started`: a job began, with what it renders (the page shows the scene's choices).
pub fn started(job: u64, s: &Started) -> String {
    json!({
        "type": "started",
        "job": job,
        "renderer": renderer_name(s.renderer),
        "lighting": lighting_name(s.lighting),
        "width": s.size.0,
        "height": s.size.1,
        "samples": s.samples,
        "orbits": s.orbits,
        "denoise": s.denoise,
        "warnings": s.warnings,
    })
    .to_string()
}

/// `progress`: `rows` of the pass's `height` rows are finished.
pub fn progress(job: u64, pass: usize, passes: usize, rows: usize, height: usize) -> String {
    json!({
        "type": "progress", "job": job, "pass": pass, "passes": passes,
        "rows": rows, "height": height,
    })
    .to_string()
}

/// What a frame is: pass `pass` (from 1) of `passes`, its size and samples per pixel.
pub struct Frame {
    /// The pass, from 1.
    pub pass: usize,
    /// How many passes the job takes.
    pub passes: usize,
    /// The image's width and height.
    pub size: (usize, usize),
    /// Samples per pixel so far.
    pub samples: u64,
    /// Milliseconds since the job started.
    pub millis: u128,
    /// Whether the image is denoised.
    pub denoised: bool,
}

/// `frame`: the binary message after it is this pass's image.
pub fn frame(job: u64, f: &Frame) -> String {
    json!({
        "type": "frame", "job": job, "pass": f.pass, "passes": f.passes,
        "width": f.size.0, "height": f.size.1, "samples": f.samples, "millis": f.millis,
        "denoised": f.denoised,
    })
    .to_string()
}

/// `done`: the job's last pass is sent.
pub fn done(job: u64, millis: u128) -> String {
    json!({"type": "done", "job": job, "millis": millis}).to_string()
}

/// `error` without a place in a file: a bad request, a size over the limit, a render refused.
pub fn error(job: Option<u64>, message: &str) -> String {
    json!({"type": "error", "job": job, "message": clip(message)}).to_string()
}

/// `error` in a file: its name, line and column (from 1), the key, and the offending line of
/// the file (cut to a window about the column) with where the error is in it, so the page can
/// show the spot as the terminal does.
pub fn scene_error(job: u64, error: &SceneError) -> String {
    let mut message = json!({
        "type": "error",
        "job": job,
        "message": clip(&error.message),
        "file": clip(&error.path.display().to_string()),
        "key": error.key.as_deref().map(clip),
    });
    if let Some(span) = error.span {
        message["line"] = json!(span.line);
        message["column"] = json!(span.column);
        if let Some((text, at, len)) = offending_line(error) {
            message["text"] = json!(text);
            message["at"] = json!(at);
            message["len"] = json!(len);
        }
    }
    message.to_string()
}

/// The line of the error's file that holds it, cut to [`WINDOW`] characters about the error (as
/// the terminal's display cuts it),
/// with the error's start and length in characters within the cut; `None` when the file can no
/// longer be read or no longer holds the place (it was saved again since).
fn offending_line(error: &SceneError) -> Option<(String, usize, usize)> {
    let ErrorLine {
        text,
        line_start: start,
        line_end: end,
        span,
    } = ErrorLine::read(error)?;
    let line = text[start..end].trim_end_matches('\r');
    let column = text[start..span.offset].chars().count();
    let skip = column.saturating_sub(LEAD);
    let shown: String = line.chars().skip(skip).take(WINDOW).collect();
    let at = column - skip;
    let len = span.len.max(1).min(WINDOW.saturating_sub(at)).max(1);
    Some((shown, at, len))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bare_request_takes_the_scenes_choices() {
        let request = parse_request(r#"{"type": "render"}"#).expect("parses");
        assert_eq!(request, Request::default());
    }

    #[test]
    fn a_full_request_is_read() {
        let request = parse_request(
            r#"{"type": "render", "renderer": "path", "lighting": "cgfs", "samples": 16,
                "width": 320, "height": null, "yaw": -12.5, "pitch": 30, "preview": true,
                "denoise": true}"#,
        )
        .expect("parses");
        assert_eq!(
            request,
            Request {
                renderer: Some(Renderer::Path),
                lighting: Some(LightingModel::Cgfs),
                samples: Some(16),
                width: Some(320),
                height: None,
                yaw: -12.5,
                pitch: 30.0,
                preview: true,
                denoise: true,
            }
        );
    }

    #[test]
    fn malformed_messages_are_explained() {
        let cases = [
            ("", "not JSON"),
            ("{\"type\": \"render\"", "not JSON"),
            ("[1, 2]", "JSON object"),
            ("{}", "needs \"type\""),
            (r#"{"type": "delete"}"#, "unknown message type `delete`"),
            (
                r#"{"type": "render", "file": "/etc/passwd"}"#,
                "unknown field `file`",
            ),
            (
                r#"{"type": "render", "renderer": "gpu"}"#,
                "unknown renderer `gpu`",
            ),
            (
                r#"{"type": "render", "lighting": 3}"#,
                "`lighting` must be a string",
            ),
            (
                r#"{"type": "render", "samples": 0}"#,
                "`samples` must be a whole number",
            ),
            (
                r#"{"type": "render", "width": -4}"#,
                "`width` must be a whole number",
            ),
            (
                r#"{"type": "render", "height": 2.5}"#,
                "`height` must be a whole number",
            ),
            (
                r#"{"type": "render", "yaw": "left"}"#,
                "`yaw` must be a number",
            ),
            (
                r#"{"type": "render", "preview": 1}"#,
                "`preview` must be true or false",
            ),
            (
                r#"{"type": "render", "denoise": "yes"}"#,
                "`denoise` must be true or false",
            ),
        ];
        for (text, expected) in cases {
            let error = parse_request(text).expect_err(text);
            assert!(error.contains(expected), "{text}: {error}");
        }
    }

    #[test]
    fn long_messages_are_refused_and_long_names_clipped() {
        let long = format!(
            r#"{{"type": "render", "renderer": "{}"}}"#,
            "x".repeat(5000)
        );
        let error = parse_request(&long).expect_err("refused");
        assert!(error.len() < 1000, "{}", error.len());
        let huge = " ".repeat(MAX_MESSAGE_BYTES + 1);
        assert!(parse_request(&huge)
            .expect_err("refused")
            .contains("at most"));
    }

    #[test]
    fn a_scene_error_carries_its_place_and_line() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let path = dir.path().join("s.yml");
        std::fs::write(&path, "- add: camera\n  width: oops\n").expect("written");
        let error = SceneError::new(&path, "width must be a number")
            .at(rayforge_scene::Span {
                line: 2,
                column: 10,
                offset: 23,
                len: 4,
            })
            .with_key("width");
        let message: Value = serde_json::from_str(&scene_error(7, &error)).expect("JSON");
        assert_eq!(message["type"], "error");
        assert_eq!(message["job"], 7);
        assert_eq!(message["line"], 2);
        assert_eq!(message["column"], 10);
        assert_eq!(message["key"], "width");
        assert_eq!(message["text"], "  width: oops");
        assert_eq!(message["at"], 9);
        assert_eq!(message["len"], 4);
    }
}
