//! Adaptive sampling (`sample-allocation: adaptive`): the plan puts samples where a scene is
//! noisy, each pixel stays an unbiased estimate, the plan does not depend on the thread count,
//! and slices of a planned render's samples merge into the whole.

use rayforge::film::{Film, SharedFilm};
use rayforge::math::{scaling, view_transform};
use rayforge::options::{PathOptions, Roulette, SampleAllocation};
use rayforge::render::path::{
    learn_roulette, plan_samples, prepare_render, render_path, PathJob, SamplePlan,
};
use rayforge::shading::{EmissionSide, Material, Physical};
use rayforge::{point, vector, Camera, Color, Object, World};

fn diffuse(albedo: f64) -> Material {
    Material {
        color: Color::new(albedo, albedo, albedo),
        physical: Some(Physical::Diffuse),
        ..Material::DEFAULT
    }
}

/// Adaptive options with the classic roulette (nothing to learn).
fn adaptive() -> PathOptions {
    PathOptions {
        allocation: SampleAllocation::ByNoise,
        roulette: Roulette::Scale(1.0),
        ..PathOptions::default()
    }
}

/// A grey sphere of albedo 0.5 in a sky of radiance 1, filling the middle of a 16 × 16
/// image: the sky's pixels never vary, the sphere's do (light sampling and the sphere's
/// sampling weighed against each other), its outline's most (half sky, half sphere).
fn grey_furnace() -> (World, Camera) {
    let world = World {
        objects: vec![Object::sphere().with_material(diffuse(0.5))],
        background: Color::WHITE,
        ..World::default()
    };
    let camera = Camera::new(16, 16, 1.0).with_transform(view_transform(
        point(0.0, 0.0, 4.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (world, camera)
}

/// Renders the samples `samples` (of the plan's nominal `0..spp`) of `world`.
fn render(
    world: &World,
    camera: &Camera,
    options: PathOptions,
    plan: Option<&SamplePlan>,
    samples: std::ops::Range<u64>,
) -> Film {
    let job = PathJob {
        plan,
        ..PathJob::new(options, samples)
    };
    let film = SharedFilm::from(Film::new(camera.hsize(), camera.vsize()));
    let mut done = vec![false; camera.vsize()];
    let stats = render_path(camera, world, &job, &film, None, &mut done).unwrap();
    assert!(done.iter().all(|&d| d));
    let expected: u64 = match plan {
        Some(plan) => (0..camera.vsize())
            .flat_map(|y| (0..camera.hsize()).map(move |x| (x, y)))
            .map(|(x, y)| {
                let r = plan.range(x, y, &job.samples);
                r.end - r.start
            })
            .sum(),
        None => (job.samples.end - job.samples.start) * (camera.hsize() * camera.vsize()) as u64,
    };
    assert_eq!(
        stats.samples, expected,
        "the samples counted are those taken"
    );
    film.into_film()
}

#[test]
fn adaptive_sampling_gives_the_noisy_pixels_more_samples_and_every_pixel_its_true_value() {
    let (world, camera) = grey_furnace();
    let plan = plan_samples(&camera, &world, &adaptive(), None, 256, false, None)
        .expect("the noise is uneven");
    assert_eq!(plan.size(), (16, 16));
    assert_eq!(plan.spp(), 256);
    // A corner sees only the sky; the middle the sphere; (4, 8) its outline.
    let (corner, middle, outline) = (plan.count(0, 0), plan.count(8, 8), plan.count(4, 8));
    let fewest = (0..16)
        .flat_map(|y| (0..16).map(move |x| (x, y)))
        .map(|(x, y)| plan.count(x, y))
        .min()
        .unwrap();
    assert_eq!(corner, fewest, "a pixel that never varies takes the fewest");
    // Its count is the plan's defence, the even share held back for what the pilot may
    // have missed, above the pilot's own eighth; trusting the pilot whole, just the eighth.
    assert!(
        corner > 256 / 8 && corner < 256 / 2,
        "the corner's floor: {corner}"
    );
    let trusting = PathOptions {
        allocation: SampleAllocation::ByNoiseTrusted,
        ..adaptive()
    };
    let trusted = plan_samples(&camera, &world, &trusting, None, 256, false, None)
        .expect("the noise is uneven");
    assert_eq!(trusted.count(0, 0), 256 / 8, "trusted, the pilot's eighth");
    assert!(
        middle > 2 * corner,
        "the sphere's pixels take more: {middle}"
    );
    assert!(outline > middle, "its outline more still: {outline}");
    // On average no more than a render of 256 samples everywhere costs (a sphere's sample
    // costs more than the sky's, so fewer samples in all).
    let total: u64 = (0..16)
        .flat_map(|y| (0..16).map(move |x| (x, y)))
        .map(|(x, y)| plan.count(x, y))
        .sum();
    assert!(total < 256 * 256, "{total} samples");
    // Each pixel is still an unbiased estimate: the sky exactly 1, the sphere's middle 0.5.
    let film = render(&world, &camera, adaptive(), Some(&plan), 0..256);
    let image = film.resolve();
    assert_eq!(image.pixel_at(0, 0), Color::WHITE);
    for (x, y) in [(7, 7), (8, 8), (7, 8), (8, 7)] {
        let c = image.pixel_at(x, y);
        assert!((c.red - 0.5).abs() <= 0.01, "({x}, {y}): {c:?}");
    }
}

#[test]
fn slices_of_a_planned_renders_samples_merge_into_the_whole() {
    let (world, camera) = grey_furnace();
    let plan = plan_samples(&camera, &world, &adaptive(), None, 256, false, None)
        .expect("the noise is uneven");
    let mut merged = render(&world, &camera, adaptive(), Some(&plan), 0..85);
    merged
        .merge(&render(&world, &camera, adaptive(), Some(&plan), 85..256))
        .unwrap();
    let whole = render(&world, &camera, adaptive(), Some(&plan), 0..256);
    for (a, b) in merged.sums().iter().zip(whole.sums()) {
        assert!(
            (a.red - b.red).abs() <= 1e-12 * b.red.abs().max(1.0),
            "{a:?} {b:?}"
        );
    }
    assert_eq!(merged.weights(), whole.weights());
    // The weights are the pixels' own counts (box filter: 1 a sample).
    assert_eq!(whole.weights()[8 * 16 + 8], plan.count(8, 8) as f64);
}

#[test]
fn the_plan_is_the_same_for_any_thread_count_and_seed_bound() {
    let (world, camera) = grey_furnace();
    let plan_on = |threads: usize, options: PathOptions| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| plan_samples(&camera, &world, &options, None, 256, false, None))
    };
    let one = plan_on(1, adaptive());
    assert!(one.is_some());
    assert_eq!(one, plan_on(3, adaptive()));
    let reseeded = PathOptions {
        seed: 7,
        ..adaptive()
    };
    assert_ne!(one, plan_on(1, reseeded), "another seed, another pilot");
}

#[test]
fn an_evenly_noisy_scene_keeps_an_even_share_and_the_bits_of_a_plain_render() {
    // Inside a closed glowing sphere every pixel is as noisy as the next: nothing to gain.
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
    let camera = Camera::new(16, 16, 1.2).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    let plan = plan_samples(&camera, &world, &adaptive(), None, 64, false, None).expect("a plan");
    assert!((0..16).all(|y| (0..16).all(|x| plan.count(x, y) == 64)));
    // The pilot's samples, kept in the plan, are the render's first: the planned render is
    // the plain one to the bit.
    let planned = render(&world, &camera, adaptive(), Some(&plan), 0..64);
    let plain = render(&world, &camera, adaptive(), None, 0..64);
    assert_eq!(planned, plain);
}

#[test]
fn a_planned_render_with_aovs_starts_from_the_pilots_sums() {
    use rayforge::render::path::Aovs;
    let (world, camera) = grey_furnace();
    let (w, h) = (camera.hsize(), camera.vsize());
    let render_aovs = |plan: Option<&SamplePlan>| {
        let job = PathJob {
            plan,
            ..PathJob::new(adaptive(), 0..64)
        };
        let (film, aovs) = (SharedFilm::from(Film::new(w, h)), Aovs::new(w, h));
        let mut done = vec![false; h];
        render_path(&camera, &world, &job, &film, Some(&aovs), &mut done).unwrap();
        let [albedo, normal, depth, samples] =
            [aovs.albedo, aovs.normal, aovs.depth, aovs.samples].map(|f| f.into_film());
        (film.into_film(), albedo, normal, depth, samples)
    };
    // A plan whose pilot kept the AOVs, and one whose pilot did not (the render then traces
    // the pilot's samples again): the same films.
    let with = plan_samples(&camera, &world, &adaptive(), None, 64, true, None).unwrap();
    assert!(with.count(8, 8) > with.count(0, 0), "an uneven plan");
    let without = plan_samples(&camera, &world, &adaptive(), None, 64, false, None).unwrap();
    let (a, b) = (render_aovs(Some(&with)), render_aovs(Some(&without)));
    assert_eq!(a, b);
    // The sample-count AOV holds each pixel's count.
    let samples = a.4.resolve();
    for (x, y) in [(0, 0), (8, 8), (4, 8)] {
        assert_eq!(samples.pixel_at(x, y).red, with.count(x, y) as f64);
    }
}

#[test]
fn a_stopped_pilot_makes_no_plan() {
    let (world, camera) = grey_furnace();
    let stop = std::sync::atomic::AtomicBool::new(true);
    assert_eq!(
        plan_samples(&camera, &world, &adaptive(), None, 256, false, Some(&stop)),
        None
    );
}

#[test]
fn few_samples_or_an_even_share_asked_for_need_no_plan() {
    // Below 16 samples per pixel the pilot's share would be too few samples to judge by.
    let (world, camera) = grey_furnace();
    assert_eq!(
        plan_samples(&camera, &world, &adaptive(), None, 15, false, None),
        None
    );
    // Asked for an even share, no plan; the roulette is learned all the same, once.
    let uniform = PathOptions {
        allocation: SampleAllocation::Uniform,
        ..PathOptions::default()
    };
    let (roulette, plan) = prepare_render(&camera, &world, &uniform, 64, false, None);
    assert_eq!(
        Some(roulette),
        learn_roulette(&camera, &world, &uniform, 64, None)
    );
    assert_eq!(plan, None);
    // A fixed scale is kept as it is, with nothing predicted.
    let fixed = PathOptions {
        roulette: Roulette::Scale(2.0),
        ..uniform
    };
    let (roulette, _) = prepare_render(&camera, &world, &fixed, 64, false, None);
    assert_eq!(roulette.scale, 2.0);
    assert_eq!(roulette.continuation, None);
    // Adaptive by default; the roulette learned once, for the pilot and the render.
    let learned = PathOptions::default();
    assert_eq!(learned.allocation, SampleAllocation::ByNoise);
    let (_, plan) = prepare_render(&camera, &world, &learned, 256, false, None);
    assert!(plan.is_some());
}
