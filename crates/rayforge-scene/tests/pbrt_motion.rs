//! Motion blur from pbrt-v4 files (`TransformTimes`, `ActiveTransform`, the camera's
//! `shutteropen`/`shutterclose`): a black ball moving before a white sky, seen by an
//! orthographic camera, covers each column (and row) of the image for the share of the
//! shutter it spends there; the rendered means are checked against that share worked out
//! from the ball's path, within the binomial noise of the samples. The same motion given as
//! a moving camera, over parts of the shutter, by an instance, and by end-time-only edits;
//! a moving lamp lights a floor alike by light sampling and by BSDF sampling; and the times
//! rayforge cannot render are refused where they are written.

mod support;

use rayforge::film::Film;
use rayforge::options::Techniques;
use rayforge_scene::{LoadOptions, Scene, SceneError};
use std::path::Path;

/// The image's side in pixels, and the samples per pixel.
const SIDE: usize = 32;
const SPP: u64 = 64;

fn load_in(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    let path = dir.join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

fn load(text: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    load_in(dir.path(), text)
}

/// The film and camera lines: a square orthographic view of the screen's `[-1, 1]²` down +z,
/// a box filter so that every sample stays in its pixel; `camera` follows the camera's name.
fn head(camera: &str) -> String {
    format!(
        "Film \"rgb\" \"integer xresolution\" {SIDE} \"integer yresolution\" {SIDE}\n\
         PixelFilter \"box\"\nCamera \"orthographic\" {camera}\n"
    )
}

/// The world: a white sky and a black material, then `body`.
fn world(body: &str) -> String {
    format!(
        "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{body}"
    )
}

/// The area of the disk of radius `r` about `centre` (one coordinate) between `a` and `b`
/// along that coordinate.
fn slab_area(centre: f64, r: f64, a: f64, b: f64) -> f64 {
    let below = |x: f64| {
        let s = (x - centre).clamp(-r, r);
        s * (r * r - s * s).sqrt() + r * r * (s / r).asin()
    };
    below(b) - below(a)
}

/// The shares of each column and each row (top first) of the screen's `[-1, 1]²` that a disk
/// of radius `r` covers on average while its centre runs along `path` (the centre at each
/// instant of the shutter, given by its fraction in [0, 1]).
fn expected(r: f64, path: impl Fn(f64) -> (f64, f64)) -> (Vec<f64>, Vec<f64>) {
    const STEPS: usize = 4000;
    let cell = 2.0 / SIDE as f64;
    let (mut columns, mut rows) = (vec![0.0; SIDE], vec![0.0; SIDE]);
    for k in 0..STEPS {
        let (cx, cy) = path((k as f64 + 0.5) / STEPS as f64);
        for i in 0..SIDE {
            let a = -1.0 + i as f64 * cell;
            columns[i] += slab_area(cx, r, a, a + cell) / (2.0 * cell) / STEPS as f64;
            let top = 1.0 - i as f64 * cell;
            rows[i] += slab_area(cy, r, top - cell, top) / (2.0 * cell) / STEPS as f64;
        }
    }
    (columns, rows)
}

/// The shares of each column and row of `film` the ball covers: one less the mean of its
/// pixels over the sky's value (a corner pixel, which the ball never reaches and which every
/// sample sees the sky from, so that it holds the sky's value exactly).
fn measured(film: &Film) -> (Vec<f64>, Vec<f64>) {
    let image = film.resolve();
    let sky = image.pixel_at(0, 0).red;
    assert!(sky > 0.1, "the sky is {sky}");
    let share = |x: usize, y: usize| 1.0 - image.pixel_at(x, y).red / sky;
    let columns = (0..SIDE)
        .map(|x| (0..SIDE).map(|y| share(x, y)).sum::<f64>() / SIDE as f64)
        .collect();
    let rows = (0..SIDE)
        .map(|y| (0..SIDE).map(|x| share(x, y)).sum::<f64>() / SIDE as f64)
        .collect();
    (columns, rows)
}

/// Checks that `text`'s render covers the columns and rows as a disk of radius `r` running
/// along `path` does, each within 4.5 standard deviations of a binomial share over the
/// column's samples (the samples are stratified, which only lowers the noise).
#[track_caller]
fn assert_covers(text: &str, r: f64, path: impl Fn(f64) -> (f64, f64)) {
    let scene = load(text).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (columns, rows) = measured(&support::render(&scene, SIDE, SIDE, SPP));
    let (want_columns, want_rows) = expected(r, path);
    let n = (SIDE as u64 * SPP) as f64;
    for (what, got, want) in [("column", columns, want_columns), ("row", rows, want_rows)] {
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            let sigma = (w * (1.0 - w) / n).sqrt();
            assert!(
                (g - w).abs() <= 4.5 * sigma + 2e-3,
                "{what} {i}: covered {g:.4}, the path covers {w:.4} (σ {sigma:.4})\n{got:.3?}\n{want:.3?}"
            );
        }
    }
}

