//! Loop subdivision as pbrt-v4's `loopsubdiv` shape does it: a triangle mesh refined `levels`
//! times, its vertices then pushed to the limit surface and given the limit surface's normals,
//! the result a triangle mesh (pbrt-v4 renders the same triangles).
//!
//! The rules are Loop's, with pbrt-v4's choices:
//! - each level splits every triangle into four: the three corners' new points and one new
//!   point on each edge, the children keeping their parent's winding;
//! - a new point on an edge shared by two faces is `3/8` of each end and `1/8` of each face's
//!   third corner; on a boundary edge (one face) it is the edge's midpoint;
//! - an interior vertex of valence `n` moves to `(1 − nβ) p + β Σ ring`, `β = 3/16` for
//!   `n = 3` and `3 / 8n` otherwise; a boundary vertex to `3/4 p + 1/8` of each of its two
//!   boundary neighbours (so a boundary refines as a curve of its own, a cubic B-spline);
//! - after the last level an interior vertex moves to the limit `(1 − nγ) p + γ Σ ring` with
//!   `γ = 1 / (n + 3 / 8β)` (Loop's exact limit), a boundary vertex to `3/5 p + 1/5` of each
//!   boundary neighbour (pbrt-v4's weights, kept for fidelity, though the B-spline's own
//!   limit is `2/3, 1/6`);
//! - each vertex's normal is the cross product of the limit surface's two tangents there
//!   (pbrt-v4's, from its one-ring, in the order pbrt-v4 walks it: the sign matters, since a
//!   triangle faces the side of its corners' normals as a `trianglemesh`'s does). pbrt-v4's
//!   walk makes that normal point against the input faces' `(p1 − p0) × (p2 − p0)`, at
//!   interior and boundary points alike, so a `loopsubdiv` fronts the other way from a
//!   `trianglemesh` of the same faces; rayforge keeps pbrt-v4's side (it decides which
//!   side a one-sided area light shines from).
//!
//! The input must be a manifold with a consistent winding, as the rules assume (pbrt-v4 reads
//! anything and its walk about a vertex goes astray): every edge in at most two faces, and in
//! opposite directions where in two; every point in some face; the faces about each point one
//! fan. Anything else is refused with what is wrong and where.

use glam::DVec3;
use std::collections::HashMap;

/// A triangle mesh: points and the corners of each face (wound as pbrt-v4's input).
pub struct TriMesh {
    pub positions: Vec<DVec3>,
    pub faces: Vec<[u32; 3]>,
}

/// The subdivided mesh on the limit surface, with its limit normals (one a point).
pub struct Limit {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub faces: Vec<[u32; 3]>,
}

/// How many triangles `faces` triangles become after `levels` levels (4 each a level),
/// `None` past `usize`.
pub fn triangles_after(faces: usize, levels: u32) -> Option<usize> {
    4usize.checked_pow(levels)?.checked_mul(faces)
}

/// The mesh's connectivity: for each face, the face across each of its edges
/// (`v[k] → v[k + 1]`), and for each point, one face it is in and whether it is on a boundary.
struct Topology {
    across: Vec<[Option<u32>; 3]>,
    start: Vec<u32>,
    boundary: Vec<bool>,
}

