//! Triangle meshes (chapter 15's OBJ models): shared vertex arrays, indexed faces and a BVH
//! over the faces, all in the mesh's object space.
//!
//! A mesh is one object to the scene however many faces it has, so a million-triangle model
//! costs its vertex data and, per face, its indices (12 bytes, twice that with normals), a
//! single-precision copy of its corners laid out four faces to a [`TrianglePacket`] in the
//! BVH's leaf order (36 bytes, plus the padding of part-filled packets) and its share of the
//! BVH, not a transform and material per triangle.
//!
//! Rays are answered in two steps: the BVH walk and the packet tests run in `f32` (eight boxes
//! or four triangles at a time), then the winning face is measured again in `f64` from
//! the original vertices, so the `t`, `u` and `v` a caller sees are as exact as the book's
//! lone triangles. Hits within a rounding error of the caller's `t_min` (a shadow ray
//! leaving the surface it starts on) are decided in `f64` as well.
//!
//! Which side of a face is its front is the mesh's [`Winding`], the convention of the format
//! it was read from: the book's for its own shapes, the right-handed counter-clockwise one for
//! OBJ models. Only the face normal follows it; the corners stay in the order given, so a
//! ray's `t`, `u` and `v` are the same under either.

mod packet;

use super::triangle::{inside, plane_crossing};
use super::LocalHit;
use crate::accel::{dispatch, pages, Bvh, Frame, Isa, Kernel, Lanes4, RayQuery};
use crate::accel::{MAX_BLOCKS, NO_PRIMITIVE};
use crate::math::{Aabb, Point3, Ray, Vec3};
use packet::{TrianglePacket, TriangleRay};
use rayon::prelude::*;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};

/// Faces tested together: one packet's lanes.
const PACKET: usize = 4;
/// A face's `f32` distance is trusted to this fraction of the mesh's size (along a unit
/// direction); nearer the caller's `t_min` than that, the hit is decided in `f64`. The `f32`
/// arithmetic errs by a few units of 2^-24 of the mesh's size; this is 2^-16.
const F32_TOLERANCE: f64 = 1.0 / 65536.0;
/// What a face without normal or texture indices stores in their place.
const NONE: u32 = u32::MAX;

/// One face: indices into the mesh's positions, and optionally into its normals (a smooth face).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshFace {
    /// Indices of the three corners in [`Mesh::positions`].
    pub vertices: [u32; 3],
    /// Indices of the corners' normals in [`Mesh::normals`], for smooth shading.
    pub normals: Option<[u32; 3]>,
    /// Indices of the corners' texture coordinates in [`Mesh::texcoords`], for texture maps.
    pub texcoords: Option<[u32; 3]>,
}

/// Why faces cannot make a mesh.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MeshError {
    /// A face names a vertex, normal or texture coordinate the mesh does not have.
    #[error("face {face} refers to {what} {index}, but the mesh has {count}")]
    BadIndex {
        /// Which face (0-based).
        face: usize,
        /// "vertex", "normal" or "texture coordinate".
        what: &'static str,
        /// The index it names (0-based).
        index: u32,
        /// How many there are.
        count: usize,
    },
    /// More faces than one BVH can hold.
    #[error("{faces} faces are more than one mesh can hold ({max})")]
    TooManyFaces {
        /// How many were given.
        faces: usize,
        /// The most a mesh holds.
        max: usize,
    },
    /// The stop flag given to [`Mesh::with_texcoords_until`] was set before the mesh was
    /// built.
    #[error("the mesh's build was stopped")]
    Stopped,
}

/// Which side of a mesh's faces is their front, told by the order of their corners: the side
/// the face normal points to, and so the side that `emission-side: front` lights, that a
/// one-sided material shows and that a glass mesh is entered from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Winding {
    /// The book's triangles': the front is the side of `e2 × e1` (`e1 = p2 − p1`,
    /// `e2 = p3 − p1`), the side from which the corners turn counter-clockwise in the book's
    /// left-handed space. The meshes built here (the polyhedra, the tessellated sphere) are
    /// wound so, and so are glTF's faces, which its reader stores reversed because it mirrors
    /// glTF's right-handed space into the book's.
    #[default]
    Book,
    /// OBJ's: the front is the side of `e1 × e2`, the side from which the corners turn
    /// counter-clockwise in the file's own right-handed axes, as Blender writes them and
    /// other renderers read them. The coordinates are read as they are, so this is the
    /// book's winding reversed.
    RightHanded,
}

