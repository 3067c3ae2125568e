//! Everything that gives off light, as the path tracer samples it: the book's lights, objects
//! whose material emits and the sky ([`Emitters`], the light list with its sampling densities
//! for multiple importance sampling), and the polished metal balls through which the sky's
//! light is sampled onto the surfaces they mirror ([`MirrorBall`]). Which light a vertex
//! samples is the `LightSampler`'s choice (`sampler.rs`): uniform, by power, or by a light tree
//! (`bvh.rs`, over each light's `light_bounds.rs`) that weighs where the vertex is.
//!
//! It sits above `scene` (a light of an emitting object samples that object's shape where the
//! object stands) and below `render` (the integrators ask it for light).

mod bvh;
mod emitters;
mod light_bounds;
mod mirror_ball;
mod sampler;

pub use emitters::{Emitters, LightSample};
pub use mirror_ball::{
    choose as choose_mirrors, expected_solves, spread as mirror_spread, MirrorBall, MirrorPath,
};
