//! pbrt-v4's cameras and film sensor: the imaging ratio (`iso`, the shutter) and white
//! balance, `screenwindow` and `frameaspectratio`, the spherical camera's layouts, and the
//! realistic camera: its lens files (written in `fixtures/lenses/`), parameters and located
//! refusals; and the same rendered: the sensor's scale and white balance over whole images,
//! and the directions each pixel of a spherical camera sees.

mod support;

use rayforge::Color;
use rayforge_scene::pbrt::PbrtLimits;
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

/// A scene of `text` in a folder of its own beside the lens files of `lenses` (name, text),
/// loaded within `limits`.
fn load_with_lenses(
    text: &str,
    lenses: &[(&str, &str)],
    limits: PbrtLimits,
) -> (tempfile::TempDir, Result<Scene, SceneError>) {
    let dir = tempfile::tempdir().unwrap();
    for (name, lens) in lenses {
        std::fs::write(dir.path().join(name), lens).unwrap();
    }
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    let options = LoadOptions {
        pbrt: limits,
        ..LoadOptions::default()
    };
    let loaded = rayforge_scene::load_file_with(&path, &options);
    (dir, loaded)
}

/// The error a load gave, which must have been refused.
fn refusal(loaded: Result<Scene, SceneError>) -> SceneError {
    match loaded {
        Err(e) => e,
        Ok(_) => panic!("read, not refused"),
    }
}

const BICONVEX: &str = include_str!("fixtures/lenses/biconvex.dat");
const TWO_LENSES: &str = include_str!("fixtures/lenses/two-lenses.dat");

/// A realistic camera of `params` looking down +z, over the lens files of the fixtures.
fn realistic(params: &str) -> (tempfile::TempDir, Result<Scene, SceneError>) {
    load_with_lenses(
        &format!(
            "LookAt 0 0 0  0 0 1  0 1 0\nFilm \"rgb\" \"integer xresolution\" 60 \"integer yresolution\" 40\nCamera \"realistic\" {params}\nWorldBegin\n"
        ),
        &[("biconvex.dat", BICONVEX), ("two-lenses.dat", TWO_LENSES)],
        PbrtLimits::DEFAULT,
    )
}

#[test]
fn a_realistic_camera_is_its_lens_file_focused_at_its_distance() {
    let (_dir, loaded) = realistic(
        "\"string lensfile\" \"biconvex.dat\" \"float focusdistance\" 1 \"float aperturediameter\" 4",
    );
    let scene = loaded.unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let lens = scene.camera.lens_system().expect("a lens system");
    // The thick-lens formula's film distance for this lens at 1 m (f = 50.85 mm, principal
    // planes 1.695 mm inside each vertex; the library's tests derive it): 52.045 mm.
    assert!(
        (lens.film_distance() - 0.052_045).abs() < 1e-6,
        "{}",
        lens.film_distance()
    );
    assert!((lens.film_diagonal() - 0.035).abs() < 1e-15);
    // The image's centre looks down pbrt's +z, its left edge towards −x as the perspective
    // camera's does (the lens turns the image over; the film is read turned back).
    let sample = |x: f64| rayforge::camera::CameraSample {
        x,
        y: 20.0,
        lens_u: 0.5,
        lens_v: 0.5,
        time: 0.5,
    };
    let centre = scene.camera.ray_for_sample(&sample(30.0)).expect("through");
    assert!(
        (centre.ray.direction - glam::DVec3::Z).length() < 1e-3,
        "{centre:?}"
    );
    assert!(centre.weight > 0.0);
    let left = scene.camera.ray_for_sample(&sample(1.0)).expect("through");
    let pinhole = load("LookAt 0 0 0  0 0 1  0 1 0\nFilm \"rgb\" \"integer xresolution\" 60 \"integer yresolution\" 40\nCamera \"perspective\"\nWorldBegin\n");
    let pinhole_left = pinhole.camera.ray_through(1.0, 20.0).direction;
    assert!(
        left.ray.direction.x < -0.1 && pinhole_left.x < 0.0,
        "{left:?}"
    );
    // Resized (--width), the same lens over the new aspect ratio's film.
    let resized = scene.camera.resized(30, 30);
    assert_eq!(resized.lens_system(), Some(lens));
}

