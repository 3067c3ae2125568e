//! Files built to take all memory while they are parsed, before any limit could refuse what
//! they build (issue 44, findings 1 and 2): each is refused, and the most memory the reader
//! held meanwhile is measured by counting the bytes the allocator hands out. A test binary of
//! its own, and one test in it, so that no other test's allocations count.
use rayforge_scene::{load_file, load_str};
use std::path::Path;

mod counting;
use counting::peak_of;

const MB: usize = 1 << 20;

#[test]
fn files_built_to_exhaust_memory_are_refused_in_bounded_memory() {
    // A glTF sparse accessor with no data and 2^40 elements: its reader asked for 13 TB.
    let dir = tempfile::tempdir().unwrap();
    let bomb = dir.path().join("bomb.gltf");
    std::fs::write(
        &bomb,
        r#"{"asset":{"version":"2.0"},
        "buffers":[{"byteLength":16,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAAAAAA=="}],
        "bufferViews":[{"buffer":0,"byteLength":12},{"buffer":0,"byteOffset":12,"byteLength":4}],
        "accessors":[{"componentType":5126,"count":1099511627776,"type":"VEC3","min":[0,0,0],"max":[1,1,1],
          "sparse":{"count":1,"indices":{"bufferView":1,"componentType":5125},"values":{"bufferView":0}}}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
        "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]}"#,
    )
    .unwrap();
    let (e, peak, _) = peak_of(|| load_file(&bomb).unwrap_err());
    assert!(e.message.contains("more than the 30000000"), "{e}");
    eprintln!("sparse bomb: refused holding at most {} MB", peak / MB);
    assert!(peak < 16 * MB, "the sparse bomb held {} MB", peak / MB);

    // A PLY header claiming 2^40 vertices, with no limit on triangles: refused from the file's
    // size, before anything is allocated for them.
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 1099511627776\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let (e, peak, _) = peak_of(|| {
        rayforge_scene::ply::parse_ply(header.as_bytes(), Path::new("bomb.ply"), usize::MAX)
            .unwrap_err()
    });
    assert!(
        e.message.contains("need at least 13194139533312 bytes"),
        "{e}"
    );
    assert!(peak < MB, "the PLY header held {} MB", peak / MB);

    // A 60 MB line of transforms in one item: its tree held 2.3 GB before the parts budget.
    let entry = "[translate, 1, 2, 3], ";
    let mut text = String::from("- add: sphere\n  transform: [");
    text.push_str(&entry.repeat(60 * MB / entry.len()));
    text.push_str("]\n");
    let (e, peak, _) = peak_of(|| load_str(&text, Path::new("line.yml")).unwrap_err());
    assert!(
        e.message
            .contains("an item holds more than 1000000 YAML values"),
        "{e}"
    );
    assert_eq!(e.span.map(|s| s.line), Some(2), "{e}");
    eprintln!(
        "60 MB of transforms: refused holding at most {} MB",
        peak / MB
    );
    assert!(
        peak < 400 * MB,
        "the line of transforms held {} MB",
        peak / MB
    );
    drop(text);

    // Exponential aliases (each list ten of the one before): a file read whole.
    let mut text = String::from("- define: a0\n  value: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n");
    for i in 1..9 {
        let j = i - 1;
        text.push_str(&format!(
            "- define: a{i}\n  value: &a{i} [*a{j}, *a{j}, *a{j}, *a{j}, *a{j}, *a{j}, *a{j}, *a{j}, *a{j}, *a{j}]\n"
        ));
    }
    let (e, peak, _) = peak_of(|| load_str(&text, Path::new("laughs.yml")).unwrap_err());
    assert!(
        e.message
            .contains("the file holds more than 4000000 YAML values"),
        "{e}"
    );
    eprintln!(
        "exponential aliases: refused holding at most {} MB",
        peak / MB
    );
    assert!(peak < 16 * MB, "the aliases held {} MB", peak / MB);
}
