//! A reading stopped by its flag (Ctrl-C, a termination signal, the page's cancel): each
//! reader looks at it once per unit of its work, so a flag already set when the reading
//! starts stops it at its first unit (nothing read after it), named by place, and the error
//! says it was interrupted, not that the file is at fault. The same files read whole with the
//! flag clear, so each test can fail.

use rayforge_scene::{LoadOptions, SceneError, StopFlag};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

fn options(set: bool) -> LoadOptions {
    LoadOptions {
        stop: StopFlag::new(Arc::new(AtomicBool::new(set))),
        ..LoadOptions::default()
    }
}

fn stopped(result: Result<rayforge_scene::Scene, SceneError>) -> SceneError {
    match result {
        Ok(_) => panic!("read whole with its stop flag set"),
        Err(e) => {
            assert!(e.interrupted, "not an interrupt: {e}");
            assert!(e.message.contains("interrupted"), "{e}");
            e
        }
    }
}

/// A thousand spheres after a camera: a YAML scene of many parts.
fn many_spheres() -> String {
    let mut text = String::from(
        "- add: camera\n  width: 8\n  height: 8\n  field-of-view: 1\n  from: [0, 0, -5]\n  \
         to: [0, 0, 0]\n  up: [0, 1, 0]\n",
    );
    for i in 0..1000 {
        text.push_str(&format!(
            "- add: sphere\n  transform: [[translate, {i}, 0, 0]]\n"
        ));
    }
    text
}

#[test]
fn a_yaml_scene_stops_at_its_first_item() {
    let text = many_spheres();
    let path = Path::new("many.yml");
    let whole = rayforge_scene::load_str_with(&text, path, &options(false)).unwrap();
    assert_eq!(whole.world.objects.len(), 1000);
    let e = stopped(rayforge_scene::load_str_with(&text, path, &options(true)));
    let span = e.span.expect("a place");
    assert_eq!(span.line, 1, "{e}");
    assert!(e.path.ends_with("many.yml"), "{e}");
}

#[test]
fn a_yaml_scene_read_whole_stops_at_its_first_part() {
    // An alias makes the reader build the file's tree whole, then its parts, each of which
    // spends from the budget: the first part built is where it stops.
    let text = format!(
        "- define: ball\n  value: &b {{ add: sphere }}\n{}- *b\n- *b\n",
        &many_spheres()[..]
    );
    let path = Path::new("aliased.yml");
    let whole = rayforge_scene::load_str_with(&text, path, &options(false)).unwrap();
    assert_eq!(whole.world.objects.len(), 1002);
    let e = stopped(rayforge_scene::load_str_with(&text, path, &options(true)));
    assert!(e.span.is_some(), "{e}");
}

#[test]
fn a_pbrt_scene_stops_at_its_first_directive() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    let mut text = String::from("Camera \"perspective\"\nWorldBegin\n");
    for i in 0..200 {
        text.push_str(&format!(
            "AttributeBegin\nTranslate {i} 0 5\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
        ));
    }
    std::fs::write(&path, &text).unwrap();
    let whole = rayforge_scene::load_file_with(&path, &options(false)).unwrap();
    assert_eq!(whole.world.objects.len(), 200);
    let e = stopped(rayforge_scene::load_file_with(&path, &options(true)));
    let span = e.span.expect("a place");
    assert_eq!((span.line, span.column), (1, 1), "{e}");
    assert_eq!(e.key.as_deref(), Some("Camera"), "{e}");
}

#[test]
fn a_gltf_model_stops_at_its_first_node() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nodes.gltf");
    let nodes = vec!["{}"; 100].join(",");
    let roots: Vec<String> = (0..100).map(|i| i.to_string()).collect();
    std::fs::write(
        &path,
        format!(
            "{{\"asset\":{{\"version\":\"2.0\"}},\"scene\":0,\"scenes\":[{{\"nodes\":[{}]}}],\
             \"nodes\":[{nodes}]}}",
            roots.join(",")
        ),
    )
    .unwrap();
    assert!(rayforge_scene::load_file_with(&path, &options(false)).is_ok());
    let e = stopped(rayforge_scene::load_file_with(&path, &options(true)));
    assert_eq!(e.key.as_deref(), Some("nodes[0]"), "{e}");
}

/// Options whose stop flag sets itself at the reader's `look`-th look at it: a stop partway
/// through a load, at a known unit, the same on every run.
fn stopped_at_look(look: u64) -> LoadOptions {
    LoadOptions {
        stop: StopFlag::set_at_look(look),
        ..LoadOptions::default()
    }
}