/// An indexed triangle mesh with its own BVH.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    positions: Vec<Point3>,
    normals: Vec<Vec3>,
    texcoords: Vec<[f64; 2]>,
    /// Each face's corners: indices into `positions`.
    corners: Vec<[u32; 3]>,
    /// Each face's normal indices ([`NONE`] for a flat face); empty when no face has any.
    corner_normals: Vec<[u32; 3]>,
    /// Each face's texture coordinate indices ([`NONE`] for none); empty when no face has any.
    corner_texcoords: Vec<[u32; 3]>,
    /// Over the faces, in blocks of [`PACKET`].
    bvh: Bvh,
    /// The faces' corners in `f32`, one packet per block of the BVH's order.
    packets: Vec<TrianglePacket>,
    /// [`F32_TOLERANCE`] times the mesh's size.
    tolerance: f64,
    /// Per-vertex tangents and colours (glTF's `TANGENT` and `COLOR_0`), when the model has
    /// them; boxed so that meshes without them (every OBJ model) stay small.
    attributes: Option<Box<VertexAttributes>>,
    /// Which side of each face is its front.
    winding: Winding,
}

/// Attributes a mesh may carry per vertex beyond position, normal and texture coordinates,
/// each list indexed like the positions (glTF gives every attribute of a vertex one index).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VertexAttributes {
    /// Tangents along which the texture's u grows, with the bitangent's sign in `w` (glTF's
    /// `TANGENT`): the frame a tangent-space normal map is read in. Empty when absent.
    pub tangents: Vec<glam::DVec4>,
    /// Linear RGBA colours that multiply the material's base colour (glTF's `COLOR_0`).
    /// Empty when absent.
    pub colors: Vec<[f32; 4]>,
}

impl Mesh {
    /// A mesh from its vertex data and faces; every index must be in range.
    pub fn new(
        positions: Vec<Point3>,
        normals: Vec<Vec3>,
        faces: Vec<MeshFace>,
    ) -> Result<Self, MeshError> {
        Self::with_texcoords(positions, normals, Vec::new(), faces)
    }

    /// A mesh with texture coordinates as well; every index must be in range.
    ///
    /// Faces with a corner beyond ±10^30 units from the others cannot be held in the BVH's
    /// single precision; they are kept (the rasterizer draws them) but rays pass them by.
    pub fn with_texcoords(
        positions: Vec<Point3>,
        normals: Vec<Vec3>,
        texcoords: Vec<[f64; 2]>,
        faces: Vec<MeshFace>,
    ) -> Result<Self, MeshError> {
        Self::with_texcoords_until(positions, normals, texcoords, faces, None)
    }

