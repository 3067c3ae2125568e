//! Reading well-formed scene files: what ends up in the world and camera.
use rayforge::color::color;
use rayforge::math::{rotation_x, scaling, translation};
use rayforge::{point, PatternKind, Shape};
use rayforge_scene::load_str;
use std::path::Path;

const CAMERA: &str = "
- add: camera
  width: 40
  height: 20
  field-of-view: 1.2
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
";

fn load(body: &str) -> rayforge_scene::Scene {
    load_str(&format!("{CAMERA}{body}"), Path::new("test.yml")).expect("scene loads")
}

#[test]
fn the_camera_takes_its_size_field_of_view_and_placement() {
    let scene = load("");
    assert_eq!((scene.camera.hsize(), scene.camera.vsize()), (40, 20));
    assert_eq!(scene.camera.field_of_view(), 1.2);
    let expected = rayforge::math::view_transform(
        point(0.0, 1.5, -5.0),
        point(0.0, 1.0, 0.0),
        rayforge::vector(0.0, 1.0, 0.0),
    );
    assert!(scene
        .camera
        .transform()
        .matrix()
        .abs_diff_eq(expected, 1e-12));
    let look_at = scene
        .look_at
        .expect("the book's camera keeps its placement");
    assert_eq!(look_at.from, point(0.0, 1.5, -5.0));
    assert_eq!(look_at.to, point(0.0, 1.0, 0.0));
    assert_eq!(look_at.up, rayforge::vector(0.0, 1.0, 0.0));
}

#[test]
fn lights_take_position_and_intensity() {
    let scene = load("- add: light\n  at: [1, 2, 3]\n  intensity: [0.5, 0.25, 1]\n- add: light\n  at: [0, 9, 0]\n  intensity: [1, 1, 1]\n");
    assert_eq!(scene.world.lights.len(), 2);
    assert_eq!(scene.world.lights[0].position(), point(1.0, 2.0, 3.0));
    assert_eq!(scene.world.lights[0].intensity(), color(0.5, 0.25, 1.0));
}

#[test]
fn transforms_apply_in_the_order_written() {
    let scene = load(
        "- add: sphere\n  transform:\n    - [translate, 1, 2, 3]\n    - [scale, 2, 2, 2]\n    - [rotate-x, 0.5]\n",
    );
    let expected = rotation_x(0.5) * scaling(2.0, 2.0, 2.0) * translation(1.0, 2.0, 3.0);
    assert!(scene.world.objects[0]
        .transform
        .matrix()
        .abs_diff_eq(expected, 1e-12));
}

#[test]
fn numbers_may_be_written_in_any_yaml_spelling() {
    let scene = load(
        "- add: sphere\n  material:\n    ambient: .75\n    shininess: 1e3\n    diffuse: 1\n    specular: -0.0\n    reflective: +0.5\n",
    );
    let m = &scene.world.objects[0].material;
    assert_eq!(m.ambient, 0.75);
    assert_eq!(m.shininess, 1000.0);
    assert_eq!(m.diffuse, 1.0);
    assert_eq!(m.specular, 0.0);
    assert_eq!(m.reflective, 0.5);
}

#[test]
fn materials_extend_defines_and_override_their_keys() {
    let scene = load(
        "
- define: white
  value:
    color: [1, 1, 1]
    diffuse: 0.7
    reflective: 0.1
- define: blue
  extend: white
  value:
    color: [0, 0, 1]
- add: cube
  material: blue
",
    );
    let m = &scene.world.objects[0].material;
    assert_eq!(scene.world.objects[0].shape, Shape::Cube);
    assert_eq!(m.color, color(0.0, 0.0, 1.0));
    assert_eq!(m.diffuse, 0.7);
    assert_eq!(m.reflective, 0.1);
    assert_eq!(m.ambient, 0.1, "unset keys keep the book's defaults");
}

#[test]
fn transform_defines_expand_in_place_and_nest() {
    let scene = load(
        "
- define: standard
  value:
    - [translate, 1, -1, 1]
    - [scale, 0.5, 0.5, 0.5]
- define: large
  value:
    - standard
    - [scale, 3.5, 3.5, 3.5]
- add: sphere
  transform:
    - large
    - [translate, 4, 0, 0]
",
    );
    let expected = translation(4.0, 0.0, 0.0)
        * scaling(3.5, 3.5, 3.5)
        * scaling(0.5, 0.5, 0.5)
        * translation(1.0, -1.0, 1.0);
    assert!(scene.world.objects[0]
        .transform
        .matrix()
        .abs_diff_eq(expected, 1e-12));
}

