//! Hostile and degenerate scenes: each gets a located error or a documented, sane result
//! (`docs/reliability.md` lists them), never a panic, a hang or a memory blowup.
use rayforge::render::{render, RenderOptions};
use rayforge_scene::{
    load_file, load_file_with, load_str, load_str_with, LoadOptions, Scene, SceneError,
};
use std::path::Path;

const CAMERA: &str = "- add: camera
  width: 10
  height: 10
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

/// A scene that uses most numeric keys of the format.
const EVERYTHING: &str = "- add: camera
  width: 6
  height: 4
  field-of-view: 1.2
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
  aperture: 0.1
  focal-distance: 5
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: light
  corner: [-1, 4, -4]
  uvec: [2, 0, 0]
  usteps: 2
  vvec: [0, 2, 0]
  vsteps: 2
  jitter: true
  intensity: [0.5, 0.5, 0.5]
- add: light
  at: [0, 5, 0]
  direction: [0, -1, 0]
  angle: 0.5
  fade: 0.1
  intensity: [0.3, 0.3, 0.3]
- add: plane
  material:
    pattern:
      type: checkers
      colors: [[1, 1, 1], [0, 0, 0]]
      transform:
        - [scale, 0.5, 0.5, 0.5]
    reflective: 0.2
- add: sphere
  transform:
    - [translate, -1, 1, 0]
    - [rotate-y, 0.5]
    - [shear, 0.1, 0, 0, 0, 0, 0]
  material:
    color: [1, 0.2, 0.2]
    ambient: 0.1
    diffuse: 0.7
    specular: 0.3
    shininess: 200
    transparency: 0.5
    refractive-index: 1.5
- add: cylinder
  min: 0
  max: 2
  closed: true
  transform:
    - [translate, 1.5, 0, 0]
    - [scale, 0.5, 1, 0.5]
- add: cone
  min: -1
  max: 0
  transform:
    - [translate, 0, 1, 2]
";

fn tiny_render(scene: &Scene) {
    let camera = scene.camera.resized(4, 3);
    let (canvas, _) = render(&camera, &scene.world, &RenderOptions::default());
    // Extreme inputs may give extreme colours; they still encode (NaN as 0, the rest
    // clamped), so the image is written.
    assert_eq!(canvas.to_rgb8().len(), 4 * 3 * 3);
}

#[track_caller]
fn assert_located_in(e: &SceneError, text: &str) {
    if let Some(span) = e.span {
        assert!(span.offset + span.len <= text.len(), "{e}");
    }
    assert!(!e.message.is_empty());
}

/// Every number in the scene, in turn, replaced by a non-finite or extreme value: each is a
/// located error or a scene that renders.
#[test]
fn every_number_replaced_by_a_hostile_value_is_an_error_or_renders() {
    let everything = load_str(EVERYTHING, Path::new("scene.yml")).unwrap();
    tiny_render(&everything);
    let numbers: Vec<(usize, usize)> = {
        let bytes = EVERYTHING.as_bytes();
        let mut spans = Vec::new();
        let mut i = 0;
        while i < bytes.len() {
            let starts_number = (bytes[i].is_ascii_digit() || bytes[i] == b'-')
                && i > 0
                && matches!(bytes[i - 1], b' ' | b'[')
                && bytes.get(i + 1).is_some_and(|b| *b != b' ');
            if starts_number {
                let start = i;
                while i < bytes.len() && matches!(bytes[i], b'0'..=b'9' | b'.' | b'-') {
                    i += 1;
                }
                spans.push((start, i));
            } else {
                i += 1;
            }
        }
        spans
    };
    assert!(numbers.len() > 80, "{}", numbers.len());
    let hostile = [
        ".nan",
        ".inf",
        "-.inf",
        "1e308",
        "-1e308",
        "-1",
        "0",
        "1e-308",
        "4294967296",
    ];
    let (mut refused, mut rendered) = (0, 0);
    for &(start, end) in &numbers {
        for value in hostile {
            let text = format!("{}{value}{}", &EVERYTHING[..start], &EVERYTHING[end..]);
            match load_str(&text, Path::new("scene.yml")) {
                Ok(scene) => {
                    tiny_render(&scene);
                    rendered += 1;
                }
                Err(e) => {
                    assert_located_in(&e, &text);
                    assert!(e.span.is_some(), "an error about a number is located: {e}");
                    refused += 1;
                }
            }
            if value.contains("nan") || value.contains("inf") {
                // Non-finite numbers are always refused.
                let e = load_str(&text, Path::new("scene.yml")).expect_err(&text[start..]);
                assert!(e.message.contains("finite"), "{e}");
            }
        }
    }
    assert!(
        refused > 0 && rendered > 0,
        "{refused} refused, {rendered} rendered"
    );
}