/// The ball's path in the first tests: from x = −0.5 to 0.5 across the middle of the screen.
fn across(tau: f64) -> (f64, f64) {
    (-0.5 + tau, 0.0)
}

#[test]
fn a_ball_moved_by_an_end_time_edit_covers_the_columns_it_crosses() {
    // The end transform edited alone (`EndTime`), then both again (`All`).
    let end_only = format!(
        "{}{}",
        head(""),
        world(
            "AttributeBegin\nTranslate -0.5 0 5\nActiveTransform EndTime\nTranslate 1 0 0\n\
             ActiveTransform All\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
        )
    );
    assert_covers(&end_only, 0.3, across);
    // The start transform edited alone instead: the same motion.
    let start_only = format!(
        "{}{}",
        head(""),
        world(
            "AttributeBegin\nTranslate 0.5 0 5\nActiveTransform StartTime\nTranslate -1 0 0\n\
             ActiveTransform All\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
        )
    );
    assert_covers(&start_only, 0.3, across);
    // A ball standing still at the start covers its own columns only: the check can fail.
    let still = format!(
        "{}{}",
        head(""),
        world("Translate -0.5 0 5\nShape \"sphere\" \"float radius\" 0.3\n")
    );
    let scene = load(&still).unwrap();
    let (columns, _) = measured(&support::render(&scene, SIDE, SIDE, SPP));
    let (want, _) = expected(0.3, across);
    assert!(
        columns[24] < 1e-9 && want[24] > 0.05,
        "{} {}",
        columns[24],
        want[24]
    );
}

#[test]
fn a_moving_camera_sees_a_ball_standing_still_move_the_other_way() {
    // The camera from x = 0.5 to x = −0.5 (its camera-from-world transform from a shift of
    // −0.5 to one of 0.5): the ball at the origin crosses its screen from −0.5 to 0.5.
    let text = format!(
        "Translate -0.5 0 0\nActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n{}{}",
        head(""),
        world("Translate 0 0 5\nShape \"sphere\" \"float radius\" 0.3\n")
    );
    assert_covers(&text, 0.3, across);
}

#[test]
fn the_shutter_sees_the_part_of_the_motion_it_is_open_for() {
    let body = "AttributeBegin\nTranslate -0.5 0 5\nActiveTransform EndTime\nTranslate 1 0 0\n\
                ActiveTransform All\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n";
    // A quarter of the default times: from a quarter of the way to half.
    let quarter = format!(
        "{}{}",
        head("\"float shutteropen\" 0.25 \"float shutterclose\" 0.5"),
        world(body)
    );
    assert_covers(&quarter, 0.3, |t| across(0.25 + 0.25 * t));
    // Times 2 to 6 and a shutter from 3 to 4: the same quarter.
    let shifted = format!(
        "TransformTimes 2 6\n{}{}",
        head("\"float shutteropen\" 3 \"float shutterclose\" 4"),
        world(body)
    );
    assert_covers(&shifted, 0.3, |t| across(0.25 + 0.25 * t));
    // A shutter open past the end time: the ball rests at its end for the rest of it.
    let past = format!(
        "TransformTimes 2 6\n{}{}",
        head("\"float shutteropen\" 5 \"float shutterclose\" 8"),
        world(body)
    );
    assert_covers(&past, 0.3, |t| across((0.75 + 0.75 * t).min(1.0)));
}

