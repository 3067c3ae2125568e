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
    assert!(e.message.contains("sphere, plane, rectangle, cube"), "{e}");
}

#[test]
fn a_light_inside_a_group_is_not_a_shape() {
    let e = error("- add: group\n  children:\n    - add: light\n      at: [0, 0, 0]\n");
    assert_error(&e, 10, 12, Some("add"), "a light cannot be");
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
fn a_zero_height() {
    let e = load_str(
        &CAMERA.replace("height: 10", "height: 0"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_error(&e, 3, 11, Some("height"), "at least 1, found 0");
}

#[test]
fn a_field_of_view_out_of_range() {
    for fov in ["90", "0", "-1", "3.14159266"] {
        let e = load_str(
            &CAMERA.replace("field-of-view: 1", &format!("field-of-view: {fov}")),
            Path::new("scene.yml"),
        )
        .unwrap_err();
        assert_error(&e, 4, 18, Some("field-of-view"), "between 0 and π");
    }
}

#[test]
fn a_camera_looking_at_its_own_position() {
    let e = load_str(
        &CAMERA.replace("to: [0, 0, 0]", "to: [0, 0, -5]"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_error(&e, 6, 7, Some("to"), "looks at its own position");
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
    // Found where `b` extends `a` again.
    assert_error(&e, 13, 11, Some("extend"), "define cycle: a → b → a");
}

#[test]
fn only_mappings_extend() {
    let e = error("- define: a\n  value: [[scale, 2, 2, 2]]\n- define: b\n  extend: a\n  value: [[translate, 1, 0, 0]]\n");
    assert_error(&e, 11, 3, Some("extend"), "its `value:` must be a mapping");
}

#[test]
fn a_transform_define_that_references_itself_is_a_cycle() {
    let e =
        error("- define: loop\n  value:\n    - loop\n- add: sphere\n  transform:\n    - loop\n");
    assert_error(&e, 10, 7, Some("transform"), "define cycle: loop → loop");
}

/// Regression: a defined object naming itself (directly or through another) overflowed the stack.
#[test]
fn an_object_define_that_instantiates_itself_is_a_cycle() {
    let e = error("- define: a\n  value: {add: b}\n- define: b\n  value: {add: a}\n- add: a\n");
    assert_error(&e, 11, 16, Some("add"), "define cycle: a → b → a");
}

/// Regression: a group template among its own children recursed until the stack overflowed.
#[test]
fn a_group_define_among_its_own_children_is_a_cycle() {
    let e = error("- define: g\n  value: {add: group, children: [{add: g}]}\n- add: g\n");
    assert_error(&e, 9, 40, Some("add"), "define cycle: g → g");
}

#[test]
fn a_csg_define_that_is_its_own_operand_is_a_cycle() {
    let e = error(
        "- define: c\n  value: {add: csg, operation: union, left: c, right: {type: cube}}\n- add: c\n",
    );
    assert_error(&e, 9, 45, Some("left"), "define cycle: c → c");
}

/// Regression: a pattern define that contains itself overflowed the stack.
#[test]
fn a_pattern_define_that_contains_itself_is_a_cycle() {
    let e = error(
        "- define: p\n  value: {type: perturbed, pattern: p}\n- add: sphere\n  material: {pattern: p}\n",
    );
    assert_error(&e, 9, 37, Some("pattern"), "define cycle: p → p");
    let e = error(
        "- define: p\n  value: {type: stripes, colors: [[1, 1, 1], p]}\n- add: sphere\n  material: {pattern: p}\n",
    );
    assert_error(&e, 9, 46, Some("pattern"), "define cycle: p → p");
}

/// Thirty defines that each use the one before twice would build 2³⁰ parts: refused, quickly.
#[test]
fn defines_that_expand_exponentially_are_refused() {
    let mut body = String::from("- define: t0\n  value: [[translate, 1, 0, 0]]\n");
    for i in 1..30 {
        body += &format!("- define: t{i}\n  value: [t{}, t{}]\n", i - 1, i - 1);
    }
    body += "- add: sphere\n  transform: [t29]\n";
    let e = error(&body);
    assert!(e.message.contains("more than 1000000 parts"), "{e}");
    assert_eq!(e.key.as_deref(), Some("transform"), "{e}");
    assert!(e.span.is_some(), "{e}");
}

/// Regression: a few hundred thousand `- ` overflowed saphyr's recursive tree builder.
#[test]
fn yaml_that_nests_too_deeply_is_refused_before_it_is_built() {
    let e = error(&format!("{}1\n", "- ".repeat(200_000)));
    assert_error(&e, 8, 257, None, "nest deeper than 128 levels");
    // Aliases count as deep as what they name.
    let mut text = format!("a0: &a0 {}1{}\n", "[".repeat(100), "]".repeat(100));
    for i in 1..10 {
        text += &format!("a{i}: &a{i} [[[[[[[[[[*a{}]]]]]]]]]]\n", i - 1);
    }
    let e = load_str(&text, Path::new("scene.yml")).unwrap_err();
    assert!(e.message.contains("nest deeper than 128 levels"), "{e}");
}

#[test]
fn groups_nested_through_defines_are_refused_without_overflowing() {
    let mut body = String::from("- define: g0\n  value: {add: sphere}\n");
    for i in 1..20 {
        let open = "{add: group, children: [".repeat(8);
        let close = "]}".repeat(8);
        body += &format!(
            "- define: g{i}\n  value: {open}{{add: g{}}}{close}\n",
            i - 1
        );
    }
    body += "- add: g19\n";
    let e = error(&body);
    assert!(e.message.contains("nest deeper than 100 levels"), "{e}");
}

#[test]
fn a_scene_without_a_camera() {
    let e = load_str("- add: sphere\n", Path::new("scene.yml")).unwrap_err();
    assert_eq!((e.span, e.key.as_deref()), (None, None), "{e}");
    assert_eq!(
        e.to_string(),
        "scene.yml: the scene has no camera: add an item `- add: camera`"
    );
}

#[test]
fn a_second_camera() {
    let e = error(CAMERA);
    assert_error(&e, 8, 8, Some("add"), "a second camera");
}

#[test]
fn a_second_yaml_document() {
    let e = error("---\n- add: sphere\n");
    assert_error(&e, 9, 1, None, "more than one YAML document");
}

#[test]
fn a_file_that_is_not_yaml_reports_the_parsers_position() {
    let e = load_str("- add: sphere\n  material: [1, 2\n", Path::new("scene.yml")).unwrap_err();
    assert_error(
        &e,
        3,
        1,
        None,
        "not valid YAML: while parsing a flow sequence, expected ',' or ']'",
    );
    // At the tab itself (saphyr marks where the scalar before it began).
    let e = load_str("- add: sphere\n\tmaterial: x\n", Path::new("scene.yml")).unwrap_err();
    assert_error(&e, 2, 1, None, "not valid YAML");
}

#[test]
fn a_top_level_that_is_not_a_list() {
    let e = load_str("\nadd: sphere\n", Path::new("scene.yml")).unwrap_err();
    assert_error(&e, 2, 1, None, "top level must be a list");
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
    assert_eq!((e.span, e.key.as_deref()), (None, None), "{e}");
}

#[test]
fn an_item_without_add_or_define() {
    let e = error("- sphere: yes\n");
    assert!(e.message.contains("`add:`, `define:` or `world:`"), "{e}");
}

#[test]
fn a_second_world_item_is_an_error() {
    let e = error("- world: {lighting: cgfs}\n- world: {background: [1, 1, 1]}\n");
    assert_error(&e, 9, 3, Some("world"), "a second `world:` item");
}

#[test]
fn an_unknown_lighting_model_is_named() {
    let e = error("- world:\n    lighting: pbr\n");
    assert_error(
        &e,
        9,
        15,
        Some("lighting"),
        "expected phong, flat, cgfs or optics",
    );
}

#[test]
fn an_unknown_light_type_is_named() {
    let e = error("- add: light\n  type: laser\n  intensity: 1\n");
    assert_error(&e, 9, 9, Some("type"), "unknown light type `laser`");
}

#[test]
fn a_directional_light_needs_its_direction() {
    let e = error("- add: light\n  type: directional\n  intensity: 0.2\n");
    assert!(e.message.contains("needs `towards:`"), "{e}");
    let e = error("- add: light\n  type: directional\n  intensity: 0.2\n  towards: [0, 0, 0]\n");
    assert_error(&e, 11, 12, Some("towards"), "zero");
}

#[test]
fn a_viewport_camera_checks_its_sizes_and_rotation() {
    let camera = |extra: &str| {
        rayforge_scene::load_str(
            &format!("- add: camera\n  width: 10\n  height: 10\n{extra}"),
            std::path::Path::new("scene.yml"),
        )
        .expect_err("rejected")
    };
    let e = camera("  viewport: [1, 0]\n");
    assert_eq!(e.key.as_deref(), Some("viewport"), "{e}");
    let e = camera("  viewport: [1, 1]\n  rotation: [[0, 0, 0], [0, 1, 0], [0, 0, 1]]\n");
    assert!(e.message.contains("cannot be inverted"), "{e}");
    let e = camera("  viewport: [1, 1]\n  position: [0, 0, 0]\n  from: [0, 0, 0]\n");
    assert!(e.message.contains("not both"), "{e}");
}

#[test]
fn a_pattern_of_an_unknown_type() {
    let e = error("- add: plane\n  material:\n    pattern:\n      type: plaid\n      colors: [[1, 1, 1], [0, 0, 0]]\n");
    assert_error(&e, 11, 13, Some("type"), "unknown pattern type `plaid`");
}

#[test]
fn a_nested_pattern_type_says_how_nesting_is_written() {
    let e = error("- add: plane\n  material:\n    pattern:\n      type: nested\n      colors: [[1, 1, 1], [0, 0, 0]]\n");
    assert_error(
        &e,
        11,
        13,
        Some("type"),
        "in place of a colour in `colors:`",
    );
}

#[test]
fn a_gradient_with_three_colors() {
    let e = error("- add: plane\n  material:\n    pattern:\n      type: gradient\n      colors: [[1, 1, 1], [0, 0, 0], [1, 0, 0]]\n");
    assert!(e.message.contains("exactly 2 colors"), "{e}");
}

#[test]
fn deeply_nested_patterns_are_refused_with_a_location_not_an_overflow() {
    // `levels` perturbed patterns around a stripes pattern, on the plane of line 10.
    let nested = |levels: usize| {
        let mut pattern = String::from("{type: stripes, colors: [[1, 1, 1], [0, 0, 0]]}");
        for _ in 0..levels {
            pattern = format!("{{type: perturbed, pattern: {pattern}}}");
        }
        format!("{CAMERA}- add: plane\n  material:\n    pattern: {pattern}\n")
    };
    // Within the pattern reader's limit of 64 levels: read, every level kept.
    let scene = load_str(&nested(60), Path::new("scene.yml")).expect("60 levels are read");
    assert_eq!(scene.world.objects.len(), 1);
    // Past it, yet within the YAML reader's 128: the pattern reader refuses the level.
    let e = load_str(&nested(70), Path::new("scene.yml")).expect_err("70 levels are refused");
    assert!(
        e.message.contains("patterns nest deeper than 64 levels"),
        "{e}"
    );
    assert_eq!(e.span.map(|s| s.line), Some(10), "{e}");
    // 200 levels: refused by the YAML reader before any recursion could overflow the stack.
    let e = load_str(&nested(200), Path::new("scene.yml")).expect_err("200 levels are refused");
    assert!(e.message.contains("nest deeper than 128 levels"), "{e}");
    assert_eq!(e.span.map(|s| s.line), Some(10), "{e}");
}

#[test]
fn a_canvas_point_needs_two_or_three_numbers() {
    let e = error("- add: canvas-line\n  from: [1, 2, 3, 4]\n  to: [0, 0]\n");
    assert_error(
        &e,
        9,
        9,
        Some("from"),
        "expected [x, y] on the canvas or [x, y, z]",
    );
}

#[test]
fn a_canvas_point_to_project_must_lie_in_front_of_the_eye() {
    let e = error("- add: canvas-line\n  from: [1, 2, -3]\n  to: [0, 0, 1]\n");
    assert_error(&e, 9, 16, Some("from"), "in front of the eye (z > 0)");
}

#[test]
fn a_canvas_line_needs_both_ends() {
    let e = error("- add: canvas-line\n  from: [1, 2]\n");
    assert_error(&e, 8, 3, Some("to"), "a canvas line needs `to:`");
}

#[test]
fn a_canvas_triangle_has_three_corners() {
    let e = error("- add: canvas-triangle\n  points: [[0, 0], [1, 1]]\n");
    assert_error(&e, 9, 11, Some("points"), "3 corners, found 2");
}

#[test]
fn a_shaded_canvas_triangle_needs_its_intensities() {
    let e = error("- add: canvas-triangle\n  points: [[0, 0], [1, 1], [0, 1]]\n  style: shaded\n");
    assert_error(&e, 8, 3, Some("intensities"), "needs `intensities:`");
    let e = error(
        "- add: canvas-triangle\n  points: [[0, 0], [1, 1], [0, 1]]\n  style: shaded\n  intensities: [1, -0.5, 0]\n",
    );
    assert_error(&e, 11, 16, Some("intensities"), "cannot be negative");
}

#[test]
fn intensities_on_an_unshaded_canvas_triangle_are_refused() {
    let e = error(
        "- add: canvas-triangle\n  points: [[0, 0], [1, 1], [0, 1]]\n  intensities: [1, 1, 1]\n",
    );
    assert_error(&e, 10, 3, Some("intensities"), "add `style: shaded`");
}

#[test]
fn an_unknown_canvas_triangle_style_names_the_styles() {
    let e = error("- add: canvas-triangle\n  points: [[0, 0], [1, 1], [0, 1]]\n  style: dotted\n");
    assert_error(
        &e,
        10,
        10,
        Some("style"),
        "expected wireframe, filled or shaded",
    );
}

#[test]
fn a_canvas_item_cannot_be_a_groups_child() {
    let e = error(
        "- add: group\n  children:\n    - add: canvas-line\n      from: [0, 0]\n      to: [1, 1]\n",
    );
    assert_error(&e, 10, 12, Some("add"), "a canvas-line cannot be");
}

#[test]
fn an_array_without_of_or_count_or_with_a_bad_count_is_located() {
    let e = error("- add: array\n  count: 3\n");
    assert_error(&e, 8, 8, Some("of"), "needs `of:`");
    let e = error("- add: array\n  of:\n    add: sphere\n");
    assert_error(&e, 8, 8, Some("count"), "needs `count:`");
    let e = error("- add: array\n  of:\n    add: sphere\n  count: [2, 0, 1]\n");
    assert_error(&e, 11, 14, Some("count"), "at least 1");
    let e = error("- add: array\n  of:\n    add: sphere\n  count: [2, 2]\n");
    assert_error(&e, 11, 10, Some("count"), "one whole number or three");
    let e = error("- add: array\n  of:\n    add: sphere\n  count: 2\n  colors: []\n");
    assert_error(&e, 12, 11, Some("colors"), "at least one colour");
}

#[test]
fn an_array_larger_than_the_parts_budget_is_refused_before_it_is_built() {
    let e = error(
        "- add: array\n  of:\n    add: group\n    children: []\n  count: [4000, 4000, 4000]\n",
    );
    assert!(e.message.contains("more than 1000000 parts"), "{e}");
}
