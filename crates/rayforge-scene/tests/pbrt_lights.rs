//! pbrt-v4's lights through the reader, beyond what `pbrt.rs` covers: image skies in either
//! layout (pbrt-v4's square equal-area maps and the latitude–longitude maps twice as wide as
//! high that pbrt-v3 read), each placed and scaled as pbrt says, and rendered against the
//! irradiance they give.

mod support;

use rayforge::Color;
use rayforge_scene::{LoadOptions, Scene, SceneError};
use std::f64::consts::PI;
use std::path::Path;

fn load_in(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    let path = dir.join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

/// pbrt's direction (+z up, φ from +x towards +y) of the point `(x, y)` of a
/// latitude–longitude map `w × h`, in texels.
fn lat_long_direction(x: f64, y: f64, w: usize, h: usize) -> glam::DVec3 {
    let (phi, theta) = (2.0 * PI * x / w as f64, PI * y / h as f64);
    glam::DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// A sky of 16 × 8 texels that differs by direction everywhere: brighter towards +x and the
/// pole, and brightest below the horizon, which a surface facing up never sees.
fn lat_long_texel(column: usize, row: usize) -> [f32; 3] {
    let below = if row >= 4 { 20.0 } else { 0.0 };
    let v = 1.0 + column as f32 * 0.25 + (7 - row) as f32 * 0.5 + below;
    [v, 0.5 * v, 2.0]
}

const HEAD: &str = "Camera \"perspective\"\nWorldBegin\n";

#[test]
fn an_infinite_light_reads_a_lat_long_image_placed_and_scaled_as_pbrt_says() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (16, 8);
    support::write_pfm(&dir.path().join("sky.pfm"), w, h, lat_long_texel);
    // Mirrored in x, as Bitterli's breakfast room's sky is, and turned.
    let text = format!(
        "{HEAD}AttributeBegin\nScale -1 1 1\nRotate 30 0 0 1\nLightSource \"infinite\" \
         \"string filename\" \"sky.pfm\" \"float scale\" 2\nAttributeEnd\n"
    );
    let scene = load_in(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    let map = scene.world.environment.as_ref().expect("a map");
    let world_from_light = glam::DMat3::from_diagonal(glam::DVec3::new(-1.0, 1.0, 1.0))
        * glam::DMat3::from_rotation_z(PI / 6.0);
    for (c, r) in [(0, 0), (3, 5), (15, 2), (7, 7)] {
        for (dx, dy) in [(0.5, 0.5), (0.05, 0.05), (0.95, 0.95)] {
            let local = lat_long_direction(c as f64 + dx, r as f64 + dy, w, h);
            let [a, b, d] = lat_long_texel(c, r);
            let want = Color::new(f64::from(a), f64::from(b), f64::from(d)) * 2.0;
            assert_eq!(
                map.radiance(world_from_light * local),
                want,
                "texel ({c}, {r})"
            );
        }
    }
    // Neither square nor twice as wide as high: refused, naming both layouts.
    support::write_pfm(&dir.path().join("wide.pfm"), 3, 1, |_, _| [1.0; 3]);
    let e = load_in(
        dir.path(),
        &format!("{HEAD}LightSource \"infinite\" \"string filename\" \"wide.pfm\"\n"),
    )
    .unwrap_err();
    assert!(e.message.contains("3×1"), "{e}");
    assert!(
        e.message.contains("square") && e.message.contains("twice as wide"),
        "{e}"
    );
    assert_eq!(e.key.as_deref(), Some("string filename"), "{e}");
    // `illuminance` as pbrt-v4 computes it for an equal-area map (its 2π / N: half the solid
    // angle of its pixels), with each texel's own solid angle: a grey sky's upper hemisphere
    // then gives π/2 per unit of radiance, in either layout.
    support::write_pfm(&dir.path().join("grey.pfm"), w, h, |_, _| [1.0; 3]);
    let scene = load_in(
        dir.path(),
        &format!(
            "{HEAD}LightSource \"infinite\" \"string filename\" \"grey.pfm\" \"float illuminance\" 3\n"
        ),
    )
    .unwrap();
    let k: f64 = (0..h / 2)
        .map(|r| {
            let (a, b) = (PI * r as f64 / h as f64, PI * (r + 1) as f64 / h as f64);
            let centre = PI * (r as f64 + 0.5) / h as f64;
            // w texels of solid angle 2π/w (cos a − cos b), halved, at their centres' cosine.
            (a.cos() - b.cos()) * 2.0 * PI * centre.cos() * 0.5
        })
        .sum();
    let got = scene
        .world
        .environment
        .as_ref()
        .unwrap()
        .radiance(glam::DVec3::Z);
    assert!((got.green - 3.0 / k).abs() < 1e-9, "{got:?} vs {}", 3.0 / k);
    assert!((k - PI / 2.0).abs() < 0.05, "{k}");
}

/// A camera above a large diffuse floor facing up (+z), seeing only the floor, with direct
/// light alone, under the light sources `lights`.
fn floor_under(lights: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20\n\
         Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\n{lights}\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
         Shape \"trianglemesh\" \"point3 P\" [-50 -50 0 50 -50 0 50 50 0 -50 50 0] \
         \"integer indices\" [0 1 2 0 2 3]\n"
    )
}

/// Asserts that the image's green channel is `want` within 4 standard errors, and that the
/// error is under 1 % of it (the pixels are independent estimates of one value: the floor is
/// lit alike everywhere the camera sees); the error.
#[track_caller]
fn assert_floor_is(scene: &Scene, want: f64) -> f64 {
    let film = support::render(scene, 24, 24, 16).resolve();
    let values: Vec<f64> = film.pixels().iter().map(|c| c.green).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();
    assert!(
        (mean - want).abs() < 4.0 * se + 1e-9,
        "{mean} ± {se} vs {want}"
    );
    assert!(se < 0.01 * want, "{se}");
    se
}

#[test]
fn a_lat_long_sky_lights_a_floor_with_its_upper_hemisphere_irradiance() {
    // The floor's radiance is ρ/π × E, E = ∫ L cos θ dω over the upper hemisphere: for texels
    // of constant radiance, each row's texels give L × 2π/W × (cos² a − cos² b)/2. The sky's
    // light below the horizon, twenty times brighter, must not reach it, and the light
    // towards +x must count as much as towards −x.
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (16, 8);
    support::write_pfm(&dir.path().join("sky.pfm"), w, h, lat_long_texel);
    let scene = load_in(
        dir.path(),
        &floor_under("LightSource \"infinite\" \"string filename\" \"sky.pfm\""),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let irradiance = lat_long_irradiance(1.0, false);
    let want = 0.5 / PI * irradiance;
    assert_floor_is(&scene, want);
}

/// The irradiance a floor facing up (+z) gets from a sky of `lat_long_texel`s (green
/// channel) times `scale`, placed by `Rotate 180 1 0 0` where `turned` (its lower half up).
fn lat_long_irradiance(scale: f64, turned: bool) -> f64 {
    let (w, h) = (16, 8);
    let rows = if turned { h / 2..h } else { 0..h / 2 };
    let mut irradiance = 0.0;
    for r in rows {
        let (a, b) = (PI * r as f64 / h as f64, PI * (r + 1) as f64 / h as f64);
        let band = 2.0 * PI / w as f64 * (a.cos().powi(2) - b.cos().powi(2)).abs() / 2.0;
        for c in 0..w {
            irradiance += f64::from(lat_long_texel(c, r)[1]) * band;
        }
    }
    irradiance * scale
}

#[test]
fn several_infinite_lights_are_summed_and_each_sampled() {
    // Two image skies (the second turned over, so that its bright lower half lights the floor,
    // and scaled) and a uniform one: the floor's irradiance is the sum of the three.
    let dir = tempfile::tempdir().unwrap();
    support::write_pfm(&dir.path().join("sky.pfm"), 16, 8, lat_long_texel);
    let lights = "LightSource \"infinite\" \"string filename\" \"sky.pfm\"\n\
                  AttributeBegin\nRotate 180 1 0 0\nLightSource \"infinite\" \"string filename\" \
                  \"sky.pfm\" \"float scale\" 0.25\nAttributeEnd\n\
                  LightSource \"infinite\" \"rgb L\" [0.3 0.3 0.3]";
    let scene = load_in(dir.path(), &floor_under(lights)).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.world.environment.is_some());
    assert_eq!(scene.world.more_environments.len(), 1);
    // The uniform sky went into the first map, and the background is the maps.
    assert_eq!(scene.world.background, Color::BLACK);
    let irradiance = lat_long_irradiance(1.0, false) + lat_long_irradiance(0.25, true) + PI * 0.3;
    let want = 0.5 / PI * irradiance;
    let se = assert_floor_is(&scene, want);
    // The first sky alone gives less by the others' share (the test tells them apart).
    let alone = 0.5 / PI * lat_long_irradiance(1.0, false);
    assert!(want - alone > 20.0 * se, "{want} vs {alone}");
}

#[test]
fn a_portal_is_checked_and_the_sky_is_the_same_with_or_without_it() {
    let dir = tempfile::tempdir().unwrap();
    support::write_pfm(&dir.path().join("sky.pfm"), 16, 8, lat_long_texel);
    let sky = "LightSource \"infinite\" \"string filename\" \"sky.pfm\"";
    let window = "\"point3 portal\" [-1 -1 3  1 -1 3  1 1 3  -1 1 3]";
    let plain = load_in(dir.path(), &floor_under(sky)).unwrap();
    let text = floor_under(&format!("{sky} {window}"));
    let portal = load_in(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    // The same light: the same map, placed alike.
    assert_eq!(portal.world.environment, plain.world.environment);
    let warning = portal
        .warnings
        .iter()
        .find(|w| w.message.contains("portal"))
        .expect("a warning that the portal is not sampled through");
    assert_eq!(warning.key.as_deref(), Some("point3 portal"), "{warning}");
    // Line 5 of `floor_under`: the light sources.
    assert_eq!(warning.span.map(|s| s.line), Some(5), "{warning}");
    // Not a rectangle, or not four corners: refused at the parameter, as pbrt-v4 refuses.
    for (bad, part) in [
        ("[-1 -1 3  1 -1 3  2 1 3  -1 1 3]", "rectangle"),
        ("[-1 -1 3  1 -1 3  1 1 3]", "four points"),
        ("[0 0 3  0 0 3  1 1 3  -1 1 3]", "distinct"),
    ] {
        let text = floor_under(&format!("{sky} \"point3 portal\" {bad}"));
        let e = load_in(dir.path(), &text).expect_err(bad);
        assert!(e.message.contains(part), "{bad}: {e}");
        assert_eq!(e.key.as_deref(), Some("point3 portal"), "{e}");
    }
}