/// One directive's bracket of 299,997 numbers (a `trianglemesh`'s points, a point a line):
/// the reader looks at the flag every 65,536 values as well as before each directive, so a
/// stop set at the fourth look (after `Camera`, `WorldBegin` and `Shape`) is seen at the
/// 65,536th value, inside the bracket (it was seen only at the next directive).
#[test]
fn a_pbrt_bracket_of_numbers_stops_inside_itself() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mesh.pbrt");
    let mut text =
        String::from("Camera \"perspective\"\nWorldBegin\nShape \"trianglemesh\" \"point3 P\" [\n");
    for i in 0..99_999 {
        text.push_str(&format!("{i} {} 5\n", i % 2));
    }
    text.push_str("] \"integer indices\" [");
    for i in 0..99_999 {
        text.push_str(&format!(" {i}"));
    }
    text.push_str("]\n");
    std::fs::write(&path, &text).unwrap();
    let whole = rayforge_scene::load_file_with(&path, &options(false)).unwrap();
    assert_eq!(whole.world.objects.len(), 1);
    let e = stopped(rayforge_scene::load_file_with(&path, &stopped_at_look(4)));
    assert_eq!(e.key.as_deref(), Some("point3 P"), "{e}");
    // The 65,536th value is the first of the 21,846th point, on line 4 + 21,845.
    let span = e.span.expect("a place");
    assert_eq!((span.line, span.column), (21_849, 1), "{e}");
}

/// A glTF primitive of 196,608 vertices: its attributes are read with a look at the flag
/// every 65,536 elements, so a stop set past the node's and the primitive's looks is seen
/// inside the positions (the primitive was read whole, and the load went on).
#[test]
fn a_huge_gltf_primitive_stops_inside_its_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.gltf");
    let count = 196_608usize;
    let mut bin = Vec::with_capacity(count * 12);
    for i in 0..count {
        let (x, y) = ((i % 3) as f32, (i / 3) as f32 * 1e-3);
        for v in [x, y, 1.0f32] {
            bin.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(dir.path().join("big.bin"), &bin).unwrap();
    std::fs::write(
        &path,
        format!(
            "{{\"asset\":{{\"version\":\"2.0\"}},\"scene\":0,\"scenes\":[{{\"nodes\":[0]}}],\
             \"nodes\":[{{\"mesh\":0}}],\"meshes\":[{{\"primitives\":[{{\"attributes\":\
             {{\"POSITION\":0}}}}]}}],\"accessors\":[{{\"bufferView\":0,\"componentType\":5126,\
             \"count\":{count},\"type\":\"VEC3\",\"min\":[0,0,1],\"max\":[2,200,1]}}],\
             \"bufferViews\":[{{\"buffer\":0,\"byteLength\":{len}}}],\"buffers\":[{{\"uri\":\
             \"big.bin\",\"byteLength\":{len}}}]}}",
            len = bin.len()
        ),
    )
    .unwrap();
    let whole = rayforge_scene::load_file_with(&path, &options(false)).unwrap();
    assert_eq!(whole.world.objects.len(), 1);
    // Looks: the node, the primitive, the positions' first element and their 65,537th.
    let e = stopped(rayforge_scene::load_file_with(&path, &stopped_at_look(4)));
    assert_eq!(e.key.as_deref(), Some("meshes[0].primitives[0]"), "{e}");
}

/// A glTF file of 9 MiB of JSON (most of it white space) is parsed through a reader that
/// looks at the flag every mebibyte: a stop at the first look is seen inside the parse, the
/// error at the file (it was seen only at the first node, after the whole parse).
#[test]
fn a_large_gltf_json_stops_inside_its_parse() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wide.gltf");
    let text = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},{}\"scene\":0,\"scenes\":[{{\"nodes\":[0]}}],\
         \"nodes\":[{{}}]}}",
        " ".repeat(9 << 20)
    );
    std::fs::write(&path, &text).unwrap();
    assert!(rayforge_scene::load_file_with(&path, &options(false)).is_ok());
    let e = stopped(rayforge_scene::load_file_with(&path, &stopped_at_look(1)));
    assert_eq!(e.key, None, "{e}");
    assert!(e.path.ends_with("wide.gltf"), "{e}");
}

/// A gzip-compressed PLY model (through a pbrt `plymesh`) is inflated a mebibyte at a time
/// with a look at the flag before each: a stop at the second look inside the model is seen
/// inside the inflating (it was seen at the second vertex, after the whole file inflated).
#[test]
fn a_compressed_ply_model_stops_while_it_inflates() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let vertices = 200_000;
    let mut ply = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement face 1\nproperty list uchar int \
         vertex_indices\nend_header\n"
    )
    .into_bytes();
    for i in 0..vertices {
        for v in [(i % 3) as f32, (i / 3) as f32, 1.0f32] {
            ply.extend_from_slice(&v.to_le_bytes());
        }
    }
    ply.push(3);
    for i in [0i32, 1, 2] {
        ply.extend_from_slice(&i.to_le_bytes());
    }
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(&ply).unwrap();
    std::fs::write(dir.path().join("m.ply.gz"), gz.finish().unwrap()).unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(
        &path,
        "Camera \"perspective\"\nWorldBegin\nShape \"plymesh\" \"string filename\" \"m.ply.gz\"\n",
    )
    .unwrap();
    assert!(rayforge_scene::load_file_with(&path, &options(false)).is_ok());
    // Looks: `Camera`, `WorldBegin`, `Shape`, the shape's build, then the model's first
    // mebibyte and its second.
    let e = stopped(rayforge_scene::load_file_with(&path, &stopped_at_look(6)));
    assert_eq!(e.key, None, "{e}");
    assert!(e.path.ends_with("m.ply.gz"), "{e}");
}
