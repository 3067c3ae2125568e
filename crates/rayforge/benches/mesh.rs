//! Criterion benchmarks for meshes: BVH build time by triangle count, and how the time per
//! camera ray grows with the triangle count (it should grow roughly with the logarithm).
//!
//! Run with `cargo bench -p rayforge --bench mesh`. Results feed `docs/performance.md`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rayforge::geometry::{sphere_mesh, Mesh};
use rayforge::math::view_transform;
use rayforge::render::{render, RenderOptions};
use rayforge::{point, vector, Camera, Color, Light, Object, World};
use std::sync::Arc;

/// A sphere mesh with about `triangles` triangles.
fn mesh_with(triangles: u32) -> Mesh {
    let rings = ((triangles / 4) as f64).sqrt().max(2.0) as u32;
    sphere_mesh(rings, rings * 2)
}

fn bvh_build(c: &mut Criterion) {
    let mut group = c.benchmark_group("mesh_build");
    group.sample_size(10);
    for triangles in [10_000u32, 100_000, 1_000_000] {
        let mesh = mesh_with(triangles);
        let (positions, normals, faces) = (
            mesh.positions().to_vec(),
            mesh.normals().to_vec(),
            mesh.faces().collect::<Vec<_>>(),
        );
        group.throughput(Throughput::Elements(faces.len() as u64));
        group.bench_with_input(
            BenchmarkId::from_parameter(triangles),
            &triangles,
            |b, _| b.iter(|| Mesh::new(positions.clone(), normals.clone(), faces.clone())),
        );
    }
    group.finish();
}

fn render_by_size(c: &mut Criterion) {
    let mut group = c.benchmark_group("mesh_render_128x128");
    group.sample_size(10);
    let camera = Camera::new(128, 128, 0.8).with_transform(view_transform(
        point(0.0, 0.5, -4.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    for triangles in [1_000u32, 10_000, 100_000, 1_000_000] {
        let world = World {
            objects: vec![Object::mesh(Arc::new(mesh_with(triangles)))],
            lights: vec![Light::point(point(-5.0, 5.0, -5.0), Color::WHITE)],
            ..World::default()
        };
        group.throughput(Throughput::Elements(128 * 128));
        group.bench_with_input(BenchmarkId::from_parameter(triangles), &world, |b, w| {
            b.iter(|| render(&camera, w, &RenderOptions::default()))
        });
    }
    group.finish();
}

criterion_group!(benches, bvh_build, render_by_size);
criterion_main!(benches);
