//! The built scene: objects and their shapes (the [`Shape`] enum over the primitives of
//! [`crate::geometry`], meshes and CSG solids), groups, CSG solids, intersections and the
//! computations prepared at a hit, the world and its acceleration index. Nothing here traces a
//! ray to a colour: that is the integrators' work, in the `render` module.

mod ball;
mod computations;
mod csg;
mod cuboid;
mod group;
mod index;
mod intersection;
mod level;
mod object;
mod shape;
mod world;

pub use computations::{
    prepare_computations, prepare_computations_with, schlick, surface_offset, Computations,
};
pub use csg::{intersection_allowed, Csg, CsgOperation};
pub use cuboid::Cuboid;
pub use group::{Group, Node};
pub use index::{WorldIndex, NO_OBJECT};
pub use intersection::{hit, sort_intersections, Intersection};
pub use object::Object;
pub use shape::Shape;
pub use world::{default_world, LightingModel, World};
