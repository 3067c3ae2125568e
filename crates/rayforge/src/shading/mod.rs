//! Materials, patterns, lights and the Phong lighting model.

mod bump;
pub mod cgfs;
mod jitter;
mod light;
mod material;
mod noise;
pub mod optics;
mod pattern;
mod phong;
mod texture;

pub use crate::math::random::{Jitter, SplitMix64};
pub use bump::{Bump, BumpKind};
pub use cgfs::unshadowed_intensity;
pub use jitter::Sequence;
pub use light::{AreaLight, DirectionalLight, Light, PointLight, SpotLight};
pub use material::Material;
pub use noise::perlin_noise;
pub use optics::matte_light;
pub use pattern::{Pattern, PatternKind};
pub use phong::{can_light, lighting_with, most_light};
pub use texture::{
    cylindrical_map, planar_map, spherical_map, CubeFace, Filter, Texture, UvMapping, UvPattern,
};
