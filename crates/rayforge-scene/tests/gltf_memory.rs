//! A glTF file of a million nodes (issue 44, finding 2): refused at 2.0 GB, after its JSON
//! was parsed and an object built for each node. A file with more nodes than the hierarchy may
//! visit is now refused before its JSON is parsed, and the visits are counted before anything
//! is built. A test binary of its own, one test in it, so that no other test's allocations
//! count (see `counting`).
use rayforge_scene::load_file;

mod counting;
use counting::peak_of;

const MB: usize = 1 << 20;

/// A model whose nodes are `nodes` (JSON objects, joined) and whose scene lists `roots`; its
/// mesh 0 is one triangle.
fn model(nodes: impl Iterator<Item = String>, roots: impl Iterator<Item = usize>) -> String {
    let nodes: Vec<String> = nodes.collect();
    let roots: Vec<String> = roots.map(|i| i.to_string()).collect();
    format!(
        r#"{{"asset":{{"version":"2.0"}},
        "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "nodes":[{}],"scenes":[{{"nodes":[{}]}}]}}"#,
        nodes.join(","),
        roots.join(",")
    )
}

#[test]
fn a_million_nodes_are_refused_before_they_are_built() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nodes.gltf");
    // Below the limit, a file of 100,000 nodes, each placing the triangle, is read.
    let placing = |n| (0..n).map(|_| r#"{"mesh":0}"#.to_string());
    std::fs::write(&path, model(placing(100_000), 0..100_000)).unwrap();
    let (read, peak, _) = peak_of(|| load_file(&path).map(|s| s.world.objects.len()));
    assert_eq!(read.ok(), Some(100_000));
    eprintln!("100,000 nodes: read holding at most {} MB", peak / MB);

    // One more than the hierarchy may visit: refused before the JSON is parsed (the file is
    // 17 MB, which the reader holds).
    std::fs::write(&path, model(placing(1_000_001), 0..1_000_001)).unwrap();
    let (e, peak, _) = peak_of(|| load_file(&path).unwrap_err());
    assert!(
        e.message.contains("more than 1000000 nodes") && e.key.as_deref() == Some("nodes"),
        "{e}"
    );
    eprintln!("1,000,001 nodes: refused holding at most {} MB", peak / MB);
    assert!(peak < 64 * MB, "1,000,001 nodes held {} MB", peak / MB);

    // Few nodes visited a million times: node 0 holds the 1,000 others, each placing the
    // triangle, and the scene names node 0 a thousand times (1,001,000 visits). Refused
    // before an object is built (each is about 1.7 KB: a million were 1.7 GB).
    let children: Vec<String> = (1..=1000).map(|i| i.to_string()).collect();
    let parent = format!(r#"{{"children":[{}]}}"#, children.join(","));
    let nodes = std::iter::once(parent).chain(placing(1000));
    std::fs::write(&path, model(nodes, std::iter::repeat_n(0, 1000))).unwrap();
    let (e, peak, _) = peak_of(|| load_file(&path).unwrap_err());
    assert!(e.message.contains("visits more than 1000000 nodes"), "{e}");
    eprintln!("shared nodes: refused holding at most {} MB", peak / MB);
    assert!(peak < 64 * MB, "the shared nodes held {} MB", peak / MB);
}