#[test]
fn a_realistic_cameras_film_diagonal_and_diaphragm_are_read() {
    let (_dir, loaded) = load_with_lenses(
        "Film \"rgb\" \"float diagonal\" 20\nCamera \"realistic\" \"string lensfile\" \"l.dat\" \"string aperture\" \"star\" \"float aperturediameter\" 30\nWorldBegin\n",
        &[("l.dat", TWO_LENSES)],
        PbrtLimits::DEFAULT,
    );
    let scene = loaded.unwrap_or_else(|e| panic!("{e}"));
    let lens = scene.camera.lens_system().expect("a lens system");
    assert!((lens.film_diagonal() - 0.02).abs() < 1e-15);
    // Wider than the file's 8 mm stop: clamped, and said so at the directive.
    assert_eq!(lens.clamped_aperture(), Some((30.0, 8.0)));
    let warning = scene.warnings.first().expect("a warning");
    assert_eq!(warning.span.map(|s| s.line), Some(2), "{warning}");
    assert!(warning.message.contains("8 mm"), "{warning}");
}

#[test]
fn a_realistic_camera_refuses_what_it_cannot_read_where_it_is_written() {
    // No lens file named: at the directive.
    let (_d, loaded) = realistic("\"float focusdistance\" 2");
    let e = refusal(loaded);
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((3, 1)), "{e}");
    assert!(e.message.contains("lensfile"), "{e}");
    // A lens file that is not there, or a folder: at the parameter that names it.
    for name in ["missing.dat", "."] {
        let (_d, loaded) = realistic(&format!("\"string lensfile\" \"{name}\""));
        let e = refusal(loaded);
        assert!(e.path.ends_with("s.pbrt"), "{e}");
        assert_eq!(e.span.map(|s| s.line), Some(3), "{e}");
        assert_eq!(e.key.as_deref(), Some("string lensfile"), "{e}");
    }
    let (_d, loaded) = realistic("\"string lensfile\" \".\"");
    assert!(refusal(loaded).message.contains("not a regular file"));
    // An image aperture: at the parameter.
    let (_d, loaded) =
        realistic("\"string lensfile\" \"biconvex.dat\" \"string aperture\" \"bokeh.png\"");
    let e = refusal(loaded);
    assert_eq!(e.key.as_deref(), Some("string aperture"), "{e}");
    assert!(
        e.message.contains("gaussian, square, pentagon, star"),
        "{e}"
    );
    // Focused closer than the lens can: at the directive.
    let (_d, loaded) =
        realistic("\"string lensfile\" \"biconvex.dat\" \"float focusdistance\" 0.1");
    let e = refusal(loaded);
    assert_eq!(e.span.map(|s| s.line), Some(3), "{e}");
    assert!(e.message.contains("too short"), "{e}");
}

#[test]
fn a_hostile_lens_file_is_refused_at_its_line_and_column() {
    let scene = "Camera \"realistic\" \"string lensfile\" \"l.dat\"\nWorldBegin\n";
    let refused = |lens: &str, limits: PbrtLimits| {
        let (_d, loaded) = load_with_lenses(scene, &[("l.dat", lens)], limits);
        let e = refusal(loaded);
        assert!(e.path.ends_with("l.dat"), "{e}");
        (e.span.map(|s| (s.line, s.column)), e.message)
    };
    let (at, message) = refused("# lens\n50 5 1.5 20\n-50 fifty 1 20\n", PbrtLimits::DEFAULT);
    assert_eq!(at, Some((3, 5)), "{message}");
    assert!(message.contains("`fifty`"), "{message}");
    let (at, message) = refused("50 5 1.5 20\n-50 NaN 1 20\n", PbrtLimits::DEFAULT);
    assert_eq!(at, Some((2, 5)), "{message}");
    let (at, message) = refused("50 5 1.5 20\n-50 50 1\n", PbrtLimits::DEFAULT);
    assert_eq!(at, Some((2, 8)), "{message}");
    // An index below 1 (nor 0, air): at its row.
    let (at, message) = refused("50 5 1.5 20\n  -50 50 0.5 20\n", PbrtLimits::DEFAULT);
    assert_eq!(at, Some((2, 3)), "{message}");
    assert!(message.contains("index of refraction"), "{message}");
    // More rows than the limit: at the first row past it, naming the flag.
    let limits = PbrtLimits {
        lens_rows: 4,
        ..PbrtLimits::DEFAULT
    };
    let (at, message) = refused(TWO_LENSES, limits);
    assert_eq!(at, Some((8, 2)), "{message}");
    assert!(message.contains("--max-pbrt-lens-rows"), "{message}");
    // Past the file size limit: refused before reading, at the parameter.
    let small = PbrtLimits {
        file_bytes: 100,
        ..PbrtLimits::DEFAULT
    };
    let (_d, loaded) = load_with_lenses(scene, &[("l.dat", TWO_LENSES)], small);
    let e = refusal(loaded);
    assert!(
        e.path.ends_with("s.pbrt") && e.message.contains("--max-pbrt-file-bytes"),
        "{e}"
    );
    // Binary: at the first byte that is not text.
    let (at, _) = refused("50 5 1.5 20\n-50 50\u{0} 1 20\n", PbrtLimits::DEFAULT);
    assert_eq!(at, Some((2, 7)));
}