#[test]
fn patterns_take_colors_transforms_and_nested_patterns() {
    let scene = load(
        "
- add: plane
  material:
    pattern:
      type: checkers
      colors:
        - type: stripes
          colors: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
          transform:
            - [scale, 0.25, 0.25, 0.25]
        - [0, 0, 0]
      transform:
        - [rotate-y, 0.5]
",
    );
    let pattern = scene.world.objects[0]
        .material
        .pattern
        .as_ref()
        .expect("a pattern");
    let PatternKind::Checkers(cells) = &pattern.kind else {
        panic!("checkers, got {:?}", pattern.kind);
    };
    assert_eq!(cells.len(), 2);
    let PatternKind::Stripes(stripes) = &cells[0].kind else {
        panic!("nested stripes");
    };
    assert_eq!(stripes.len(), 3);
    assert!(cells[0]
        .transform
        .matrix()
        .abs_diff_eq(scaling(0.25, 0.25, 0.25), 1e-12));
    assert_eq!(cells[1].kind, PatternKind::Solid(color(0.0, 0.0, 0.0)));
}

#[test]
fn the_chapter_extras_read_as_patterns() {
    let scene = load(
        "
- add: sphere
  material:
    pattern:
      type: blended
      patterns:
        - type: stripes
          colors: [[1, 1, 1], [0, 0, 0]]
        - type: perturbed
          scale: 0.1
          pattern:
            type: radial-gradient
            colors: [[1, 0, 0], [0, 0, 1]]
",
    );
    let p = scene.world.objects[0].material.pattern.as_ref().unwrap();
    let PatternKind::Blended(parts) = &p.kind else {
        panic!("blended");
    };
    let PatternKind::Perturbed { pattern, scale } = &parts[1].kind else {
        panic!("perturbed");
    };
    assert_eq!(*scale, 0.1);
    assert!(matches!(pattern.kind, PatternKind::RadialGradient(..)));
}

#[test]
fn rings_may_be_spelt_ring_and_take_any_number_of_colors() {
    let scene = load(
        "
- define: three
  value: {type: ring, colors: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}
- add: plane
  material: {pattern: three}
- add: plane
  material:
    pattern: {type: rings, colors: [[1, 1, 1], [0, 0, 0]]}
",
    );
    for (object, n) in scene.world.objects.iter().zip([3, 2]) {
        let p = object.material.pattern.as_ref().unwrap();
        let PatternKind::Rings(parts) = &p.kind else {
            panic!("rings, got {:?}", p.kind);
        };
        assert_eq!(parts.len(), n);
    }
}

#[test]
fn a_transform_may_be_a_single_defined_name() {
    let scene = load(
        "
- define: up
  value:
    - [translate, 0, 1, 0]
- add: sphere
  transform: up
",
    );
    assert!(scene.world.objects[0]
        .transform
        .matrix()
        .abs_diff_eq(translation(0.0, 1.0, 0.0), 1e-12));
}

#[test]
fn a_defined_object_may_build_on_another() {
    let scene = load(
        "
- define: ball
  value:
    add: sphere
    material: {color: [1, 0, 0], reflective: 0.5}
    transform: [[scale, 2, 2, 2]]
- define: raised-ball
  value:
    add: ball
    transform: [[translate, 0, 1, 0]]
- add: raised-ball
  shadow: false
  transform: [[rotate-y, 1]]
",
    );
    let [ball] = &scene.world.objects[..] else {
        panic!("one object");
    };
    assert_eq!(ball.shape, Shape::Sphere);
    assert_eq!(ball.material.reflective, 0.5);
    assert!(!ball.casts_shadow);
    // The innermost template's transform first, the item's last.
    let expected =
        rayforge::math::rotation_y(1.0) * translation(0.0, 1.0, 0.0) * scaling(2.0, 2.0, 2.0);
    assert!(ball.transform.matrix().abs_diff_eq(expected, 1e-12));
}

#[test]
fn shadow_false_makes_an_object_cast_no_shadow() {
    let scene = load("- add: sphere\n  shadow: false\n- add: sphere\n");
    assert!(!scene.world.objects[0].casts_shadow);
    assert!(scene.world.objects[1].casts_shadow);
}

