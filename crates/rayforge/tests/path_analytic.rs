//! The path tracer against answers known in closed form, at small sizes: a closed glowing
//! room, white and grey furnaces. Each test renders a few pixels at a fixed seed and fails
//! when any pixel leaves the interval the issue states.

use rayforge::film::{Film, SharedFilm};
use rayforge::math::{scaling, view_transform};
use rayforge::options::{PathOptions, SamplerKind};
use rayforge::render::path::{render_path, Aovs, PathJob};
use rayforge::shading::{EmissionSide, Material, Physical};
use rayforge::{point, vector, Camera, Color, Object, World};

/// Renders `world` through `camera` at `spp` samples per pixel with `sampler`.
fn render(world: &World, camera: &Camera, spp: u64, sampler: SamplerKind) -> Film {
    let job = PathJob {
        options: PathOptions {
            sampler,
            ..PathOptions::default()
        },
        samples: 0..spp,
        progress: None,
        cancel: None,
        on_row: None,
    };
    let film = SharedFilm::from(Film::new(camera.hsize(), camera.vsize()));
    let mut done = vec![false; camera.vsize()];
    render_path(camera, world, &job, &film, None, &mut done).unwrap();
    assert!(done.iter().all(|&d| d));
    film.into_film()
}

fn diffuse(albedo: f64) -> Material {
    Material {
        color: Color::new(albedo, albedo, albedo),
        physical: Some(Physical::Diffuse),
        ..Material::DEFAULT
    }
}

/// Every pixel's channels, resolved.
fn pixels(film: &Film) -> Vec<f64> {
    let canvas = film.resolve();
    let mut out = Vec::new();
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            let c = canvas.pixel_at(x, y);
            out.extend([c.red, c.green, c.blue]);
        }
    }
    out
}

#[test]
fn inside_a_closed_sphere_of_albedo_half_that_emits_half_every_pixel_is_one() {
    // L = Le + a L  ⇒  L = 0.5 / (1 − 0.5) = 1 everywhere inside.
    let sphere = Object::sphere()
        .with_transform(scaling(10.0, 10.0, 10.0))
        .with_material(Material {
            emission: Color::new(0.5, 0.5, 0.5),
            emission_side: EmissionSide::Back,
            ..diffuse(0.5)
        });
    let world = World {
        objects: vec![sphere],
        ..World::default()
    };
    let camera = Camera::new(6, 6, 1.2).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        for (i, v) in pixels(&render(&world, &camera, 256, sampler))
            .into_iter()
            .enumerate()
        {
            assert!((v - 1.0).abs() <= 0.025, "{sampler:?}: channel {i} is {v}");
        }
    }
}

/// A sphere of `albedo` in a sky of radiance 1, seen whole by a small camera.
fn furnace(albedo: f64) -> (World, Camera) {
    let world = World {
        objects: vec![Object::sphere().with_material(diffuse(albedo))],
        background: Color::WHITE,
        ..World::default()
    };
    let camera = Camera::new(6, 6, 0.8).with_transform(view_transform(
        point(0.0, 0.0, 4.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (world, camera)
}

#[test]
fn the_white_furnace_vanishes() {
    // An object that loses nothing in a uniform sky is invisible: every pixel is 1.
    let (world, camera) = furnace(1.0);
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        for (i, v) in pixels(&render(&world, &camera, 64, sampler))
            .into_iter()
            .enumerate()
        {
            assert!((v - 1.0).abs() <= 0.01, "{sampler:?}: channel {i} is {v}");
        }
    }
}

#[test]
fn a_grey_convex_object_in_the_furnace_shows_its_albedo() {
    // A convex object sees only the sky: one bounce, L = albedo × 1 on the sphere, 1 beside.
    let (world, camera) = furnace(0.8);
    let values = pixels(&render(&world, &camera, 64, SamplerKind::Sobol));
    // The 6 × 6 image spans 0.8 rad; the sphere (radius 1, 4 units away) spans 0.51 in the
    // middle, and the corner pixels lie wholly beside it.
    let centre = (3 * 6 + 3) * 3;
    assert!((values[centre] - 0.8).abs() <= 0.01, "{}", values[centre]);
    assert!(
        (values[0] - 1.0).abs() <= 1e-12,
        "the corner sees the sky: {}",
        values[0]
    );
}

#[test]
fn a_floor_far_from_a_square_light_gets_the_light_its_form_factor_gives() {
    // A floor point lit at a grazing angle by a 2 × 2 light: the shadow ray must not stop on
    // the light's own surface. The floor's radiance is albedo/π times the irradiance, which a
    // fine quadrature over the light gives.
    use rayforge::math::{rotation_x, translation};
    use rayforge::render::path::{PathContext, SampleStream};
    use rayforge::scene::{Emitters, WorldIndex};
    use rayforge::{Ray, Shape};
    let floor = Object::new(Shape::Rectangle)
        .with_transform(scaling(10.0, 1.0, 10.0))
        .with_material(diffuse(0.5));
    let light = Object::new(Shape::Rectangle)
        .with_transform(translation(0.0, 3.0, 0.5) * rotation_x(std::f64::consts::PI))
        .with_material(Material {
            emission: Color::new(15.0, 15.0, 15.0),
            ..diffuse(0.0)
        });
    let world = World {
        objects: vec![floor, light],
        ..World::default()
    };
    let (emitters, index) = (Emitters::new(&world), WorldIndex::build(&world));
    let mut context = PathContext::new(&world, &index, &emitters, 64, 5);
    for z in [0.0, -3.0, -6.0, -9.0] {
        // Irradiance by the midpoint rule over 200 × 200 patches of the light.
        let n = 200;
        let mut irradiance = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let lz = -0.5 + 2.0 * (j as f64 + 0.5) / n as f64;
                let d = point(x, 3.0, lz) - point(0.0, 0.0, z);
                let r2 = d.length_squared();
                let cos = d.y / r2.sqrt();
                irradiance += 15.0 * cos * cos / r2 * (4.0 / (n * n) as f64);
            }
        }
        let expected = 0.5 / std::f64::consts::PI * irradiance;
        let from = point(0.0, 1.5, 5.0);
        let ray = Ray::new(from, (point(0.0, 0.0, z) - from).normalize());
        let samples = 4096;
        let mut sum = 0.0;
        for s in 0..samples {
            let mut stream = SampleStream::new(SamplerKind::Sobol, 0, 0, 0, s);
            sum += context.radiance(ray, &mut stream).0.red;
        }
        let mean = sum / samples as f64;
        assert!(
            (mean - expected).abs() <= 0.01 * expected,
            "at z = {z}: {mean}, expected {expected}"
        );
    }
}