#[test]
fn negative_huge_and_fractional_sizes_are_refused_at_the_key() {
    for (size, words) in [
        ("-5", "at least 1"),
        ("4294967296", "whole number"),
        ("1e308", "whole number"),
        ("2.5", "whole number"),
    ] {
        let e = load_str(
            &CAMERA.replace("width: 10", &format!("width: {size}")),
            Path::new("scene.yml"),
        )
        .unwrap_err();
        assert_eq!(e.key.as_deref(), Some("width"), "{e}");
        assert_eq!(e.span.map(|s| s.line), Some(2), "{e}");
        assert!(e.message.contains(words), "{size}: {e}");
    }
}

/// A camera of 100,000 × 100,000 pixels (10 gigapixels) is read without allocating anything:
/// the image is only allocated by the renderer, and the command line refuses it first
/// (`--max-pixels`, tested in rayforge-cli).
#[test]
fn a_ten_gigapixel_camera_costs_nothing_to_read() {
    let scene = load_str(
        &CAMERA
            .replace("width: 10", "width: 100000")
            .replace("height: 10", "height: 100000"),
        Path::new("scene.yml"),
    )
    .unwrap();
    assert_eq!(
        (scene.camera.hsize(), scene.camera.vsize()),
        (100_000, 100_000)
    );
}

/// Without lights the image is black: ambient light is part of each light's contribution,
/// as the book computes it, so there is none.
#[test]
fn a_scene_without_lights_renders_black() {
    let scene = load_str(
        &format!("{CAMERA}- add: sphere\n  material:\n    color: [1, 0, 0]\n    ambient: 0.5\n"),
        Path::new("scene.yml"),
    )
    .unwrap();
    assert!(scene.world.lights.is_empty());
    let (canvas, _) = render(&scene.camera, &scene.world, &RenderOptions::default());
    assert!(canvas.pixels().iter().all(|c| *c == rayforge::Color::BLACK));
}

#[test]
fn a_scene_without_objects_renders_black() {
    let scene = load_str(
        &format!("{CAMERA}- add: light\n  at: [0, 0, -5]\n  intensity: [1, 1, 1]\n"),
        Path::new("scene.yml"),
    )
    .unwrap();
    let (canvas, stats) = render(&scene.camera, &scene.world, &RenderOptions::default());
    assert!(canvas.pixels().iter().all(|c| *c == rayforge::Color::BLACK));
    assert_eq!(stats.rays, 100);
}

/// A light inside an opaque sphere lights only its inside; the camera outside sees the
/// sphere dark (ambient only) and a floor in the sphere's shadow everywhere.
#[test]
fn a_light_inside_a_solid_lights_nothing_outside_it() {
    let scene = load_str(
        &format!(
            "{CAMERA}- add: light\n  at: [0, 0, 0]\n  intensity: [1, 1, 1]\n- add: sphere\n  material:\n    color: [1, 1, 1]\n    ambient: 0.1\n- add: plane\n  transform: [[translate, 0, -1, 0]]\n  material:\n    ambient: 0\n"
        ),
        Path::new("scene.yml"),
    )
    .unwrap();
    let (canvas, _) = render(&scene.camera, &scene.world, &RenderOptions::default());
    for c in canvas.pixels() {
        assert!(
            c.to_array()
                .iter()
                .all(|v| v.is_finite() && *v <= 0.1 + 1e-9),
            "{c:?}"
        );
    }
    // The middle of the image is the sphere at its ambient level.
    assert_eq!(canvas.pixel_at(5, 5), rayforge::Color::new(0.1, 0.1, 0.1));
}