#[test]
fn a_turning_instance_swings_its_shapes_along_the_arc() {
    // The object's ball half a unit from its origin; the instance turned by 150° about the
    // view axis while the shutter is open: the ball's centre runs along the circle of radius
    // 0.5 (not the chord, which would stay far below the top of the circle).
    let text = format!(
        "{}{}",
        head(""),
        world(
            "ObjectBegin \"ball\"\nTranslate 0.5 0 0\nShape \"sphere\" \"float radius\" 0.25\n\
             ObjectEnd\nAttributeBegin\nTranslate 0 0 5\nActiveTransform EndTime\n\
             Rotate 150 0 0 1\nActiveTransform All\nObjectInstance \"ball\"\nAttributeEnd\n"
        )
    );
    assert_covers(&text, 0.25, |t| {
        let angle = (150.0 * t).to_radians();
        (0.5 * angle.cos(), 0.5 * angle.sin())
    });
    // A shape that moves in its object's definition, placed by an instance standing still.
    let inside = format!(
        "{}{}",
        head(""),
        world(
            "ObjectBegin \"mover\"\nActiveTransform EndTime\nTranslate 1 0 0\n\
             ActiveTransform All\nShape \"sphere\" \"float radius\" 0.3\nObjectEnd\n\
             Translate -0.5 0 5\nObjectInstance \"mover\"\n"
        )
    );
    assert_covers(&inside, 0.3, across);
}

