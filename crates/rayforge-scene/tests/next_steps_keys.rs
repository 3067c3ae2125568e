//! The scene keys of chapter 17's extensions that the community dialect has no spelling for:
//! the torus, motion blur (`motion:`, `velocity:`, the camera's `shutter:`) and the toroidal
//! mapping.
mod support;

use rayforge::math::translation;
use rayforge::{point, PatternKind, Shape};
use rayforge_scene::load_str;
use std::path::Path;
use support::{load_after_camera, CAMERA};

#[test]
fn a_torus_takes_its_two_radii() {
    let scene =
        load_after_camera("- add: torus\n  major-radius: 3\n  minor-radius: 0.5\n").unwrap();
    assert_eq!(
        scene.world.objects[0].shape,
        Shape::Torus {
            major: 3.0,
            minor: 0.5
        }
    );
    let defaults = load_after_camera("- add: torus\n").unwrap();
    assert_eq!(
        defaults.world.objects[0].shape,
        Shape::Torus {
            major: 1.0,
            minor: 0.25
        }
    );
}

#[test]
fn a_torus_radius_must_be_positive() {
    let e = load_after_camera("- add: torus\n  minor-radius: 0\n").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("minor-radius"), "{e}");
    assert_eq!(e.span.unwrap().line, 9, "{e}");
    assert!(e.message.contains("positive"), "{e}");
}

#[test]
fn the_shutter_defaults_to_the_whole_motion() {
    assert_eq!(load_after_camera("").unwrap().camera.shutter(), (0.0, 1.0));
    let scene = load_str(
        &CAMERA.replace("up: [0, 1, 0]", "up: [0, 1, 0]\n  shutter: [0.25, 0.5]"),
        Path::new("scene.yml"),
    )
    .unwrap();
    assert_eq!(scene.camera.shutter(), (0.25, 0.5));
}

#[test]
fn a_shutter_that_closes_before_it_opens_is_an_error() {
    let e = load_str(
        &CAMERA.replace("up: [0, 1, 0]", "up: [0, 1, 0]\n  shutter: [1, 0]"),
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("shutter"), "{e}");
    assert_eq!(e.span.unwrap().line, 8, "{e}");
}

#[test]
fn velocity_moves_an_object_by_that_much_while_the_shutter_is_open() {
    let scene = load_after_camera(
        "- add: sphere\n  transform:\n    - [translate, 1, 0, 0]\n  velocity: [0, 2, 0]\n",
    )
    .unwrap();
    let sphere = &scene.world.objects[0];
    let motion = sphere.motion.as_ref().expect("the sphere moves");
    assert_eq!(motion.start().matrix(), translation(1.0, 0.0, 0.0));
    assert_eq!(motion.end().matrix(), translation(1.0, 2.0, 0.0));
}

#[test]
fn motion_gives_the_transform_when_the_shutter_closes() {
    let scene = load_after_camera(
        "- add: cube\n  transform: [[translate, 1, 0, 0]]\n  motion: [[rotate-y, 1], [translate, 1, 0, 0]]\n",
    )
    .unwrap();
    let motion = scene.world.objects[0].motion.as_ref().expect("it moves");
    let expected = translation(1.0, 0.0, 0.0) * rayforge::math::rotation_y(1.0);
    assert!(motion.end().matrix().abs_diff_eq(expected, 1e-12));
}

#[test]
fn a_moving_group_moves_every_child() {
    let scene = load_after_camera(
        "- add: group\n  velocity: [0, 0, 1]\n  children:\n    - add: sphere\n    - add: cube\n      transform: [[translate, 3, 0, 0]]\n",
    )
    .unwrap();
    for object in &scene.world.objects {
        let motion = object.motion.as_ref().expect("each child moves");
        let shift =
            motion.end().point(point(0.0, 0.0, 0.0)) - motion.start().point(point(0.0, 0.0, 0.0));
        assert!((shift - point(0.0, 0.0, 1.0)).length() < 1e-12, "{shift:?}");
    }
}

#[test]
fn motion_and_velocity_together_are_an_error() {
    let e = load_after_camera(
        "- add: sphere\n  motion: [[translate, 1, 0, 0]]\n  velocity: [1, 0, 0]\n",
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("velocity"), "{e}");
    assert!(e.message.contains("not both"), "{e}");
}

#[test]
fn a_singular_end_transform_is_an_error() {
    let e = load_after_camera("- add: sphere\n  motion: [[scale, 0, 1, 1]]\n").unwrap_err();
    assert_eq!(e.span.unwrap().line, 9, "{e}");
    assert!(e.message.contains("singular"), "{e}");
}

#[test]
fn a_toroidal_mapping_takes_the_torus_major_radius() {
    let scene = load_after_camera(
        "- add: torus\n  major-radius: 2\n  material:\n    pattern:\n      type: map\n      mapping: toroidal\n      major-radius: 2\n      uv_pattern:\n        type: checkers\n        width: 16\n        height: 4\n        colors: [[1, 1, 1], [0, 0, 0]]\n",
    )
    .unwrap();
    let pattern = scene.world.objects[0].material.pattern.as_ref().unwrap();
    match &pattern.kind {
        PatternKind::Map { mapping, .. } => assert_eq!(
            *mapping,
            rayforge::shading::UvMapping::Toroidal { major: 2.0 }
        ),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_complement_takes_one_operand() {
    let scene = load_after_camera(
        "- add: csg\n  operation: intersection\n  left:\n    type: sphere\n  right:\n    type: csg\n    operation: complement\n    left:\n      type: cube\n      transform: [[scale, 0.5, 0.5, 0.5]]\n",
    )
    .unwrap();
    let solid = &scene.world.objects[0];
    assert!(solid.contains(point(0.0, 0.0, 0.8)));
    assert!(
        !solid.contains(point(0.0, 0.0, 0.2)),
        "inside the cube taken out"
    );
    let e = load_after_camera("- add: csg\n  operation: complement\n  left:\n    type: sphere\n  right:\n    type: cube\n")
        .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("right"), "{e}");
    assert!(e.message.contains("one operand"), "{e}");
}
