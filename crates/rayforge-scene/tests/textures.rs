//! Texture maps in scene files: `type: map` with UV patterns, cube maps and image files.
use rayforge::color::color;
use rayforge::shading::{Filter, UvMapping, UvPattern};
use rayforge::{point, PatternKind};
use std::path::Path;

const CAMERA: &str = "- add: camera\n  width: 8\n  height: 8\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n";

fn pattern_of(scene: &rayforge_scene::Scene) -> &rayforge::Pattern {
    scene.world.objects[0]
        .material
        .pattern
        .as_ref()
        .expect("a pattern")
}

#[test]
fn a_spherical_map_of_uv_checkers() {
    let scene = rayforge_scene::load_str(
        &format!(
            "{CAMERA}- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: spherical\n      uv_pattern:\n        type: checkers\n        width: 16\n        height: 8\n        colors: [[0, 0, 0], [1, 1, 1]]\n"
        ),
        Path::new("scene.yml"),
    )
    .unwrap();
    let p = pattern_of(&scene);
    let PatternKind::Map { mapping, uv } = &p.kind else {
        panic!("a map, got {:?}", p.kind);
    };
    assert_eq!(*mapping, UvMapping::Spherical);
    assert!(
        matches!(uv, UvPattern::Checkers { width, height, .. } if *width == 16.0 && *height == 8.0)
    );
    // The bonus chapter's first sample point lands on a white square.
    assert_eq!(
        p.pattern_at(point(0.4315, 0.4670, 0.7719)),
        color(1.0, 1.0, 1.0)
    );
}

#[test]
fn a_cube_map_of_align_checks_and_an_image() {
    let dir = tempfile::tempdir().unwrap();
    // A 2×2 PPM: red, green / blue, white.
    std::fs::write(
        dir.path().join("tile.ppm"),
        "P3\n2 2\n255\n255 0 0  0 255 0\n0 0 255  255 255 255\n",
    )
    .unwrap();
    let check = |c: &str| {
        format!("\n        type: align_check\n        colors:\n          main: {c}\n          ul: [1, 0, 0]\n          ur: [1, 1, 0]\n          bl: [0, 1, 0]\n          br: [0, 1, 1]")
    };
    let faces: String = ["left", "front", "right", "back", "up"]
        .iter()
        .map(|f| format!("      {f}:{}\n", check("[1, 1, 1]")))
        .collect();
    let scene_text = format!(
        "{CAMERA}- add: cube\n  material:\n    pattern:\n      type: map\n      mapping: cube\n{faces}      down:\n        type: image\n        file: tile.ppm\n        filter: nearest\n"
    );
    let scene_path = dir.path().join("scene.yml");
    std::fs::write(&scene_path, scene_text).unwrap();
    let scene = rayforge_scene::load_file(&scene_path).unwrap();
    let p = pattern_of(&scene);
    let PatternKind::CubeMap(faces) = &p.kind else {
        panic!("a cube map");
    };
    let UvPattern::Image(texture) = &faces[5] else {
        panic!("an image on the bottom face");
    };
    assert_eq!(texture.filter, Filter::Nearest);
    // The bottom face: u along +x, v along +z; (0, 0) is the image's bottom-left (blue).
    assert_eq!(p.pattern_at(point(-0.9, -1.0, -0.9)), color(0.0, 0.0, 1.0));
    assert_eq!(p.pattern_at(point(0.9, -1.0, 0.9)), color(0.0, 1.0, 0.0));
    // The front face's upper-left marker.
    assert_eq!(p.pattern_at(point(-0.9, 0.9, 1.0)), color(1.0, 0.0, 0.0));
}

