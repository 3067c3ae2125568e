//! Reading a glTF model: the file parsed and validated, its buffers, meshes, materials and
//! node hierarchy read into a [`GltfModel`] in glTF's own space.

use super::buffers;
use super::materials;
use super::meshes;
use super::nodes::{self, GltfCamera, GltfLight};
use super::paths::error;
use crate::error::{SceneError, Span};
use crate::files::{read_bounded, Folder};
use crate::images::ImageMemory;
use crate::obj::MAX_MODEL_BYTES;
use crate::stop::StopFlag;
use glam::{DMat4, DVec3};
use rayforge::Object;
use std::path::Path;

/// A glTF model read from a file, in glTF's own space (see [`GLTF_TO_BOOK`](super::space::GLTF_TO_BOOK)).
#[derive(Debug, Clone)]
pub struct GltfModel {
    /// Each mesh primitive placed by its node: the meshes are shared between the nodes that
    /// use them.
    pub objects: Vec<Object>,
    /// The cameras of the scene's nodes, in node order.
    pub cameras: Vec<GltfCamera>,
    /// The lights (`KHR_lights_punctual`) of the scene's nodes.
    pub lights: Vec<GltfLight>,
    /// What was read but left out (points and lines, unsupported extensions), for warnings.
    pub notes: Vec<String>,
}

impl GltfModel {
    /// The box around the model's objects after `placement`, or `None` for an empty model.
    pub fn bounds(&self, placement: &DMat4) -> Option<(DVec3, DVec3)> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for object in &self.objects {
            let b = object.bounds();
            if !(b.min.is_finite() && b.max.is_finite()) {
                continue;
            }
            for i in 0..8 {
                let corner = DVec3::new(
                    if i & 1 == 0 { b.min.x } else { b.max.x },
                    if i & 2 == 0 { b.min.y } else { b.max.y },
                    if i & 4 == 0 { b.min.z } else { b.max.z },
                );
                let p = placement.transform_point3(corner);
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }
}

/// What reading a model may use: the scene's folder rules, its images' memory, and how many
/// triangles are left of the scene's budget.
pub(crate) struct Limits<'a> {
    /// Where the model's buffers and images may be.
    pub folder: &'a Folder,
    /// The scene's images' memory.
    pub memory: &'a mut ImageMemory,
    /// The most triangles the model may hold.
    pub max_triangles: usize,
    /// The flag that stops the reading part-way.
    pub stop: &'a StopFlag,
}

/// Reads the glTF model at `path`, within `limits`.
pub(crate) fn read_gltf(path: &Path, limits: Limits<'_>) -> Result<GltfModel, SceneError> {
    let bytes = read_bounded(path, MAX_MODEL_BYTES)
        .map_err(|e| SceneError::new(path, format!("cannot read the glTF file: {e}")))?;
    nodes::check_node_count(path, &bytes)?;
    let mut gltf = parse(path, &bytes, limits.stop)?;
    let buffers = buffers::load(path, &mut gltf, limits.folder)?;
    let mut materials = materials::Materials::new(path, &buffers, limits.folder, limits.memory);
    let mut meshes = meshes::Meshes::new(path, &buffers, limits.max_triangles, limits.stop);
    let mut notes = Vec::new();
    for extension in gltf.extensions_required() {
        if APPROXIMATED_EXTENSIONS.contains(&extension) {
            notes.push(format!(
                "the model requires `{extension}`; it is rendered without that extension's effect"
            ));
        } else if !SUPPORTED_EXTENSIONS.contains(&extension) {
            return Err(error(
                path,
                "extensionsRequired",
                format!(
                    "the model requires the extension `{extension}`, which rayforge does not \
                     read (it reads {})",
                    SUPPORTED_EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    let required: Vec<&str> = gltf.extensions_required().collect();
    for extension in gltf.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&extension) && !required.contains(&extension) {
            notes.push(format!("the extension `{extension}` is ignored"));
        }
    }
    // Every reference was validated and every accessor is checked before it is read; a panic
    // left in the `gltf` crate's accessors on some damaged file is that file's error.
    let walk = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        nodes::walk(path, &gltf, &mut meshes, &mut materials)
    }))
    .map_err(|_| SceneError::new(path, "the glTF reader failed on the file (it is damaged)"))??;
    notes.extend(meshes.notes);
    notes.extend(materials.notes);
    Ok(GltfModel {
        objects: walk.objects,
        cameras: walk.cameras,
        lights: walk.lights,
        notes,
    })
}

/// The extensions whose meaning rayforge renders.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_texture_transform",
];

/// Material extensions whose effect is a refinement of the metallic-roughness model: a
/// model that requires one is rendered without it (with a warning) rather than refused, since
/// the material underneath is still the one its authors meant.
pub const APPROXIMATED_EXTENSIONS: &[&str] = &[
    "KHR_materials_clearcoat",
    "KHR_materials_dispersion",
    "KHR_materials_iridescence",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_volume",
    "KHR_materials_anisotropy",
];