    /// [`Mesh::with_texcoords`] that gives up ([`MeshError::Stopped`]) once `stop` is set
    /// (Ctrl-C, a server's cancel): looked at between the build's passes and as each node of
    /// the BVH is begun, so a model of tens of millions of faces stops within one node's split.
    /// Not stopped, the very mesh [`Mesh::with_texcoords`] makes.
    pub fn with_texcoords_until(
        positions: Vec<Point3>,
        normals: Vec<Vec3>,
        texcoords: Vec<[f64; 2]>,
        faces: Vec<MeshFace>,
        stop: Option<&AtomicBool>,
    ) -> Result<Self, MeshError> {
        let stopped = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
        if faces.len() >= MAX_BLOCKS {
            return Err(MeshError::TooManyFaces {
                faces: faces.len(),
                max: MAX_BLOCKS - 1,
            });
        }
        // Every index in range (checked in parallel: a million-face model is common).
        let bad_index = |face: usize, f: &MeshFace| {
            let lists = [
                ("vertex", Some(f.vertices), positions.len()),
                ("normal", f.normals, normals.len()),
                ("texture coordinate", f.texcoords, texcoords.len()),
            ];
            lists.into_iter().find_map(|(what, indices, count)| {
                let index = indices?.into_iter().find(|&i| i as usize >= count)?;
                Some(MeshError::BadIndex {
                    face,
                    what,
                    index,
                    count,
                })
            })
        };
        // One pass over the faces (a million-face model's faces take tens of megabytes, so
        // each pass costs): the first bad face, and whether any has normals or texture
        // coordinates.
        let (first_bad, any_normals, any_texcoords) = faces
            .par_iter()
            .enumerate()
            .with_min_len(4096)
            .map(|(i, f)| {
                let bad = bad_index(i, f).is_some().then_some(i);
                (bad, f.normals.is_some(), f.texcoords.is_some())
            })
            .reduce(
                || (None, false, false),
                |a, b| (a.0.into_iter().chain(b.0).min(), a.1 || b.1, a.2 || b.2),
            );
        if let Some(face) = first_bad {
            return Err(bad_index(face, &faces[face]).expect("the face just found"));
        }
        let corners: Vec<[u32; 3]> = pages::collect(faces.par_iter().map(|f| f.vertices));
        let optional = |any: bool, pick: fn(&MeshFace) -> Option<[u32; 3]>| -> Vec<[u32; 3]> {
            if any {
                pages::collect(faces.par_iter().map(|f| pick(f).unwrap_or([NONE; 3])))
            } else {
                Vec::new()
            }
        };
        let corner_normals = optional(any_normals, |f| f.normals);
        let corner_texcoords = optional(any_texcoords, |f| f.texcoords);
        drop(faces);
        if stopped() {
            return Err(MeshError::Stopped);
        }
        let (bvh, packets, tolerance) =
            index(&positions, &corners, stop).ok_or(MeshError::Stopped)?;
        Ok(Self {
            positions,
            normals,
            texcoords,
            corners,
            corner_normals,
            corner_texcoords,
            bvh,
            packets,
            tolerance,
            attributes: None,
            winding: Winding::Book,
        })
    }

    /// The same mesh with its faces' fronts told by `winding` (a new mesh has the book's).
    pub fn with_winding(self, winding: Winding) -> Self {
        Self { winding, ..self }
    }

    /// Which side of each face is its front.
    pub fn winding(&self) -> Winding {
        self.winding
    }

    /// The same mesh with per-vertex tangents and colours; each list must be empty or hold
    /// one entry per position (`None` otherwise).
    pub fn with_attributes(mut self, attributes: VertexAttributes) -> Option<Self> {
        let fits = |len: usize| len == 0 || len == self.positions.len();
        if !fits(attributes.tangents.len()) || !fits(attributes.colors.len()) {
            return None;
        }
        let empty = attributes.tangents.is_empty() && attributes.colors.is_empty();
        self.attributes = (!empty).then(|| Box::new(attributes));
        Some(self)
    }

    /// The per-vertex tangents and colours, if the mesh has any.
    pub fn attributes(&self) -> Option<&VertexAttributes> {
        self.attributes.as_deref()
    }

    /// A per-vertex quantity at a hit, blended from its face's corners by `u`, `v`.
    #[inline]
    fn blend<T: Copy, R>(
        &self,
        hit: &LocalHit,
        list: &[T],
        mix: impl Fn([T; 3], [f64; 3]) -> R,
    ) -> Option<R> {
        let corners = self.corners.get(hit.face as usize)?;
        let values = [
            *list.get(corners[0] as usize)?,
            *list.get(corners[1] as usize)?,
            *list.get(corners[2] as usize)?,
        ];
        Some(mix(values, [1.0 - hit.u - hit.v, hit.u, hit.v]))
    }

    /// The tangent at a hit (object space, not normalised) and the bitangent's sign, when the
    /// mesh has tangents.
    #[inline]
    pub fn tangent_at(&self, hit: &LocalHit) -> Option<(Vec3, f64)> {
        let tangents = &self.attributes.as_deref()?.tangents;
        self.blend(hit, tangents, |t, w| {
            let v = t[0] * w[0] + t[1] * w[1] + t[2] * w[2];
            (v.truncate(), if t[0].w < 0.0 { -1.0 } else { 1.0 })
        })
    }

    /// The vertex colour (linear RGBA) at a hit, when the mesh has colours.
    #[inline]
    pub fn color_at(&self, hit: &LocalHit) -> Option<[f64; 4]> {
        let colors = &self.attributes.as_deref()?.colors;
        self.blend(hit, colors, |c, w| {
            std::array::from_fn(|i| {
                f64::from(c[0][i]) * w[0] + f64::from(c[1][i]) * w[1] + f64::from(c[2][i]) * w[2]
            })
        })
    }