#[test]
fn cylinders_and_cones_take_min_max_and_closed() {
    let scene = load("- add: cylinder\n  min: -1\n  max: 2\n  closed: true\n- add: cone\n");
    assert_eq!(
        scene.world.objects[0].shape,
        Shape::Cylinder {
            minimum: -1.0,
            maximum: 2.0,
            closed: true
        }
    );
    assert_eq!(scene.world.objects[1].shape, Shape::CONE);
}

#[test]
fn a_defined_object_is_instantiated_with_the_items_overrides() {
    let scene = load(
        "
- define: ball
  value:
    add: sphere
    material:
      color: [1, 0, 0]
    transform:
      - [scale, 2, 2, 2]
- add: ball
  transform:
    - [translate, 0, 1, 0]
- add: ball
  material:
    color: [0, 1, 0]
",
    );
    let [a, b] = &scene.world.objects[..] else {
        panic!("two objects");
    };
    assert_eq!(a.shape, Shape::Sphere);
    assert_eq!(a.material.color, color(1.0, 0.0, 0.0));
    let expected = translation(0.0, 1.0, 0.0) * scaling(2.0, 2.0, 2.0);
    assert!(a.transform.matrix().abs_diff_eq(expected, 1e-12));
    assert_eq!(b.material.color, color(0.0, 1.0, 0.0));
}

/// The appendix's cover scene, repaired as SEED-NOTES.md says, has 30 items.
#[test]
fn the_repaired_cover_scene_loads_with_all_its_items() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/trtc/cover.yml");
    let scene = rayforge_scene::load_file(&path).expect("cover loads");
    assert_eq!(scene.world.lights.len(), 2);
    let count = |s: Shape| scene.world.objects.iter().filter(|o| o.shape == s).count();
    assert_eq!(count(Shape::Plane), 1);
    assert_eq!(count(Shape::Sphere), 1);
    assert_eq!(count(Shape::Cube), 17);
    assert_eq!(scene.world.objects.len(), 19);
    assert_eq!((scene.camera.hsize(), scene.camera.vsize()), (100, 100));
    assert_eq!(scene.camera.field_of_view(), 0.785);
    // Objects keep the file's order: the plane, the glass sphere, then the cubes.
    let glass = &scene.world.objects[1].material;
    assert_eq!((glass.transparency, glass.refractive_index), (0.7, 1.5));
    // The first cube: `medium-object` (itself `standard-transform` then a scale), then a move.
    let cube = &scene.world.objects[2];
    let expected = translation(4.0, 0.0, 0.0)
        * scaling(3.0, 3.0, 3.0)
        * scaling(0.5, 0.5, 0.5)
        * translation(1.0, -1.0, 1.0);
    assert!(cube.transform.matrix().abs_diff_eq(expected, 1e-12));
    // `blue-material` extends `white-material`: its colour, white's diffuse and reflective.
    let blue = &scene.world.objects[3].material;
    assert_eq!(blue.color, color(0.537, 0.831, 0.914));
    assert_eq!((blue.diffuse, blue.reflective), (0.7, 0.1));
}

/// Every chapter scene shipped in `scenes/trtc/` loads (the showcase scenes read models from
/// `../shared`, which a fresh clone does not have).
#[test]
fn every_shipped_scene_loads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/trtc");
    let mut count = 0;
    let mut dirs = vec![root];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "yml") {
                if let Err(e) = rayforge_scene::load_file(&path) {
                    panic!("{e}");
                }
                count += 1;
            }
        }
    }
    assert!(count >= 7, "expected the chapter scenes, found {count}");
}

#[test]
fn groups_bake_their_transforms_into_their_children_parent_first() {
    let scene = load(
        "
- add: group
  transform:
    - [scale, 2, 2, 2]
  children:
    - add: sphere
      transform:
        - [translate, 5, 0, 0]
    - add: group
      transform:
        - [rotate-y, 1]
      children:
        - add: cube
",
    );
    let [sphere, cube] = &scene.world.objects[..] else {
        panic!("two shapes, got {}", scene.world.objects.len());
    };
    let expected = scaling(2.0, 2.0, 2.0) * translation(5.0, 0.0, 0.0);
    assert!(sphere.transform.matrix().abs_diff_eq(expected, 1e-12));
    let expected = scaling(2.0, 2.0, 2.0) * rayforge::math::rotation_y(1.0);
    assert!(cube.transform.matrix().abs_diff_eq(expected, 1e-12));
}

