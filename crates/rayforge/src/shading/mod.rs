//! Materials, patterns, lights and the Phong lighting model.

mod light;
mod material;
mod noise;
mod pattern;
mod phong;

pub use light::{Light, PointLight};
pub use material::Material;
pub use noise::perlin_noise;
pub use pattern::{Pattern, PatternKind};
pub use phong::lighting;
