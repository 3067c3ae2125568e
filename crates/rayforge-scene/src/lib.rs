//! The YAML scene format of *The Ray Tracer Challenge* (appendix A1) and its community dialect,
//! read into a renderable [`Scene`].
//!
//! Only this crate knows YAML. It reads the file with saphyr, keeping every node's position, so
//! each error names the file, line, column and key ([`SceneError`]). The reference for users is
//! `docs/scene-format.md`.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod assets;
mod budget;
mod canvas_items;
mod defines;
mod document;
mod environment;
mod error;
pub mod files;
mod film_sensor;
pub mod gltf;
mod hdr;
mod images;
mod items;
mod material;
mod media;
pub mod obj;
pub mod pbrt;
pub mod ply;
mod scene;
mod settings;
mod source;
mod stop;
mod text_line;
mod transform;

pub use assets::texture_from_bytes;
pub use error::{clip, clip_to, SceneError, Span, MAX_SHOWN_CHARS};
pub use images::{DEFAULT_MAX_IMAGE_MEMORY, MAX_IMAGE_BYTES, MAX_TEXTURE_PIXELS, MAX_TEXTURE_SIDE};
pub use obj::DEFAULT_MAX_TRIANGLES;
pub use scene::{CameraChoice, LoadOptions, Scene, Written};
pub use settings::MAX_DEPTH as MAX_RAY_DEPTH;
pub use stop::StopFlag;

use defines::Defines;
use document::Items;
use items::camera::CameraItem;
pub use items::camera::{LookAt, MAX_PATH_SAMPLES, MAX_RAY_SAMPLES};
use items::Contents;
use source::{Node, Source};
use std::path::Path;

/// Scene files larger than this are refused before parsing (a scene is text written by hand or
/// a tool; anything this large is a mistake, and parsing it would take all memory).
pub const MAX_SCENE_BYTES: u64 = 64 * 1024 * 1024;

/// Reads and builds the scene in the file at `path`.
pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
    load_file_with(path, &LoadOptions::default())
}

/// [`load_file`] within `options`' limits. A glTF model (`.gltf`, `.glb`) is read as a whole
/// scene of its own: see [`gltf`]; a pbrt-v4 scene (`.pbrt`, `.pbrt.gz`) too: see [`pbrt`].
pub fn load_file_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    if gltf::is_model_file(path) {
        return gltf::model_scene(path, options);
    }
    if pbrt::is_scene_file(path) {
        return pbrt::load(path, options);
    }
    let bytes = read_scene_file(path)
        .map_err(|e| SceneError::new(path, format!("cannot read the scene file: {e}")))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| SceneError::new(path, "the scene file is not UTF-8 text"))?;
    load_str_with(&text, path, options)
}

/// The bytes of the scene file at `path` as [`load_file_with`] reads them: a regular file
/// (see [`files::open_regular`]) of at most [`MAX_SCENE_BYTES`], or [`obj::MAX_MODEL_BYTES`]
/// for a glTF model. The command reads a scene again through it for the fingerprint of its
/// checkpoints and parts; the error is the reason, for the caller to name the file.
pub fn read_scene_file(path: &Path) -> Result<Vec<u8>, String> {
    let limit = if gltf::is_model_file(path) {
        obj::MAX_MODEL_BYTES
    } else {
        MAX_SCENE_BYTES
    };
    files::read_bounded(path, limit)
}

/// The stack the reader runs on. Reading recurses once per level of nesting (YAML lists and
/// mappings, groups, patterns, references), and each level is bounded (see
/// `docs/scene-format.md`, "Limits"); at their bounds an unoptimised build needs about 10 MiB.
/// A thread of its own with this much room makes the reader safe whatever stack its caller has
/// (test threads get 2 MiB). Only the pages it touches are ever committed.
const READER_STACK_BYTES: usize = 64 << 20;

/// Builds a scene from YAML text; `path` names the file in errors, and its folder is where the
/// files the scene names are found (and, unless [`LoadOptions::allow_outside`], must stay).
pub fn load_str(text: &str, path: &Path) -> Result<Scene, SceneError> {
    load_str_with(text, path, &LoadOptions::default())
}

