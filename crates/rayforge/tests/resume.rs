//! Cancelling a render between rows and resuming it from the rows it finished gives exactly
//! the image of an uninterrupted render.
use rayforge::color::color;
use rayforge::math::{translation, view_transform};
use rayforge::render::{render, render_rows, PartialImage, RenderOptions, Sampling};
use rayforge::{point, vector, Camera, Color, Light, Object, World};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

fn scene() -> (Camera, World) {
    let mut w = World::new();
    let mut floor = Object::plane();
    floor.material.reflective = 0.4;
    let mut ball = Object::glass_sphere().with_transform(translation(0.0, 1.0, 0.0));
    ball.material.reflective = 0.8;
    w.objects = vec![floor, ball];
    w.lights
        .push(Light::point(point(-5.0, 8.0, -6.0), color(1.0, 1.0, 1.0)));
    let camera = Camera::new(20, 30, 1.0).with_transform(view_transform(
        point(0.0, 1.5, -5.0),
        point(0.0, 1.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (camera, w)
}

fn bits(pixels: &[Color]) -> Vec<[u64; 3]> {
    pixels
        .iter()
        .map(|c| c.to_array().map(f64::to_bits))
        .collect()
}

fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn a_cancelled_render_resumed_equals_an_uninterrupted_one() {
    let (camera, world) = scene();
    let sampling = Sampling::with_samples(4);
    let whole = render(
        &camera,
        &world,
        &RenderOptions {
            sampling,
            ..RenderOptions::default()
        },
    )
    .0;
    // Cancel once 7 rows are done.
    let cancel = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let progress = |n: usize| {
        if done.fetch_add(n, Ordering::SeqCst) + n >= 7 {
            cancel.store(true, Ordering::SeqCst);
        }
    };
    let seen = Mutex::new(Vec::new());
    let on_row = |y: usize, row: &[Color]| seen.lock().unwrap().push((y, row.to_vec()));
    let (partial, first) = one_thread(|| {
        render_rows(
            &camera,
            &world,
            &RenderOptions {
                sampling,
                progress: Some(&progress),
                cancel: Some(&cancel),
                on_row: Some(&on_row),
                ..RenderOptions::default()
            },
        )
    });
    assert_eq!(
        partial.finished_rows(),
        7,
        "one thread stops right after the 7th row"
    );
    assert!(!partial.is_complete());
    // Every finished row was handed out once, with its pixels.
    let seen = seen.lock().unwrap().clone();
    assert_eq!(seen.len(), 7);
    for (y, row) in &seen {
        assert_eq!(bits(partial.row(*y).unwrap()), bits(row));
    }
    // Rebuild the partial image from the rows handed out (as a checkpoint file would).
    let mut saved = PartialImage::new(20, 30);
    for (y, row) in &seen {
        assert!(saved.set_row(*y, row));
    }
    let rows_done = AtomicUsize::new(0);
    let count = |n: usize| {
        rows_done.fetch_add(n, Ordering::SeqCst);
    };
    let (resumed, second) = render_rows(
        &camera,
        &world,
        &RenderOptions {
            sampling,
            finished: Some(&saved),
            progress: Some(&count),
            ..RenderOptions::default()
        },
    );
    assert!(resumed.is_complete());
    assert_eq!(
        rows_done.into_inner(),
        30 - 7,
        "finished rows are not traced again"
    );
    assert_eq!(
        bits(resumed.film().resolve().pixels()),
        bits(whole.pixels())
    );
    let all = render_rows(
        &camera,
        &world,
        &RenderOptions {
            sampling,
            ..RenderOptions::default()
        },
    )
    .1;
    assert_eq!(first.rays + second.rays, all.rays);
}

#[test]
fn a_render_cancelled_before_it_starts_renders_nothing() {
    let (camera, world) = scene();
    let cancel = AtomicBool::new(true);
    let (image, stats) = render_rows(
        &camera,
        &world,
        &RenderOptions {
            cancel: Some(&cancel),
            ..RenderOptions::default()
        },
    );
    assert_eq!((image.finished_rows(), stats.rays), (0, 0));
    assert!(image
        .film()
        .resolve()
        .pixels()
        .iter()
        .all(|c| *c == Color::BLACK));
}

#[test]
fn finished_rows_of_another_size_are_ignored() {
    let (camera, world) = scene();
    let mut wrong = PartialImage::new(5, 5);
    assert!(wrong.set_row(0, &[Color::WHITE; 5]));
    let (image, _) = render_rows(
        &camera,
        &world,
        &RenderOptions {
            finished: Some(&wrong),
            ..RenderOptions::default()
        },
    );
    assert!(image.is_complete());
    assert_eq!(
        bits(image.film().resolve().pixels()),
        bits(camera.render(&world).pixels())
    );
}

#[test]
fn partial_images_refuse_rows_that_do_not_fit() {
    let mut p = PartialImage::new(3, 2);
    assert!(!p.set_row(2, &[Color::WHITE; 3]));
    assert!(!p.set_row(0, &[Color::WHITE; 2]));
    assert!(p.set_row(1, &[Color::WHITE; 3]));
    assert_eq!(
        (p.finished_rows(), p.is_done(1), p.is_done(0)),
        (1, true, false)
    );
    assert_eq!(p.row(0), None);
    assert!(!p.is_done(99));
}
