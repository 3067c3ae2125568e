//! Findings of the second round of hostile input, in the scene reader: each error names the
//! key the file has, at the place that is wrong, and says what is wrong; defined transform
//! lists cost what they compute; shares of light stay within 0 to 1.
use rayforge_scene::{load_str, SceneError};
use std::path::Path;
use std::time::Instant;

const CAMERA: &str = "- add: camera
  width: 10
  height: 10
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

fn error(text: &str) -> SceneError {
    load_str(text, Path::new("scene.yml")).expect_err("the scene must be rejected")
}

#[track_caller]
fn assert_at(e: &SceneError, line: usize, column: usize, key: Option<&str>, words: &str) {
    let span = e.span.unwrap_or_else(|| panic!("no position in: {e}"));
    assert_eq!((span.line, span.column), (line, column), "{e}");
    assert_eq!(e.key.as_deref(), key, "{e}");
    assert!(e.message.contains(words), "{e}");
}

#[test]
fn a_camera_looking_at_a_point_1e_12_away_is_blamed_on_to_not_up() {
    let e = error(&CAMERA.replace("to: [0, 0, 0]", "to: [0, 0, -4.999999999999]"));
    assert_at(&e, 6, 7, Some("to"), "looks at its own position");
    let e = error(&CAMERA.replace("up: [0, 1, 0]", "up: [0, 0, 2]"));
    assert_at(&e, 7, 7, Some("up"), "parallel");
    // Far from the origin, a short but real view direction is fine.
    let far = CAMERA
        .replace("from: [0, 0, -5]", "from: [0, 0, 1e-3]")
        .replace("to: [0, 0, 0]", "to: [0, 0, 2e-3]");
    load_str(&far, Path::new("scene.yml")).expect("a millimetre of sight is enough");
}

#[test]
fn a_disc_of_radius_zero_names_the_radius_it_has() {
    let e = error(&format!("{CAMERA}- add: disc\n  radius: 0\n"));
    assert_at(
        &e,
        9,
        11,
        Some("radius"),
        "the inner radius 0 must be smaller",
    );
    let e = error(&format!(
        "{CAMERA}- add: ring\n  inner-radius: 2\n  outer-radius: 1\n"
    ));
    assert_at(&e, 9, 17, Some("inner-radius"), "smaller than the outer 1");
}

#[test]
fn a_tab_is_reported_where_it_is() {
    let e = error("- add: sphere\n\t material: {}\n");
    assert_at(&e, 2, 1, None, "tab");
}

#[test]
fn a_scale_of_1e300_is_too_large_not_singular() {
    let e = error(&format!(
        "{CAMERA}- add: sphere\n  transform: [[scale, 1e300, 1e300, 1e300]]\n"
    ));
    assert!(e.message.contains("too large"), "{e}");
    assert!(!e.message.contains("singular"), "{e}");
    let e = error(&format!(
        "{CAMERA}- add: sphere\n  transform: [[scale, 0, 1, 1]]\n"
    ));
    assert!(e.message.contains("singular"), "{e}");
}

#[test]
fn a_defined_transform_list_used_many_times_is_bounded_by_the_parts_budget() {
    // 57 KB: a list of 2000 entries, used 1000 times by another, used 40 times: 80 million
    // matrix products, which took over a minute when each use counted as one part.
    let mut text = String::from(CAMERA);
    text.push_str("- define: t\n  value:\n");
    text.push_str(&"    - [translate, 0, 0, 0]\n".repeat(2000));
    text.push_str(&format!(
        "- define: u\n  value: [{}]\n",
        vec!["t"; 1000].join(", ")
    ));
    text.push_str(&"- add: sphere\n  transform: [u, u]\n".repeat(20));
    let started = Instant::now();
    let e = error(&text);
    assert!(e.message.contains("parts"), "{e}");
    assert!(e.message.contains("transform entries"), "{e}");
    assert_eq!(e.key.as_deref(), Some("transform"));
    assert!(started.elapsed().as_secs() < 30);
}

#[test]
fn shares_of_light_outside_0_to_1_are_refused_at_their_key() {
    for (material, key, column) in [
        ("reflective: 5", "reflective", 27),
        ("transparency: 1.5", "transparency", 29),
        ("opacity: -0.5", "opacity", 24),
        ("gloss: [1, 2, 1]", "gloss", 22),
    ] {
        let e = error(&format!(
            "{CAMERA}- add: sphere\n  material: {{ {material} }}\n"
        ));
        assert_at(&e, 9, column, Some(key), "share of light from 0 to 1");
    }
    let balance = "matte-gloss-balance: { balance: 0.5, matte: [1, 1, 1], gloss: [3, 1, 1] }";
    let e = error(&format!(
        "{CAMERA}- add: sphere\n  material: {{ {balance} }}\n"
    ));
    assert!(e.message.contains("share of light"), "{e}");
    // The edges are fine.
    load_str(
        &format!(
            "{CAMERA}- add: sphere\n  material: {{ reflective: 1, transparency: 0, opacity: 1, gloss: [0, 1, 0] }}\n"
        ),
        Path::new("scene.yml"),
    )
    .expect("0 and 1 are shares");
}