#[test]
fn a_groups_material_and_shadow_apply_to_children_that_set_none() {
    let scene = load(
        "
- add: group
  material:
    color: [1, 0, 0]
  shadow: false
  children:
    - add: sphere
    - add: sphere
      material:
        color: [0, 0, 1]
",
    );
    let [a, b] = &scene.world.objects[..] else {
        panic!("two shapes");
    };
    assert_eq!(a.material.color, color(1.0, 0.0, 0.0));
    assert_eq!(b.material.color, color(0.0, 0.0, 1.0));
    assert!(!a.casts_shadow && !b.casts_shadow);
}

#[test]
fn a_defined_group_can_be_reused() {
    let scene = load(
        "
- define: pair
  value:
    add: group
    children:
      - add: sphere
      - add: cube
- add: pair
  transform:
    - [translate, 0, 3, 0]
- add: pair
",
    );
    assert_eq!(scene.world.objects.len(), 4);
    assert!(scene.world.objects[0]
        .transform
        .matrix()
        .abs_diff_eq(translation(0.0, 3.0, 0.0), 1e-12));
}

#[test]
fn groups_nested_too_deeply_are_refused() {
    let mut child = String::from("{add: sphere}");
    for _ in 0..300 {
        child = format!("{{add: group, children: [{child}]}}");
    }
    let e = load_str(&format!("{CAMERA}- {child}\n"), Path::new("test.yml")).unwrap_err();
    // Either the YAML reader's own nesting limit or ours refuses it; neither overflows.
    assert!(
        e.message.contains("nest deeper") || e.message.contains("recursion limit"),
        "{e}"
    );
}

#[test]
fn a_csg_takes_an_operation_and_two_operands_in_either_spelling() {
    let scene = load(
        "
- define: hole
  value:
    add: cylinder
    min: -2
    max: 2
    closed: true
    transform:
      - [scale, 0.5, 1, 0.5]
- add: csg
  operation: difference
  material:
    color: [1, 0, 0]
  left:
    type: cube
  right:
    add: csg
    operation: intersect
    left: hole
    right:
      type: group
      children:
        - add: sphere
          material:
            color: [0, 0, 1]
  transform:
    - [translate, 0, 1, 0]
",
    );
    let [csg] = &scene.world.objects[..] else {
        panic!("one csg");
    };
    let Shape::Csg(c) = &csg.shape else {
        panic!("a csg, got {:?}", csg.shape);
    };
    assert_eq!(c.operation(), rayforge::CsgOperation::Difference);
    assert_eq!(c.leaves().len(), 3);
    // The CSG's material reaches leaves that set none; a leaf's own material wins.
    assert_eq!(c.leaves()[0].material.color, color(1.0, 0.0, 0.0));
    assert_eq!(c.leaves()[2].material.color, color(0.0, 0.0, 1.0));
    // The CSG's transform moves its leaves.
    assert!(c.leaves()[0]
        .transform
        .matrix()
        .abs_diff_eq(translation(0.0, 1.0, 0.0), 1e-12));
}

#[test]
fn a_csg_with_an_unknown_operation_is_refused() {
    let e = load_str(
        &format!("{CAMERA}- add: csg\n  operation: xor\n  left: {{type: cube}}\n  right: {{type: sphere}}\n"),
        Path::new("test.yml"),
    )
    .unwrap_err();
    assert!(e.message.contains("unknown operation `xor`"), "{e}");
    assert_eq!(e.key.as_deref(), Some("operation"));
}

#[test]
fn area_lights_take_a_corner_two_edges_their_steps_and_jitter() {
    let scene = load(
        "- add: light\n  corner: [-1, 2, 4]\n  uvec: [2, 0, 0]\n  usteps: 10\n  vvec: [0, 2, 0]\n  vsteps: 5\n  jitter: true\n  intensity: [1.5, 1.5, 1.5]\n",
    );
    let rayforge::Light::Area(light) = scene.world.lights[0] else {
        panic!("an area light");
    };
    assert_eq!(light.corner, point(-1.0, 2.0, 4.0));
    assert_eq!(light.uvec, rayforge::vector(0.2, 0.0, 0.0));
    assert_eq!(light.vvec, rayforge::vector(0.0, 0.4, 0.0));
    assert_eq!(light.samples(), 50);
    assert!(light.jitter);
    assert_eq!(light.intensity, color(1.5, 1.5, 1.5));
}