    /// The vertex positions.
    pub fn positions(&self) -> &[Point3] {
        &self.positions
    }

    /// The vertex normals (empty when the mesh has none).
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// The texture coordinates (empty when the mesh has none).
    pub fn texcoords(&self) -> &[[f64; 2]] {
        &self.texcoords
    }

    /// How many faces the mesh has.
    pub fn face_count(&self) -> usize {
        self.corners.len()
    }

    /// Face `index` (`index < face_count()`).
    pub fn face(&self, index: usize) -> MeshFace {
        let optional = |list: &[[u32; 3]]| list.get(index).filter(|i| i[0] != NONE).copied();
        MeshFace {
            vertices: self.corners[index],
            normals: optional(&self.corner_normals),
            texcoords: optional(&self.corner_texcoords),
        }
    }

    /// The faces, in the order they were given.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = MeshFace> + '_ {
        (0..self.corners.len()).map(|i| self.face(i))
    }

    /// The texture coordinates at a hit, blended from its face's corners by `u`, `v`; `None`
    /// when the face has none.
    pub fn texcoord_at(&self, hit: &LocalHit) -> Option<(f64, f64)> {
        let [t1, t2, t3] = self
            .corner_texcoords
            .get(hit.face as usize)
            .filter(|i| i[0] != NONE)?
            .map(|i| self.texcoords[i as usize]);
        let w = 1.0 - hit.u - hit.v;
        Some((
            t1[0] * w + t2[0] * hit.u + t3[0] * hit.v,
            t1[1] * w + t2[1] * hit.u + t3[1] * hit.v,
        ))
    }

    /// Bytes the mesh holds beyond its vertex data (positions, normals, texture coordinates):
    /// its faces' indices, the `f32` packets and the BVH. The performance budget is stated
    /// per triangle in these terms (see `docs/performance.md`).
    pub fn index_bytes(&self) -> usize {
        let indices = self.corners.len() + self.corner_normals.len() + self.corner_texcoords.len();
        indices * std::mem::size_of::<[u32; 3]>()
            + self.packets.len() * std::mem::size_of::<TrianglePacket>()
            + self.bvh.heap_bytes()
    }

    /// The box around every face the BVH holds.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The corners of a face.
    #[inline]
    pub fn corners(&self, face: &MeshFace) -> [Point3; 3] {
        face.vertices.map(|i| self.positions[i as usize])
    }

    /// Every hit of the ray on the mesh's faces (negative `t` included), through the BVH.
    #[inline]
    pub fn intersect(&self, ray: &Ray, hit: impl FnMut(LocalHit)) {
        self.intersect_up_to(ray, f64::INFINITY, hit);
    }

    /// Every hit with `t <= t_max` (negative `t` included); boxes beyond `t_max` are skipped.
    pub fn intersect_up_to(&self, ray: &Ray, t_max: f64, hit: impl FnMut(LocalHit)) {
        dispatch(EveryHit {
            mesh: self,
            ray,
            t_max,
            hit,
        });
    }

    /// How far an `f32` distance along `ray` may be from the truth: [`F32_TOLERANCE`] of
    /// the mesh's size, in units of the ray's direction.
    #[inline]
    fn tolerance_along(&self, ray: &Ray) -> f32 {
        (self.tolerance / ray.direction.length()) as f32
    }

    /// The nearest hit with `t_min <= t < t_max`: the BVH walk skips boxes beyond the nearest
    /// hit found so far, so a ray costs a few dozen boxes and triangles even on a large model.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<LocalHit> {
        let mut best = None;
        dispatch(Search {
            mesh: self,
            ray,
            t_min,
            t_max,
            accept: |face, t, _| {
                best = Some(face);
                t
            },
        });
        // The f32 search already placed the hit in range; a last rounding step of the f64
        // measurement must not move it out.
        self.measure(best?, ray).map(|h| LocalHit {
            t: h.t.max(t_min).min(t_max),
            ..h
        })
    }

    /// Whether any face meets the ray with `t_min <= t < t_max` (shadow rays): the walk stops
    /// at the first one.
    #[inline]
    pub fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let mut found = false;
        dispatch(Search {
            mesh: self,
            ray,
            t_min,
            t_max,
            accept: |_, _, _| {
                found = true;
                f32::NEG_INFINITY
            },
        });
        found
    }

    /// [`Mesh::closest_hit`] among the hits that `keep` accepts (a material's alpha mask
    /// cutting holes in the surface): a refused hit lets the walk go on to those behind it.
    #[inline]
    pub fn closest_hit_where(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut keep: impl FnMut(&LocalHit) -> bool,
    ) -> Option<LocalHit> {
        let mut best = None;
        dispatch(Search {
            mesh: self,
            ray,
            t_min,
            t_max,
            accept: |face, t, limit| match self.measure(face, ray) {
                Some(h) if keep(&h) => {
                    best = Some(h);
                    t
                }
                _ => limit,
            },
        });
        best.map(|h| LocalHit {
            t: h.t.max(t_min).min(t_max),
            ..h
        })
    }

    /// [`Mesh::any_hit`] among the hits that `keep` accepts.
    #[inline]
    pub fn any_hit_where(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut keep: impl FnMut(&LocalHit) -> bool,
    ) -> bool {
        let mut found = false;
        dispatch(Search {
            mesh: self,
            ray,
            t_min,
            t_max,
            accept: |face, _, limit| {
                if self.measure(face, ray).is_some_and(|h| keep(&h)) {
                    found = true;
                    f32::NEG_INFINITY
                } else {
                    limit
                }
            },
        });
        found
    }

    /// Walks the BVH for the ray `q`, nearest boxes first, testing the packets of each leaf
    /// it reaches, and calls `hit` with each face hit in `[t_min, limit)`, its query distance
    /// and the limit (at first `t_max`), which `hit` may lower to skip farther boxes; `Break`
    /// stops the walk.
    #[inline(always)]
    fn walk_faces<I: Isa>(
        &self,
        isa: I,
        q: &RayQuery,
        t_min: f32,
        t_max: f32,
        mut hit: impl FnMut(u32, f32, &mut f32) -> ControlFlow<()>,
    ) {
        let tri = TriangleRay::new(isa, q);
        self.bvh.walk(
            isa,
            q,
            t_min,
            t_max,
            #[inline(always)]
            |slots, limit| {
                for block in slots.start / PACKET..slots.end / PACKET {
                    let packet = &self.packets[block];
                    let (mut lanes, t) = packet.intersect(isa, &tri, t_min, *limit);
                    if lanes == 0 {
                        continue;
                    }
                    let t = t.to_array();
                    while lanes != 0 {
                        let lane = lanes.trailing_zeros() as usize;
                        lanes &= lanes - 1;
                        hit(packet.faces[lane], t[lane], limit)?;
                    }
                }
                ControlFlow::Continue(())
            },
        );
    }

    /// The hit of the ray on `face` measured in `f64` (Möller–Trumbore, as for the book's
    /// triangles). For a ray the watertight `f32` test saw cross the face exactly at an edge,
    /// where `f64` may fall a rounding error outside, `u` and `v` are clamped to the face.
    fn measure(&self, face: u32, ray: &Ray) -> Option<LocalHit> {
        let [p1, p2, p3] = self.corners[face as usize].map(|i| self.positions[i as usize]);
        let (e1, e2) = (p2 - p1, p3 - p1);
        let (t, u, v) = plane_crossing(ray, p1, e1, e2)?;
        let (u, v) = if inside(u, v) {
            (u, v)
        } else {
            let u = u.clamp(0.0, 1.0);
            (u, v.clamp(0.0, 1.0 - u))
        };
        Some(LocalHit {
            t,
            u,
            v,
            face,
            time: ray.time,
            ..LocalHit::default()
        })
    }

    /// Face `face`'s geometric normal (not normalised), towards its front by the mesh's
    /// [`Winding`].
    #[inline]
    pub fn face_normal(&self, face: u32) -> Vec3 {
        let Some(corners) = self.corners.get(face as usize) else {
            return Vec3::ZERO;
        };
        self.front_of(corners.map(|i| self.positions[i as usize]))
    }

    /// The normal of the triangle `p1 p2 p3` (not normalised) towards its front by the mesh's
    /// winding. (`a × b` is exactly `−(b × a)` in floating point, so the two windings' normals
    /// differ only in sign.)
    #[inline]
    fn front_of(&self, [p1, p2, p3]: [Point3; 3]) -> Vec3 {
        match self.winding {
            Winding::Book => (p3 - p1).cross(p2 - p1),
            Winding::RightHanded => (p2 - p1).cross(p3 - p1),
        }
    }

    /// The normal at a hit: the vertex normals blended by `u`, `v` on smooth faces (as the
    /// file gave them, whatever the winding), the face normal otherwise.
    #[inline]
    pub fn normal_at(&self, hit: &LocalHit) -> Vec3 {
        let Some(corners) = self.corners.get(hit.face as usize) else {
            return Vec3::ZERO;
        };
        match self
            .corner_normals
            .get(hit.face as usize)
            .filter(|n| n[0] != NONE)
        {
            Some(n) => {
                let [n1, n2, n3] = n.map(|i| self.normals[i as usize]);
                n2 * hit.u + n3 * hit.v + n1 * (1.0 - hit.u - hit.v)
            }
            None => self
                .front_of(corners.map(|i| self.positions[i as usize]))
                .normalize_or_zero(),
        }
    }
}

