//! Objects in the world, intersections, and the Whitted tracer that shades them.

mod cgfs;
mod computations;
mod csg;
mod group;
mod index;
mod intersection;
mod object;
mod optics;
mod trace_log;
mod tracer;
mod world;

pub use cgfs::unshadowed_intensity;
pub use computations::{prepare_computations, schlick, Computations};
pub use csg::{intersection_allowed, Csg, CsgOperation};
pub use group::{Group, Node};
pub use index::WorldIndex;
pub use intersection::{hit, sort_intersections, Intersection};
pub use object::Object;
pub use optics::matte_light;
pub use tracer::{Tracer, DEFAULT_MAX_DEPTH};
pub use world::{default_world, LightingModel, World};
