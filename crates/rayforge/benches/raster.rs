//! Criterion benchmark for the rasterizer: a procedurally generated mesh of about a million
//! triangles (a rippled height field filling the view) at 1920×1080, Phong-shaded under two
//! lights, and a scene of 25 tessellated spheres on a plane.
//!
//! Run with `cargo bench -p rayforge --bench raster`. Results feed `docs/performance.md`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rayforge::math::view_transform;
use rayforge::raster::{self, RasterOptions, Shading};
use rayforge::{point, vector, Camera, Color, Light, Object, World};

#[path = "support/height_field.rs"]
mod height_field;
use height_field::scene;

fn raster_million(c: &mut Criterion) {
    let (camera, world) = scene();
    let mut group = c.benchmark_group("raster_1m_triangles_1920x1080");
    group.sample_size(10);
    group.throughput(Throughput::Elements(2 * 708 * 708));
    for (name, shading) in [
        ("phong", Shading::Phong),
        ("gouraud", Shading::Gouraud),
        ("flat", Shading::Flat),
    ] {
        let options = RasterOptions {
            shading,
            ..RasterOptions::default()
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                raster::render(&camera, &world, &options).expect("within the triangle budget")
            })
        });
    }
    group.finish();
}

fn raster_spheres(c: &mut Criterion) {
    let camera = Camera::new(1920, 1080, 1.0).with_transform(view_transform(
        point(0.0, 1.5, -8.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let mut objects =
        vec![Object::plane().with_transform(rayforge::math::translation(0.0, -1.0, 0.0))];
    for i in 0..25 {
        let (x, z) = ((i % 5) as f64 * 2.0 - 4.0, (i / 5) as f64 * 2.0 - 2.0);
        objects.push(Object::sphere().with_transform(
            rayforge::math::translation(x, -0.4, z) * rayforge::math::scaling(0.6, 0.6, 0.6),
        ));
    }
    let world = World {
        objects,
        lights: vec![Light::point(point(-10.0, 10.0, -10.0), Color::WHITE)],
        background: Color::BLACK,
        ..World::default()
    };
    let options = RasterOptions::default();
    let mut group = c.benchmark_group("raster_scene_1920x1080");
    group.sample_size(10);
    group.bench_function("25_spheres_and_a_plane", |b| {
        b.iter(|| raster::render(&camera, &world, &options).expect("within the triangle budget"))
    });
    group.finish();
}

criterion_group!(benches, raster_million, raster_spheres);
criterion_main!(benches);