/// The walk for hits in `[t_min, t_max)`, nearest boxes first, as a [`Kernel`]: `accept`
/// receives each face hit nearer than the current limit, its query distance and that limit,
/// and returns the new limit (its distance for a closest-hit search, the limit unchanged for
/// a hit it refuses; −∞ stops the walk).
struct Search<'a, A> {
    mesh: &'a Mesh,
    ray: &'a Ray,
    t_min: f64,
    t_max: f64,
    accept: A,
}

impl<A: FnMut(u32, f32, f32) -> f32> Kernel for Search<'_, A> {
    type Output = ();

    #[inline(always)]
    fn run<I: Isa>(self, isa: I) {
        let Self {
            mesh,
            ray,
            t_min,
            t_max,
            mut accept,
        } = self;
        let q = mesh.bvh.query(ray.origin, ray.direction);
        let tolerance = mesh.tolerance_along(ray);
        let (lower, upper) = (q.t_below(t_min), q.t_above(t_max));
        let doubtful = lower + tolerance;
        mesh.walk_faces(
            isa,
            &q,
            lower - tolerance,
            upper,
            #[inline(always)]
            |face, t, limit| {
                if t >= *limit {
                    return ControlFlow::Continue(());
                }
                if t < doubtful {
                    // Too close to call in f32 (a ray leaving this very surface): in f64.
                    let inside = mesh
                        .measure(face, ray)
                        .is_some_and(|h| h.t >= t_min && h.t < t_max);
                    if !inside {
                        return ControlFlow::Continue(());
                    }
                }
                *limit = accept(face, t, *limit);
                if *limit == f32::NEG_INFINITY {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        );
    }
}

/// Every hit with `t <= t_max`, negative `t` included, as a [`Kernel`].
struct EveryHit<'a, H> {
    mesh: &'a Mesh,
    ray: &'a Ray,
    t_max: f64,
    hit: H,
}

