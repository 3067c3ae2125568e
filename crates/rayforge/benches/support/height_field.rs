//! The rasterizer benchmark's scene, shared by `benches/raster.rs` and the
//! `raster_million` example (which times frames outside criterion).

use rayforge::geometry::{Mesh, MeshFace};
use rayforge::math::view_transform;
use rayforge::{point, vector, Camera, Color, Light, Material, Object, Point3, Vec3, World};
use std::sync::Arc;

/// A `n × n` grid of quads (2·n² triangles) over [-4, 4]², rippled, with smooth normals.
pub fn height_field(n: u32) -> Mesh {
    let height =
        |x: f64, z: f64| 0.15 * (3.0 * x).sin() * (2.0 * z).cos() + 0.05 * (7.0 * (x + z)).sin();
    let at = |i: u32| -4.0 + 8.0 * i as f64 / n as f64;
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    let mut normals = Vec::with_capacity(positions.capacity());
    let e = 1e-4;
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (at(i), at(j));
            positions.push(Point3::new(x, height(x, z), z));
            let dx = (height(x + e, z) - height(x - e, z)) / (2.0 * e);
            let dz = (height(x, z + e) - height(x, z - e)) / (2.0 * e);
            normals.push(Vec3::new(-dx, 1.0, -dz).normalize());
        }
    }
    let index = |i: u32, j: u32| j * (n + 1) + i;
    let mut faces = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            for v in [[a, b, c], [a, c, d]] {
                faces.push(MeshFace {
                    vertices: v,
                    normals: Some(v),
                    texcoords: None,
                });
            }
        }
    }
    Mesh::new(positions, normals, faces).expect("indices in range")
}

/// The benchmark's view: the height field of 708 × 708 quads (1 002 528 triangles) filling
/// a 1920×1080 image, under two lights.
pub fn scene() -> (Camera, World) {
    let camera = Camera::new(1920, 1080, 1.0).with_transform(view_transform(
        point(0.0, 2.5, -5.5),
        point(0.0, 0.0, 0.5),
        vector(0.0, 1.0, 0.0),
    ));
    let terrain = Object::mesh(Arc::new(height_field(708))).with_material(Material {
        color: Color::new(0.4, 0.7, 0.3),
        specular: 0.3,
        ..Material::DEFAULT
    });
    let world = World {
        objects: vec![terrain],
        lights: vec![
            Light::point(point(-10.0, 10.0, -10.0), Color::new(0.8, 0.8, 0.8)),
            Light::point(point(10.0, 5.0, -5.0), Color::new(0.3, 0.3, 0.4)),
        ],
        background: Color::new(0.1, 0.1, 0.15),
        ..World::default()
    };
    (camera, world)
}
