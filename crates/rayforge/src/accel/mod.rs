//! Acceleration structures: a bounding volume hierarchy over anything with a bounding box.

mod bvh;

pub use bvh::{Bvh, BvhNode};