/// [`load_str`] within `options`' limits.
pub fn load_str_with(text: &str, path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    std::thread::scope(|scope| {
        let reader = std::thread::Builder::new()
            .name("rayforge-scene".into())
            .stack_size(READER_STACK_BYTES)
            .spawn_scoped(scope, || read(text, path, options))
            .map_err(|e| {
                SceneError::new(
                    path,
                    format!("cannot start a thread to read the scene: {e}"),
                )
            })?;
        // The reader returns errors as values; a panic would be a bug in it: pass it on.
        reader
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

/// [`load_str`]'s work, on the reader's own thread.
fn read(text: &str, path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    if text.contains('\0') {
        return Err(SceneError::new(
            path,
            "the scene file is binary, not YAML text",
        ));
    }
    let source = Source::new(path, text, options.stop.clone());
    let mut items = Items::open(&source)?;
    let mut defines = Defines::default();
    let mut assets = assets::Assets::new(
        path,
        options.allow_outside,
        options.max_triangles,
        options.max_image_memory,
        options.stop.clone(),
    );
    let mut read = Contents::default();
    let mut settings: Option<settings::Settings> = None;
    let mut world_medium: Option<media::NamedLater> = None;
    // Each item is dropped once read, except a define's, which later items name.
    let defined = typed_arena::Arena::new();
    while let Some(item) = items.next_item(&source) {
        let item = item?;
        if items::is_define(&item) {
            let item: &Node<'_> = defined.alloc(item);
            defines.add(&source, &source.entries(item, "")?)?;
            continue;
        }
        let entries = source.entries(&item, "")?;
        if media::is_medium(&entries) {
            let (name, medium) = media::medium(
                &source,
                &defines,
                &mut assets,
                &item,
                &entries,
                options.max_grid_samples,
            )?;
            let at = entries
                .iter()
                .find(|e| e.name == "medium")
                .expect("a medium item");
            let id = medium
                .within_optical_depth(options.max_optical_depth)
                .and_then(|medium| read.world.media.add(medium))
                .map_err(|e| source.error(at.value, "medium", e.to_string()))?;
            defines.add_medium(name, id);
            continue;
        }
        if let Some(e) = entries.iter().find(|e| e.name == "world") {
            if entries.len() > 1 || settings.is_some() {
                let message = if settings.is_some() {
                    "a second `world:` item: a scene has at most one"
                } else {
                    "a `world:` item has nothing beside it"
                };
                return Err(source.error(e.key, "world", message));
            }
            if let Some(m) = source
                .entries(e.value, "world")?
                .iter()
                .find(|m| m.name == "medium")
            {
                world_medium = Some(media::NamedLater::new(&source, m.value, "medium")?);
            }
            settings = Some(settings::apply(
                &source,
                e.value,
                &mut read.world,
                &mut assets,
            )?);
            continue;
        }
        items::add_item(
            &source,
            &defines,
            &mut assets,
            &item,
            &mut read,
            options.frame,
        )?;
    }
    let Contents {
        mut world,
        camera,
        canvas_items,
        camera_medium,
    } = read;
    // The world's medium is all around: the camera's (unless it names its own) and every
    // boundary's outside that names none.
    let around = world_medium
        .map(|m| m.resolve(&defines))
        .transpose()?
        .flatten();
    media::resolve_around(&mut world.objects, around);
    world.camera_medium = match camera_medium {
        Some(m) => m.resolve(&defines)?,
        None => around,
    };
    let CameraItem {
        camera,
        samples,
        samples_at,
        anti_alias,
        look_at,
    } = camera.ok_or_else(|| {
        SceneError::new(path, "the scene has no camera: add an item `- add: camera`")
    })?;
    let written = |span, key: &str| Written {
        file: path.to_path_buf(),
        span,
        key: key.into(),
    };
    // Canvas coordinates are pixels of the camera's canvas.
    let overlay = rayforge::draw2d::Overlay::new(canvas_items, camera.hsize(), camera.vsize());
    Ok(Scene {
        overlay,
        world,
        camera,
        samples,
        samples_at: samples_at.map(|span| written(span, "samples")),
        anti_alias,
        max_depth: settings.as_ref().and_then(|s| s.max_depth),
        max_depth_at: settings
            .as_ref()
            .and_then(|s| s.max_depth_at)
            .map(|span| written(span, "max-depth")),
        raster: settings.as_ref().and_then(|s| s.raster),
        path: settings.and_then(|s| s.path),
        warnings: source.take_warnings(),
        look_at,
        files: assets.files(path),
    })
}