/// Parses and validates the file's JSON (or GLB container).
fn parse(path: &Path, bytes: &[u8], stop: &StopFlag) -> Result<::gltf::Gltf, SceneError> {
    // Validated here rather than by `from_slice`, which refuses every required extension it
    // does not know, including those rendered approximately.
    let parsed = std::panic::catch_unwind(|| {
        let gltf = match unvalidated(bytes, stop) {
            Err(_) if stop.is_set() => return Ok(Err(SceneError::interrupted(path))),
            parsed => parsed?,
        };
        // The validator indexes the POSITION accessor without a check, and the readers assume
        // an image in a buffer view has a MIME type and any other a URI: checked here first.
        let json = gltf.document.as_json();
        for (i, image) in json.images.iter().enumerate() {
            let complete = match (&image.buffer_view, &image.uri) {
                (Some(_), _) => image.mime_type.is_some(),
                (None, uri) => uri.is_some(),
            };
            if !complete {
                return Ok(Err(error(
                    path,
                    format!("images[{i}]"),
                    "an image needs a `uri`, or a `bufferView` with its `mimeType`",
                )));
            }
        }
        for (i, mesh) in json.meshes.iter().enumerate() {
            for (j, primitive) in mesh.primitives.iter().enumerate() {
                let position =
                    ::gltf::json::validation::Checked::Valid(::gltf::Semantic::Positions);
                if let Some(index) = primitive.attributes.get(&position) {
                    if index.value() >= json.accessors.len() {
                        let at = format!("meshes[{i}].primitives[{j}].attributes.POSITION");
                        return Ok(Err(error(
                            path,
                            at,
                            format!(
                                "accessor {} does not exist (the file has {})",
                                index.value(),
                                json.accessors.len()
                            ),
                        )));
                    }
                }
            }
        }
        let mut problems = Vec::new();
        ::gltf::json::validation::Validate::validate(
            gltf.document.as_json(),
            gltf.document.as_json(),
            ::gltf::json::Path::new,
            &mut |path, error| {
                let about_required = path().as_str().starts_with("extensionsRequired");
                if !about_required {
                    problems.push((path(), error));
                }
            },
        );
        if problems.is_empty() {
            Ok(Ok(gltf))
        } else {
            Err(::gltf::Error::Validation(problems))
        }
    })
    .map_err(|_| SceneError::new(path, "the glTF reader failed on the file (it is damaged)"))?;
    parsed.map_err(|e| located(path, bytes, e))?
}

/// JSON at least this long is parsed through [`StopReader`], so that a stop reaches inside the
/// parse; shorter JSON (under a tenth of a second's parse) from the slice, which `serde_json`
/// reads about twice as fast.
const STOPPABLE_JSON: usize = 8 << 20;

/// The file's document and binary chunk, as `gltf::Gltf::from_slice_without_validation` makes
/// them, the JSON parsed so that a stop reaches inside it (see [`STOPPABLE_JSON`]).
fn unvalidated(bytes: &[u8], stop: &StopFlag) -> Result<::gltf::Gltf, ::gltf::Error> {
    let root = |json: &[u8]| {
        if json.len() < STOPPABLE_JSON {
            ::gltf::json::Root::from_slice(json)
        } else {
            ::gltf::json::Root::from_reader(StopReader {
                json,
                stop,
                since_look: 0,
            })
        }
    };
    let (json, blob) = if bytes.starts_with(b"glTF") {
        let mut glb = ::gltf::binary::Glb::from_slice(bytes)?;
        (root(&glb.json)?, glb.bin.take().map(|b| b.into_owned()))
    } else {
        (root(bytes)?, None)
    };
    Ok(::gltf::Gltf {
        document: ::gltf::Document::from_json_without_validation(json),
        blob,
    })
}

/// The JSON of a glTF file as `serde_json` reads it, failing once the stop flag is set: looked
/// at every [`STOP_READ_EVERY`] bytes (the parser asks for one byte at a time).
struct StopReader<'a> {
    json: &'a [u8],
    stop: &'a StopFlag,
    /// Bytes handed out since the flag was last looked at.
    since_look: usize,
}

/// Bytes of JSON parsed between two looks at the stop flag (a few milliseconds).
const STOP_READ_EVERY: usize = 1 << 20;

impl std::io::Read for StopReader<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.since_look >= STOP_READ_EVERY {
            self.since_look = 0;
            if self.stop.is_set() {
                return Err(std::io::Error::other("the reading was stopped"));
            }
        }
        let n = self.json.read(buf)?;
        self.since_look += n;
        Ok(n)
    }
}

/// A parsing or validation error of the `gltf` crate as a scene error.
fn located(path: &Path, bytes: &[u8], e: ::gltf::Error) -> SceneError {
    match e {
        ::gltf::Error::Deserialize(json) => {
            let mut err = SceneError::new(path, format!("the glTF JSON cannot be read: {json}"));
            // A `.gltf` file is the JSON itself: point at the place (in text the error
            // display can show: valid UTF-8, and on a character's start).
            if let (false, Ok(text)) = (bytes.starts_with(b"glTF"), std::str::from_utf8(bytes)) {
                if json.line() > 0 {
                    err = err.at(span_at(text, json.line(), json.column()));
                }
            }
            err
        }
        ::gltf::Error::Validation(errors) => {
            let count = errors.len();
            let (at, what) = errors
                .into_iter()
                .next()
                .map(|(p, e)| (p.to_string(), e.to_string()))
                .unwrap_or_default();
            let more = if count > 1 {
                format!(" (and {} more problems)", count - 1)
            } else {
                String::new()
            };
            error(
                path,
                at,
                format!("the glTF file is not valid: {what}{more}"),
            )
        }
        ::gltf::Error::Binary(b) => {
            SceneError::new(path, format!("the GLB container is damaged: {b:?}"))
        }
        other => SceneError::new(path, format!("cannot read the glTF file: {other}")),
    }
}

/// The span of 1-based `line` and byte `column` in `text`, moved back to a character's
/// start where the column falls inside one.
fn span_at(text: &str, line: usize, column: usize) -> Span {
    // serde_json counts the column of an empty line's end (and of an empty file) as 0.
    let column = column.max(1);
    let mut offset = 0;
    for (i, l) in text.split('\n').enumerate() {
        if i + 1 == line {
            offset += column.saturating_sub(1).min(l.len());
            break;
        }
        offset += l.len() + 1;
    }
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    Span {
        line,
        column,
        offset,
        len: 0,
    }
}
