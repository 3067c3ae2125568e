//! pbrt-v4's realistic camera against optics known in closed form: a thick lens focuses
//! where the thick-lens formula says, the exit pupil's bounds hold every ray that gets
//! through, the image darkens towards its corners, and a small light in focus is a small
//! spot (out of focus, a large one). The lens systems are written here, row by row.

mod path_support;

use path_support::render_counted;
use rayforge::camera::{ApertureShape, LensInterface, LensSettings, LensSystem};
use rayforge::math::view_transform;
use rayforge::math::Jitter;
use rayforge::options::PathOptions;
use rayforge::shading::Material;
use rayforge::{point, vector, Camera, Color, Object, Vec3, World};
use std::sync::Arc;

fn row(curvature_radius: f64, thickness: f64, eta: f64, aperture_diameter: f64) -> LensInterface {
    LensInterface {
        curvature_radius,
        thickness,
        eta,
        aperture_diameter,
    }
}

/// A symmetric biconvex lens of crown glass: radii ±50 mm, 5 mm thick, 20 mm across.
fn biconvex() -> Vec<LensInterface> {
    vec![row(50.0, 5.0, 1.5, 20.0), row(-50.0, 50.0, 1.0, 20.0)]
}

/// Two lenses with the stop between them: off the axis its elements cut the light off.
fn two_lenses() -> Vec<LensInterface> {
    vec![
        row(40.0, 4.0, 1.6, 24.0),
        row(-200.0, 10.0, 1.0, 24.0),
        row(0.0, 10.0, 0.0, 8.0),
        row(100.0, 4.0, 1.6, 16.0),
        row(-60.0, 40.0, 1.0, 16.0),
    ]
}

fn settings(focus: f64, aperture: f64) -> LensSettings {
    LensSettings {
        focus_distance: focus,
        aperture_diameter: aperture,
        ..LensSettings::DEFAULT
    }
}

