//! Same input, same bytes: every sampling mode gives bit-identical images on 1 and 4 threads
//! (each pixel's random choices are seeded by the pixel alone, never by the thread or order).
use rayforge::color::color;
use rayforge::math::{scaling, translation, view_transform};
use rayforge::render::{render, RenderOptions, Sampling};
use rayforge::{point, vector, AreaLight, Camera, Canvas, Light, Object, World};

/// Reflection, refraction and shadows, lit by a point light or a jittered area light.
fn world(area_light: bool) -> World {
    let mut w = World::new();
    let mut floor = Object::plane();
    floor.material.reflective = 0.3;
    floor.material.color = color(0.8, 0.9, 0.8);
    let mut glass = Object::glass_sphere().with_transform(translation(-0.7, 1.0, 0.0));
    glass.material.reflective = 0.9;
    let mut red =
        Object::sphere().with_transform(translation(1.2, 0.5, 1.5) * scaling(0.5, 0.5, 0.5));
    red.material.color = color(1.0, 0.2, 0.1);
    w.objects = vec![floor, glass, red];
    w.lights.push(if area_light {
        let mut light = AreaLight::new(
            point(-3.0, 4.0, -3.0),
            vector(2.0, 0.0, 0.0),
            4,
            vector(0.0, 2.0, 0.0),
            4,
            color(1.0, 1.0, 1.0),
        );
        light.jitter = true;
        Light::Area(light)
    } else {
        Light::point(point(-5.0, 8.0, -6.0), color(1.0, 1.0, 1.0))
    });
    w
}

fn camera(blur: bool) -> Camera {
    let c = Camera::new(24, 16, 1.0).with_transform(view_transform(
        point(0.0, 1.5, -5.0),
        point(0.0, 0.7, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    if blur {
        c.with_lens(0.4, 5.0)
    } else {
        c
    }
}

fn on_threads(threads: usize, camera: &Camera, world: &World, sampling: Sampling) -> Canvas {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let options = RenderOptions {
        sampling,
        ..RenderOptions::default()
    };
    pool.install(|| render(camera, world, &options).0)
}

fn bits(canvas: &Canvas) -> Vec<[u64; 3]> {
    canvas
        .pixels()
        .iter()
        .map(|c| c.to_array().map(f64::to_bits))
        .collect()
}

#[track_caller]
fn same_on_1_and_4_threads(camera: &Camera, world: &World, sampling: Sampling) {
    let one = on_threads(1, camera, world, sampling);
    let four = on_threads(4, camera, world, sampling);
    assert_eq!(bits(&one), bits(&four), "{sampling:?}");
    // And the image is not trivially black.
    assert!(one.pixels().iter().any(|c| c.red > 0.1), "{sampling:?}");
}

#[test]
fn centre_sampling_is_the_same_on_any_thread_count() {
    same_on_1_and_4_threads(&camera(false), &world(false), Sampling::Centre);
}

#[test]
fn stratified_sampling_is_the_same_on_any_thread_count() {
    same_on_1_and_4_threads(&camera(false), &world(false), Sampling::with_samples(9));
}

#[test]
fn adaptive_sampling_is_the_same_on_any_thread_count() {
    let adaptive = Sampling::Adaptive {
        threshold: 0.05,
        depth: 2,
    };
    same_on_1_and_4_threads(&camera(false), &world(false), adaptive);
}

#[test]
fn jittered_area_lights_are_the_same_on_any_thread_count() {
    same_on_1_and_4_threads(&camera(false), &world(true), Sampling::Centre);
    same_on_1_and_4_threads(&camera(false), &world(true), Sampling::with_samples(4));
}

#[test]
fn focal_blur_is_the_same_on_any_thread_count() {
    same_on_1_and_4_threads(&camera(true), &world(false), Sampling::with_samples(9));
    same_on_1_and_4_threads(&camera(true), &world(true), Sampling::with_samples(4));
}

#[test]
fn a_render_repeated_is_the_same() {
    let (c, w) = (camera(true), world(true));
    let s = Sampling::with_samples(4);
    assert_eq!(
        bits(&on_threads(3, &c, &w, s)),
        bits(&on_threads(3, &c, &w, s))
    );
}
