//! The media keys: `medium:` items (homogeneous, grid and cloud, coefficients or albedo and
//! density, inline data or a `.vol` file, pbrt-v4's cloud parameters), `interior:`/`exterior:` and `material: interface` on objects
//! and groups, `medium:` on the camera and in `world:`, and their errors, each located.
mod support;

use rayforge::media::{Medium, MediumId, MediumInterface};
use rayforge::Color;
use rayforge_scene::load_str;
use std::path::Path;
use support::{assert_located, load_after_camera, CAMERA};

const FOG: &str = "- medium: fog
  sigma-a: 0.1
  sigma-s: [0.2, 0.3, 0.4]
  scale: 2
  g: 0.5
";

#[test]
fn a_homogeneous_medium_is_read_with_its_coefficients() {
    let scene = load_after_camera(FOG).expect("loads");
    assert_eq!(scene.world.media.len(), 1);
    let Medium::Homogeneous(m) = scene.world.media.get(MediumId(0)) else {
        panic!("homogeneous")
    };
    assert_eq!(m.sigma_a, Color::new(0.2, 0.2, 0.2));
    assert_eq!(m.sigma_s, Color::new(0.4, 0.6, 0.8));
    assert_eq!(m.phase.g, 0.5);
}

#[test]
fn albedo_and_density_give_the_coefficients() {
    let scene = load_after_camera("- medium: milk\n  albedo: 0.75\n  density: 4\n").expect("loads");
    let Medium::Homogeneous(m) = scene.world.media.get(MediumId(0)) else {
        panic!("homogeneous")
    };
    assert_eq!(m.sigma_a, Color::new(1.0, 1.0, 1.0));
    assert_eq!(m.sigma_s, Color::new(3.0, 3.0, 3.0));
}

#[test]
fn objects_and_groups_bound_media_and_the_world_fills_the_rest() {
    let body = format!(
        "{FOG}- medium: juice
  sigma-a: [0.1, 0.5, 0.9]
- world:
    renderer: path
    medium: fog
- add: sphere
  interior: juice
- add: group
  material: interface
  interior: juice
  children:
    - add: cube
    - add: sphere
      exterior: vacuum
- add: plane
"
    );
    let scene = load_after_camera(&body).expect("loads");
    let (fog, juice) = (Some(MediumId(0)), Some(MediumId(1)));
    let objects = &scene.world.objects;
    assert_eq!(scene.world.camera_medium, fog);
    assert_eq!(
        objects[0].media,
        Some(MediumInterface {
            inside: juice,
            outside: fog,
            index_matched: false
        })
    );
    assert_eq!(
        objects[1].media,
        Some(MediumInterface {
            inside: juice,
            outside: fog,
            index_matched: true
        })
    );
    assert_eq!(
        objects[2].media,
        Some(MediumInterface {
            inside: juice,
            outside: None,
            index_matched: true
        })
    );
    // Saying nothing: a ray crossing it stays where it is.
    assert_eq!(objects[3].media, None);
}

#[test]
fn the_camera_names_its_own_medium() {
    let body = format!("{FOG}- medium: water\n  sigma-a: 1\n- world:\n    medium: fog\n");
    let text = format!(
        "- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n  medium: water\n{body}"
    );
    let scene = load_str(&text, Path::new("scene.yml")).expect("loads");
    assert_eq!(scene.world.camera_medium, Some(MediumId(1)));
}

#[test]
fn a_grid_medium_reads_its_data_and_box() {
    let body = "- medium: smoke
  type: grid
  sigma-s: 2
  size: [2, 1, 1]
  data: [0, 1]
  bounds: [[-1, -1, -1], [1, 1, 1]]
  transform:
    - [translate, 0, 1, 0]
";
    let scene = load_after_camera(body).expect("loads");
    let Medium::Grid(g) = scene.world.media.get(MediumId(0)) else {
        panic!("grid")
    };
    assert_eq!(g.density.size(), [2, 1, 1]);
    assert_eq!(g.sigma_s, Color::new(2.0, 2.0, 2.0));
    let p = g.to_unit(rayforge::point(0.5, 1.0, 0.0));
    assert!((p - rayforge::point(0.75, 0.5, 0.5)).length() < 1e-12);
}

