//! glTF files that rendered a wrong image without a word (issue 44, finding 9) and the places
//! of glTF errors (finding 10): each is now a located error naming the JSON path. The models
//! are written here, their buffers inline as `data:` URIs.
use base64::Engine;
use rayforge_scene::{load_file, load_str, SceneError};
use std::path::Path;

/// A triangle's three positions as a buffer, then whatever `extra` bytes follow.
fn buffer(floats: &[f32], extra: &[u8]) -> String {
    let mut bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    bytes.extend_from_slice(extra);
    format!(
        "{{\"byteLength\":{},\"uri\":\"data:application/octet-stream;base64,{}\"}}",
        bytes.len(),
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    )
}

const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// A model of one triangle (accessor 0, 36 bytes of view 0) with `more` JSON members, its
/// node given `node` members too.
fn model(
    buffers: &str,
    views: &str,
    accessors: &str,
    attributes: &str,
    node: &str,
    more: &str,
) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{buffers}],"bufferViews":[{views}],
        "accessors":[{accessors}],
        "meshes":[{{"primitives":[{{"attributes":{{{attributes}}}}}]}}],
        "nodes":[{{"mesh":0{node}}}],"scenes":[{{"nodes":[0]}}]{more}}}"#
    )
}

const POSITIONS: &str =
    r#"{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}"#;

/// The error of loading `json` as `name` in a folder of its own.
fn refused(name: &str, json: &str) -> SceneError {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, json).unwrap();
    load_file(&path).expect_err("the model loaded")
}

fn key(e: &SceneError) -> &str {
    e.key.as_deref().unwrap_or_default()
}