/// A small lit scene of pbrt-v4's: a glossy sphere and a diffuse floor under a sky and a lamp,
/// the film `film`'s parameters and the camera's `camera`: paths of several bounces, so
/// every pixel's value is a sum of many differently weighted samples.
fn lit_scene(camera: &str, film: &str) -> Scene {
    load(&format!(
        "LookAt 0 1 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 50 {camera}\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 12 {film}\n\
         WorldBegin\nLightSource \"infinite\" \"rgb L\" [0.2 0.3 0.5]\n\
         AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [6 5 4]\n\
         Translate 1.5 3 -1\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n\
         Material \"coateddiffuse\" \"rgb reflectance\" [0.7 0.2 0.1] \"float roughness\" 0.1\n\
         AttributeBegin\nTranslate 0 0.6 0\nShape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
         Shape \"trianglemesh\" \"point3 P\" [-5 0 -5  5 0 -5  5 0 5  -5 0 5] \
         \"integer indices\" [0 2 1  0 3 2]\n"
    ))
}

/// The imaging ratio scales the rendered image, not just one recorded colour: every pixel of
/// a render with `iso` 400 and the shutter open half the time is twice the same render's
/// without them (the same seed, so the same paths), to the bit, as doubling rounds nothing;
/// a ratio of 0.3 (`iso` 60) within the rounding of each sample's product.
#[test]
fn the_imaging_ratio_scales_the_rendered_image_pixel_by_pixel() {
    let render = |camera: &str, film: &str| {
        let scene = lit_scene(camera, film);
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        support::render(&scene, 16, 12, 8).resolve()
    };
    let plain = render("", "");
    let shutter = "\"float shutteropen\" 0 \"float shutterclose\" 0.5";
    let doubled = render(shutter, "\"float iso\" 400");
    let scaled = render(shutter, "\"float iso\" 60");
    let mut lit = 0;
    for y in 0..12 {
        for x in 0..16 {
            let p = plain.pixel_at(x, y);
            assert_eq!(doubled.pixel_at(x, y), p * 2.0, "pixel ({x}, {y})");
            let s = scaled.pixel_at(x, y);
            for (a, b) in [(s.red, p.red), (s.green, p.green), (s.blue, p.blue)] {
                assert!(
                    (a - 0.3 * b).abs() <= 1e-12 * b.abs(),
                    "pixel ({x}, {y}): {s:?}"
                );
            }
            if p.red > 0.05 && p.red != p.green {
                lit += 1;
            }
        }
    }
    // The comparison means something: most pixels are lit, and not grey.
    assert!(lit > 100, "{lit} pixels lit");
}

