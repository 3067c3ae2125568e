//! pbrt-v4's lights through the reader, beyond what `pbrt.rs` covers: image skies in either
//! layout (pbrt-v4's square equal-area maps and the latitude–longitude maps twice as wide as
//! high that pbrt-v3 read), each placed and scaled as pbrt says, and rendered against the
//! irradiance they give; the goniometric and projection lights, their intensity per direction
//! against pbrt-v4's formulas and a floor they light against `I(ω) cos θ / d²`.

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

/// The image light of the scene's only light.
fn pattern_light(scene: &Scene) -> &rayforge::shading::PatternLight {
    match scene.world.lights.as_slice() {
        [rayforge::shading::Light::Pattern(l)] => l,
        other => panic!("one image light, not {other:?}"),
    }
}

/// A goniometric light's texel: every one apart, the channels apart too (pbrt-v4 averages
/// them).
fn gonio_texel(column: usize, row: usize) -> [f32; 3] {
    let v = 1.0 + column as f32 + 8.0 * row as f32;
    [v, 0.5 * v, 2.0]
}

/// pbrt-v4's goniometric intensity of the light of `rgb I`, scale `scale` and image
/// `gonio_texel` (`n × n`), along the light-space direction `w` (before its y–z swap):
/// `scale · I · Y(EqualAreaSphereToSquare(w'))` with `w' = (x, z, y)` and `Y` the average of
/// the nearest texel's channels.
fn gonio_intensity(i: f64, scale: f64, n: usize, w: glam::DVec3) -> f64 {
    let swapped = glam::DVec3::new(w.x, w.z, w.y).normalize();
    let (u, v) = rayforge::shading::equal_area_sphere_to_square(swapped);
    let at = |t: f64| ((t * n as f64) as usize).min(n - 1);
    let [r, g, b] = gonio_texel(at(u), at(v));
    scale * i * f64::from(r + g + b) / 3.0
}

/// A projection light's texel, every one apart.
fn slide_texel(column: usize, row: usize) -> [f32; 3] {
    let v = 1.0 + column as f32 + 4.0 * row as f32;
    [v, 2.0 * v, 0.25]
}

/// pbrt-v4's projection intensity (rgb) of a light of `scale`, `fov` degrees and image
/// `slide_texel` (`w × h`) along the light-space direction `d`: 0 below its near plane or
/// outside its screen window; else the nearest texel of the window's point, the light's y
/// flipped (pbrt-v4's `Scale 1 -1 1`) and the window ±aspect by ±1 (or ±1 by ±1/aspect).
fn slide_intensity(scale: f64, fov: f64, w: usize, h: usize, d: glam::DVec3) -> [f64; 3] {
    let d = glam::DVec3::new(d.x, -d.y, d.z).normalize();
    if d.z < 1e-3 {
        return [0.0; 3];
    }
    let t = (fov.to_radians() / 2.0).tan();
    let (px, py) = (d.x / (d.z * t), d.y / (d.z * t));
    let aspect = w as f64 / h as f64;
    let (ax, ay) = if aspect > 1.0 {
        (aspect, 1.0)
    } else {
        (1.0, 1.0 / aspect)
    };
    if px.abs() > ax || py.abs() > ay {
        return [0.0; 3];
    }
    let (u, v) = ((px + ax) / (2.0 * ax), (py + ay) / (2.0 * ay));
    let c = ((u * w as f64) as usize).min(w - 1);
    let r = ((v * h as f64) as usize).min(h - 1);
    slide_texel(c, r).map(|x| scale * f64::from(x))
}

