//! Shapes as triangle meshes: a tessellated sphere of any resolution, for benchmarks, tests and
//! (later) the rasterizer, which can only draw triangles.

use super::{Mesh, MeshFace};
use crate::math::{Point3, Vec3};
use std::f64::consts::PI;

/// The unit sphere as `rings` bands of `segments` quads (two triangles each), with smooth vertex
/// normals: `2 · rings · segments` triangles, less the degenerate ones at the poles' fans.
pub fn sphere_mesh(rings: u32, segments: u32) -> Mesh {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let mut positions = Vec::with_capacity(((rings + 1) * segments) as usize);
    for r in 0..=rings {
        let theta = PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = 2.0 * PI * s as f64 / segments as f64;
            positions.push(Point3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ));
        }
    }
    let normals: Vec<Vec3> = positions.clone();
    let index = |r: u32, s: u32| r * segments + s % segments;
    let mut faces = Vec::with_capacity((2 * rings * segments) as usize);
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (
                index(r, s),
                index(r + 1, s),
                index(r + 1, s + 1),
                index(r, s + 1),
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
    match Mesh::new(positions, normals, faces) {
        Ok(mesh) => mesh,
        // Every index above is below (rings + 1) · segments by construction.
        Err(e) => unreachable!("sphere tessellation produced a bad index: {e}"),
    }
}