/// A grey surface lit by a blackbody light of temperature T renders neutral grey through a
/// film balanced at T, and orange without the balance. pbrt-v4 balances from its daylight
/// illuminant `D(T)`, a blackbody at T × 1.4388 / 1.4380 below 4000 K, so a blackbody of T
/// itself is neutral within that shift of 0.06 % in temperature: the tolerance, 0.5 % of
/// the green, is about ten times what the shift leaves (above 4000 K `D(T)` is CIE daylight,
/// off the blackbody locus, and a blackbody of T is not neutral under it).
#[test]
fn white_balance_renders_a_surface_under_a_blackbody_of_its_temperature_grey() {
    for t in [2700.0, 3500.0] {
        let render = |film: &str| {
            let scene = load(&format!(
                "Camera \"perspective\" \"float fov\" 40\n\
                 Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 {film}\n\
                 WorldBegin\nLightSource \"distant\" \"blackbody L\" [{t}] \"float scale\" 3\n\
                 Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
                 Shape \"trianglemesh\" \"point3 P\" [-1 -1 1  1 -1 1  1 1 1  -1 1 1] \
                 \"integer indices\" [0 1 2  0 2 3]\n"
            ));
            assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
            support::render(&scene, 8, 8, 4).resolve()
        };
        let balanced = render(&format!("\"float whitebalance\" {t}"));
        let raw = render("");
        for (x, y) in [(2, 2), (4, 4), (5, 3)] {
            let c = balanced.pixel_at(x, y);
            assert!(c.green > 0.1, "{t} K: lit, {c:?}");
            for v in [c.red, c.blue] {
                assert!(
                    (v - c.green).abs() < 5e-3 * c.green,
                    "{t} K: {c:?} is not grey"
                );
            }
            let c = raw.pixel_at(x, y);
            assert!(
                c.red > 1.3 * c.blue && c.red > c.green,
                "{t} K: {c:?} is not orange"
            );
        }
    }
}

/// The direction of pbrt-v4's spherical camera at image point `(u, v)` (fractions of the width
/// and height) in the world, for a camera left where pbrt's is without a transform: pbrt's
/// map's direction (equirectangular: θ = π v, φ = 2π u; equal area: Clarberg's octahedral
/// map), then y and z swapped as pbrt's `SphericalCamera` swaps them.
fn pbrt_spherical_direction(equal_area: bool, u: f64, v: f64) -> glam::DVec3 {
    use std::f64::consts::{FRAC_PI_4, PI};
    let d = if equal_area {
        let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        let signed = 1.0 - (a.abs() + b.abs());
        let r = 1.0 - signed.abs();
        let phi = if r == 0.0 {
            FRAC_PI_4
        } else {
            ((b.abs() - a.abs()) / r + 1.0) * FRAC_PI_4
        };
        let z = (1.0 - r * r).copysign(signed);
        let s = r * (2.0 - r * r).max(0.0).sqrt();
        glam::DVec3::new(phi.cos().copysign(a) * s, phi.sin().copysign(b) * s, z)
    } else {
        let (theta, phi) = (PI * v, 2.0 * PI * u);
        glam::DVec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    };
    glam::DVec3::new(d.x, d.z, d.y)
}

/// Under a sky whose radiance is its direction (each texel of a latitude–longitude map the
/// unit vector of its centre plus 1, so every channel is positive), a spherical camera's
/// pixel sees the direction its mapping gives its centre: the pixel averages the directions
/// over its area, within 0.04 of the centre's at these sizes (a pixel spans 11° at most, a
/// texel 1.4°). A mapping mirrored, or turned by a quarter, is off by 1 or more somewhere.
#[test]
fn a_spherical_cameras_pixels_see_the_directions_of_its_mapping() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (256, 128);
    // The latitude–longitude layout as the reader takes it: +z up, row 0 at +z, φ across
    // from +x towards +y.
    support::write_pfm(&dir.path().join("sky.pfm"), w, h, |c, r| {
        let theta = std::f64::consts::PI * (r as f64 + 0.5) / h as f64;
        let phi = std::f64::consts::TAU * (c as f64 + 0.5) / w as f64;
        let d = [
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        ];
        d.map(|v| (v + 1.0) as f32)
    });
    for (mapping, width, height) in [("equirectangular", 32, 16), ("equalarea", 24, 24)] {
        let text = format!(
            "Film \"rgb\" \"integer xresolution\" {width} \"integer yresolution\" {height}\n\
             Camera \"spherical\" \"string mapping\" \"{mapping}\"\n\
             WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.pfm\"\n"
        );
        let path = dir.path().join("s.pbrt");
        std::fs::write(&path, text).unwrap();
        let scene = rayforge_scene::load_file_with(&path, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let img = support::render(&scene, width, height, 16).resolve();
        let equal_area = mapping == "equalarea";
        let pixels: &[(usize, usize)] = if equal_area {
            &[
                (12, 12),
                (3, 9),
                (20, 5),
                (7, 18),
                (1, 1),
                (17, 22),
                (11, 2),
            ]
        } else {
            &[(16, 8), (8, 8), (3, 2), (27, 11), (20, 14), (10, 5)]
        };
        for &(x, y) in pixels {
            let want = pbrt_spherical_direction(
                equal_area,
                (x as f64 + 0.5) / width as f64,
                (y as f64 + 0.5) / height as f64,
            );
            let c = img.pixel_at(x, y);
            let got = glam::DVec3::new(c.red - 1.0, c.green - 1.0, c.blue - 1.0);
            assert!(
                (got - want).length() < 0.04,
                "{mapping} pixel ({x}, {y}) sees {got:?}, its mapping says {want:?}"
            );
        }
    }
}

