//! The path tracer's techniques, each switched off in turn (`next-event`, `mis`, `roulette`,
//! `glass-split`, `mirror-balls`, `sphere-cones`, `equiangular`, and the mirror balls' cap): every combination is an
//! unbiased estimate of the same image, so the image with a technique off has the mean of the
//! image with it on, within noise.
//!
//! The test is a z-test on the pixels' differences: two renders of the same scene, one with
//! the technique and one without, differ pixel by pixel by independent amounts of mean 0
//! (each pixel's samples are its own), whose mean over the image, divided by its standard
//! error, is about normal. Every render is seeded, so each test gives the same answer every
//! time; each one fails when the weighting of its technique is broken (a light counted twice,
//! a share weighed wrongly), as was checked by breaking each in turn.

mod support;

use rayforge::film::Film;
use rayforge::options::{MirrorBallBudget, Roulette, Techniques};
use rayforge::shading::EnvironmentMap;
use rayforge::Color;
use rayforge_scene::{load_str, Scene};
use std::path::Path;
use std::sync::Arc;
use support::render;

/// How many standard errors apart two means of one image may lie: beyond four, one test in
/// about 16,000 would fail by chance, and every test here is seeded, so it fails always or
/// never.
const Z_LIMIT: f64 = 4.0;

/// The scene of `body`, for the path tracer with the classic roulette (no pilot to learn one)
/// and at most `max_depth` bounces, through a camera at `from` looking at `to`.
fn scene(body: &str, from: [f64; 3], to: [f64; 3], max_depth: u32) -> Scene {
    let text = format!(
        "- world:\n    renderer: path\n    roulette-scale: 1\n    roulette-depth: 2\n    \
         max-depth: {max_depth}\n\
         - add: camera\n  width: 16\n  height: 16\n  field-of-view-degrees: 50\n  \
         handedness: right\n  from: {from:?}\n  to: {to:?}\n  up: [0, 1, 0]\n{body}"
    );
    load_str(&text, Path::new("techniques.yml")).unwrap()
}

/// A coarse sky: pale blue, with a sun of one texel towards +x, 45° up, wide enough for
/// bouncing paths to find it in a mirror ball often enough to compare.
fn sky() -> Arc<EnvironmentMap> {
    let (w, h) = (8, 5);
    let mut texels = vec![Color::new(0.6, 0.7, 0.9); w * h];
    texels[w + 1] = Color::new(12.0, 11.0, 10.0);
    Arc::new(EnvironmentMap::new(w, h, texels, 1.0).unwrap())
}

/// An even grey sky: sampled alike in every direction, so that every technique that samples
/// it finds all of it often (a sun's light through a ball, found by BSDF sampling alone, is
/// rare and bright, and hides a small bias in its noise).
fn even_sky() -> Arc<EnvironmentMap> {
    Arc::new(EnvironmentMap::new(4, 3, vec![Color::WHITE; 12], 1.0).unwrap())
}

/// The pixels' luminance-like mean of channels.
fn values(film: &Film) -> Vec<f64> {
    film.resolve()
        .pixels()
        .iter()
        .map(|c| (c.red + c.green + c.blue) / 3.0)
        .collect()
}

/// `scene` rendered at `spp` with the techniques `with` and with `without`: how many
/// standard errors apart the two images' means are, and the first's mean.
fn z_score(scene: &Scene, spp: u64, with: Techniques, without: Techniques) -> (f64, f64) {
    let render_with = |techniques: Techniques, seed: u64| {
        let mut scene_with = scene.clone();
        let options = scene_with.path.as_mut().unwrap();
        options.techniques = techniques;
        options.seed = seed;
        values(&render(&scene_with, 16, 16, spp))
    };
    let (a, b) = (render_with(with, 1), render_with(without, 2));
    let n = a.len() as f64;
    let differences: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
    let mean = differences.iter().sum::<f64>() / n;
    let variance = differences.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let z = mean / (variance / n).sqrt();
    (z, a.iter().sum::<f64>() / n)
}

#[track_caller]
fn assert_agrees(scene: &Scene, spp: u64, with: Techniques, without: Techniques, what: &str) {
    let (z, mean) = z_score(scene, spp, with, without);
    assert!(
        z.abs() < Z_LIMIT,
        "{what}: the means differ by {z:.2} standard errors (mean {mean})"
    );
    // A dark image would agree with anything.
    assert!(mean > 0.02, "{what}: mean {mean}");
}