#[test]
fn extra_transform_numbers_are_ignored_with_a_located_warning() {
    let scene = load("- add: sphere\n  transform:\n    - [rotate-y, 0,7853981634]\n");
    assert!(scene.world.objects[0]
        .transform
        .matrix()
        .abs_diff_eq(rayforge::math::rotation_y(0.0), 1e-12));
    let [warning] = &scene.warnings[..] else {
        panic!("one warning, got {:?}", scene.warnings);
    };
    assert_eq!(warning.span.unwrap().line, 11);
    assert!(
        warning.message.contains("extra ones are ignored"),
        "{warning}"
    );
}

#[test]
fn warnings_stop_after_a_hundred() {
    let scene = load(&"- add: sphere\n  transform: [[rotate-y, 0,5]]\n".repeat(150));
    assert_eq!(scene.world.objects.len(), 150);
    assert_eq!(scene.warnings.len(), 101);
    assert!(scene.warnings[100]
        .message
        .contains("the rest are not shown"));
}

#[test]
fn the_camera_may_ask_for_samples_per_pixel() {
    assert_eq!(load("").samples, 1);
    let scene = load_str(
        &CAMERA.replace("  up: [0, 1, 0]", "  up: [0, 1, 0]\n  samples: 9"),
        Path::new("test.yml"),
    )
    .unwrap();
    assert_eq!(scene.samples, 9);
}

