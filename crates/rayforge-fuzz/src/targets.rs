//! What is fuzzed: the scene reader, the pbrt-v4 reader ([`pbrt`]), the OBJ/MTL reader, the
//! glTF reader, the PLY reader ([`ply`]) and the image-texture decoder (8-bit and HDR), each followed by a tiny render of what it produced,
//! so that values the readers let through are also fed to the renderer; and the command's own
//! readers of outside bytes (`rayforge_cli::untrusted`): part files through the whole merge,
//! and what a browser sends the live page's server.
//!
//! Each target is a function of the input's bytes that says whether the reader accepted them
//! (the seeds' test checks that seeds reach past the first checks; the engine ignores it).
//! Errors are the expected answer to bad input; a panic is a bug, and so is an error whose
//! position lies outside the text, which would break its display. A new target is a function
//! here, one line in `tests/fuzz.rs`, and its seeds in `corpus/NAME/`.

use rayforge::render::{render, RenderOptions, Sampling};
use rayforge::{point, vector, Camera, Color, Light, Object, World};
use rayforge_cli::failure::Failure;
use rayforge_scene::obj::{parse_mtl, parse_obj_with_limit, to_meshes};
use rayforge_scene::{load_file_with, load_str_with, texture_from_bytes, LoadOptions, SceneError};
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub mod denoise;
pub mod media;
pub mod pbrt;
pub mod ply;

/// The mesh size limit while fuzzing: low, so that inputs that multiply faces stay quick.
const FUZZ_MAX_TRIANGLES: usize = 200_000;

/// The repository's root (scene inputs are read as if they were in `scenes/trtc/`, so the
/// models and images they name resolve to real files).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The pbrt-v4 reader on a scene's files (the top-level one, those it includes, gzip, PLY),
/// and what it built, rendered: see [`pbrt::run`].
pub fn pbrt(input: &[u8]) -> bool {
    pbrt::run(input)
}

/// The images `rayforge denoise` reads (OpenEXR and PFM, the image and its guides), checked
/// as the command checks them before OIDN: see [`denoise::run`].
pub fn denoise(input: &[u8]) -> bool {
    denoise::run(input)
}

/// Participating media read from pbrt-v4 and YAML scenes (`MakeNamedMedium` of every type,
/// `medium:` items, `.vol` files), then path traced: see [`media::run`].
pub fn media(input: &[u8]) -> bool {
    media::run(input)
}

/// The PLY reader (text, binary, gzip) and the mesh it builds, rendered: see [`ply::run`].
pub fn ply(input: &[u8]) -> bool {
    ply::run(input)
}

/// `rayforge_scene::load_str_with` on YAML text, as if it were in `scenes/trtc/` (so the
/// models and images it names exist), from frame 3 (so that `per-frame` steps run too).
pub fn scene(input: &[u8]) -> bool {
    let text = String::from_utf8_lossy(input);
    let path = repo_root().join("scenes/trtc/fuzz-input.yml");
    let options = LoadOptions {
        max_triangles: FUZZ_MAX_TRIANGLES,
        // A frame beyond 0, so that `per-frame` steps are exercised too.
        frame: 3,
        ..LoadOptions::default()
    };
    rendered(load_str_with(&text, &path, &options), &path, &text)
}

/// The OBJ parser, the meshes built from it and a tiny render of them; the same text as an
/// MTL library.
pub fn obj(input: &[u8]) -> bool {
    let text = String::from_utf8_lossy(input);
    let path = Path::new("fuzz-input.obj");
    let accepted = match parse_obj_with_limit(&text, path, FUZZ_MAX_TRIANGLES) {
        Ok(obj) => {
            let mut world = World::new();
            for (mesh, material) in to_meshes(&obj) {
                let mut object = Object::mesh(mesh);
                object.material = material.unwrap_or_default();
                world.objects.push(object);
            }
            lit_model_render(world);
            true
        }
        Err(e) => {
            check_error(&e, path, &text);
            false
        }
    };
    // The same text as a material library, its images refused.
    let mut no_images = |p: &Path| -> Result<Arc<rayforge::shading::Texture>, SceneError> {
        Err(SceneError::new(p, "no images while fuzzing"))
    };
    if let Err(e) = parse_mtl(&text, path, &mut no_images) {
        check_error(&e, path, &text);
    }
    accepted
}

/// The image decoding that `image` patterns, `map_Kd` and environment maps use, then samples
/// of the texture at ordinary and non-finite coordinates.
pub fn image(input: &[u8]) -> bool {
    let Ok(texture) = texture_from_bytes(input, Path::new("fuzz-input.img")) else {
        return false;
    };
    {
        for (u, v) in [
            (0.0, 0.0),
            (0.5, 0.5),
            (1.0, 1.0),
            (-3.5, 7.25),
            (f64::NAN, f64::INFINITY),
        ] {
            let _ = texture.sample(u, v);
        }
    }
    true
}