impl<H: FnMut(LocalHit)> Kernel for EveryHit<'_, H> {
    type Output = ();

    #[inline(always)]
    fn run<I: Isa>(self, isa: I) {
        let Self {
            mesh,
            ray,
            t_max,
            mut hit,
        } = self;
        let q = mesh.bvh.query(ray.origin, ray.direction);
        // The f32 search reaches a little past t_max, so that a hit measured in f64 at
        // exactly t_max (the hit a closest-hit search returned) is never left out.
        let upper = q.t_above(t_max) + mesh.tolerance_along(ray);
        mesh.walk_faces(
            isa,
            &q,
            f32::NEG_INFINITY,
            upper,
            #[inline(always)]
            |face, _, _| {
                if let Some(h) = mesh.measure(face, ray) {
                    if h.t <= t_max {
                        hit(h);
                    }
                }
                ControlFlow::Continue(())
            },
        );
    }
}

/// Builds the BVH over the faces and their packets, and the mesh's `f32` tolerance; `None`
/// when `stop` was set before the BVH was through.
fn index(
    positions: &[Point3],
    corners: &[[u32; 3]],
    stop: Option<&AtomicBool>,
) -> Option<(Bvh, Vec<TrianglePacket>, f64)> {
    // The frame is centred on the vertices that fit in f32 (a stray vertex at 1e300 must not
    // drag the base point away from everything else).
    let fits = |p: &Point3| p.is_finite() && p.abs().max_element() <= 1.0e30;
    let mut extent = Aabb::EMPTY;
    for p in positions.iter().filter(|p| fits(p)) {
        extent.add_point(*p);
    }
    let frame = Frame::around(&extent);
    let face_box = |c: &[u32; 3]| {
        let [a, b, c] = c.map(|i| positions[i as usize]);
        (a.min(b).min(c), a.max(b).max(c))
    };
    let refs = frame.prim_refs(corners.len(), |i| Some(face_box(&corners[i])));
    // The exact (f64) box of the faces the BVH holds.
    let bounds = corners
        .par_iter()
        .with_min_len(4096)
        .map(face_box)
        .filter(|&(min, max)| frame.prim_ref(0, min, max).is_some())
        .map(|(min, max)| Aabb::new(min, max))
        .reduce(|| Aabb::EMPTY, |a, b| a.union(&b));
    let bvh = crate::accel::build(refs, PACKET, frame, bounds, stop)?;
    let packets: Vec<TrianglePacket> = pages::collect(
        bvh.order()
            .par_chunks(PACKET)
            .with_min_len(1024)
            .map(|faces| {
                let mut packet = TrianglePacket::EMPTY;
                for (lane, &face) in faces.iter().enumerate() {
                    if face != NO_PRIMITIVE {
                        let relative = corners[face as usize]
                            .map(|i| (positions[i as usize] - frame.base).as_vec3().to_array());
                        packet.set(lane, face, relative);
                    }
                }
                packet
            }),
    );
    let size = bounds.extent().max_element();
    let tolerance = if size.is_finite() {
        size * F32_TOLERANCE
    } else {
        0.0
    };
    Some((bvh, packets, tolerance))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Triangle;

    /// The book's triangle (its chapter 15 scenario) as a one-face mesh wound `winding`.
    fn book_triangle(winding: Winding) -> Mesh {
        let corners = vec![
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
        ];
        let face = MeshFace {
            vertices: [0, 1, 2],
            normals: None,
            texcoords: None,
        };
        Mesh::new(corners, Vec::new(), vec![face])
            .unwrap()
            .with_winding(winding)
    }

    #[test]
    fn a_book_wound_face_has_the_book_triangles_normal() {
        let book = Triangle::new(
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
        );
        // The book: "the normal of the triangle is (0, 0, -1)".
        assert_eq!(book.normal, Vec3::new(0.0, 0.0, -1.0));
        let mesh = book_triangle(Winding::Book);
        assert_eq!(mesh.winding(), Winding::default());
        assert_eq!(mesh.face_normal(0).normalize(), book.normal);
        let hit = mesh.closest_hit(&Ray::new(Point3::new(0.0, 0.5, -2.0), Vec3::Z), 0.0, 9.0);
        assert_eq!(mesh.normal_at(&hit.unwrap()), book.normal);
    }

    #[test]
    fn a_right_handed_face_fronts_the_side_its_corners_turn_counter_clockwise_in_right_handed_axes()
    {
        // Seen from +z in right-handed axes (x right, y up, z towards the viewer), the
        // corners (0, 1, 0), (-1, 0, 0), (1, 0, 0) turn counter-clockwise: OBJ's front is +z.
        let mesh = book_triangle(Winding::RightHanded);
        assert_eq!(mesh.face_normal(0).normalize(), Vec3::Z);
        let ray = Ray::new(Point3::new(0.0, 0.5, -2.0), Vec3::Z);
        let hit = mesh.closest_hit(&ray, 0.0, 9.0).unwrap();
        assert_eq!(mesh.normal_at(&hit), Vec3::Z);
        // Only the normal turns: the hit itself is the book-wound mesh's, to the bit.
        let book = book_triangle(Winding::Book).closest_hit(&ray, 0.0, 9.0);
        assert_eq!(Some(hit), book);
    }
}
