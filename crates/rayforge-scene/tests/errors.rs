//! Bad scene files: each gets a located error naming the key, never a panic.
use rayforge_scene::{load_str, SceneError};
use std::path::Path;

const CAMERA: &str = "- add: camera
  width: 10
  height: 10
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

/// Loads `body` after a valid camera (7 lines), expecting an error.
fn error(body: &str) -> SceneError {
    load_str(&format!("{CAMERA}{body}"), Path::new("scene.yml"))
        .expect_err("the scene must be rejected")
}

#[track_caller]
fn assert_error(e: &SceneError, line: usize, column: usize, key: Option<&str>, words: &str) {
    let span = e.span.unwrap_or_else(|| panic!("no position in: {e}"));
    assert_eq!((span.line, span.column), (line, column), "{e}");
    assert_eq!(e.key.as_deref(), key, "{e}");
    assert!(e.message.contains(words), "{e}");
    assert!(
        e.to_string()
            .starts_with(&format!("scene.yml:{line}:{column}: ")),
        "{e}"
    );
}

#[test]
fn an_unknown_kind_is_named_with_the_kinds_there_are() {
    let e = error("- add: teapot\n");
    assert_error(&e, 8, 8, Some("add"), "unknown kind `teapot`");
    assert!(e.message.contains("sphere, plane, cube"), "{e}");
}

#[test]
fn an_unknown_key_lists_the_allowed_ones() {
    let e = error("- add: sphere\n  colour: [1, 0, 0]\n");
    assert_error(&e, 9, 3, Some("colour"), "unknown key for a sphere");
    assert!(e.message.contains("material, transform"), "{e}");
}

#[test]
fn an_unknown_material_key_is_located() {
    let e = error("- add: sphere\n  material:\n    shiny: 1\n");
    assert_error(&e, 10, 5, Some("shiny"), "unknown key for a material");
}

#[test]
fn a_reference_to_an_undefined_name() {
    let e = error("- add: sphere\n  material: glass\n");
    assert_error(&e, 9, 13, Some("material"), "`glass` is not defined");
}

#[test]
fn a_wrong_number_of_transform_arguments() {
    let e = error("- add: sphere\n  transform:\n    - [translate, 1, 2]\n");
    assert_error(&e, 10, 7, Some("translate"), "takes 3 numbers, found 2");
}

#[test]
fn an_unknown_transform() {
    let e = error("- add: sphere\n  transform:\n    - [twist, 1]\n");
    assert_error(&e, 10, 8, Some("transform"), "unknown transform `twist`");
}

#[test]
fn a_non_numeric_value() {
    let e = error("- add: sphere\n  material:\n    ambient: lots\n");
    assert_error(
        &e,
        10,
        14,
        Some("ambient"),
        "expected a number, found the text `lots`",
    );
}

#[test]
fn a_non_finite_number() {
    let e = error("- add: sphere\n  transform:\n    - [scale, .inf, 1, 1]\n");
    assert_error(&e, 10, 15, Some("scale"), "finite");
}

#[test]
fn a_singular_transform() {
    let e = error("- add: sphere\n  transform:\n    - [scale, 0, 1, 1]\n");
    assert_error(&e, 10, 5, Some("transform"), "singular");
}

#[test]
fn a_zero_width() {
    let e = load_str(
        &CAMERA.replace("width: 10", "width: 0"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_error(&e, 2, 10, Some("width"), "at least 1");
}

#[test]
fn a_field_of_view_out_of_range() {
    let e = load_str(
        &CAMERA.replace("field-of-view: 1", "field-of-view: 90"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_error(&e, 4, 18, Some("field-of-view"), "radians");
}

#[test]
fn up_parallel_to_the_view_direction() {
    let e = load_str(
        &CAMERA.replace("up: [0, 1, 0]", "up: [0, 0, 3]"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_error(&e, 7, 7, Some("up"), "parallel");
}

#[test]
fn a_define_that_extends_itself_is_a_cycle() {
    let e = error(
        "- define: a\n  extend: b\n  value:\n    ambient: 1\n- define: b\n  extend: a\n  value:\n    diffuse: 1\n- add: sphere\n  material: a\n",
    );
    assert!(e.message.contains("define cycle"), "{e}");
    assert!(e.message.contains("a → b → a"), "{e}");
}

#[test]
fn a_transform_define_that_references_itself_is_a_cycle() {
    let e =
        error("- define: loop\n  value:\n    - loop\n- add: sphere\n  transform:\n    - loop\n");
    assert!(e.message.contains("define cycle: loop → loop"), "{e}");
}

#[test]
fn a_scene_without_a_camera() {
    let e = load_str("- add: sphere\n", Path::new("scene.yml")).unwrap_err();
    assert!(e.message.contains("no camera"), "{e}");
}

#[test]
fn a_file_that_is_not_yaml_reports_the_parsers_position() {
    let e = load_str("- add: sphere\n  material: [1, 2\n", Path::new("scene.yml")).unwrap_err();
    assert!(e.message.contains("not valid YAML"), "{e}");
    assert!(e.span.is_some(), "{e}");
}

#[test]
fn a_top_level_that_is_not_a_list() {
    let e = load_str("add: sphere\n", Path::new("scene.yml")).unwrap_err();
    assert!(e.message.contains("top level must be a list"), "{e}");
}

#[test]
fn an_empty_file() {
    let e = load_str("", Path::new("scene.yml")).unwrap_err();
    assert!(e.message.contains("empty"), "{e}");
}

#[test]
fn a_binary_file() {
    let e = load_str("\u{0}\u{1}\u{2}PNG", Path::new("scene.yml")).unwrap_err();
    assert!(e.message.contains("binary"), "{e}");
}

#[test]
fn a_missing_file_names_the_path() {
    let e = rayforge_scene::load_file(Path::new("/no/such/scene.yml")).unwrap_err();
    assert!(e.to_string().starts_with("/no/such/scene.yml: "), "{e}");
    assert!(e.message.contains("cannot read"), "{e}");
}

#[test]
fn an_item_without_add_or_define() {
    let e = error("- sphere: yes\n");
    assert!(e.message.contains("`add:` or `define:`"), "{e}");
}

#[test]
fn a_pattern_of_an_unknown_type() {
    let e = error("- add: plane\n  material:\n    pattern:\n      type: plaid\n      colors: [[1, 1, 1], [0, 0, 0]]\n");
    assert_error(&e, 11, 13, Some("type"), "unknown pattern type `plaid`");
}

#[test]
fn a_gradient_with_three_colors() {
    let e = error("- add: plane\n  material:\n    pattern:\n      type: gradient\n      colors: [[1, 1, 1], [0, 0, 0], [1, 0, 0]]\n");
    assert!(e.message.contains("exactly 2 colors"), "{e}");
}

#[test]
fn deeply_nested_patterns_are_refused_or_read_without_overflow() {
    // 200 levels of perturbed patterns: must not overflow the stack.
    let mut pattern = String::from("{type: stripes, colors: [[1, 1, 1], [0, 0, 0]]}");
    for _ in 0..200 {
        pattern = format!("{{type: perturbed, pattern: {pattern}}}");
    }
    let scene = format!("{CAMERA}- add: plane\n  material:\n    pattern: {pattern}\n");
    let _ = load_str(&scene, Path::new("scene.yml"));
}
