//! pbrt-v4's cameras and film sensor: the imaging ratio (`iso`, the shutter) and white
//! balance, `screenwindow` and `frameaspectratio`, the spherical camera's layouts, and the
//! realistic camera's located refusal.

use rayforge::Color;
use rayforge_scene::{LoadOptions, Scene, SceneError};

fn load_text(text: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

fn load(text: &str) -> Scene {
    load_text(text).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn iso_and_the_shutter_scale_the_image_as_pbrts_imaging_ratio() {
    let record = |camera: &str, film: &str| {
        let scene = load(&format!(
            "Camera \"perspective\" {camera}\nFilm \"rgb\" {film}\nWorldBegin\n"
        ));
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        scene.camera.record(Color::new(0.2, 0.4, 0.8))
    };
    assert_eq!(record("", ""), Color::new(0.2, 0.4, 0.8));
    assert_eq!(record("", "\"float iso\" 200"), Color::new(0.4, 0.8, 1.6));
    let half = record("\"float shutteropen\" 0.25 \"float shutterclose\" 0.75", "");
    assert_eq!(half, Color::new(0.1, 0.2, 0.4));
}

#[test]
fn white_balance_takes_the_daylight_white_to_srgbs_white() {
    let scene =
        load("Camera \"perspective\"\nFilm \"rgb\" \"float whitebalance\" 3000\nWorldBegin\n");
    // Light of a 3000 K blackbody's colour (3000 × 1.4388 / 1.4380 correlated) is white.
    let t = 3000.0 * 1.4388 / 1.4380;
    let xyz =
        rayforge::shading::spectrum::spectrum_to_xyz(|l| rayforge::shading::spectrum::planck(l, t));
    let c = rayforge::shading::spectrum::xyz_to_linear_srgb(xyz.map(|v| v / xyz[1]));
    let out = scene.camera.record(c);
    for v in [out.red, out.green, out.blue] {
        assert!((v - 1.0).abs() < 2e-3, "{out:?}");
    }
    // Without the balance the same light is orange.
    assert!(c.red > 1.5 * c.blue, "{c:?}");
}

#[test]
fn a_screen_window_bounds_the_image() {
    let head = "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 100\n";
    let whole = load(&format!(
        "{head}Camera \"perspective\" \"float fov\" 90\nWorldBegin\n"
    ));
    let half = load(&format!(
        "{head}Camera \"perspective\" \"float fov\" 90 \"float screenwindow\" [-0.5 0.5 -0.5 0.5]\nWorldBegin\n"
    ));
    // The left edge's ray: 45° off the axis, then atan(0.5).
    let edge = |s: &Scene| {
        let d = s.camera.ray_through(0.0, 50.0).direction;
        (d.x.abs() / d.z.abs()).atan().to_degrees()
    };
    assert!((edge(&whole) - 45.0).abs() < 1e-9);
    assert!((edge(&half) - 0.5f64.atan().to_degrees()).abs() < 1e-9);
    // Off the axis: the window 0..1 across puts the image's left edge on the axis.
    let off = load(&format!(
        "{head}Camera \"perspective\" \"float fov\" 90 \"float screenwindow\" [0 1 -1 1]\nWorldBegin\n"
    ));
    let d = off.camera.ray_through(0.0, 50.0).direction;
    assert!(d.x.abs() < 1e-12 && (d.z - 1.0).abs() < 1e-12, "{d:?}");
    let right = off.camera.ray_through(100.0, 50.0).direction;
    assert!(right.x > 0.7, "the image's right is pbrt's +x: {right:?}");
    let Err(e) = load_text(&format!(
        "{head}Camera \"perspective\" \"float screenwindow\" [0 1 2]\nWorldBegin\n"
    )) else {
        panic!("three values");
    };
    assert_eq!(e.span.map(|s| s.line), Some(2), "{e}");
}

#[test]
fn a_spherical_cameras_centre_looks_where_pbrts_does() {
    let film = "Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 32\n";
    let scene = load(&format!(
        "{film}Camera \"spherical\" \"string mapping\" \"equirectangular\"\nWorldBegin\n"
    ));
    // pbrt: θ = π/2, φ = π, (−1, 0, 0) after its y–z swap.
    let d = scene.camera.ray_through(32.0, 16.0).direction;
    assert!(
        (d - glam::DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12,
        "{d:?}"
    );
    let up = scene.camera.ray_through(32.0, 0.0).direction;
    assert!((up.y - 1.0).abs() < 1e-12, "{up:?}");
    let quarter = scene.camera.ray_through(16.0, 16.0).direction;
    assert!((quarter.z - 1.0).abs() < 1e-12, "{quarter:?}");
    let square = "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n";
    let area = load(&format!("{square}Camera \"spherical\"\nWorldBegin\n"));
    // The equal-area square's centre is its pole, +z, which pbrt swaps to +y.
    let d = area.camera.ray_through(16.0, 16.0).direction;
    assert!((d.y - 1.0).abs() < 1e-12, "{d:?}");
}

#[test]
fn the_realistic_camera_is_refused_at_its_directive() {
    let Err(e) = load_text("LookAt 0 0 0  0 0 1  0 1 0\n  Camera \"realistic\" \"string lensfile\" \"a.dat\"\nWorldBegin\n") else {
        panic!("refused");
    };
    let span = e.span.expect("a place");
    assert_eq!((span.line, span.column), (2, 3), "{e}");
    assert!(e.path.ends_with("s.pbrt"), "{e}");
    assert_eq!(e.key.as_deref(), Some("Camera"), "{e}");
    assert!(e.message.contains("realistic"), "{e}");
}