/// A camera node beside the triangle's: `camera` is the camera's JSON, `node` the camera
/// node's extra members.
fn with_camera(camera: &str, node: &str) -> String {
    let json = model(
        &buffer(&TRIANGLE, &[]),
        r#"{"buffer":0,"byteLength":36}"#,
        POSITIONS,
        r#""POSITION":0"#,
        "",
        &format!(",\"cameras\":[{camera}]"),
    );
    json.replace(
        r#""scenes":[{"nodes":[0]}]"#,
        r#""scenes":[{"nodes":[0,1]}]"#,
    )
    .replace(
        r#""nodes":[{"mesh":0}]"#,
        &format!(r#""nodes":[{{"mesh":0}},{{"camera":0,"translation":[0,0,3]{node}}}]"#),
    )
}

#[test]
fn cameras_gltf_does_not_allow_are_refused_at_their_key() {
    let perspective =
        |inner: &str| format!(r#"{{"type":"perspective","perspective":{{{inner},"znear":0.1}}}}"#);
    let orthographic = |x: f32, y: f32| {
        format!(
            r#"{{"type":"orthographic","orthographic":{{"xmag":{x:?},"ymag":{y:?},"znear":0.1,"zfar":10}}}}"#
        )
    };
    for (camera, at) in [
        (perspective(r#""yfov":0"#), "cameras[0].perspective.yfov"),
        (perspective(r#""yfov":-1"#), "cameras[0].perspective.yfov"),
        (perspective(r#""yfov":4"#), "cameras[0].perspective.yfov"),
        (
            perspective(r#""yfov":0.8,"aspectRatio":0"#),
            "cameras[0].perspective.aspectRatio",
        ),
        (orthographic(1.0, 0.0), "cameras[0].orthographic.ymag"),
        (orthographic(1.0, -1.0), "cameras[0].orthographic.ymag"),
        (orthographic(0.0, 1.0), "cameras[0].orthographic.xmag"),
    ] {
        let e = refused("camera.gltf", &with_camera(&camera, ""));
        assert_eq!(key(&e), at, "{e}");
    }
    // A zero rotation quaternion: the camera (or whatever the node holds) has no orientation.
    let good = perspective(r#""yfov":0.8"#);
    let e = refused(
        "camera.gltf",
        &with_camera(&good, r#","rotation":[0,0,0,0]"#),
    );
    assert_eq!(key(&e), "nodes[1].rotation", "{e}");
    assert!(e.message.contains("not a unit quaternion"), "{e}");
    // And the same camera, placed properly, loads.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("camera.gltf");
    std::fs::write(&path, with_camera(&good, r#","rotation":[0,0,0,1]"#)).unwrap();
    load_file(&path).unwrap();
}

/// A POSITION accessor over the triangle whose sparse part replaces the vertices `indices`
/// (u16) with `values`.
fn sparse_triangle(indices: &[u16]) -> String {
    let mut extra: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    extra.resize(8, 0);
    let values: Vec<f32> = indices.iter().flat_map(|_| [0.5f32, 0.5, 0.5]).collect();
    extra.extend(values.iter().flat_map(|f| f.to_le_bytes()));
    let n = indices.len();
    model(
        &buffer(&TRIANGLE, &extra),
        &format!(
            r#"{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":{}}},
            {{"buffer":0,"byteOffset":44,"byteLength":{}}}"#,
            2 * n,
            12 * n
        ),
        &format!(
            r#"{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0.5],
            "sparse":{{"count":{n},"indices":{{"bufferView":1,"componentType":5123}},"values":{{"bufferView":2}}}}}}"#
        ),
        r#""POSITION":0"#,
        "",
        "",
    )
}

#[test]
fn sparse_indices_past_the_accessor_or_out_of_order_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sparse.gltf");
    std::fs::write(&path, sparse_triangle(&[1])).unwrap();
    load_file(&path).expect("a sparse index inside the accessor loads");
    let at = "meshes[0].primitives[0].attributes.POSITION.sparse";
    let e = refused("sparse.gltf", &sparse_triangle(&[5]));
    assert_eq!(key(&e), at, "{e}");
    assert!(
        e.message
            .contains("its index 0 is 5, past the accessor's 3 elements"),
        "{e}"
    );
    let e = refused("sparse.gltf", &sparse_triangle(&[2, 1]));
    assert_eq!(key(&e), at, "{e}");
    assert!(e.message.contains("not strictly increasing"), "{e}");
    let e = refused("sparse.gltf", &sparse_triangle(&[0, 1, 2, 2]));
    assert!(
        e.message
            .contains("replaces 4 of its elements, but it has 3"),
        "{e}"
    );
}

#[test]
fn a_sparse_accessor_with_no_data_and_a_huge_count_is_refused_by_its_count() {
    // 2^40 elements of nothing: read, they would take 13 TB.
    let json = model(
        &buffer(&[0.0; 3], &[0, 0, 0, 0]),
        r#"{"buffer":0,"byteLength":12},{"buffer":0,"byteOffset":12,"byteLength":4}"#,
        r#"{"componentType":5126,"count":1099511627776,"type":"VEC3","min":[0,0,0],"max":[1,1,1],
        "sparse":{"count":1,"indices":{"bufferView":1,"componentType":5125},"values":{"bufferView":0}}}"#,
        r#""POSITION":0"#,
        "",
        "",
    );
    let e = refused("bomb.gltf", &json);
    assert_eq!(
        key(&e),
        "meshes[0].primitives[0].attributes.POSITION",
        "{e}"
    );
    assert!(
        e.message
            .contains("has 1099511627776 elements, more than the 30000000"),
        "{e}"
    );
}

#[test]
fn normals_and_positions_that_are_not_numbers_are_refused() {
    let mut floats = TRIANGLE.to_vec();
    floats.extend([0.0, 0.0, 1.0, f32::NAN, 0.0, 1.0, 0.0, 0.0, 1.0]);
    let json = model(
        &buffer(&floats, &[]),
        r#"{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":36}"#,
        &format!(r#"{POSITIONS},{{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}}"#),
        r#""POSITION":0,"NORMAL":1"#,
        "",
        "",
    );
    let e = refused("nan.gltf", &json);
    assert_eq!(key(&e), "meshes[0].primitives[0].attributes.NORMAL", "{e}");
    assert!(e.message.contains("its element 1 is"), "{e}");
}

#[test]
fn a_gltf_error_through_add_gltf_is_placed_at_the_file_key_and_names_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let json = sparse_triangle(&[5]);
    std::fs::write(dir.path().join("bad.gltf"), json).unwrap();
    let scene = dir.path().join("scene.yml");
    let text = "- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: gltf\n  file: bad.gltf\n";
    let e = load_str(text, &scene).unwrap_err();
    assert_eq!(e.path, scene, "{e}");
    assert_eq!(e.key.as_deref(), Some("file"), "{e}");
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((9, 9)), "{e}");
    assert!(
        e.message
            .contains("bad.gltf`, at `meshes[0].primitives[0].attributes.POSITION.sparse`"),
        "{e}"
    );
    // A scene named without a folder: the folder is `.`, not an empty name.
    let e = load_str("- add: gltf\n  file: ../x.gltf\n", Path::new("scene.yml")).unwrap_err();
    assert!(
        e.message.contains("outside the scene's folder (`.`)"),
        "{e}"
    );
}
