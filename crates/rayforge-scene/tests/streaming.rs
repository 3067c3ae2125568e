//! The reader takes a file's items one at a time (the `document` module): what it reads is
//! the same as from the whole tree (a file with an alias is still read whole), and its errors
//! are located as before. Its memory is measured in `streaming_memory.rs`.
use rayforge_scene::load_str;
use std::path::Path;

mod common;
use common::{many_items, CAMERA};

#[test]
fn items_read_one_at_a_time_are_the_same_as_items_read_from_the_whole_tree() {
    let streamed = many_items(50);
    // An alias anywhere (here in a comment's `*`) makes the reader build the whole tree.
    let whole = format!("{streamed}# *\n");
    let a = load_str(&streamed, Path::new("a.yml")).expect("streamed");
    let b = load_str(&whole, Path::new("b.yml")).expect("whole");
    assert_eq!(a.world, b.world);
    assert_eq!(a.camera, b.camera);
}

#[test]
fn an_alias_may_name_an_anchor_in_an_earlier_item() {
    let text = format!(
        "{CAMERA}- add: sphere\n  material: &red\n    color: [1, 0, 0]\n\
         - add: cube\n  material: *red\n"
    );
    let scene = load_str(&text, Path::new("alias.yml")).expect("the alias resolves");
    let [sphere, cube] = &scene.world.objects[..] else {
        panic!("two objects");
    };
    assert_eq!(sphere.material, cube.material);
    assert_eq!(cube.material.color, rayforge::color::color(1.0, 0.0, 0.0));
}

#[test]
fn a_key_given_twice_in_a_later_item_is_located() {
    let text = format!("{CAMERA}- add: sphere\n- add: cube\n  shadow: false\n  shadow: true\n");
    let e = load_str(&text, Path::new("twice.yml")).unwrap_err();
    assert!(e.message.contains("duplicated key"), "{e}");
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((11, 3)), "{e}");
}

#[test]
fn a_syntax_error_late_in_the_file_is_located() {
    let text = format!(
        "{}- add: cube\n  material: {{color: [1, 0, 0}}\n",
        many_items(3)
    );
    let line = text.lines().count();
    let e = load_str(&text, Path::new("late.yml")).unwrap_err();
    assert!(e.message.starts_with("not valid YAML"), "{e}");
    assert_eq!(e.span.map(|s| s.line), Some(line), "{e}");
}

#[test]
fn a_second_document_that_nests_too_deeply_is_refused_before_it_is_built() {
    let text = format!("{CAMERA}---\n{}1\n", "- ".repeat(100_000));
    let e = load_str(&text, Path::new("deep.yml")).unwrap_err();
    assert!(e.message.contains("nest deeper than 128 levels"), "{e}");
    let e = load_str(&format!("{CAMERA}---\n- 1\n"), Path::new("two.yml")).unwrap_err();
    assert!(e.message.contains("more than one YAML document"), "{e}");
    // An empty second document is nothing to refuse.
    load_str(&format!("{CAMERA}---\n"), Path::new("empty.yml")).expect("loads");
}
