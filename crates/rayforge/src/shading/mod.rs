//! Materials, patterns, lights and the Phong lighting model.

mod bump;
mod jitter;
mod light;
mod material;
mod noise;
mod pattern;
mod phong;
mod texture;

pub use bump::{Bump, BumpKind};
pub use jitter::{Jitter, Sequence, SplitMix64};
pub use light::{AreaLight, DirectionalLight, Light, PointLight, SpotLight};
pub use material::Material;
pub use noise::perlin_noise;
pub use pattern::{Pattern, PatternKind};
pub use phong::{can_light, lighting, lighting_with, most_light};
pub use texture::{
    cylindrical_map, planar_map, spherical_map, CubeFace, Filter, Texture, UvMapping, UvPattern,
};