#[test]
fn spotlights_take_a_direction_an_angle_and_a_fade() {
    let scene = load("- add: light\n  at: [0, 5, 0]\n  direction: [0, -1, 0]\n  angle: 0.5\n  fade: 0.1\n  intensity: [1, 1, 1]\n");
    let rayforge::Light::Spot(s) = scene.world.lights[0] else {
        panic!("a spotlight");
    };
    assert_eq!(s.direction, rayforge::vector(0.0, -1.0, 0.0));
    assert!((s.cos_outer - 0.5f64.cos()).abs() < 1e-12);
    assert!((s.cos_inner - 0.4f64.cos()).abs() < 1e-12);
    let e = load_str(
        &format!("{CAMERA}- add: light\n  at: [0, 5, 0]\n  direction: [0, -1, 0]\n  angle: 4\n  intensity: [1, 1, 1]\n"),
        Path::new("test.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("angle"));
}

#[test]
fn a_camera_with_an_aperture_focuses_at_its_focal_distance() {
    let scene = load_str(
        &CAMERA.replace(
            "  up: [0, 1, 0]",
            "  up: [0, 1, 0]\n  aperture: 0.5\n  focal-distance: 4",
        ),
        Path::new("test.yml"),
    )
    .unwrap();
    assert_eq!(scene.camera.aperture(), 0.5);
    assert_eq!(scene.camera.focal_distance(), 4.0);
    let e = load_str(
        &CAMERA.replace("  up: [0, 1, 0]", "  up: [0, 1, 0]\n  aperture: 0.5"),
        Path::new("test.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("focal-distance"));
}

#[test]
fn materials_take_bumps() {
    let scene = load(
        "- add: plane\n  material:\n    bump:\n      type: waves\n      amplitude: 0.2\n      wavelength: 0.5\n- add: sphere\n  material:\n    bump: {type: noise, strength: 0.3, transform: [[scale, 0.1, 0.1, 0.1]]}\n",
    );
    let waves = scene.world.objects[0].material.bump.as_ref().unwrap();
    assert_eq!(
        waves.kind,
        rayforge::shading::BumpKind::Waves {
            amplitude: 0.2,
            wavelength: 0.5
        }
    );
    let noise = scene.world.objects[1].material.bump.as_ref().unwrap();
    assert_eq!(
        noise.kind,
        rayforge::shading::BumpKind::Noise { strength: 0.3 }
    );
    let e = load_str(
        &format!("{CAMERA}- add: plane\n  material:\n    bump: {{type: waves, amplitude: 1, wavelength: 0}}\n"),
        Path::new("test.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("wavelength"));
}

#[test]
fn canvas_items_are_kept_in_order_for_the_cameras_canvas() {
    use rayforge::raster::{CanvasItem, CanvasPoint, TriangleStyle};
    let scene = load(
        "
- add: canvas-triangle
  points: [[-10, -5], [10, -5], [0, 8]]
  color: [0, 1, 0]
  style: shaded
  intensities: [0.3, 0.1, 1]
- add: canvas-line
  from: [-2, -0.5, 5]
  to: [3, 4]
",
    );
    let items = scene.overlay.items();
    assert_eq!(items.len(), 2);
    assert_eq!(
        items[0],
        CanvasItem::Triangle {
            points: [
                CanvasPoint::Canvas(glam::DVec2::new(-10.0, -5.0)),
                CanvasPoint::Canvas(glam::DVec2::new(10.0, -5.0)),
                CanvasPoint::Canvas(glam::DVec2::new(0.0, 8.0)),
            ],
            color: color(0.0, 1.0, 0.0),
            style: TriangleStyle::Shaded([0.3, 0.1, 1.0]),
        }
    );
    assert_eq!(
        items[1],
        CanvasItem::Line {
            from: CanvasPoint::Projected(glam::DVec3::new(-2.0, -0.5, 5.0)),
            to: CanvasPoint::Canvas(glam::DVec2::new(3.0, 4.0)),
            color: color(0.0, 0.0, 0.0),
        },
        "black unless a colour is given"
    );
    assert!(scene.world.objects.is_empty(), "nothing in the 3D world");
}

#[test]
fn a_scene_lists_every_file_it_read_besides_itself() {
    // What a render's fingerprint covers and what the live page watches: the model, the
    // material library it names and the image that library names, in the order read.
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| std::fs::write(dir.path().join(name), bytes).unwrap();
    write(
        "tri.obj",
        b"mtllib tri.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n",
    );
    write("tri.mtl", b"newmtl red\nKd 1 0 0\nmap_Kd red.ppm\n");
    write("red.ppm", b"P3\n1 1\n255\n255 0 0\n");
    write("scene.yml", b"- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: obj\n  file: tri.obj\n");
    let scene = rayforge_scene::load_file(&dir.path().join("scene.yml")).unwrap();
    let names: Vec<String> = scene
        .files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["tri.obj", "tri.mtl", "red.ppm"]);
}

#[test]
fn an_array_places_copies_of_a_defined_object_on_its_grid_inside_its_transform() {
    let scene = load(
        "
- define: ball
  value:
    add: sphere
    transform:
      - [scale, 0.5, 0.5, 0.5]
- add: array
  of: ball
  count: [3, 1, 2]
  step: [2, 0, 5]
  transform:
    - [translate, 0, 1, 0]
  colors: [[1, 0, 0], [0, 1, 0]]
",
    );
    let objects = &scene.world.objects;
    assert_eq!(objects.len(), 6);
    // x varies fastest, then y, then z; the colours cycle in that order.
    for (n, object) in objects.iter().enumerate() {
        let (x, z) = ((n % 3) as f64, (n / 3) as f64);
        let expected = translation(0.0, 1.0, 0.0)
            * translation(2.0 * x, 0.0, 5.0 * z)
            * scaling(0.5, 0.5, 0.5);
        assert!(
            object.transform.matrix().abs_diff_eq(expected, 1e-12),
            "copy {n}"
        );
        let c = if n % 2 == 0 {
            color(1.0, 0.0, 0.0)
        } else {
            color(0.0, 1.0, 0.0)
        };
        assert_eq!(object.material.color, c, "copy {n}");
    }
}

#[test]
fn an_array_of_an_inline_group_copies_every_part_with_the_arrays_material() {
    let scene = load(
        "
- add: array
  of:
    add: group
    children:
      - add: sphere
      - add: cube
        material:
          color: [0, 0, 1]
  count: 4
  step: [3, 0, 0]
  material:
    color: [1, 1, 0]
  shadow: false
",
    );
    let objects = &scene.world.objects;
    assert_eq!(objects.len(), 8);
    for (n, pair) in objects.chunks(2).enumerate() {
        assert!(matches!(pair[0].shape, Shape::Sphere) && matches!(pair[1].shape, Shape::Cube));
        assert_eq!(pair[0].material.color, color(1.0, 1.0, 0.0));
        assert_eq!(pair[1].material.color, color(0.0, 0.0, 1.0));
        assert!(!pair[0].casts_shadow && !pair[1].casts_shadow);
        let expected = translation(3.0 * n as f64, 0.0, 0.0);
        assert!(pair[0].transform.matrix().abs_diff_eq(expected, 1e-12));
    }
}