/// A camera inside an opaque sphere sees its inside, lit by a light inside too, and nothing
/// beyond.
#[test]
fn a_camera_inside_a_solid_sees_its_inside() {
    let scene = load_str(
        "- add: camera\n  width: 8\n  height: 8\n  field-of-view: 1\n  from: [0, 0, 0]\n  to: [0, 0, 1]\n  up: [0, 1, 0]\n- add: light\n  at: [0, 0.5, 0]\n  intensity: [1, 1, 1]\n- add: sphere\n  transform: [[scale, 3, 3, 3]]\n  material:\n    color: [0, 1, 0]\n    specular: 0\n- add: sphere\n  transform: [[translate, 0, 0, 10]]\n  material:\n    color: [1, 0, 0]\n    ambient: 1\n",
        Path::new("scene.yml"),
    )
    .unwrap();
    let (canvas, _) = render(&scene.camera, &scene.world, &RenderOptions::default());
    for c in canvas.pixels() {
        assert!(c.to_array().iter().all(|v| v.is_finite()), "{c:?}");
        assert_eq!(c.red, 0.0, "the red sphere outside is hidden: {c:?}");
        assert!(c.green > 0.0, "the inside is lit: {c:?}");
    }
}

#[test]
fn zero_length_vectors_are_refused_or_degenerate_safely() {
    // A spotlight needs a direction.
    let e = load_str(
        &format!("{CAMERA}- add: light\n  at: [0, 5, 0]\n  direction: [0, 0, 0]\n  angle: 0.5\n  intensity: [1, 1, 1]\n"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("direction"), "{e}");
    // An area light with zero-length edges is a point light at its corner.
    let flat = load_str(
        &format!("{CAMERA}- add: light\n  corner: [-5, 5, -5]\n  uvec: [0, 0, 0]\n  usteps: 2\n  vvec: [0, 0, 0]\n  vsteps: 2\n  intensity: [1, 1, 1]\n- add: sphere\n"),
        Path::new("scene.yml"),
    )
    .unwrap();
    let point = load_str(
        &format!(
            "{CAMERA}- add: light\n  at: [-5, 5, -5]\n  intensity: [1, 1, 1]\n- add: sphere\n"
        ),
        Path::new("scene.yml"),
    )
    .unwrap();
    let a = render(&flat.camera, &flat.world, &RenderOptions::default()).0;
    let b = render(&point.camera, &point.world, &RenderOptions::default()).0;
    for (x, y) in a.pixels().iter().zip(b.pixels()) {
        assert!(
            (*x - *y).to_array().iter().all(|d| d.abs() < 1e-9),
            "{x:?} {y:?}"
        );
    }
}

fn dir_with(files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    dir
}

#[test]
fn a_binary_scene_file_is_refused_as_not_text() {
    let dir = dir_with(&[("scene.yml", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")]);
    let e = load_file(&dir.path().join("scene.yml")).unwrap_err();
    assert!(e.message.contains("not UTF-8 text"), "{e}");
}

/// Devices and directories named where a file belongs are refused without reading them (a
/// read of `/dev/zero` would never end).
#[test]
fn devices_and_directories_are_not_files() {
    let e = load_file(Path::new("/dev/zero")).unwrap_err();
    assert!(e.message.contains("not a regular file"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let e = load_file(dir.path()).unwrap_err();
    assert!(e.message.contains("not a regular file"), "{e}");
    // `/dev/zero` is outside the scene's folder: only allowed outside files reach the check.
    let outside = LoadOptions {
        allow_outside: true,
        ..LoadOptions::default()
    };
    for what in [
        "- add: obj\n  file: /dev/zero\n",
        "- add: obj\n  file: .\n",
        "- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: spherical\n      uv_pattern: {type: image, file: /dev/zero}\n",
    ] {
        let e = load_str_with(&format!("{CAMERA}{what}"), &dir.path().join("s.yml"), &outside)
            .unwrap_err();
        assert!(e.message.contains("not a regular file"), "{e}");
        assert_eq!(e.key.as_deref(), Some("file"), "{e}");
        assert!(e.span.is_some(), "{e}");
    }
}

/// The mesh size limit counts the triangles of all the scene's models, a model used twice
/// once.
#[test]
fn the_mesh_limit_counts_each_model_once() {
    let tri = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let dir = dir_with(&[("a.obj", tri), ("b.obj", tri)]);
    let scene = |body: &str| {
        let path = dir.path().join("s.yml");
        std::fs::write(&path, format!("{CAMERA}{body}")).unwrap();
        load_file_with(
            &path,
            &LoadOptions {
                max_triangles: 1,
                ..LoadOptions::default()
            },
        )
    };
    let twice = "- add: obj\n  file: a.obj\n- add: obj\n  file: a.obj\n";
    assert_eq!(scene(twice).unwrap().world.objects.len(), 2);
    let two_models = "- add: obj\n  file: a.obj\n- add: obj\n  file: b.obj\n";
    let e = scene(two_models).unwrap_err();
    assert!(e.message.contains("hold 2 together"), "{e}");
    assert!(e.message.contains("--max-triangles"), "{e}");
    // At the `file:` that names the second model.
    assert_eq!(e.key.as_deref(), Some("file"), "{e}");
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((11, 9)), "{e}");
}

/// A model's degenerate faces (a corner used twice, three corners on a line) render without
/// a NaN reaching the image.
#[test]
fn degenerate_faces_render_without_nan() {
    let dir = dir_with(&[(
        "flat.obj",
        b"v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 4\nf 4 4 4\n",
    )]);
    let scene = load_str(
        &format!("{CAMERA}- add: light\n  at: [-5, 5, -5]\n  intensity: [1, 1, 1]\n- add: obj\n  file: flat.obj\n"),
        &dir.path().join("s.yml"),
    )
    .unwrap();
    let (canvas, _) = render(&scene.camera, &scene.world, &RenderOptions::default());
    assert!(canvas
        .pixels()
        .iter()
        .all(|c| c.to_array().iter().all(|v| v.is_finite())));
}

/// An image whose header claims 10000 × 10000 pixels is refused before any pixel memory is
/// taken.
#[test]
fn an_image_claiming_too_many_pixels_is_refused_before_decoding() {
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend_from_slice(&10_000u32.to_be_bytes());
    ihdr.extend_from_slice(&10_000u32.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for chunk in [&ihdr[..], b"IDAT\x78\x01\x03\x00\x00\x00\x00\x01", b"IEND"] {
        png.extend_from_slice(&(chunk.len() as u32 - 4).to_be_bytes());
        png.extend_from_slice(chunk);
        png.extend_from_slice(&crc32(chunk).to_be_bytes());
    }
    let e = rayforge_scene::texture_from_bytes(&png, Path::new("huge.png")).unwrap_err();
    assert!(e.message.contains("10000×10000"), "{e}");
    assert!(e.message.contains("67108864 pixels"), "{e}");
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// The scene's images together are held to a memory limit (an image used twice counts once):
/// each keeps 24 bytes a pixel, and the one being read also takes its file and the decoder's
/// output, so the second image is refused before it is decoded.
#[test]
fn the_images_of_a_scene_are_held_to_a_memory_limit() {
    let ppm = b"P3\n2 2\n255\n255 0 0  0 255 0\n0 0 255  255 255 255\n";
    let dir = dir_with(&[("a.ppm", ppm), ("b.ppm", ppm)]);
    let image = |file: &str| {
        format!("- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: spherical\n      uv_pattern: {{type: image, file: {file}}}\n")
    };
    let path = dir.path().join("s.yml");
    // One image: the file, 4 × 3 bytes of decoder output, 4 colours of 24 bytes kept.
    let kept = 4 * 24;
    let reading = ppm.len() as u64 + 4 * 3 + kept;
    let options = LoadOptions {
        max_image_memory: kept + reading - 1,
        ..LoadOptions::default()
    };
    let twice = format!("{CAMERA}{}{}", image("a.ppm"), image("a.ppm"));
    std::fs::write(&path, twice).unwrap();
    assert!(load_file_with(&path, &options).is_ok());
    let two = format!("{CAMERA}{}{}", image("a.ppm"), image("b.ppm"));
    std::fs::write(&path, two).unwrap();
    let e = load_file_with(&path, &options).unwrap_err();
    assert!(e.message.contains(&format!("takes {reading} bytes")), "{e}");
    assert!(
        e.message
            .contains(&format!("other images hold {kept} bytes")),
        "{e}"
    );
    assert!(e.message.contains("max_image_memory"), "{e}");
    assert_eq!(e.key.as_deref(), Some("file"), "{e}");
    assert_eq!(e.span.map(|s| s.line), Some(19), "{e}");
}