/// Reads `input` as a glTF model (a `.glb` when it starts with GLB's magic, else a `.gltf`),
/// from a file of this process's own (the reader takes files, as its buffers and images may
/// be beside them), and renders it.
pub fn gltf(input: &[u8]) -> bool {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::tempdir().expect("a scratch folder");
    }
    let name = if input.starts_with(b"glTF") {
        "fuzz-input.glb"
    } else {
        "fuzz-input.gltf"
    };
    let path = DIR.with(|dir| dir.path().join(name));
    if std::fs::write(&path, input).is_err() {
        return false;
    }
    let options = LoadOptions {
        max_triangles: FUZZ_MAX_TRIANGLES,
        ..LoadOptions::default()
    };
    let text = String::from_utf8_lossy(input);
    rendered(load_file_with(&path, &options), &path, &text)
}

/// Merges `input` as a part file: alone (a part of one slice merges into an image), named
/// twice (a duplicate, refused), and with its checksums repaired, so that changes reach the
/// fields behind them. Whether the first merge was accepted. A refusal must say something.
pub fn part(input: &[u8]) -> bool {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::tempdir().expect("a scratch folder");
    }
    let (path, output) = DIR.with(|dir| (dir.path().join("fuzz.part"), dir.path().join("out.png")));
    let merged = |bytes: &[u8], parts: &[PathBuf]| {
        if std::fs::write(&path, bytes).is_err() {
            return false;
        }
        match rayforge_cli::untrusted::merge_parts(parts, &output) {
            Ok(()) => true,
            // A damaged part is bad input (exit 2), never "something that should not happen".
            Err(Failure::Input(why)) => {
                assert!(!why.trim().is_empty(), "an empty refusal");
                false
            }
            Err(Failure::Scene(_)) => false,
            Err(other) => panic!("a part file made the merge fail so: {other:?}"),
        }
    };
    let accepted = merged(input, std::slice::from_ref(&path));
    assert!(
        !merged(input, &[path.clone(), path.clone()]),
        "a part named twice was merged"
    );
    let repaired = rayforge_cli::untrusted::with_part_checksums_repaired(input);
    if repaired != input {
        merged(&repaired, std::slice::from_ref(&path));
    }
    accepted
}

/// Hands `input` to the live page's server as a WebSocket request's headers and a message
/// (the input's first line is the `Host`, its second the `Origin`, `-` for none, the rest the
/// message); whether it was taken. A refusal must say something.
pub fn page(input: &[u8]) -> bool {
    let text = String::from_utf8_lossy(input);
    let mut lines = text.splitn(3, '\n');
    let host = lines.next().unwrap_or_default();
    let origin = lines.next().filter(|o| *o != "-");
    let message = lines.next().unwrap_or_default();
    match rayforge_cli::untrusted::page_message(host, origin, PAGE_PORT, message) {
        Ok(()) => true,
        Err(why) => {
            assert!(!why.trim().is_empty(), "an empty refusal");
            false
        }
    }
}

/// The port of the server the page target's requests are checked against.
pub const PAGE_PORT: u16 = 8765;

/// A scene the reader built, rendered small (its warnings checked), or its error checked:
/// whether it was accepted.
fn rendered(read: Result<rayforge_scene::Scene, SceneError>, path: &Path, text: &str) -> bool {
    match read {
        Ok(scene) => {
            for w in &scene.warnings {
                check_error(w, path, text);
            }
            let camera = scene.camera.resized(3, 2);
            tiny_render(&camera, &scene.world);
            true
        }
        Err(e) => {
            check_error(&e, path, text);
            false
        }
    }
}

/// A model's `world` under a point light, seen from in front, rendered by [`tiny_render`].
fn lit_model_render(mut world: World) {
    world
        .lights
        .push(Light::point(point(-10.0, 10.0, -10.0), Color::WHITE));
    let camera = Camera::new(3, 2, 1.0).with_transform(rayforge::math::view_transform(
        point(0.5, 1.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    tiny_render(&camera, &world);
}

/// A 3×2 render with every kind of sampling touched lightly.
fn tiny_render(camera: &Camera, world: &World) {
    let options = RenderOptions {
        max_depth: 3,
        sampling: Sampling::Adaptive {
            threshold: 0.1,
            depth: 1,
        },
        ..RenderOptions::default()
    };
    let _ = render(camera, world, &options);
}

/// An error located in `text` must lie within it, on character boundaries (the command line
/// shows the line it points at), and must say something.
fn check_error(e: &SceneError, path: &Path, text: &str) {
    let shown = e.to_string();
    assert!(!e.message.trim().is_empty(), "an empty message: {shown}");
    if e.path != path {
        return;
    }
    if let Some(span) = e.span {
        let end = span.offset.checked_add(span.len);
        assert!(
            end.is_some_and(|end| end <= text.len()
                && text.is_char_boundary(span.offset)
                && text.is_char_boundary(end)),
            "the error's span {span:?} is outside the text ({} bytes) or splits a character: {shown}",
            text.len()
        );
        assert!(span.line >= 1 && span.column >= 1, "{shown}");
    }
}
