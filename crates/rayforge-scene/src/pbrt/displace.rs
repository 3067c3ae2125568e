//! A `plymesh`'s displacement (`"texture displacement"`, `"float edgelength"`, the option
//! `displacementedgescale`), by pbrt-v4's rules (its `TriQuadMesh::Displace`, described here
//! in our own words):
//!
//! - Where the PLY file gives no normals, each corner's normal is the normalized sum of the
//!   unit normals `(p1 − p0) × (p2 − p1)` of the faces around it.
//! - Each triangle is split while any of its edges, measured after the shape's transform, is
//!   not shorter than `edgelength × displacementedgescale`: the longest edge is cut at its
//!   midpoint (shared with the neighbour that cuts the same edge), and the two halves are
//!   refined in turn. A new point's position and (u, v) are its edge's means; its normal is
//!   the normalized sum of its edge's.
//! - Every point is moved along its normal by the float texture read at its (u, v) and at its
//!   position in the shape's own space (pbrt-v4 gives the texture that point as it is).
//! - The normals are made again from the displaced faces, as for a file without normals.
//!
//! The triangles the refinement makes are counted, within what `--max-triangles` leaves,
//! before any is made, so a tiny `edgelength` is refused rather than filling memory.

use super::params::ParamType;
use super::reader::{Description, Options, ShapeEntity};
use super::textures::SceneTextures;
use crate::error::SceneError;
use glam::{DMat4, DVec3};
use rayforge::shading::texture_graph::TextureContext;
use std::collections::HashMap;

/// What a shape's displacement reads besides the shape: the scene's float textures and the
/// option `displacementedgescale`.
pub struct Displacing<'a> {
    /// The scene's textures.
    pub textures: &'a SceneTextures,
    /// The scene's description (for the textures' names).
    pub desc: &'a Description,
    /// `Option "displacementedgescale"` (default 1).
    pub edge_scale: f64,
}

/// The option `displacementedgescale`: a positive finite number, 1 when not given.
pub fn edge_scale(options: &Options) -> Result<f64, SceneError> {
    let mut scale = 1.0;
    for (name, value, loc) in &options.options {
        if name == "displacementedgescale" {
            scale = value
                .parse::<f64>()
                .ok()
                .filter(|s| s.is_finite() && *s > 0.0)
                .ok_or_else(|| {
                    loc.error(
                        Some("Option"),
                        format!(
                            "the option \"displacementedgescale\" takes a positive number, \
                             found `{}`",
                            crate::error::clip_to(value, 40)
                        ),
                    )
                })?;
        }
    }
    Ok(scale)
}

/// A triangle mesh: points with their normals and (u, v), and faces.
pub struct Displaced {
    /// Positions, in the shape's space.
    pub positions: Vec<DVec3>,
    /// One normal a point.
    pub normals: Vec<DVec3>,
    /// One (u, v) a point.
    pub texcoords: Vec<[f64; 2]>,
    /// Three points a face.
    pub indices: Vec<u32>,
}

/// The mesh `input` (its `normals` empty where it has none; its `texcoords` empty or one a
/// point) refined and displaced as the [module](self) says, when `shape` has a
/// `displacement`; `input` as it is when it has none. `left` triangles are what
/// `--max-triangles` leaves for it.
pub fn displace(
    shape: &ShapeEntity,
    with: &Displacing<'_>,
    input: Displaced,
    left: usize,
    stop: &crate::stop::StopFlag,
) -> Result<Displaced, SceneError> {
    let params = &shape.entity.params;
    // Read whether or not the mesh is displaced, as pbrt-v4 reads it.
    let edge = params.float_at("edgelength")?;
    let Some(texture) = params.find("displacement", &[ParamType::Texture]) else {
        return Ok(input);
    };
    let node = with.textures.named(texture, "float", with.desc)?;
    let max_length = edge.map_or(1.0, |(e, _)| e) * with.edge_scale;
    if !(max_length.is_finite() && max_length > 0.0) {
        let message = format!(
            "a displaced plymesh's edgelength (times the option displacementedgescale) is a \
             positive length, found {max_length}"
        );
        return Err(match edge {
            Some((_, p)) => p.error(message),
            None => texture.error(message),
        });
    }
    let Displaced {
        positions,
        normals,
        texcoords,
        indices,
    } = input;
    if texcoords.len() != positions.len() || positions.is_empty() {
        return Err(texture.error(
            "a displaced plymesh needs (u, v) at every point of its PLY file (as pbrt-v4 does)",
        ));
    }
    let mut mesh = Displaced {
        normals: if normals.len() == positions.len() {
            normals
        } else {
            corner_normals(&positions, &indices)
        },
        positions,
        texcoords,
        indices: Vec::new(),
    };
    let length = Length(shape.world_from_object);
    let count = refined_count(&mesh.positions, &indices, &length, max_length, left, stop);
    if count > left {
        let message = format!(
            "displacing this plymesh with edgelength {max_length} makes more than the {left} \
             triangles `--max-triangles` leaves for it"
        );
        return Err(match edge {
            Some((_, p)) => p.error(message),
            None => texture.error(message),
        });
    }
    if stop.is_set() {
        return Err(SceneError::interrupted(&shape.entity.loc.file)
            .at(shape.entity.loc.span)
            .with_key("Shape"));
    }
    mesh.indices.reserve(3 * count);
    let mut split = HashMap::new();
    for t in indices.chunks_exact(3) {
        refine(
            &mut mesh,
            [t[0], t[1], t[2]],
            &length,
            max_length,
            &mut split,
        );
    }
    let graph = &with.textures.graph;
    for ((p, n), uv) in mesh
        .positions
        .iter_mut()
        .zip(&mesh.normals)
        .zip(&mesh.texcoords)
    {
        let ctx = TextureContext {
            uv: (uv[0], uv[1]),
            point: *p,
            normal: *n,
        };
        let d = graph.evaluate(node, &ctx).red;
        *p += d * *n;
    }
    mesh.normals = corner_normals(&mesh.positions, &mesh.indices);
    Ok(mesh)
}

