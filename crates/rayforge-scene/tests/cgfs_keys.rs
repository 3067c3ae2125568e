//! Computer Graphics from Scratch's keys: the `world:` item, `type:` lights and the viewport
//! camera, read from the shipped scenes and from small ones.
// The book writes √½ as 0.7071 in its rotation; the test reads back its number.
#![allow(clippy::approx_constant)]
use rayforge::{point, vector, Light, LightingModel};
use rayforge_scene::{load_file, load_str};
use std::path::Path;

fn shipped(name: &str) -> rayforge_scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/cgfs/{name}.yml"));
    load_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_turned_camera_stage_reads_as_the_book_writes_it() {
    let scene = shipped("raytracer-06");
    assert_eq!(scene.world.lighting, LightingModel::Cgfs);
    assert_eq!(scene.max_depth, Some(3));
    assert_eq!(scene.world.background, rayforge::Color::BLACK);
    let viewport = scene.camera.viewport_of().expect("a viewport camera");
    assert_eq!(
        (viewport.width, viewport.height, viewport.distance),
        (1.0, 1.0, 1.0)
    );
    assert_eq!(viewport.position, point(3.0, 0.0, 1.0));
    assert_eq!(viewport.rotation[0], [0.7071, 0.0, -0.7071]);
    assert_eq!((scene.camera.hsize(), scene.camera.vsize()), (600, 600));
    assert!(
        matches!(scene.world.lights[0], Light::Ambient(c) if c == rayforge::Color::new(0.2, 0.2, 0.2))
    );
    match &scene.world.lights[2] {
        Light::Directional(l) => assert_eq!(l.towards, vector(1.0, 4.0, 4.0)),
        other => panic!("{other:?}"),
    }
    assert_eq!(scene.world.objects.len(), 4);
    assert_eq!(scene.world.objects[3].material.shininess, 1000.0);
}

#[test]
fn the_first_stage_is_flat_and_white_behind() {
    let scene = shipped("raytracer-01");
    assert_eq!(scene.world.lighting, LightingModel::Flat);
    assert_eq!(scene.world.background, rayforge::Color::WHITE);
    assert!(scene.world.lights.is_empty());
    assert_eq!(scene.world.objects.len(), 3);
}

#[test]
fn every_cgfs_scene_loads() {
    for name in [
        "raytracer-01",
        "raytracer-02",
        "raytracer-03",
        "raytracer-04",
        "raytracer-05",
        "raytracer-06",
        "transparency",
    ] {
        shipped(name);
    }
}

#[test]
fn a_directional_light_may_say_which_way_the_light_travels() {
    let scene = load_str(
        "- add: camera\n  width: 4\n  height: 4\n  viewport: [1, 1]\n- add: light\n  type: directional\n  direction: [0, -1, 0]\n  intensity: [1, 0.5, 0.25]\n",
        Path::new("s.yml"),
    )
    .unwrap();
    match &scene.world.lights[0] {
        Light::Directional(l) => {
            assert_eq!(l.towards, vector(0.0, 1.0, 0.0));
            assert_eq!(l.intensity, rayforge::Color::new(1.0, 0.5, 0.25));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_viewport_camera_may_look_at_a_point() {
    let scene = load_str(
        "- add: camera\n  width: 4\n  height: 4\n  viewport: [1, 1]\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n",
        Path::new("s.yml"),
    )
    .unwrap();
    let viewport = scene.camera.viewport_of().unwrap();
    assert_eq!(viewport.position, point(0.0, 0.0, -5.0));
    assert_eq!(
        viewport.rotation,
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    );
}

#[test]
fn a_scene_may_choose_the_rasterizer_and_its_options() {
    let scene = load_str(
        "- world:\n    renderer: raster\n    shading: flat\n    sphere-divisions: 15\n    wireframe: true\n- add: camera\n  width: 4\n  height: 4\n  viewport: [1, 1]\n",
        Path::new("s.yml"),
    )
    .unwrap();
    let raster = scene.raster.expect("the rasterizer");
    assert_eq!(raster.sphere_divisions, 15);
    assert!(raster.wireframe);
    assert_eq!(raster.shading, rayforge::raster::Shading::Flat);
    let e = load_str(
        "- world:\n    wireframe: true\n- add: camera\n  width: 4\n  height: 4\n  viewport: [1, 1]\n",
        Path::new("s.yml"),
    )
    .unwrap_err();
    assert!(e.message.contains("renderer: raster"), "{e}");
}