impl Topology {
    /// The connectivity of `mesh`, or what makes it no manifold.
    fn of(mesh: &TriMesh) -> Result<Self, String> {
        let n = mesh.positions.len();
        let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.faces.len() * 3);
        let mut incident = vec![0usize; n];
        let mut start = vec![u32::MAX; n];
        for (f, face) in mesh.faces.iter().enumerate() {
            let [a, b, c] = *face;
            if a == b || b == c || c == a {
                return Err(format!(
                    "triangle {f} uses point {} twice",
                    if a == b { a } else { c }
                ));
            }
            for k in 0..3 {
                let edge = (face[k], face[(k + 1) % 3]);
                if directed.insert(edge, f as u32).is_some() {
                    return Err(format!(
                        "the edge from point {} to point {} is in two triangles the same way \
                         round (the faces' windings disagree, or the edge is in more than two)",
                        edge.0, edge.1
                    ));
                }
                incident[face[k] as usize] += 1;
                start[face[k] as usize] = f as u32;
            }
        }
        let mut across = vec![[None; 3]; mesh.faces.len()];
        for (f, face) in mesh.faces.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (face[k], face[(k + 1) % 3]);
                across[f][k] = directed.get(&(b, a)).copied();
            }
        }
        let mut topology = Topology {
            across,
            start,
            boundary: vec![false; n],
        };
        for (v, &faces) in incident.iter().enumerate() {
            if topology.start[v] == u32::MAX {
                return Err(format!("point {v} is in no triangle"));
            }
            // Walk forward about the point; a walk that ends is at a boundary.
            let mut f = topology.start[v];
            let mut seen = 1;
            loop {
                match topology.next_face(mesh, f, v as u32) {
                    Some(g) if g == topology.start[v] => break,
                    Some(g) => {
                        f = g;
                        seen += 1;
                        if seen > faces {
                            break;
                        }
                    }
                    None => {
                        topology.boundary[v] = true;
                        break;
                    }
                }
            }
            if topology.boundary[v] {
                // Count the faces behind the start as well.
                let mut f = topology.start[v];
                while let Some(g) = topology.prev_face(mesh, f, v as u32) {
                    f = g;
                    seen += 1;
                    if seen > faces {
                        break;
                    }
                }
            }
            if seen != faces {
                return Err(format!(
                    "the triangles about point {v} are not one fan (the surface is pinched there)"
                ));
            }
        }
        Ok(topology)
    }

    /// The slot of point `v` in face `f`.
    fn slot(mesh: &TriMesh, f: u32, v: u32) -> usize {
        let face = mesh.faces[f as usize];
        (0..3).find(|&k| face[k] == v).unwrap_or(0)
    }

    /// The face across the edge from `v` to the next corner of `f` (pbrt-v4's `nextFace`).
    fn next_face(&self, mesh: &TriMesh, f: u32, v: u32) -> Option<u32> {
        self.across[f as usize][Self::slot(mesh, f, v)]
    }

    /// The face across the edge from the previous corner of `f` to `v` (`prevFace`).
    fn prev_face(&self, mesh: &TriMesh, f: u32, v: u32) -> Option<u32> {
        self.across[f as usize][(Self::slot(mesh, f, v) + 2) % 3]
    }

    /// The points about `v` in pbrt-v4's order: an interior point's from its start face on
    /// by the next corners; a boundary point's from one boundary neighbour to the other (its
    /// first and last), so its length is the valence.
    fn ring(&self, mesh: &TriMesh, v: u32) -> Vec<u32> {
        let corner =
            |f: u32, step: usize| mesh.faces[f as usize][(Self::slot(mesh, f, v) + step) % 3];
        let start = self.start[v as usize];
        let mut ring = Vec::with_capacity(8);
        if !self.boundary[v as usize] {
            let mut f = start;
            loop {
                ring.push(corner(f, 1));
                match self.next_face(mesh, f, v) {
                    Some(g) if g != start => f = g,
                    _ => break,
                }
            }
        } else {
            let mut f = start;
            while let Some(g) = self.next_face(mesh, f, v) {
                f = g;
            }
            ring.push(corner(f, 1));
            let mut f = Some(f);
            while let Some(g) = f {
                ring.push(corner(g, 2));
                f = self.prev_face(mesh, g, v);
            }
        }
        ring
    }
}

/// Loop's β for an interior point of valence `n`.
fn beta(n: usize) -> f64 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f64)
    }
}

/// `(1 − nw) p + w Σ ring`.
fn one_ring(p: DVec3, ring: &[u32], positions: &[DVec3], w: f64) -> DVec3 {
    let sum: DVec3 = ring.iter().map(|&i| positions[i as usize]).sum();
    (1.0 - ring.len() as f64 * w) * p + w * sum
}

/// `(1 − 2w) p + w` (the first and last of the ring: the boundary neighbours).
fn boundary(p: DVec3, ring: &[u32], positions: &[DVec3], w: f64) -> DVec3 {
    let first = positions[ring[0] as usize];
    let last = positions[ring[ring.len() - 1] as usize];
    (1.0 - 2.0 * w) * p + w * (first + last)
}