/// The light a moving lamp gives a floor, found by light sampling alone and by BSDF sampling
/// alone: the two images' left and right halves agree within their noise (measured from 32
/// independent batches of samples each). Light sampling that drew the lamp where it stands
/// when the shutter opens would light the left half far more (11 standard errors here).
#[test]
fn a_moving_lamp_lights_the_floor_alike_by_light_and_by_bsdf_sampling() {
    let text = "LookAt 0 4 -3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\n\
                Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 16\n\
                PixelFilter \"box\"\nWorldBegin\n\
                Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
                Shape \"trianglemesh\" \"point3 P\" [-6 0 -6  6 0 -6  6 0 6  -6 0 6] \
                \"integer indices\" [0 2 1  0 3 2]\n\
                AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [8 8 8]\n\
                Translate -2 0.8 0\nActiveTransform EndTime\nTranslate 4 0 0\n\
                ActiveTransform All\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n";
    let mut scene = load(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    let warning = scene.warnings[0].to_string();
    assert!(
        warning.contains("s.pbrt:14:1") && warning.contains("pbrt-v4 refuses"),
        "{warning}"
    );
    let halves = |scene: &Scene, techniques: Techniques| {
        let mut scene = scene.clone();
        scene.path.as_mut().unwrap().techniques = techniques;
        let camera = scene.camera.clone();
        (0..32u64)
            .map(|batch| {
                let (film, stats) =
                    support::render_samples(&scene, &camera, batch * 16..(batch + 1) * 16);
                assert_eq!(stats.discarded, 0);
                let image = film.resolve();
                let mut sums = [0.0; 2];
                for y in 0..16 {
                    for x in 0..24 {
                        sums[x / 12] += image.pixel_at(x, y).green;
                    }
                }
                sums
            })
            .collect::<Vec<_>>()
    };
    scene.path.as_mut().unwrap().max_depth = 2;
    let light = halves(
        &scene,
        Techniques {
            mis: false,
            ..Techniques::default()
        },
    );
    let bsdf = halves(
        &scene,
        Techniques {
            next_event: false,
            mis: false,
            ..Techniques::default()
        },
    );
    let stats = |batches: &[[f64; 2]], half: usize| {
        let n = batches.len() as f64;
        let mean = batches.iter().map(|b| b[half]).sum::<f64>() / n;
        let var = batches
            .iter()
            .map(|b| (b[half] - mean).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        (mean, var / n)
    };
    for half in 0..2 {
        let ((a, va), (b, vb)) = (stats(&light, half), stats(&bsdf, half));
        let z = (a - b).abs() / (va + vb).sqrt();
        assert!(
            z < 4.5,
            "half {half}: light sampling {a}, BSDF sampling {b}, z {z}"
        );
        assert!(a > 1.0, "half {half} is lit: {a}");
    }
}

#[test]
fn times_rayforge_cannot_move_on_are_refused_where_they_are_written() {
    // An end that is not after the start, with something moving.
    let moving = "AttributeBegin\nActiveTransform EndTime\nTranslate 1 0 5\n\
                  ActiveTransform All\nShape \"sphere\"\nAttributeEnd\n";
    let e = load(&format!(
        "TransformTimes 1 1\n{}{}",
        head(""),
        world(moving)
    ))
    .unwrap_err();
    assert!(e.to_string().contains("s.pbrt:1:1"), "{e}");
    assert!(e.message.contains("TransformTimes 1 1"), "{e}");
    // The same times with nothing moving are harmless.
    let still = "Translate 0 0 5\nShape \"sphere\"\n";
    let scene = load(&format!("TransformTimes 1 1\n{}{}", head(""), world(still))).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // A moving camera on other times than the world's.
    let e = load(&format!(
        "ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n{}TransformTimes 0 2\n{}",
        head(""),
        world(still)
    ))
    .unwrap_err();
    assert!(e.to_string().contains("s.pbrt:6:1"), "{e}");
    assert!(e.message.contains("one clock"), "{e}");
}

#[test]
fn lights_media_and_textures_under_a_moving_transform_stand_at_its_start() {
    let text = format!(
        "{}WorldBegin\nActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n\
         LightSource \"point\" \"rgb I\" [1 1 1]\n\
         Texture \"t\" \"spectrum\" \"checkerboard\"\n\
         MakeNamedMedium \"m\" \"string type\" \"homogeneous\"\n",
        head("")
    );
    let scene = load(&text).unwrap_or_else(|e| panic!("{e}"));
    let lines: Vec<String> = scene.warnings.iter().map(|w| w.to_string()).collect();
    for (line, what) in [(8, "light"), (9, "texture"), (10, "medium")] {
        assert!(
            lines.iter().any(|w| w.contains(&format!("s.pbrt:{line}:1"))
                && w.contains(&format!("a {what} does not"))),
            "{what}: {lines:?}"
        );
    }
    // The point light stands where the start transform puts it: at the origin.
    let rayforge::Light::Point(light) = &scene.world.lights[0] else {
        panic!("{:?}", scene.world.lights[0]);
    };
    assert_eq!(light.position, glam::DVec3::ZERO);
}

#[test]
fn a_moving_shape_in_a_turning_instance_is_warned_about_at_the_instance() {
    let body = |instance_motion: &str| {
        format!(
            "{}{}",
            head(""),
            world(&format!(
                "ObjectBegin \"mover\"\nActiveTransform EndTime\nTranslate 1 0 0\n\
                 ActiveTransform All\nShape \"sphere\" \"float radius\" 0.3\nObjectEnd\n\
                 Translate -0.5 0 5\nActiveTransform EndTime\n{instance_motion}\n\
                 ActiveTransform All\nObjectInstance \"mover\"\n"
            ))
        )
    };
    // Turning: the two motions' product is interpolated, not each one (pbrt-v4's way).
    let turned = load(&body("Rotate 30 0 0 1")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(turned.warnings.len(), 1, "{:?}", turned.warnings);
    let w = turned.warnings[0].to_string();
    assert!(
        w.contains("s.pbrt:17:1") && w.contains("pbrt-v4 each one apart"),
        "{w}"
    );
    // Translating: the two agree, and nothing is said.
    let shifted = load(&body("Translate 0 0.2 0")).unwrap_or_else(|e| panic!("{e}"));
    assert!(shifted.warnings.is_empty(), "{:?}", shifted.warnings);
}

/// pbrt-v4 interpolates an instance's motion in its render space, whose origin is the camera's
/// eye: with the eye at p = (−0.2, 0.2, 0) (the camera moved by (0.2, −0.2, 0) from the
/// world), the ball's centre in the world is `Rz(θt)·(b − p) + lerp(p, Rz(θ)·p, t)`, the
/// instance's origin (p in render space) running along the chord from p to its turned place;
/// the camera sees it shifted by −p. (pbrt-v4 renders this scene so, within its noise; its
/// `--render-coord-sys world` would swing the ball about the world's origin instead.)
#[test]
fn a_turning_instance_is_interpolated_about_the_cameras_eye_as_pbrt_v4_does() {
    let text = format!(
        "Translate 0.2 -0.2 0\n{}{}",
        head(""),
        world(
            "ObjectBegin \"ball\"\nTranslate 0.5 0 0\nShape \"sphere\" \"float radius\" 0.2\n\
             ObjectEnd\nAttributeBegin\nTranslate 0 0 5\nActiveTransform EndTime\n\
             Rotate 150 0 0 1\nActiveTransform All\nObjectInstance \"ball\"\nAttributeEnd\n"
        )
    );
    let (px, py) = (-0.2f64, 0.2f64);
    let turn = |a: f64, (x, y): (f64, f64)| (x * a.cos() - y * a.sin(), x * a.sin() + y * a.cos());
    let path = |t: f64| {
        let end = 150f64.to_radians();
        let (sx, sy) = turn(end * t, (0.5 - px, -py));
        let (ex, ey) = turn(end, (px, py));
        let (cx, cy) = (sx + px + (ex - px) * t, sy + py + (ey - py) * t);
        assert!(cx.abs().max(cy.abs()) < 0.75);
        (cx - px, cy - py)
    };
    assert_covers(&text, 0.2, path);
}
