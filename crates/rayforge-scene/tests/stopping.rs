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
