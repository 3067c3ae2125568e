//! pbrt-v4's cut quadrics, bilinear patches and Loop subdivision surfaces as the reader builds
//! them: what each becomes, its uv and area, the errors at the parameter that fails.

use glam::DVec3;
use rayforge::geometry::{LocalHit, PartialQuadric};
use rayforge::shading::SurfacePoint;
use rayforge::{Ray, Shape};
use rayforge_scene::{LoadOptions, Scene, SceneError};

/// The scene of `text`, written to `s.pbrt` in a fresh folder.
fn load_text(text: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

fn load(text: &str) -> Scene {
    load_text(text).unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> SceneError {
    match load_text(text) {
        Ok(_) => panic!("loaded, but should not have:\n{text}"),
        Err(e) => e,
    }
}

/// Asserts `e` is at `line:col` of `s.pbrt` with `key`, its message containing `part`.
fn assert_at(e: &SceneError, line: usize, column: usize, key: &str, part: &str) {
    let span = e.span.unwrap_or_else(|| panic!("no place: {e}"));
    assert_eq!((span.line, span.column), (line, column), "{e}");
    assert!(e.path.ends_with("s.pbrt"), "{e}");
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert!(e.message.contains(part), "`{part}` not in: {e}");
}

const HEAD: &str = "Camera \"perspective\"\nWorldBegin\n";

/// The cut quadric object `i` of `scene` is.
fn partial(scene: &Scene, i: usize) -> PartialQuadric {
    match &scene.world.objects[i].shape {
        Shape::Partial(q) => **q,
        other => panic!("object {i} is {other:?}"),
    }
}

#[test]
fn cut_spheres_disks_and_cylinders_become_cut_quadrics() {
    let scene = load(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" 2 \"float zmin\" -1 \"float zmax\" 1.5\n\
         Shape \"sphere\" \"float radius\" 2 \"float phimax\" 90\n\
         Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1 \"float phimax\" 180\n\
         Shape \"cylinder\" \"float radius\" 1 \"float phimax\" 270\n\
         Shape \"sphere\" \"float radius\" 2 \"float zmin\" -5 \"float zmax\" 5 \"float phimax\" 400\n\
         Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1\n"
    ));
    assert_eq!(
        partial(&scene, 0),
        PartialQuadric::sphere(2.0, -1.0, 1.5, 360.0).unwrap()
    );
    assert_eq!(partial(&scene, 1).phi_max(), std::f64::consts::FRAC_PI_2);
    assert_eq!(
        partial(&scene, 2),
        PartialQuadric::disk(0.0, 2.0, 1.0, 180.0).unwrap()
    );
    assert_eq!(
        partial(&scene, 3),
        PartialQuadric::cylinder(1.0, -1.0, 1.0, 270.0).unwrap()
    );
    // Cuts past the poles and beyond a whole turn are pbrt's whole sphere; a whole annulus is
    // a ring.
    assert_eq!(scene.world.objects[4].shape, Shape::Sphere);
    assert!(matches!(scene.world.objects[5].shape, Shape::Ring { .. }));
    // Placed as pbrt places them, and cut: a ray down the axis passes the hole above
    // z = 1.5 and the one below z = −1, so it meets nothing; one at x = 1.5 meets the upper
    // side (z = +1.32, kept) and not the lower (z = −1.32, cut away).
    let object = &scene.world.objects[0];
    let down = |x: f64| {
        let ray = Ray::new(DVec3::new(x, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
        let hits = object.intersections(&ray);
        hits.iter().map(|h| h.t).collect::<Vec<_>>()
    };
    assert!(down(0.0).is_empty(), "{:?}", down(0.0));
    let t = down(1.5);
    let z = (4.0f64 - 2.25).sqrt();
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0] - (5.0 - z)).abs() < 1e-9, "{t:?}");
}

#[test]
fn cut_quadrics_have_pbrts_uv() {
    let scene = load(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" 2 \"float zmin\" 0 \"float phimax\" 180\n\
         Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1 \"float phimax\" 90 \
         \"float height\" 0.5\n\
         Shape \"cylinder\" \"float radius\" 1 \"float zmin\" 0 \"float zmax\" 2 \
         \"float phimax\" 180\n"
    ));
    let uv = |i: usize, p: DVec3| {
        let ctx = scene.world.objects[i].texture_context(
            p,
            &SurfacePoint::default(),
            &LocalHit::at(0.0),
            DVec3::Z,
        );
        ctx.uv
    };
    let close = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
    // u = φ / φmax; v from the lower cut's angle to the upper's, from the rim in, from zmin.
    for (i, p, want) in [
        (0, DVec3::new(0.0, 2.0, 0.0), (0.5, 0.0)),
        (0, DVec3::new(0.0, 0.0, 2.0), (0.0, 1.0)),
        (1, DVec3::new(0.0, 1.5, 0.5), (1.0, 0.5)),
        (2, DVec3::new(-1.0, 0.0, 0.5), (1.0, 0.25)),
    ] {
        let got = uv(i, p);
        assert!(close(got, want), "object {i} at {p}: {got:?}, not {want:?}");
    }
}

#[test]
fn a_cut_that_leaves_nothing_is_an_error_at_its_parameter() {
    let e = error(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" 1\n    \"float phimax\" 0\n"
    ));
    assert_at(&e, 4, 5, "float phimax", "above 0");
    let e = error(&format!(
        "{HEAD}Shape \"sphere\" \"float zmin\" 2 \"float zmax\" 3\n"
    ));
    assert_at(&e, 3, 31, "float zmax", "keeps nothing");
    let e = error(&format!("{HEAD}Shape \"disk\" \"float innerradius\" 1\n"));
    assert_at(&e, 3, 14, "float innerradius", "below its radius");
}

#[test]
fn a_cut_lamps_power_is_spread_over_its_cut_area() {
    // pbrt-v4's `power` is the lamp's emitted power over its own-space area: half a sphere of
    // radius 1 (area 2π) given power 2π² has radiance power / (π · area) = 1.
    let scene = load(&format!(
        "{HEAD}AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" {p}\n\
         Shape \"sphere\" \"float zmin\" 0\nAttributeEnd\n",
        p = std::f64::consts::PI * 2.0 * std::f64::consts::PI
    ));
    let emission = scene.world.objects[0].material.emission;
    assert!((emission.red - 1.0).abs() < 1e-9, "{emission:?}");
}
