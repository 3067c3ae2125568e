//! The meshes the benchmarks trace: a bumpy sphere of any size, generated, and a model from an
//! OBJ file subdivided until it is large enough. Both sides of a comparison must see the same
//! triangles, so positions are kept in `f32` (what Embree takes) and rayforge gets exactly those
//! values widened to `f64`.

use rayforge::geometry::{Mesh, MeshError, MeshFace};
use rayforge::Point3;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;

/// Triangles over shared vertices, as the mesh file stores them.
#[derive(Debug, Clone, Default)]
pub struct Soup {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Corner indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
}

impl Soup {
    /// The same triangles as rayforge's mesh, flat-shaded (primary rays need no normals).
    /// Building the BVH is what this costs; the benchmarks time this call.
    pub fn to_mesh(&self) -> Result<Mesh, MeshError> {
        let (positions, faces) = self.mesh_parts();
        Mesh::new(positions, Vec::new(), faces)
    }

    /// The positions and faces [`Mesh::new`] takes, converted ahead of a timed build.
    pub fn mesh_parts(&self) -> (Vec<Point3>, Vec<MeshFace>) {
        let positions = self
            .positions
            .iter()
            .map(|p| Point3::new(p[0] as f64, p[1] as f64, p[2] as f64))
            .collect();
        let faces = self
            .triangles
            .iter()
            .map(|&vertices| MeshFace {
                vertices,
                normals: None,
                texcoords: None,
            })
            .collect();
        (positions, faces)
    }