/// A grey floor and a red ball under a glowing ball and a glowing panel, in a sky with a sun.
fn lit_floor() -> Scene {
    let mut scene = scene(
        "- add: rectangle
  material: { type: diffuse, color: [0.6, 0.6, 0.6] }
  transform: [[scale, 3, 1, 3]]
- add: sphere
  material: { type: diffuse, color: [0.8, 0.3, 0.2] }
  transform: [[scale, 0.5, 0.5, 0.5], [translate, -0.4, 0.5, 0]]
- add: sphere
  material: { type: diffuse, color: [0, 0, 0], emission: [6, 6, 5] }
  transform: [[scale, 0.25, 0.25, 0.25], [translate, 0.8, 1.2, 0.3]]
- add: rectangle
  material: { type: diffuse, color: [0, 0, 0], emission: [3, 3, 4] }
  transform: [[scale, 0.5, 1, 0.5], [rotate-x-degrees, 180], [translate, -0.5, 2, -0.5]]
",
        [0.0, 1.6, 3.5],
        [0.0, 0.4, 0.0],
        6,
    );
    scene.world.environment = Some(sky());
    scene
}

#[test]
fn without_next_event_estimation_the_image_is_the_same() {
    let on = Techniques::default();
    let off = Techniques {
        next_event: false,
        ..on
    };
    assert_agrees(&lit_floor(), 128, on, off, "next-event off");
}

#[test]
fn without_mis_the_image_is_the_same() {
    let on = Techniques::default();
    let off = Techniques { mis: false, ..on };
    assert_agrees(&lit_floor(), 64, on, off, "mis off");
    // Without either, every light is found by BSDF sampling alone.
    let neither = Techniques {
        next_event: false,
        ..off
    };
    assert_agrees(&lit_floor(), 128, on, neither, "mis and next-event off");
}

#[test]
fn without_the_roulette_the_image_is_the_same() {
    // A box of pale walls, open at the camera's end, lit through a hole in its top by the
    // sky: most of its light has bounced several times, where the roulette ends paths.
    let mut scene = scene(
        "- add: cube
  material: { type: diffuse, color: [0.85, 0.85, 0.85] }
  transform: [[scale, 1, 1, 1]]
- add: rectangle
  material: { type: diffuse, color: [0, 0, 0], emission: [4, 4, 4] }
  transform: [[scale, 0.3, 1, 0.3], [rotate-x-degrees, 180], [translate, 0, 0.99, 0]]
",
        [0.0, 0.0, 0.9],
        [0.0, 0.0, -1.0],
        12,
    );
    // Inside the cube: its faces are two-sided diffuse walls.
    let options = scene.path.as_mut().unwrap();
    options.roulette = Roulette::Scale(1.0);
    options.roulette_depth = 1;
    let on = Techniques::default();
    let off = Techniques {
        roulette: false,
        ..on
    };
    assert_agrees(&scene, 64, on, off, "roulette off");
}

#[test]
fn without_the_sphere_cones_the_image_is_the_same() {
    // The floor's glowing ball drawn by area, not in the cone it subtends.
    let scene = lit_floor();
    let on = Techniques::default();
    let off = Techniques {
        sphere_cones: false,
        ..on
    };
    assert_agrees(&scene, 64, on, off, "sphere-cones off");
}

/// The lit floor in a box of thin fog, with a point light besides its lamps: light the fog scatters
/// from a point, a ball and a panel, once and many times.
fn foggy_floor() -> Scene {
    let mut scene = scene(
        "- medium: fog
  sigma-a: 0.05
  sigma-s: [0.3, 0.35, 0.45]
  g: 0.3
- add: cube
  material: interface
  interior: fog
  transform: [[scale, 2.5, 1.5, 2.5], [translate, 0, 1.2, 0]]
- add: light
  at: [-0.6, 1.0, 0.8]
  intensity: [2, 2, 2]
- add: rectangle
  material: { type: diffuse, color: [0.6, 0.6, 0.6] }
  transform: [[scale, 3, 1, 3]]
- add: sphere
  material: { type: diffuse, color: [0, 0, 0], emission: [6, 6, 5] }
  transform: [[scale, 0.25, 0.25, 0.25], [translate, 0.8, 1.2, 0.3]]
- add: rectangle
  material: { type: diffuse, color: [0, 0, 0], emission: [3, 3, 4] }
  transform: [[scale, 0.5, 1, 0.5], [rotate-x-degrees, 180], [translate, -0.5, 2, -0.5]]
",
        [0.0, 1.6, 3.5],
        [0.0, 0.4, 0.0],
        6,
    );
    scene.world.background = Color::new(0.2, 0.2, 0.3);
    scene
}