/// The film distance behind the rear vertex that focuses a point `focus` metres from the film
/// through a thick lens (radii `r1`, `r2`, thickness `d`, index `n`, all in metres), by the
/// lensmaker's equation for a thick lens, its principal planes and the Gaussian lens
/// equation, solved by bisection.
fn thick_lens_film_distance(r1: f64, r2: f64, d: f64, n: f64, focus: f64) -> f64 {
    let power = (n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2));
    let f = 1.0 / power;
    // Principal planes from their vertices, positive towards the film.
    let front = -f * (n - 1.0) * d / (n * r2);
    let rear = -f * (n - 1.0) * d / (n * r1);
    let residual = |film: f64| {
        let image = film - rear;
        let object = focus - film - d + front;
        1.0 / object + 1.0 / image - 1.0 / f
    };
    let (mut lo, mut hi) = (f * 0.5, f * 3.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if residual(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn a_thick_lens_focuses_where_the_thick_lens_formula_says() {
    for focus in [0.3, 1.0, 10.0] {
        let lens = LensSystem::new(&biconvex(), &settings(focus, 1.0)).unwrap();
        let expected = thick_lens_film_distance(0.05, -0.05, 0.005, 1.5, focus);
        let found = lens.film_distance();
        assert!(
            (found - expected).abs() < 1e-6 * expected.max(1.0) + 2e-8,
            "focus {focus}: film at {found}, the formula says {expected}"
        );
        // pbrt-v4's thick-lens step alone agrees to the paraxial rays' aberration.
        let thick = lens.thick_lens_film_distance();
        assert!(
            (thick - expected).abs() < 1e-5 * expected,
            "{thick} {expected}"
        );
    }
    // Rays from the point in focus, through the whole lens, meet at the film's centre: a
    // point on the axis at 1 m, rays to many heights of the front surface.
    let lens = LensSystem::new(&biconvex(), &settings(1.0, 1.0)).unwrap();
    let front = 0.005 + lens.film_distance();
    for h in [0.5e-3, 2e-3, 4e-3] {
        let target = Vec3::new(h, 0.0, front);
        let source = Vec3::new(0.0, 0.0, 1.0);
        let out = lens
            .trace_from_scene(source, target - source)
            .expect("a ray near the axis gets through");
        let t = -out.origin.z / out.direction.z;
        let at_film = out.origin + out.direction * t;
        // Only spherical aberration, growing as the height's cube (40 µm at 4 mm): at the
        // paraxial limit the rays meet at the film.
        assert!(
            at_film.x.abs() < 60e-6 * (h / 4e-3).powi(3),
            "{h}: {at_film}"
        );
    }
}

#[test]
fn the_exit_pupil_bounds_hold_every_ray_that_gets_through() {
    for lenses in [biconvex(), two_lenses()] {
        let lens = LensSystem::new(&lenses, &settings(2.0, 6.0)).unwrap();
        let half_diagonal = lens.film_diagonal() / 2.0;
        let rear_z = lens.film_distance();
        let rear_radius = 12e-3;
        let mut random = rayforge::math::SplitMix64::new(7);
        let (mut through, mut inside_bounds) = (0, 0);
        for _ in 0..400 {
            let r = random.next_offset() * half_diagonal;
            let bounds = lens.exit_pupil_bounds(r);
            for _ in 0..400 {
                let x = (2.0 * random.next_offset() - 1.0) * 1.5 * rear_radius;
                let y = (2.0 * random.next_offset() - 1.0) * 1.5 * rear_radius;
                let film = Vec3::new(r, 0.0, 0.0);
                if lens
                    .trace_from_film(film, Vec3::new(x, y, rear_z) - film)
                    .is_some()
                {
                    through += 1;
                    let b = bounds.unwrap_or_else(|| panic!("no bounds at {r}, a ray through"));
                    assert!(b.contains(x, y), "({x}, {y}) from {r} outside {b:?}");
                    inside_bounds += 1;
                }
            }
        }
        assert!(through > 1000, "{through}");
        assert_eq!(through, inside_bounds);
    }
}

/// The film's irradiance at `r` off its centre along its diagonal: the mean weight of
/// `n × n` stratified lens samples (a vignetted one weighs 0), and the fraction that got
/// through.
fn irradiance(lens: &LensSystem, r_fraction: f64, n: usize) -> (f64, f64) {
    let (w, h) = lens.film_half_extent(3, 2);
    // From the centre (s, t) = (0.5, 0.5) to the bottom right corner (1, 1).
    let s = 0.5 + 0.5 * r_fraction;
    let (mut sum, mut through) = (0.0, 0);
    for j in 0..n {
        for i in 0..n {
            let u = (i as f64 + 0.5) / n as f64;
            let v = (j as f64 + 0.5) / n as f64;
            if let Some((_, weight)) = lens.ray((s, s), (w, h), (u, v)) {
                sum += weight;
                through += 1;
            }
        }
    }
    (sum / (n * n) as f64, through as f64 / (n * n) as f64)
}

#[test]
fn the_image_darkens_towards_its_corners() {
    let lens = LensSystem::new(&two_lenses(), &settings(2.0, 6.0)).unwrap();
    let at: Vec<(f64, f64)> = [0.0, 0.25, 0.5, 0.75, 1.0]
        .iter()
        .map(|&r| irradiance(&lens, r, 64))
        .collect();
    for pair in at.windows(2) {
        assert!(pair[1].0 < pair[0].0, "{at:?}");
    }
    // Not cos⁴ alone: the area of the exit pupil itself shrinks, the elements cutting off
    // light the stop lets through (the passing share of the bounds times their area).
    let bounds = |r: f64| {
        lens.exit_pupil_bounds(r * lens.film_diagonal() / 2.0)
            .unwrap()
    };
    let area = |k: usize, r: f64| at[k].1 * bounds(r).area();
    assert!(
        area(4, 1.0) < 0.8 * area(0, 0.0),
        "{at:?} {} {}",
        area(4, 1.0),
        area(0, 0.0)
    );
}

/// A black world with one small glowing sphere (radius 3 mm) at `at`.
fn one_small_light(at: rayforge::Point3) -> World {
    let light = Object::sphere()
        .with_transform(
            rayforge::math::translation(at.x, at.y, at.z)
                * rayforge::math::scaling(3e-3, 3e-3, 3e-3),
        )
        .with_material(Material {
            color: Color::BLACK,
            emission: Color::new(1.0, 1.0, 1.0),
            ..Material::DEFAULT
        });
    World {
        objects: vec![light],
        ..World::default()
    }
}

/// The image (luminance per pixel) of `world` through `lens` at `size × size` pixels.
fn image(world: &World, lens: LensSystem, size: usize, spp: u64) -> Vec<f64> {
    let camera = Camera::realistic(size, size, Arc::new(lens)).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    let (film, _) = render_counted(world, &camera, spp, PathOptions::default());
    let canvas = film.resolve();
    let mut out = Vec::with_capacity(size * size);
    for y in 0..size {
        for x in 0..size {
            let c = canvas.pixel_at(x, y);
            out.push(c.red + c.green + c.blue);
        }
    }
    out
}

/// The share of the image's light in the 3 × 3 pixels about its brightest, and where that is.
fn concentration(pixels: &[f64], size: usize) -> (f64, (usize, usize)) {
    let total: f64 = pixels.iter().sum();
    let brightest = (0..pixels.len())
        .max_by(|&a, &b| pixels[a].total_cmp(&pixels[b]))
        .unwrap();
    let (bx, by) = (brightest % size, brightest / size);
    let mut near = 0.0;
    for y in by.saturating_sub(1)..=(by + 1).min(size - 1) {
        for x in bx.saturating_sub(1)..=(bx + 1).min(size - 1) {
            near += pixels[y * size + x];
        }
    }
    (near / total, (bx, by))
}

#[test]
fn a_small_light_in_focus_is_a_small_spot_and_out_of_focus_a_large_one() {
    let size = 63;
    let world = one_small_light(point(0.0, 0.0, 1.0));
    let sharp = image(
        &world,
        LensSystem::new(&biconvex(), &settings(1.0, 1.0)).unwrap(),
        size,
        16,
    );
    let (share, at) = concentration(&sharp, size);
    assert!(share > 0.95, "in focus, {share} of the light near {at:?}");
    assert_eq!(at, (31, 31), "on the axis, the image's centre");
    let blurred = image(
        &world,
        LensSystem::new(&biconvex(), &settings(0.25, 1.0)).unwrap(),
        size,
        16,
    );
    let (share, _) = concentration(&blurred, size);
    assert!(
        share < 0.5,
        "out of focus, {share} of the light in 3 × 3 pixels"
    );
    // The same light in the same total: the lens passes what it passes whatever its focus
    // (to the noise of 16 samples and the magnification's few percent).
    let (a, b): (f64, f64) = (sharp.iter().sum(), blurred.iter().sum());
    assert!((a / b - 1.0).abs() < 0.25, "{a} {b}");

    // Off the axis, up and to the image's right of a camera looking down +z with +y up: the
    // spot is where the equivalent pinhole sees it (not mirrored), to the lens's distortion.
    let lens = LensSystem::new(&biconvex(), &settings(1.0, 1.0)).unwrap();
    let world = one_small_light(point(-0.15, 0.1, 1.0));
    let camera =
        Camera::realistic(size, size, Arc::new(lens.clone())).with_transform(view_transform(
            point(0.0, 0.0, 0.0),
            point(0.0, 0.0, 1.0),
            vector(0.0, 1.0, 0.0),
        ));
    let (_, at) = concentration(&image(&world, lens, size, 16), size);
    let aimed = camera
        .ray_through(at.0 as f64 + 0.5, at.1 as f64 + 0.5)
        .direction;
    let towards = Vec3::new(-0.15, 0.1, 1.0).normalize();
    assert!(
        aimed.dot(towards) > (0.03f64).cos(),
        "spot at {at:?}: {aimed} vs {towards}"
    );
}

#[test]
fn the_built_in_diaphragms_shape_the_blur_and_pass_the_circles_light() {
    let circle = LensSystem::new(&two_lenses(), &settings(2.0, 6.0)).unwrap();
    let (centre, _) = irradiance(&circle, 0.0, 96);
    for shape in [
        ApertureShape::Gaussian,
        ApertureShape::Square,
        ApertureShape::Pentagon,
        ApertureShape::Star,
    ] {
        let lens = LensSystem::new(
            &two_lenses(),
            &LensSettings {
                aperture: shape,
                ..settings(2.0, 6.0)
            },
        )
        .unwrap();
        let (shaped, _) = irradiance(&lens, 0.0, 96);
        assert!(
            (shaped / centre - 1.0).abs() < 0.05,
            "{shape:?}: {shaped} vs {centre}"
        );
    }
}

#[test]
fn a_lens_system_that_cannot_be_built_says_why() {
    let e = LensSystem::new(&[], &LensSettings::DEFAULT).unwrap_err();
    assert!(e.message.contains("at least one"), "{e}");
    let mut rows = biconvex();
    rows[1].eta = 0.5;
    let e = LensSystem::new(&rows, &LensSettings::DEFAULT).unwrap_err();
    assert_eq!(e.row, Some(1), "{e}");
    // Closer than four focal lengths from the film, no film distance focuses.
    let e = LensSystem::new(&biconvex(), &settings(0.1, 1.0)).unwrap_err();
    assert!(e.message.contains("too short"), "{e}");
    // A diaphragm asked wider than the lens file's stop is clamped to it.
    let lens = LensSystem::new(&two_lenses(), &settings(2.0, 20.0)).unwrap();
    assert_eq!(lens.clamped_aperture(), Some((20.0, 8.0)));
}

/// The book's default world seen through the biconvex lens from 5 units away, focused there.
fn default_world_through_a_lens(size: usize) -> (World, Camera) {
    let lens = LensSystem::new(&biconvex(), &settings(5.0, 1.0)).unwrap();
    let camera = Camera::realistic(size, size, Arc::new(lens)).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (rayforge::default_world(), camera)
}

#[test]
fn the_rasterizer_refuses_a_lens_system_and_the_ray_tracer_draws_through_it() {
    let (world, camera) = default_world_through_a_lens(24);
    let e = rayforge::raster::render(&camera, &world, &rayforge::raster::RasterOptions::default())
        .unwrap_err();
    assert!(e.to_string().contains("realistic"), "{e}");
    // The Whitted renderer's one ray a pixel, from the centre of each ring's exit pupil:
    // the default world's spheres at the image's centre, the black sky at its corner.
    let canvas = camera.render(&world);
    let centre = canvas.pixel_at(12, 12);
    assert!(centre.red > 0.0 && centre.red.is_finite(), "{centre:?}");
    assert_eq!(canvas.pixel_at(0, 0), Color::BLACK);
}

#[test]
fn a_stop_flag_ends_the_exit_pupils_tracing_and_an_unset_one_changes_nothing() {
    use std::sync::atomic::AtomicBool;
    let settings = settings(1.0, 1.0);
    let stopped = LensSystem::new_until(&biconvex(), &settings, Some(&AtomicBool::new(true)));
    assert!(matches!(stopped, Ok(None)), "{stopped:?}");
    let free = LensSystem::new_until(&biconvex(), &settings, Some(&AtomicBool::new(false)))
        .unwrap()
        .expect("not stopped");
    let plain = LensSystem::new(&biconvex(), &settings).unwrap();
    for r in [0.0, 0.005, 0.01] {
        assert_eq!(free.exit_pupil_bounds(r), plain.exit_pupil_bounds(r));
    }
}