#[test]
fn sample_ranges_rendered_apart_merge_into_the_render_of_their_union() {
    // Samples are numbered per pixel: 0..5 and 5..12 rendered apart and merged give the film
    // of 0..12 (to rounding: the sums are added in another order).
    let (world, camera) = furnace(0.5);
    let render_range = |samples: std::ops::Range<u64>| {
        let job = PathJob {
            options: PathOptions::default(),
            samples,
            progress: None,
            cancel: None,
            on_row: None,
        };
        let film = SharedFilm::from(Film::new(camera.hsize(), camera.vsize()));
        let mut done = vec![false; camera.vsize()];
        render_path(&camera, &world, &job, &film, None, &mut done).unwrap();
        film.into_film()
    };
    let mut merged = render_range(0..5);
    merged.merge(&render_range(5..12)).unwrap();
    let whole = render_range(0..12);
    for (a, b) in merged.sums().iter().zip(whole.sums()) {
        assert!(
            (a.red - b.red).abs() <= 1e-12 * b.red.abs().max(1.0),
            "{a:?} {b:?}"
        );
    }
    assert_eq!(merged.weights(), whole.weights());
    // And a range is not the whole: the first five samples alone differ.
    assert_ne!(render_range(0..5).sums(), whole.sums());
}

#[test]
fn passes_into_one_film_give_the_bits_of_a_single_pass() {
    // Progressive rendering: each pass goes on from the pixels' sums, so 1 + 1 + 2 + 4 + 4
    // samples in five passes sum in the same order as 12 in one, and the film is identical to
    // the bit, with the albedo and normal too.
    let (world, camera) = furnace(0.5);
    let (width, height) = (camera.hsize(), camera.vsize());
    let film = SharedFilm::from(Film::new(width, height));
    let aovs = Aovs::new(width, height);
    for samples in [0..1, 1..2, 2..4, 4..8, 8..12] {
        let job = PathJob {
            options: PathOptions::default(),
            samples,
            progress: None,
            cancel: None,
            on_row: None,
        };
        let mut done = vec![false; height];
        render_path(&camera, &world, &job, &film, Some(&aovs), &mut done).unwrap();
        assert!(done.iter().all(|&d| d));
    }
    let single = SharedFilm::from(Film::new(width, height));
    let single_aovs = Aovs::new(width, height);
    let job = PathJob {
        options: PathOptions::default(),
        samples: 0..12,
        progress: None,
        cancel: None,
        on_row: None,
    };
    let mut done = vec![false; height];
    render_path(
        &camera,
        &world,
        &job,
        &single,
        Some(&single_aovs),
        &mut done,
    )
    .unwrap();
    let bits = |film: Film| -> Vec<u64> {
        film.sums()
            .iter()
            .flat_map(|c| [c.red, c.green, c.blue])
            .chain(film.weights().iter().copied())
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(film.into_film()), bits(single.into_film()));
    assert_eq!(
        bits(aovs.albedo.into_film()),
        bits(single_aovs.albedo.into_film())
    );
    assert_eq!(
        bits(aovs.normal.into_film()),
        bits(single_aovs.normal.into_film())
    );
}

#[test]
fn a_one_sided_surface_is_black_from_behind() {
    // A grey square facing up, in a white sky, seen from below: two-sided its back returns half
    // the sky (it sees only sky on that side); with `two_sided: false` it is black.
    let from_below = |two_sided: bool| {
        let square = Object::new(rayforge::Shape::Rectangle)
            .with_transform(scaling(10.0, 1.0, 10.0))
            .with_material(Material {
                two_sided,
                ..diffuse(0.5)
            });
        let world = World {
            objects: vec![square],
            background: Color::WHITE,
            ..World::default()
        };
        let camera = Camera::new(2, 2, 0.5).with_transform(view_transform(
            point(0.0, -2.0, 0.0),
            point(0.0, 0.0, 0.0),
            vector(0.0, 0.0, 1.0),
        ));
        pixels(&render(&world, &camera, 16, SamplerKind::Sobol))
    };
    assert!(
        from_below(true).iter().all(|&v| (v - 0.5).abs() < 1e-12),
        "{:?}",
        from_below(true)
    );
    assert!(
        from_below(false).iter().all(|&v| v == 0.0),
        "{:?}",
        from_below(false)
    );
}