#[test]
fn without_equiangular_sampling_the_image_is_the_same() {
    // Points drawn towards the lamps through the fog, weighed against distance sampling (and,
    // without MIS, in its place).
    let scene = foggy_floor();
    let on = Techniques::default();
    let off = Techniques {
        equiangular: false,
        ..on
    };
    assert_agrees(&scene, 64, on, off, "equiangular off");
    let alone = Techniques { mis: false, ..on };
    assert_agrees(&scene, 64, alone, off, "equiangular without MIS");
}

#[test]
fn without_the_glass_split_the_image_is_the_same() {
    // A glass ball before a red one on a grey floor, under an even white sky (no caustic to
    // speckle it).
    let body = "- add: rectangle
  material: { type: diffuse, color: [0.6, 0.6, 0.6] }
  transform: [[scale, 3, 1, 3]]
- add: sphere
  material: { type: diffuse, color: [0.8, 0.2, 0.1] }
  transform: [[scale, 0.5, 0.5, 0.5], [translate, 0.3, 0.5, -1.5]]
- add: sphere
  material: { type: dielectric, refractive-index: 1.5 }
  transform: [[scale, 0.6, 0.6, 0.6], [translate, 0, 0.6, 0]]
";
    let mut scene = scene(body, [0.0, 1.0, 2.0], [0.0, 0.5, 0.0], 8);
    scene.world.background = Color::WHITE;
    let on = Techniques::default();
    let off = Techniques {
        glass_split: false,
        ..on
    };
    assert_agrees(&scene, 64, on, off, "glass-split off");
}

/// Mirror balls of polished aluminium on a grey floor under `sky`: `balls` of them in a row
/// along x, each `radius` in size, `gap` apart.
fn mirror_balls(balls: usize, radius: f64, gap: f64, sky: Arc<EnvironmentMap>) -> Scene {
    let mut body = String::from(
        "- add: rectangle
  material: { type: diffuse, color: [0.6, 0.6, 0.6] }
  transform: [[scale, 4, 1, 4]]
",
    );
    let start = -(balls as f64 - 1.0) * gap / 2.0;
    for i in 0..balls {
        let x = start + i as f64 * gap;
        body.push_str(&format!(
            "- add: sphere
  material: {{ type: conductor, metal: aluminium }}
  transform: [[scale, {radius}, {radius}, {radius}], [translate, {x}, {radius}, 0]]
"
        ));
    }
    // Looking down at the floor on the side away from the sun, where the balls' caustics fall.
    let mut scene = scene(&body, [-0.8, 2.2, -1.6], [-0.2, 0.0, -0.4], 6);
    scene.world.environment = Some(sky);
    scene
}

#[test]
fn without_the_mirror_ball_sampling_the_image_is_the_same() {
    let on = Techniques::default();
    let off = Techniques {
        mirror_balls: false,
        ..on
    };
    let sunny = mirror_balls(2, 0.4, 1.0, sky());
    assert_agrees(&sunny, 128, on, off, "mirror-balls off");
    // Without MIS, the sky beyond a ball counts where the ball's sampling draws it alone.
    let even = mirror_balls(2, 0.4, 1.0, even_sky());
    let no_mis = Techniques { mis: false, ..on };
    assert_agrees(&even, 64, on, no_mis, "mis off with mirror balls");
}

#[test]
fn the_mirror_ball_cap_and_cull_leave_the_image_the_same() {
    // Twelve balls close together: with a cap of one, a vertex solves one of them, chosen by
    // its share, against all twelve uncapped. The cull's balls are found by BSDF sampling
    // alone: under an even sky, where their light is most of what they give.
    let uncapped = Techniques {
        mirror_ball_budget: MirrorBallBudget { cap: 64, cull: 0.0 },
        ..Techniques::default()
    };
    // The cull's balls add little: more samples, to see that it is not lost.
    for (sky, cap, cull, spp) in [
        (sky(), 1, 0.0, 64),
        (sky(), 3, 0.0, 64),
        (even_sky(), 2, 0.0, 64),
        (even_sky(), 64, 0.03, 256),
        (even_sky(), 2, 0.03, 256),
    ] {
        let scene = mirror_balls(12, 0.2, 0.45, sky);
        let capped = Techniques {
            mirror_ball_budget: MirrorBallBudget { cap, cull },
            ..uncapped
        };
        let what = format!("cap {cap}, cull {cull}");
        assert_agrees(&scene, spp, uncapped, capped, &what);
    }
}