/// An edge's length after the shape's transform (pbrt-v4 measures in its render space,
/// whose distances are the world's).
struct Length(DMat4);

impl Length {
    fn of(&self, a: DVec3, b: DVec3) -> f64 {
        self.0
            .transform_point3(a)
            .distance(self.0.transform_point3(b))
    }
}

/// Each point's normal: the normalized sum of its faces' unit normals (zero where it has
/// none, or only degenerate ones).
fn corner_normals(positions: &[DVec3], indices: &[u32]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
        let n = (b - a).cross(c - b);
        if n.length_squared() > 0.0 {
            let n = n.normalize();
            for &i in t {
                normals[i as usize] += n;
            }
        }
    }
    for n in &mut normals {
        if n.length_squared() > 0.0 {
            *n = n.normalize();
        }
    }
    normals
}

/// The corners of the triangle `p` turned so that its first edge is its longest (pbrt-v4's order among
/// equal ones), with whether it needs splitting.
fn longest_first(p: [DVec3; 3], length: &Length, max: f64) -> Option<[usize; 3]> {
    let [d01, d12, d20] = [
        length.of(p[0], p[1]),
        length.of(p[1], p[2]),
        length.of(p[2], p[0]),
    ];
    if d01 < max && d12 < max && d20 < max {
        return None;
    }
    Some(if d01 > d12 {
        if d01 > d20 {
            [0, 1, 2]
        } else {
            [2, 0, 1]
        }
    } else if d12 > d20 {
        [1, 2, 0]
    } else {
        [2, 0, 1]
    })
}

/// How many triangles refining `indices` makes, counting no further than `left + 1` (and
/// stopping there, or when `stop` is set): the same splits as [`refine`], on positions only.
fn refined_count(
    positions: &[DVec3],
    indices: &[u32],
    length: &Length,
    max: f64,
    left: usize,
    stop: &crate::stop::StopFlag,
) -> usize {
    let mut count = 0usize;
    let mut todo: Vec<[DVec3; 3]> = Vec::new();
    for t in indices.chunks_exact(3) {
        todo.push([t[0], t[1], t[2]].map(|i| positions[i as usize]));
        while let Some(p) = todo.pop() {
            match longest_first(p, length, max) {
                None => {
                    count += 1;
                    if count > left || (count % 4096 == 0 && stop.is_set()) {
                        return count;
                    }
                }
                Some([a, b, c]) => {
                    let mid = (p[a] + p[b]) / 2.0;
                    todo.push([mid, p[b], p[c]]);
                    todo.push([p[a], mid, p[c]]);
                }
            }
        }
    }
    count
}

/// Refines the triangle `t` into `mesh`'s faces (its new points added to `mesh`, each edge's
/// midpoint once, through `split`), in pbrt-v4's order: the first half before the second.
fn refine(
    mesh: &mut Displaced,
    t: [u32; 3],
    length: &Length,
    max: f64,
    split: &mut HashMap<(u32, u32), u32>,
) {
    let mut todo = vec![t];
    while let Some(t) = todo.pop() {
        let p = t.map(|i| mesh.positions[i as usize]);
        let Some([a, b, c]) = longest_first(p, length, max) else {
            mesh.indices.extend_from_slice(&t);
            continue;
        };
        let (v0, v1, v2) = (t[a], t[b], t[c]);
        let key = (v0.min(v1), v0.max(v1));
        let mid = *split.entry(key).or_insert_with(|| {
            let (i, j) = (v0 as usize, v1 as usize);
            let id = mesh.positions.len() as u32;
            mesh.positions
                .push((mesh.positions[i] + mesh.positions[j]) / 2.0);
            let n = mesh.normals[i] + mesh.normals[j];
            mesh.normals.push(if n.length_squared() > 0.0 {
                n.normalize()
            } else {
                n
            });
            let (s, u) = (mesh.texcoords[i], mesh.texcoords[j]);
            mesh.texcoords
                .push([(s[0] + u[0]) / 2.0, (s[1] + u[1]) / 2.0]);
            id
        });
        todo.push([mid, v1, v2]);
        todo.push([v0, mid, v2]);
    }
}
