//! `add: camera`'s spherical projections (`projection`) and film keys (`iso`,
//! `exposure-time`, `white-balance`, `max-component`): each read onto the library's camera
//! and sensor exactly as the same settings of a pbrt-v4 file are, and each bad value refused
//! at its file:line:col and key.

mod support;

use rayforge::camera::SphericalMapping;
use rayforge::Color;
use rayforge_scene::{load_str, LoadOptions, Scene, SceneError};
use std::path::Path;
use support::assert_located;

/// A camera item of six lines, at the eye looking down +z with +y up: keys added after it
/// begin on line 7.
const HEAD: &str = "- add: camera\n  width: 32\n  height: 16\n  from: [0, 0, 0]\n  to: [0, 0, 1]\n  up: [0, 1, 0]\n";

fn yaml(keys: &str) -> Result<Scene, SceneError> {
    load_str(&format!("{HEAD}{keys}"), Path::new("scene.yml"))
}

fn pbrt(text: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// A spherical camera placed by `from`, `to` and `up` sees what pbrt-v4's spherical camera
/// placed by the same `LookAt` sees, pixel for pixel (pbrt's world is left-handed, as the
/// book's is): the equirectangular image's centre to the left of the view, a quarter in from
/// its left along it, its top row up; the equal-area image's centre up.
#[test]
fn a_spherical_projection_sees_what_pbrts_spherical_camera_sees() {
    for (key, mapping, name) in [
        (
            "equirectangular",
            SphericalMapping::Equirectangular,
            "equirectangular",
        ),
        ("equal-area", SphericalMapping::EqualArea, "equalarea"),
    ] {
        let ours = yaml(&format!("  projection: {key}\n")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(ours.camera.spherical_mapping(), Some(mapping));
        let theirs = pbrt(&format!(
            "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"spherical\" \"string mapping\" \"{name}\"\n\
             Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 16\nWorldBegin\n"
        ));
        for (x, y) in [
            (16.0, 8.0),
            (8.0, 8.0),
            (3.5, 1.5),
            (27.25, 12.0),
            (16.0, 0.0),
        ] {
            let (a, b) = (
                ours.camera.ray_through(x, y).direction,
                theirs.camera.ray_through(x, y).direction,
            );
            assert!((a - b).length() < 1e-12, "{key} ({x}, {y}): {a:?} vs {b:?}");
        }
    }
    let ours = yaml("  projection: equirectangular\n").unwrap();
    let d = |x, y| ours.camera.ray_through(x, y).direction;
    assert!(
        (d(8.0, 8.0) - glam::DVec3::Z).length() < 1e-12,
        "{:?}",
        d(8.0, 8.0)
    );
    assert!((d(16.0, 8.0) - glam::DVec3::NEG_X).length() < 1e-12);
    assert!((d(16.0, 0.0) - glam::DVec3::Y).length() < 1e-12);
    // `perspective` is the default's name.
    let pinhole = yaml("  projection: perspective\n  field-of-view: 1\n").unwrap();
    assert_eq!(pinhole.camera.spherical_mapping(), None);
}

#[test]
fn a_bad_projection_or_a_key_a_spherical_camera_cannot_use_is_refused_at_its_key() {
    assert_located(
        yaml("  projection: fisheye\n"),
        7,
        15,
        "projection",
        "unknown projection `fisheye`",
    );
    assert_located(yaml("  projection: 3\n"), 7, 15, "projection", "");
    for key in [
        "field-of-view: 1",
        "field-of-view-degrees: 90",
        "aperture: 0.1",
    ] {
        let name = key.split(':').next().unwrap();
        assert_located(
            yaml(&format!("  projection: equal-area\n  {key}\n")),
            8,
            3,
            name,
            "no meaning for it",
        );
    }
    // A perspective camera still needs its field of view.
    assert_located(yaml(""), 1, 3, "field-of-view", "field-of-view");
}

/// The film keys make the sensor pbrt-v4's `Film` and shutter make for the same settings,
/// to the bit; without them the camera records the radiance as it is.
#[test]
fn the_film_keys_make_pbrts_sensor() {
    let same = |keys: &str, camera: &str, film: &str| {
        let ours = yaml(&format!("  field-of-view: 1\n{keys}")).unwrap_or_else(|e| panic!("{e}"));
        let theirs = pbrt(&format!(
            "Camera \"perspective\" {camera}\nFilm \"rgb\" {film}\nWorldBegin\n"
        ));
        assert_eq!(ours.camera.sensor(), theirs.camera.sensor(), "{keys}");
        ours
    };
    let plain = same("", "", "");
    assert!(plain.camera.sensor().is_identity());
    let c = Color::new(0.2, 0.4, 0.8);
    let iso = same("  iso: 200\n", "", "\"float iso\" 200");
    assert_eq!(iso.camera.record(c), c * 2.0);
    let time = same("  exposure-time: 0.5\n", "\"float shutterclose\" 0.5", "");
    assert_eq!(time.camera.record(c), c * 0.5);
    same("  white-balance: 3000\n", "", "\"float whitebalance\" 3000");
    let all = same(
        "  iso: 400\n  exposure-time: 0.25\n  white-balance: 5000\n  max-component: 2\n",
        "\"float shutterclose\" 0.25",
        "\"float iso\" 400 \"float whitebalance\" 5000 \"float maxcomponentvalue\" 2",
    );
    assert_eq!(all.camera.sensor().max_component(), Some(2.0));
    // The exposure time is the film's, not the shutter's interval of object motions.
    assert_eq!(time.camera.shutter(), (0.0, 1.0));
    // On a spherical camera too.
    let spherical = yaml("  projection: equirectangular\n  iso: 50\n").unwrap();
    assert_eq!(spherical.camera.record(c), c * 0.5);
}

#[test]
fn a_bad_film_value_is_refused_at_its_key() {
    let at = |keys: &str, key: &str, words: &str| {
        assert_located(
            yaml(&format!("  field-of-view: 1\n{keys}")),
            8,
            5 + key.len(),
            key,
            words,
        );
    };
    at("  iso: 0\n", "iso", "must be above 0");
    at("  iso: high\n", "iso", "");
    at("  exposure-time: -1\n", "exposure-time", "must be above 0");
    at(
        "  white-balance: -3000\n",
        "white-balance",
        "colour temperature",
    );
    at("  max-component: 0\n", "max-component", "must be above 0");
    at(
        "  iso: 1e308\n  exposure-time: 1e300\n",
        "iso",
        "largest number",
    );
}

/// The film keys work on the viewport and zoom cameras as on the book's.
#[test]
fn film_keys_work_on_viewport_and_zoom_cameras() {
    let c = Color::new(0.2, 0.4, 0.8);
    let viewport = load_str(
        "- add: camera\n  width: 8\n  height: 8\n  viewport: [1, 1]\n  iso: 200\n",
        Path::new("scene.yml"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(viewport.camera.record(c), c * 2.0);
    let zoom = load_str(
        "- add: camera\n  width: 8\n  height: 8\n  zoom: 1\n  exposure-time: 0.5\n",
        Path::new("scene.yml"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(zoom.camera.record(c), c * 0.5);
}

/// `max-component` caps the sensor's value before the white balance, as pbrt-v4's RGB film
/// does: the capped record is the uncapped one scaled, and its largest component is not the
/// cap (capping after the balance would make it exactly the cap).
#[test]
fn the_max_component_cap_comes_before_the_white_balance() {
    let c = Color::new(8.0, 1.0, 0.5);
    let free = yaml("  field-of-view: 1\n  white-balance: 3000\n").unwrap();
    let capped = yaml("  field-of-view: 1\n  white-balance: 3000\n  max-component: 2\n").unwrap();
    let (f, k) = (free.camera.record(c), capped.camera.record(c));
    let scale = k.red / f.red;
    assert!(scale < 1.0, "{f:?} {k:?}");
    for (a, b) in [(f.green, k.green), (f.blue, k.blue)] {
        assert!(
            (a * scale - b).abs() < 1e-9 * a.abs().max(1.0),
            "{f:?} {k:?}"
        );
    }
    let largest = k.red.max(k.green).max(k.blue);
    assert!((largest - 2.0).abs() > 0.02, "{k:?}");
}
