//! Triangle meshes (chapter 15's OBJ models): shared vertex arrays, indexed faces and a BVH
//! over the faces, all in the mesh's object space.
//!
//! A mesh is one object to the scene however many faces it has, so a million-triangle model
//! costs its vertex data, 28 bytes per face and the BVH, not a transform and material per
//! triangle.

use super::triangle::moller_trumbore;
use super::LocalHit;
use crate::accel::Bvh;
use crate::math::{Aabb, Point3, Ray, Vec3};
use std::ops::ControlFlow;

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

/// A face that names a vertex or normal the mesh does not have.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("face {face} refers to {what} {index}, but the mesh has {count}")]
pub struct MeshError {
    /// Which face (0-based).
    pub face: usize,
    /// "vertex", "normal" or "texture coordinate".
    pub what: &'static str,
    /// The index it names (0-based).
    pub index: u32,
    /// How many there are.
    pub count: usize,
}

/// An indexed triangle mesh with its own BVH.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    positions: Vec<Point3>,
    normals: Vec<Vec3>,
    texcoords: Vec<[f64; 2]>,
    faces: Vec<MeshFace>,
    bvh: Bvh,
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
    pub fn with_texcoords(
        positions: Vec<Point3>,
        normals: Vec<Vec3>,
        texcoords: Vec<[f64; 2]>,
        faces: Vec<MeshFace>,
    ) -> Result<Self, MeshError> {
        for (face, f) in faces.iter().enumerate() {
            let check = |what, index: u32, count: usize| {
                if index as usize >= count {
                    Err(MeshError {
                        face,
                        what,
                        index,
                        count,
                    })
                } else {
                    Ok(())
                }
            };
            for i in f.vertices {
                check("vertex", i, positions.len())?;
            }
            for i in f.normals.into_iter().flatten() {
                check("normal", i, normals.len())?;
            }
            for i in f.texcoords.into_iter().flatten() {
                check("texture coordinate", i, texcoords.len())?;
            }
        }
        let boxes: Vec<Aabb> = faces
            .iter()
            .map(|f| {
                let mut b = Aabb::EMPTY;
                for i in f.vertices {
                    b.add_point(positions[i as usize]);
                }
                b
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        Ok(Self {
            positions,
            normals,
            texcoords,
            faces,
            bvh,
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

    /// The texture coordinates at a hit, blended from its face's corners by `u`, `v`; `None`
    /// when the face has none.
    pub fn texcoord_at(&self, hit: &LocalHit) -> Option<(f64, f64)> {
        let [t1, t2, t3] = self
            .faces
            .get(hit.face as usize)?
            .texcoords?
            .map(|i| self.texcoords[i as usize]);
        let w = 1.0 - hit.u - hit.v;
        Some((
            t1[0] * w + t2[0] * hit.u + t3[0] * hit.v,
            t1[1] * w + t2[1] * hit.u + t3[1] * hit.v,
        ))
    }

    /// The faces.
    pub fn faces(&self) -> &[MeshFace] {
        &self.faces
    }

    /// The box around every face.
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
    #[inline]
    pub fn intersect_up_to(&self, ray: &Ray, t_max: f64, mut hit: impl FnMut(LocalHit)) {
        self.bvh.traverse(
            ray.origin,
            ray.direction,
            f64::NEG_INFINITY,
            t_max,
            |index, _| {
                let [p1, p2, p3] = self.corners(&self.faces[index as usize]);
                if let Some((t, u, v)) = moller_trumbore(ray, p1, p2 - p1, p3 - p1) {
                    if t <= t_max {
                        hit(LocalHit {
                            t,
                            u,
                            v,
                            face: index,
                            leaf: 0,
                            time: ray.time,
                        });
                    }
                }
                ControlFlow::Continue(())
            },
        );
    }

    /// The nearest hit with `t_min <= t < t_max`: the BVH walk skips boxes beyond the nearest
    /// hit found so far, so a ray costs a few dozen boxes and triangles even on a large model.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<LocalHit> {
        let mut best = None;
        self.bvh
            .traverse(ray.origin, ray.direction, t_min, t_max, |index, limit| {
                let [p1, p2, p3] = self.corners(&self.faces[index as usize]);
                if let Some((t, u, v)) = moller_trumbore(ray, p1, p2 - p1, p3 - p1) {
                    if t >= t_min && t < *limit {
                        *limit = t;
                        best = Some(LocalHit {
                            t,
                            u,
                            v,
                            face: index,
                            leaf: 0,
                            time: ray.time,
                        });
                    }
                }
                ControlFlow::Continue(())
            });
        best
    }

    /// The normal at a hit: the vertex normals blended by `u`, `v` on smooth faces, the face
    /// normal otherwise.
    #[inline]
    pub fn normal_at(&self, hit: &LocalHit) -> Vec3 {
        let Some(face) = self.faces.get(hit.face as usize) else {
            return Vec3::ZERO;
        };
        match face.normals {
            Some(n) => {
                let [n1, n2, n3] = n.map(|i| self.normals[i as usize]);
                n2 * hit.u + n3 * hit.v + n1 * (1.0 - hit.u - hit.v)
            }
            None => {
                let [p1, p2, p3] = self.corners(face);
                (p3 - p1).cross(p2 - p1).normalize_or_zero()
            }
        }
    }
}