/// pbrt-v4's `maxcomponentvalue` caps each sample where pbrt-v4's `RGBFilm::AddSample` does:
/// in its sensor's space (XYZ for the default sensor) after the imaging ratio. Two lamps face
/// the camera side by side, a bright one (`L` 6 5 4, whose largest component in XYZ is its Y,
/// 5.14) on the image's left, a dim one on its right; capped at 2, the bright one's pixels are
/// its radiance scaled to Y = 2, its hue kept (its red, 2.33, above the cap: the cap is not on
/// sRGB's channels), and the dim one's are as they were. With `iso` 200 the capped pixels do
/// not change (the ratio is applied before the cap) and the dim ones double. A cap above
/// every sample changes no bit of the image, and without one the sensor is the identity.
#[test]
fn the_largest_component_of_each_sample_is_capped_in_the_sensors_space() {
    let render = |film: &str| {
        let scene = load(&format!(
            "Camera \"perspective\" \"float fov\" 40\nPixelFilter \"box\"\n\
             Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 {film}\n\
             WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0 0 0]\n\
             AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [6 5 4]\n\
             Shape \"trianglemesh\" \"point3 P\" [-1 -1 1  0 -1 1  0 1 1  -1 1 1] \
             \"integer indices\" [0 2 1  0 3 2]\nAttributeEnd\n\
             AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [0.1 0.2 0.3]\n\
             Shape \"trianglemesh\" \"point3 P\" [0 -1 1  1 -1 1  1 1 1  0 1 1] \
             \"integer indices\" [0 2 1  0 3 2]\nAttributeEnd\n"
        ));
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        let sensor = *scene.camera.sensor();
        (sensor, support::render(&scene, 8, 8, 4).resolve())
    };
    let (plain_sensor, plain) = render("");
    assert!(plain_sensor.is_identity());
    let (_, capped) = render("\"float maxcomponentvalue\" 2");
    let (_, brighter) = render("\"float maxcomponentvalue\" 2 \"float iso\" 200");
    let (_, high) = render("\"float maxcomponentvalue\" 1e300");
    let bright = Color::new(6.0, 5.0, 4.0);
    let y = rayforge::shading::spectrum::linear_srgb_to_xyz(bright)[1];
    assert!((y - 5.14).abs() < 0.01, "{y}");
    let near = |a: Color, b: Color| {
        (a.red - b.red).abs() + (a.green - b.green).abs() + (a.blue - b.blue).abs() < 1e-12
    };
    for py in 0..8 {
        for px in 0..8 {
            let (p, c, b) = (
                plain.pixel_at(px, py),
                capped.pixel_at(px, py),
                brighter.pixel_at(px, py),
            );
            assert_eq!(high.pixel_at(px, py), p, "({px}, {py})");
            if px < 4 {
                assert_eq!(p, bright, "({px}, {py})");
                assert!(near(c, bright * (2.0 / y)), "({px}, {py}): {c:?}");
                assert!(near(b, c), "({px}, {py}): {b:?}");
            } else {
                assert_eq!(p, Color::new(0.1, 0.2, 0.3), "({px}, {py})");
                assert_eq!(c, p, "({px}, {py})");
                assert!(near(b, p * 2.0), "({px}, {py}): {b:?}");
            }
        }
    }
    // Refused: a cap of 0 or below, at the parameter.
    for bad in ["0", "-1"] {
        let Err(e) = load_text(&format!(
            "Camera \"perspective\"\nFilm \"rgb\" \"float maxcomponentvalue\" {bad}\nWorldBegin\n"
        )) else {
            panic!("{bad} refused");
        };
        let span = e.span.expect("a place");
        assert_eq!((span.line, span.column), (2, 12), "{e}");
        assert!(e.message.contains("above 0"), "{e}");
    }
}
