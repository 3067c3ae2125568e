//! Criterion benchmarks: the intersection kernels and a small full render.
//!
//! Run with `cargo bench -p rayforge`. Results feed `docs/performance.md`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rayforge::math::{scaling, translation, view_transform};
use rayforge::render::{render, RenderOptions};
use rayforge::{default_world, point, vector, Camera, Object, Ray, Shape};
use std::hint::black_box;

fn intersections(c: &mut Criterion) {
    let mut group = c.benchmark_group("intersect");
    group.throughput(Throughput::Elements(1));
    let ray = Ray::new(point(0.1, 0.2, -5.0), vector(0.0, 0.0, 1.0));
    for (name, shape) in [
        ("sphere", Shape::Sphere),
        ("plane", Shape::Plane),
        ("cube", Shape::Cube),
    ] {
        let object =
            Object::new(shape).with_transform(translation(0.1, 0.0, 0.0) * scaling(1.5, 1.0, 1.0));
        let mut xs = Vec::with_capacity(8);
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| {
                xs.clear();
                object.intersect(black_box(&ray), &mut xs);
                xs.len()
            })
        });
    }
    group.finish();
}

fn small_render(c: &mut Criterion) {
    let world = default_world();
    let camera = Camera::new(64, 64, std::f64::consts::FRAC_PI_2).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let mut group = c.benchmark_group("render");
    group.throughput(Throughput::Elements(64 * 64));
    group.bench_function("default_world_64x64", |b| {
        b.iter(|| render(&camera, &world, &RenderOptions::default()))
    });
    group.finish();
}

criterion_group!(benches, intersections, small_render);
criterion_main!(benches);
