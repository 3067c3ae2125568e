//! Acceleration structures: an eight-wide bounding volume hierarchy over anything with a
//! bounding box, with single-precision boxes, and the ray form its walk uses.

mod build;
mod bvh;
#[allow(unsafe_code)]
mod isa;
#[allow(unsafe_code)]
pub(crate) mod pages;
mod query;

pub(crate) use build::{build, Frame};
pub use bvh::{Bvh, Node, MAX_BLOCKS, NO_PRIMITIVE};
pub(crate) use isa::{dispatch, Isa, Kernel, Lanes4};
pub use query::RayQuery;