#[test]
fn a_goniometric_light_gives_its_image_in_each_direction_as_pbrt_does() {
    let dir = tempfile::tempdir().unwrap();
    let n = 8;
    support::write_pfm(&dir.path().join("web.pfm"), n, n, gonio_texel);
    let text = format!(
        "{HEAD}AttributeBegin\nTranslate 1 2 3\nRotate 35 1 1 0\nLightSource \"goniometric\" \
         \"rgb I\" [2 2 2] \"float scale\" 0.5 \"string filename\" \"web.pfm\"\nAttributeEnd\n"
    );
    let scene = load_in(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    let light = pattern_light(&scene);
    let at = glam::DVec3::new(1.0, 2.0, 3.0);
    assert!((light.position - at).length() < 1e-12);
    let world_from_light = glam::DMat3::from_axis_angle(
        glam::DVec3::new(1.0, 1.0, 0.0).normalize(),
        35f64.to_radians(),
    );
    let mut seen = std::collections::HashSet::new();
    let mut rng = 7u64;
    for _ in 0..2000 {
        let mut next = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let w = glam::DVec3::new(next(), next(), next());
        if w.length() < 0.1 || w.length() > 1.0 {
            continue;
        }
        let want = gonio_intensity(2.0, 0.5, n, w);
        seen.insert(want.to_bits());
        // rayforge keeps I/π (a surface facing it gets π times its intensity).
        let got = light.intensity_at(at + world_from_light * w * 3.0) * PI;
        for c in [got.red, got.green, got.blue] {
            assert!((c - want).abs() < 1e-9 * want, "{w:?}: {got:?} vs {want}");
        }
    }
    assert!(seen.len() > 40, "{} texels met", seen.len());
    // `power`: pbrt-v4's k_e = 4π × the image's mean, I scaled so that I × k_e is the power
    // (I's luminance 1 for a grey rgb).
    let text = format!(
        "{HEAD}LightSource \"goniometric\" \"rgb I\" [2 2 2] \"float power\" 10 \
         \"string filename\" \"web.pfm\"\n"
    );
    let scene = load_in(dir.path(), &text).unwrap();
    let light = pattern_light(&scene);
    let mean: f64 = (0..n * n)
        .map(|i| {
            let [r, g, b] = gonio_texel(i % n, i / n);
            f64::from(r + g + b) / 3.0
        })
        .sum::<f64>()
        / (n * n) as f64;
    let i = light.intensity.green * PI;
    assert!((i * 4.0 * PI * mean - 10.0).abs() < 1e-9, "{i}");
}

#[test]
fn a_projection_light_gives_its_image_through_its_frustum_as_pbrt_does() {
    let dir = tempfile::tempdir().unwrap();
    for (w, h, fov) in [(4, 2, 60.0), (3, 5, 40.0)] {
        support::write_pfm(&dir.path().join("slide.pfm"), w, h, slide_texel);
        let text = format!(
            "{HEAD}AttributeBegin\nTranslate -1 0 2\nRotate 120 0 1 1\nLightSource \
             \"projection\" \"float scale\" 3 \"float fov\" {fov} \"string filename\" \
             \"slide.pfm\"\nAttributeEnd\n"
        );
        let scene = load_in(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
        let light = pattern_light(&scene);
        let at = glam::DVec3::new(-1.0, 0.0, 2.0);
        let world_from_light = glam::DMat3::from_axis_angle(
            glam::DVec3::new(0.0, 1.0, 1.0).normalize(),
            120f64.to_radians(),
        );
        let (mut lit, mut dark) = (std::collections::HashSet::new(), 0);
        let steps = 60;
        for i in 0..steps {
            for j in 0..steps {
                // Directions over and beyond the window, and some behind the light.
                let x = 2.4 * (i as f64 + 0.37) / steps as f64 - 1.2;
                let y = 2.4 * (j as f64 + 0.61) / steps as f64 - 1.2;
                let z = if (i + j) % 7 == 0 { -0.5 } else { 0.6 };
                let d = glam::DVec3::new(x, y, z);
                let want = slide_intensity(3.0, fov, w, h, d);
                let got = light.intensity_at(at + world_from_light * d * 2.0) * PI;
                for (g, v) in [got.red, got.green, got.blue].into_iter().zip(want) {
                    assert!((g - v).abs() <= 1e-9 * v, "{d:?}: {got:?} vs {want:?}");
                }
                if want[0] > 0.0 {
                    lit.insert(want[0].to_bits());
                } else {
                    dark += 1;
                }
            }
        }
        assert_eq!(lit.len(), w * h, "every texel met");
        assert!(dark > 100, "{dark}");
        // `power`: pbrt-v4's A × the mean of luminance × cos³θ at the texels' centres.
        let text = format!(
            "{HEAD}LightSource \"projection\" \"float power\" 7 \"float fov\" {fov} \
             \"string filename\" \"slide.pfm\"\n"
        );
        let scene = load_in(dir.path(), &text).unwrap();
        let scale = pattern_light(&scene).intensity.red * PI;
        let t = (f64::to_radians(fov) / 2.0).tan();
        let aspect = w as f64 / h as f64;
        let (ax, ay) = if aspect > 1.0 {
            (aspect, 1.0)
        } else {
            (1.0, 1.0 / aspect)
        };
        let area = 4.0 * t * t * aspect.max(1.0 / aspect);
        let mut sum = 0.0;
        for r in 0..h {
            for c in 0..w {
                let px = ax * (2.0 * (c as f64 + 0.5) / w as f64 - 1.0) * t;
                let py = ay * (2.0 * (r as f64 + 0.5) / h as f64 - 1.0) * t;
                let cos = 1.0 / (1.0 + px * px + py * py).sqrt();
                let [a, b, d] = slide_texel(c, r).map(f64::from);
                sum += Color::new(a, b, d).luminance() * cos.powi(3);
            }
        }
        let phi = scale * area * sum / (w * h) as f64;
        assert!((phi - 7.0).abs() < 1e-9, "{phi}");
    }
}

/// The path-traced floor of `floor_under(lights)` (a box filter: each pixel the mean over its
/// area) against `radiance` at the floor's points, averaged over each pixel by a grid of
/// points: the pixels' differences from it have mean 0 within 4 standard errors, and the
/// image differs from the same light made uniform (its mean over the pixels) by far more.
fn assert_floor_matches(dir: &Path, lights: &str, radiance: impl Fn(glam::DVec3) -> f64) {
    let text = floor_under(lights).replace(
        "WorldBegin",
        "PixelFilter \"box\"\nSampler \"independent\"\nWorldBegin",
    );
    let scene = load_in(dir, &text).unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (24, 24);
    let camera = scene.camera.resized(w, h);
    let film = support::render(&scene, w, h, 64).resolve();
    let grid = 6;
    let mut diffs = Vec::new();
    let mut wants = Vec::new();
    for py in 0..h {
        for px in 0..w {
            let mut want = 0.0;
            for k in 0..grid * grid {
                let x = px as f64 + ((k % grid) as f64 + 0.5) / grid as f64;
                let y = py as f64 + ((k / grid) as f64 + 0.5) / grid as f64;
                let ray = camera.ray_through(x, y);
                let t = -ray.origin.z / ray.direction.z;
                want += radiance(ray.origin + ray.direction * t);
            }
            want /= (grid * grid) as f64;
            diffs.push(film.pixels()[py * w + px].green - want);
            wants.push(want);
        }
    }
    let n = diffs.len() as f64;
    let mean = diffs.iter().sum::<f64>() / n;
    let var = diffs.iter().map(|d| (d - mean) * (d - mean)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();
    let level = wants.iter().sum::<f64>() / n;
    assert!(
        mean.abs() < 4.0 * se + 1e-9,
        "off by {mean} ± {se} (level {level})"
    );
    // Each pixel near its own expectation (the grid's error at the image's edges, and noise).
    let worst = diffs.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    let peak = wants.iter().fold(0.0f64, |m, v| m.max(*v));
    assert!(worst < 0.2 * peak, "{worst} vs {peak}");
    // The pattern shows: a uniform light of the same mean would be far off.
    let flat: f64 = wants.iter().map(|v| (v - level).abs()).sum::<f64>() / n;
    assert!(flat > 10.0 * se, "{flat} vs {se}");
}

#[test]
fn a_goniometric_light_lights_a_floor_by_its_intensity_cosine_over_distance_squared() {
    // Above the floor, its pole (the light's +y) turned down: the floor sees the square's
    // centre, several texels of it.
    let dir = tempfile::tempdir().unwrap();
    let n = 8;
    support::write_pfm(&dir.path().join("web.pfm"), n, n, gonio_texel);
    let lights = "AttributeBegin\nTranslate 0 0 2\nRotate -90 1 0 0\nLightSource \
                  \"goniometric\" \"rgb I\" [1 1 1] \"string filename\" \"web.pfm\"\n\
                  AttributeEnd";
    let light_at = glam::DVec3::new(0.0, 0.0, 2.0);
    let light_from_world = glam::DMat3::from_rotation_x(90f64.to_radians());
    assert_floor_matches(dir.path(), lights, |p| {
        let to = p - light_at;
        let d2 = to.length_squared();
        let cos = -to.z / d2.sqrt();
        let i = gonio_intensity(1.0, 1.0, n, light_from_world * to.normalize());
        0.5 / PI * i * cos / d2
    });
}

#[test]
fn a_projection_light_casts_its_image_on_a_floor() {
    // Looking down from above the floor (its +z turned to −z), the window's short side
    // inside the camera's view: its edges show.
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (4, 2);
    support::write_pfm(&dir.path().join("slide.pfm"), w, h, slide_texel);
    let lights = "AttributeBegin\nTranslate 0 0 2\nRotate 180 1 0 0\nLightSource \
                  \"projection\" \"float fov\" 30 \"string filename\" \"slide.pfm\"\n\
                  AttributeEnd";
    let light_at = glam::DVec3::new(0.0, 0.0, 2.0);
    let light_from_world = glam::DMat3::from_rotation_x(PI);
    assert_floor_matches(dir.path(), lights, |p| {
        let to = p - light_at;
        let d2 = to.length_squared();
        let cos = -to.z / d2.sqrt();
        let i = slide_intensity(1.0, 30.0, w, h, light_from_world * to);
        0.5 / PI * i[1] * cos / d2
    });
}

#[test]
fn image_lights_refuse_what_pbrt_refuses_at_the_parameter() {
    let dir = tempfile::tempdir().unwrap();
    support::write_pfm(&dir.path().join("wide.pfm"), 4, 2, slide_texel);
    let at = |text: &str| load_in(dir.path(), &format!("{HEAD}{text}\n"));
    // A missing file, at `filename` (line 3, the parameter's column).
    let e = at("LightSource \"goniometric\" \"string filename\" \"none.pfm\"").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("string filename"), "{e}");
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((3, 27)), "{e}");
    assert!(e.to_string().contains("s.pbrt:3:27"), "{e}");
    let e = at("LightSource \"projection\" \"string filename\" \"none.png\"").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("string filename"), "{e}");
    // Not an image.
    std::fs::write(dir.path().join("text.pfm"), "hello").unwrap();
    let e = at("LightSource \"projection\" \"string filename\" \"text.pfm\"").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("string filename"), "{e}");
    assert!(e.message.contains("text.pfm"), "{e}");
    // No file at all: at the directive.
    for light in ["goniometric", "projection"] {
        let e = at(&format!("LightSource \"{light}\"")).unwrap_err();
        assert!(e.message.contains("filename"), "{e}");
        assert_eq!(e.span.map(|s| s.line), Some(3), "{e}");
    }
    // A goniometric image that is not square.
    let e = at("LightSource \"goniometric\" \"string filename\" \"wide.pfm\"").unwrap_err();
    assert!(
        e.message.contains("4×2") && e.message.contains("square"),
        "{e}"
    );
    assert_eq!(e.key.as_deref(), Some("string filename"), "{e}");
    // A field of view out of (0, 180).
    for fov in ["0", "180", "-5"] {
        let e = at(&format!(
            "LightSource \"projection\" \"float fov\" {fov} \"string filename\" \"wide.pfm\""
        ))
        .unwrap_err();
        assert_eq!(e.key.as_deref(), Some("float fov"), "{e}");
    }
}
