//! Fundamentals of Ray Tracing's regular polyhedra (chapter "Polyhedra"): the icosahedron and
//! the dodecahedron, as flat-faced meshes around the origin.
//!
//! The vertices are the classical coordinates built from the golden ratio φ, for the book's
//! size parameter `s` = 1: the icosahedron's twelve are `(0, ±1, ±φ)`, `(±1, ±φ, 0)`,
//! `(±φ, 0, ±1)`; the dodecahedron's twenty are `(±1, ±1, ±1)`, `(0, ±1/φ, ±φ)`,
//! `(±1/φ, ±φ, 0)`, `(±φ, 0, ±1/φ)`. The faces are not listed by hand: they are the planes
//! through three vertices with every other vertex behind them (the convex hull), each face's
//! vertices in order around it, split into a fan of triangles (a pentagon into three).

use super::{Mesh, MeshFace};
use crate::math::{Point3, Vec3};

/// The golden ratio.
fn phi() -> f64 {
    (1.0 + 5f64.sqrt()) / 2.0
}

/// Every combination of signs of `(a, b, c)`, skipping the sign of zero components.
fn signed(a: f64, b: f64, c: f64, out: &mut Vec<Point3>) {
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                let p = Point3::new(a * sx, b * sy, c * sz);
                if !out.iter().any(|q| (*q - p).length() < 1e-12) {
                    out.push(p);
                }
            }
        }
    }
}

/// The icosahedron with the book's `s` = 1 (edge 2): twelve vertices, twenty triangles.
pub fn icosahedron() -> Mesh {
    let p = phi();
    let mut v = Vec::new();
    signed(0.0, 1.0, p, &mut v);
    signed(1.0, p, 0.0, &mut v);
    signed(p, 0.0, 1.0, &mut v);
    convex_hull_mesh(v)
}

/// The dodecahedron with the book's `s` = 1 (edge 2/φ): twenty vertices, twelve pentagons
/// (thirty-six triangles).
pub fn dodecahedron() -> Mesh {
    let (p, r) = (phi(), 1.0 / phi());
    let mut v = Vec::new();
    signed(1.0, 1.0, 1.0, &mut v);
    signed(0.0, r, p, &mut v);
    signed(r, p, 0.0, &mut v);
    signed(p, 0.0, r, &mut v);
    convex_hull_mesh(v)
}

/// The flat-faced mesh of the convex hull of `vertices` (all of which must be on the hull,
/// around the origin): each face found once, wound so that the mesh's normal (the book's
/// `cross(e2, e1)`) points out of the solid.
fn convex_hull_mesh(vertices: Vec<Point3>) -> Mesh {
    const TOLERANCE: f64 = 1e-9;
    let n = vertices.len();
    let mut seen: Vec<Vec<usize>> = Vec::new();
    let mut faces = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let (a, b, c) = (vertices[i], vertices[j], vertices[k]);
                let mut normal = (b - a).cross(c - a);
                if normal.length() < TOLERANCE {
                    continue;
                }
                if normal.dot(a) < 0.0 {
                    normal = -normal;
                }
                let normal = normal.normalize();
                let offset = normal.dot(a);
                if vertices.iter().any(|v| normal.dot(*v) > offset + TOLERANCE) {
                    continue; // not a supporting plane
                }
                let on_face: Vec<usize> = (0..n)
                    .filter(|&m| (normal.dot(vertices[m]) - offset).abs() < TOLERANCE)
                    .collect();
                if seen.contains(&on_face) {
                    continue;
                }
                seen.push(on_face.clone());
                fan(&vertices, on_face, normal, &mut faces);
            }
        }
    }
    Mesh::new(vertices, Vec::new(), faces).expect("faces index the hull's own vertices")
}

/// Orders a face's vertices clockwise seen from outside (along `-normal`), which makes the
/// triangle normal `cross(e2, e1)` point outward, and splits the face into a fan of triangles
/// from its first vertex.
fn fan(vertices: &[Point3], mut face: Vec<usize>, normal: Vec3, out: &mut Vec<MeshFace>) {
    let centre = face.iter().map(|&i| vertices[i]).sum::<Point3>() / face.len() as f64;
    let u = (vertices[face[0]] - centre).normalize();
    let w = normal.cross(u);
    let angle = |i: usize| {
        let d = vertices[i] - centre;
        d.dot(w).atan2(d.dot(u))
    };
    face.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    for k in 1..face.len() - 1 {
        out.push(MeshFace {
            vertices: [face[0] as u32, face[k + 1] as u32, face[k] as u32],
            normals: None,
            texcoords: None,
        });
    }
}