/// One level: every triangle into four (see the [module](self)).
fn refine(mesh: &TriMesh, topology: &Topology) -> TriMesh {
    let positions = &mesh.positions;
    let mut out: Vec<DVec3> = (0..positions.len() as u32)
        .map(|v| {
            let ring = topology.ring(mesh, v);
            let p = positions[v as usize];
            if topology.boundary[v as usize] {
                boundary(p, &ring, positions, 1.0 / 8.0)
            } else {
                one_ring(p, &ring, positions, beta(ring.len()))
            }
        })
        .collect();
    let mut edge_points: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.faces.len() * 2);
    let mut faces = Vec::with_capacity(mesh.faces.len() * 4);
    for (f, face) in mesh.faces.iter().enumerate() {
        let mut mid = [0u32; 3];
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            mid[k] = *edge_points.entry(key).or_insert_with(|| {
                let (pa, pb) = (positions[a as usize], positions[b as usize]);
                let p = match topology.across[f][k] {
                    None => 0.5 * (pa + pb),
                    Some(g) => {
                        let third = |face: [u32; 3]| {
                            face.into_iter().find(|&i| i != a && i != b).unwrap_or(a)
                        };
                        let c = positions[third(*face) as usize];
                        let d = positions[third(mesh.faces[g as usize]) as usize];
                        3.0 / 8.0 * (pa + pb) + 1.0 / 8.0 * (c + d)
                    }
                };
                out.push(p);
                (out.len() - 1) as u32
            });
        }
        let [a, b, c] = *face;
        // mid[0] on a–b, mid[1] on b–c, mid[2] on c–a; each child wound as its parent.
        faces.push([a, mid[0], mid[2]]);
        faces.push([mid[0], b, mid[1]]);
        faces.push([mid[2], mid[1], c]);
        faces.push([mid[0], mid[1], mid[2]]);
    }
    TriMesh {
        positions: out,
        faces,
    }
}

/// `mesh` refined `levels` times, pushed to the limit surface, with its limit normals; or
/// what makes the input no manifold (see the [module](self)).
pub fn subdivide(mesh: TriMesh, levels: u32) -> Result<Limit, String> {
    let mut topology = Topology::of(&mesh)?;
    let mut mesh = mesh;
    for _ in 0..levels {
        mesh = refine(&mesh, &topology);
        // A refined manifold is one: its connectivity cannot fail.
        topology = Topology::of(&mesh)?;
    }
    let rings: Vec<Vec<u32>> = (0..mesh.positions.len() as u32)
        .map(|v| topology.ring(&mesh, v))
        .collect();
    let limit: Vec<DVec3> = rings
        .iter()
        .enumerate()
        .map(|(v, ring)| {
            let p = mesh.positions[v];
            if topology.boundary[v] {
                boundary(p, ring, &mesh.positions, 1.0 / 5.0)
            } else {
                let n = ring.len();
                let gamma = 1.0 / (n as f64 + 3.0 / (8.0 * beta(n)));
                one_ring(p, ring, &mesh.positions, gamma)
            }
        })
        .collect();
    let normals = rings
        .iter()
        .enumerate()
        .map(|(v, ring)| {
            let at = |i: usize| limit[ring[i] as usize];
            let p = limit[v];
            let n = ring.len();
            let (s, t) = if !topology.boundary[v] {
                let angle = |j: usize| std::f64::consts::TAU * j as f64 / n as f64;
                let s: DVec3 = (0..n).map(|j| angle(j).cos() * at(j)).sum();
                let t: DVec3 = (0..n).map(|j| angle(j).sin() * at(j)).sum();
                (s, t)
            } else {
                let s = at(n - 1) - at(0);
                let t = match n {
                    2 => at(0) + at(1) - 2.0 * p,
                    3 => at(1) - p,
                    4 => -at(0) + 2.0 * at(1) + 2.0 * at(2) - at(3) - 2.0 * p,
                    _ => {
                        let theta = std::f64::consts::PI / (n - 1) as f64;
                        let mut t = theta.sin() * (at(0) + at(n - 1));
                        for k in 1..n - 1 {
                            t += (2.0 * theta.cos() - 2.0) * (k as f64 * theta).sin() * at(k);
                        }
                        -t
                    }
                };
                (s, t)
            };
            s.cross(t)
        })
        .collect();
    Ok(Limit {
        positions: limit,
        normals,
        faces: mesh.faces,
    })
}