#[test]
fn a_missing_image_is_reported_at_its_file_key() {
    let e = rayforge_scene::load_str(
        &format!("{CAMERA}- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: planar\n      uv_pattern:\n        type: image\n        file: nowhere.png\n"),
        Path::new("/tmp/scene.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("file"));
    assert_eq!(e.span.unwrap().line, 15);
    assert!(e.message.contains("nowhere.png"), "{e}");
}

#[test]
fn an_unknown_mapping_is_refused() {
    let e = rayforge_scene::load_str(
        &format!("{CAMERA}- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: conical\n      uv_pattern: {{type: checkers, width: 2, height: 2, colors: [[0, 0, 0], [1, 1, 1]]}}\n"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert!(e.message.contains("unknown mapping `conical`"), "{e}");
}

#[test]
fn a_corrupt_image_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let scene_path = dir.path().join("scene.yml");
    std::fs::write(
        &scene_path,
        format!("{CAMERA}- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: spherical\n      uv_pattern: {{type: image, file: bad.png}}\n"),
    )
    .unwrap();
    let e = rayforge_scene::load_file(&scene_path).unwrap_err();
    assert!(e.message.contains("cannot read the image"), "{e}");
}

/// A 2×2 colour PFM (rows bottom first, little-endian): bottom row `bottom`, top row `top`.
fn pfm(bottom: [[f32; 3]; 2], top: [[f32; 3]; 2]) -> Vec<u8> {
    let mut bytes = b"PF\n2 2\n-1.0\n".to_vec();
    for texel in bottom.iter().chain(&top) {
        for v in texel {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

/// The same image as OpenEXR (32-bit float R, G, B), rows top first.
fn exr(bottom: [[f32; 3]; 2], top: [[f32; 3]; 2]) -> Vec<u8> {
    use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};
    let rows = [top, bottom];
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let [r, g, b] = rows[y][x];
        (r, g, b)
    });
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_channels((2, 2), channels)
        .write()
        .to_buffered(&mut bytes)
        .unwrap();
    bytes.into_inner()
}

#[test]
fn hdr_images_are_textures_with_their_linear_values_beyond_one() {
    let dir = tempfile::tempdir().unwrap();
    let (bottom, top) = (
        [[4.0, 0.5, 0.0], [0.0, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.25, 2.5, 16.0]],
    );
    std::fs::write(dir.path().join("sky.pfm"), pfm(bottom, top)).unwrap();
    std::fs::write(dir.path().join("sky.exr"), exr(bottom, top)).unwrap();
    for file in ["sky.pfm", "sky.exr"] {
        let scene_path = dir.path().join("scene.yml");
        std::fs::write(
            &scene_path,
            format!("{CAMERA}- add: plane\n  material:\n    pattern:\n      type: map\n      mapping: planar\n      uv_pattern:\n        type: image\n        file: {file}\n        filter: nearest\n"),
        )
        .unwrap();
        let scene = rayforge_scene::load_file(&scene_path).unwrap();
        let p = pattern_of(&scene);
        // Planar: u = x, v = z (fractional parts); (0, 0) the image's bottom-left.
        assert_eq!(
            p.pattern_at(point(0.25, 0.0, 0.25)),
            color(4.0, 0.5, 0.0),
            "{file}"
        );
        assert_eq!(
            p.pattern_at(point(0.75, 0.0, 0.75)),
            color(0.25, 2.5, 16.0),
            "{file}"
        );
    }
    // A damaged HDR texture is an error naming it.
    std::fs::write(dir.path().join("bad.pfm"), b"PF\n2 2\n-1.0\n\x00\x00").unwrap();
    let scene_path = dir.path().join("bad.yml");
    std::fs::write(
        &scene_path,
        format!("{CAMERA}- add: plane\n  material:\n    pattern:\n      type: map\n      mapping: planar\n      uv_pattern:\n        type: image\n        file: bad.pfm\n"),
    )
    .unwrap();
    let e = rayforge_scene::load_file(&scene_path).unwrap_err();
    assert!(e.message.contains("bad.pfm"), "{e}");
    assert_eq!(e.key.as_deref(), Some("file"));
}
