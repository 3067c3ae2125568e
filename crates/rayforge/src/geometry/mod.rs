//! Primitive shapes in object space: each file holds one shape's intersection and normal (and
//! meshes their own BVH), with the hit record they all produce, [`LocalHit`], and each finite
//! shape's sampling by area, which `sampling.rs` gathers into [`ShapeSampler`]: points drawn by
//! area and, on a shape placed by a transform, by solid angle from a point (the path tracer's
//! light sampling asks it; what a point gives off is the lights' business).
//!
//! The closed enum over them, `Shape` (which also names CSG solids, built of scene objects),
//! lives one layer up, in the `scene` module. Rays arrive already in object space; transforms are
//! the business of the scene's objects, but for sampling by solid angle, which takes the
//! transform an object places its shape by (what a shape looks like from a point depends on it).

use crate::math::Vec3;

pub mod cone;
pub mod cube;
pub mod curve;
pub mod curves;
pub mod cylinder;
mod mesh;
mod partial;
pub mod plane;
mod polyhedra;
pub mod rectangle;
pub mod ring;
mod sampling;
pub mod sphere;
mod tessellate;
pub mod torus;
mod triangle;

pub use curves::Curves;
pub use mesh::{Mesh, MeshError, MeshFace, VertexAttributes, Winding};
pub use partial::{CutError, PartialQuadric};
pub use polyhedra::{dodecahedron, icosahedron};
pub use sampling::{AreaSample, Heights, ShapeSampler, SolidAngleSample};
pub use tessellate::sphere_mesh;
pub use torus::toroidal_map;
pub use triangle::Triangle;

/// One intersection in object space: the distance and where on the surface it is.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LocalHit {
    /// Distance along the object-space ray.
    pub t: f64,
    /// Surface coordinate u (barycentric on triangles, towards the second vertex).
    pub u: f64,
    /// Surface coordinate v (barycentric on triangles, towards the third vertex).
    pub v: f64,
    /// Which face of a mesh was hit (0 for other shapes).
    pub face: u32,
    /// Which primitive of a CSG solid was hit (0 for other shapes).
    pub leaf: u32,
    /// When the ray that made the hit was cast (see [`Ray::time`]): where a moving object was.
    pub time: f64,
    /// The object-space normal where the ray that made the hit decides it, not the point: a
    /// flat curve faces the ray that met it ([`Curves`]). Zero for every other shape, whose
    /// normal is found from the point and the hit's `u`, `v`, `face`.
    pub normal: Vec3,
}

impl LocalHit {
    /// A hit at `t` with no surface coordinates.
    #[inline]
    pub const fn at(t: f64) -> Self {
        Self {
            t,
            u: 0.0,
            v: 0.0,
            face: 0,
            leaf: 0,
            time: 0.0,
            normal: Vec3::ZERO,
        }
    }
}