#[test]
fn a_grid_medium_reads_a_vol_file() {
    let dir = std::env::temp_dir().join(format!("rayforge-media-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let mut bytes = b"VOL\x03".to_vec();
    for i in [1i32, 2, 2, 1, 1] {
        bytes.extend(i.to_le_bytes());
    }
    for f in [0.0f32, 0.0, 0.0, 2.0, 2.0, 1.0, 1.0, 2.0, 3.0, 4.0] {
        bytes.extend(f.to_le_bytes());
    }
    std::fs::write(dir.join("puff.vol"), &bytes).expect("write");
    let text = format!("{CAMERA}- medium: puff\n  type: grid\n  sigma-a: 1\n  file: puff.vol\n");
    let scene = load_str(&text, &dir.join("scene.yml")).expect("loads");
    let Medium::Grid(g) = scene.world.media.get(MediumId(0)) else {
        panic!("grid")
    };
    assert_eq!(g.bounds.max, rayforge::point(2.0, 2.0, 1.0));
    assert_eq!(g.density.lookup(rayforge::point(0.75, 0.75, 0.5)), 4.0);
    assert!(scene.files.iter().any(|f| f.ends_with("puff.vol")));
    std::fs::write(dir.join("bad.vol"), &bytes[..40]).expect("write");
    let text = format!("{CAMERA}- medium: puff\n  type: grid\n  file: bad.vol\n");
    let e = load_str(&text, &dir.join("scene.yml")).expect_err("refused");
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((10, 9)), "{e}");
    assert!(e.message.contains("bad.vol"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_cloud_is_read_with_pbrts_parameters_and_placed_by_its_transform() {
    let body = "- medium: sky
  type: cloud
  sigma-a: 0.5
  sigma-s: [1, 2, 3]
  scale: 2
  g: 0.4
  density: 3
  wispiness: 0.5
  frequency: 2
  bounds: [[-1, 0, -1], [1, 1, 1]]
  transform:
    - [translate, 0, 2, 0]
- medium: plain
  type: cloud
  albedo: 0.75
";
    let scene = load_after_camera(body).expect("loads");
    let cloud = |id: u32| match scene.world.media.get(MediumId(id)) {
        Medium::Cloud(c) => c.clone(),
        other => panic!("not a cloud: {other:?}"),
    };
    let (sky, plain) = (cloud(0), cloud(1));
    assert_eq!(sky.sigma_a, Color::new(1.0, 1.0, 1.0));
    assert_eq!(sky.sigma_s, Color::new(2.0, 4.0, 6.0));
    assert_eq!(sky.phase.g, 0.4);
    assert_eq!((sky.density, sky.wispiness, sky.frequency), (3.0, 0.5, 2.0));
    assert_eq!(sky.bounds.min, rayforge::point(-1.0, 0.0, -1.0));
    assert_eq!(sky.bounds.max, rayforge::point(1.0, 1.0, 1.0));
    // The box is placed by the transform: the world point (0, 2.5, 0) is its (0, 0.5, 0).
    let p = sky.transform.inverse_point(rayforge::point(0.0, 2.5, 0.0));
    assert!((p - rayforge::point(0.0, 0.5, 0.0)).length() < 1e-12, "{p}");
    // pbrt-v4's defaults: density 1, wispiness 1, frequency 5 over the unit cube; an albedo
    // gives the coefficients where the density is 1.
    assert_eq!(
        (plain.density, plain.wispiness, plain.frequency),
        (1.0, 1.0, 5.0)
    );
    assert_eq!(plain.bounds.min, rayforge::point(0.0, 0.0, 0.0));
    assert_eq!(plain.bounds.max, rayforge::point(1.0, 1.0, 1.0));
    assert_eq!(plain.sigma_a, Color::new(0.25, 0.25, 0.25));
    assert_eq!(plain.sigma_s, Color::new(0.75, 0.75, 0.75));
    assert_eq!(plain.phase.g, 0.0);
}

#[test]
fn bad_clouds_are_refused_where_they_are_written() {
    let cloud = |rest: &str| load_after_camera(&format!("- medium: m\n  type: cloud\n{rest}"));
    assert_located(cloud("  density: -1\n"), 10, 12, "density", "at least 0");
    assert_located(
        cloud("  wispiness: -0.5\n"),
        10,
        14,
        "wispiness",
        "at least 0",
    );
    assert_located(
        cloud("  frequency: -2\n"),
        10,
        14,
        "frequency",
        "at least 0",
    );
    assert_located(
        cloud("  bounds: [[0, 0, 0], [1, 0, 1]]\n"),
        10,
        11,
        "bounds",
        "positive, finite extent",
    );
    assert_located(cloud("  emission: 1\n"), 10, 3, "emission", "no light");
    assert_located(cloud("  data: [1]\n"), 10, 3, "data", "type: grid");
    assert_located(
        cloud("  albedo: 0.5\n  sigma-a: 1\n"),
        11,
        3,
        "sigma-a",
        "not both",
    );
    // The cloud's own keys belong to no other medium.
    assert_located(
        load_after_camera("- medium: m\n  type: grid\n  frequency: 2\n"),
        10,
        3,
        "frequency",
        "type: cloud",
    );
    assert_located(
        load_after_camera("- medium: m\n  wispiness: 2\n"),
        9,
        3,
        "wispiness",
        "type: cloud",
    );
    assert_located(
        load_after_camera("- medium: m\n  bounds: [[0, 0, 0], [1, 1, 1]]\n"),
        9,
        3,
        "bounds",
        "type: grid` or `type: cloud",
    );
}

#[test]
fn bad_media_are_refused_where_they_are_written() {
    assert_located(
        load_after_camera("- medium: m\n  type: nanovdb\n"),
        9,
        9,
        "type",
        "homogeneous, grid or cloud",
    );
    assert_located(
        load_after_camera("- medium: m\n  sigma-a: -1\n"),
        9,
        12,
        "sigma-a",
        "at least 0",
    );
    assert_located(
        load_after_camera("- medium: m\n  g: 1\n"),
        9,
        6,
        "g",
        "between",
    );
    assert_located(
        load_after_camera("- medium: m\n  albedo: 0.5\n  sigma-s: 1\n"),
        10,
        3,
        "sigma-s",
        "not both",
    );
    assert_located(
        load_after_camera("- medium: m\n  albedo: 2\n"),
        9,
        11,
        "albedo",
        "between 0 and 1",
    );
    assert_located(
        load_after_camera("- medium: m\n  size: [1, 1, 1]\n"),
        9,
        3,
        "size",
        "type: grid",
    );
    assert_located(
        load_after_camera("- medium: m\n  type: grid\n  size: [2, 2, 2]\n  data: [1, 2]\n"),
        11,
        9,
        "data",
        "holds 8 values, found 2",
    );
    assert_located(
        load_after_camera("- medium: m\n  type: grid\n"),
        8,
        3,
        "data",
        "needs `data:`",
    );
    assert_located(
        load_after_camera("- medium: vacuum\n"),
        8,
        11,
        "medium",
        "empty space",
    );
    assert_located(
        load_after_camera("- add: sphere\n  interior: mist\n"),
        9,
        13,
        "interior",
        "no medium is named `mist`",
    );
    assert_located(
        load_after_camera("- world:\n    medium: mist\n"),
        9,
        13,
        "medium",
        "no medium is named `mist`",
    );
}

#[test]
fn a_medium_too_dense_to_track_is_refused_at_its_name_until_the_limit_is_raised() {
    // σs 10⁹ over the unit cube: one pass crosses up to 10⁹ × √3, each unit about a step of
    // a ray's tracking.
    let body = "- medium: m\n  type: cloud\n  sigma-s: 1e9\n";
    let e = assert_located(
        load_after_camera(body),
        8,
        11,
        "medium",
        "--max-optical-depth",
    );
    assert!(e.message.contains("1.732e9"), "{e}");
    let raised = rayforge_scene::LoadOptions {
        max_optical_depth: 1e10,
        ..rayforge_scene::LoadOptions::default()
    };
    let text = format!("{CAMERA}{body}");
    rayforge_scene::load_str_with(&text, Path::new("scene.yml"), &raised).expect("loads");
}