    /// The centre and radius of a sphere around every vertex (for framing a camera).
    pub fn bounding_sphere(&self) -> (Point3, f64) {
        let mut lo = Point3::splat(f64::INFINITY);
        let mut hi = Point3::splat(f64::NEG_INFINITY);
        for p in &self.positions {
            let p = Point3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let centre = (lo + hi) * 0.5;
        let radius = self
            .positions
            .iter()
            .map(|p| (Point3::new(p[0] as f64, p[1] as f64, p[2] as f64) - centre).length())
            .fold(0.0, f64::max);
        (centre, radius)
    }
}

/// A sphere of radius about 1, its surface displaced by a few sine waves (up to ±8 %) so the
/// BVH faces real relief rather than a perfect ball, tessellated as a cube projected onto the
/// sphere: each cube face an n×n grid of quads, two triangles each, so 12·n² triangles with
/// n chosen to come nearest `triangles`. Every size samples the same surface, so a camera
/// frames them all alike and only the triangle count changes between sizes.
pub fn bumpy_sphere(triangles: usize) -> Soup {
    let n = ((triangles as f64 / 12.0).sqrt().round() as usize).max(1);
    let side = n + 1;
    let mut soup = Soup {
        positions: Vec::with_capacity(6 * side * side),
        triangles: Vec::with_capacity(12 * n * n),
    };
    // Each face: a normal axis and two axes spanning it, ordered so every face winds outward.
    let faces: [([f64; 3], [f64; 3], [f64; 3]); 6] = [
        ([1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ];
    for (normal, u_axis, v_axis) in faces {
        let base = soup.positions.len() as u32;
        for j in 0..side {
            for i in 0..side {
                // Points spaced by angle (tan) rather than evenly on the cube face, so the
                // triangles come out of similar size all over the sphere.
                let a = (PI / 4.0 * (2.0 * i as f64 / n as f64 - 1.0)).tan();
                let b = (PI / 4.0 * (2.0 * j as f64 / n as f64 - 1.0)).tan();
                let p = Point3::from(normal) + a * Point3::from(u_axis) + b * Point3::from(v_axis);
                let d = p.normalize();
                let r = 1.0 + relief(d);
                let q = d * r;
                soup.positions.push([q.x as f32, q.y as f32, q.z as f32]);
            }
        }
        let at = |i: usize, j: usize| base + (j * side + i) as u32;
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                soup.triangles.push([a, b, c]);
                soup.triangles.push([a, c, d]);
            }
        }
    }
    soup
}

/// The displacement of the bumpy sphere along direction `d`: two octaves of sine waves,
/// smooth and deterministic (no seed to carry between the two sides).
fn relief(d: Point3) -> f64 {
    0.06 * (5.0 * d.x + 1.0).sin() * (6.0 * d.y + 2.0).sin() * (7.0 * d.z + 3.0).sin()
        + 0.02 * (17.0 * d.x).sin() * (19.0 * d.y + 1.0).sin() * (23.0 * d.z + 2.0).sin()
}

/// Splits every triangle into four at its edges' midpoints (shared between neighbours, so the
/// surface stays closed), until there are at least `at_least` triangles.
pub fn subdivide_until(mut soup: Soup, at_least: usize) -> Soup {
    while soup.triangles.len() < at_least && !soup.triangles.is_empty() {
        soup = subdivide(&soup);
    }
    soup
}

fn subdivide(soup: &Soup) -> Soup {
    let mut positions = soup.positions.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(soup.triangles.len() * 2);
    let mut midpoint = |a: u32, b: u32, positions: &mut Vec<[f32; 3]>| {
        let key = (a.min(b), a.max(b));
        *midpoints.entry(key).or_insert_with(|| {
            let (p, q) = (positions[a as usize], positions[b as usize]);
            positions.push([
                (p[0] + q[0]) * 0.5,
                (p[1] + q[1]) * 0.5,
                (p[2] + q[2]) * 0.5,
            ]);
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(soup.triangles.len() * 4);
    for &[a, b, c] in &soup.triangles {
        let ab = midpoint(a, b, &mut positions);
        let bc = midpoint(b, c, &mut positions);
        let ca = midpoint(c, a, &mut positions);
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Soup {
        positions,
        triangles,
    }
}

/// Every triangle of an OBJ file as one soup (all groups and materials together).
pub fn read_obj(path: &Path) -> Result<Soup, String> {
    let mut no_textures = |p: &Path| {
        Err(rayforge_scene::SceneError::new(
            p,
            "textures are not read by the benchmark",
        ))
    };
    let obj = rayforge_scene::obj::read_obj_file(path, &mut no_textures)
        .map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    let mut soup = Soup::default();
    for (mesh, _) in rayforge_scene::obj::to_meshes(&obj) {
        let base = soup.positions.len() as u32;
        soup.positions.extend(
            mesh.positions()
                .iter()
                .map(|p| [p.x as f32, p.y as f32, p.z as f32]),
        );
        soup.triangles
            .extend(mesh.faces().map(|f| f.vertices.map(|i| i + base)));
    }
    if soup.triangles.is_empty() {
        return Err(format!("`{}` has no triangles", path.display()));
    }
    Ok(soup)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bumpy_sphere_has_the_size_asked_for_and_every_index_in_range() {
        let soup = bumpy_sphere(1_000);
        assert_eq!(soup.triangles.len(), 12 * 9 * 9);
        let n = soup.positions.len() as u32;
        assert!(soup.triangles.iter().flatten().all(|&i| i < n));
        let (centre, radius) = soup.bounding_sphere();
        assert!(
            centre.length() < 0.1 && (1.0..1.1).contains(&radius),
            "{centre} {radius}"
        );
    }

    #[test]
    fn subdividing_quadruples_triangles_and_shares_midpoints() {
        // Two triangles sharing an edge: 4 vertices, 5 edges, so 5 midpoints.
        let soup = Soup {
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let finer = subdivide_until(soup, 3);
        assert_eq!(finer.triangles.len(), 8);
        assert_eq!(finer.positions.len(), 9);
    }

    #[test]
    fn rays_through_the_bumpy_sphere_hit_it() {
        let mesh = bumpy_sphere(300).to_mesh().unwrap();
        let ray = rayforge::Ray::new(Point3::new(0.0, 0.0, -5.0), rayforge::vector(0.0, 0.0, 1.0));
        let hit = mesh.closest_hit(&ray, 0.0, f64::INFINITY).expect("a hit");
        assert!((3.8..4.2).contains(&hit.t), "{}", hit.t);
    }
}
