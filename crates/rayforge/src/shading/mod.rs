//! What surfaces and lights are, and how light meets a surface at one point: materials,
//! patterns, textures, bumps, lights and environment maps, and the local illumination of each lighting model:
//! [`phong`](lighting_with) (The Ray Tracer Challenge), [`cgfs`] (Computer Graphics from
//! Scratch) and [`optics`] (Fundamentals of Ray Tracing). The ray tracer's integrators and the
//! rasterizer both light points with them; neither shadows nor secondary rays are known here.

pub mod bsdf;
mod bump;
pub mod cgfs;
mod environment;
mod jitter;
mod light;
mod material;
pub mod metal_rough;
mod noise;
pub mod optics;
mod pattern;
mod phong;
mod physical;
pub mod spectrum;
mod texture;
pub mod texture_graph;
pub mod texture_noise;

pub use crate::math::random::{Jitter, SplitMix64};
pub use crate::math::{equal_area_sphere_to_square, equal_area_square_to_sphere};
pub use bump::{Bump, BumpKind};
pub use cgfs::unshadowed_intensity;
pub use environment::{EnvironmentError, EnvironmentMap, SkyDraw};
pub use jitter::Sequence;
pub use light::{
    AreaLight, DirectionalLight, Light, LightImage, PatternLight, PatternShape, PointLight,
    SpotLight,
};
pub use material::{Alpha, EmissionSide, Material, MaterialMix, PhysicalPatterns};
pub use metal_rough::{AlphaMode, MetalRough, SurfacePoint};
pub use noise::perlin_noise;
pub use optics::matte_light;
pub use pattern::{Pattern, PatternKind};
pub use phong::{can_light, lighting_with, most_light};
pub use physical::{conductor_of_reflectance, HitParameters, Layer, Physical, Scattering};
pub use texture::{
    cylindrical_map, planar_map, spherical_map, CubeFace, Filter, TexelGrid, Texture, UvMapping,
    UvPattern,
};
