//! Everything that gives off light, as the path tracer samples it: one file per kind of light
//! (`point.rs`, `spot.rs`, `pattern.rs` for a point light an image shapes, `directional.rs`,
//! `area.rs` for any surface that emits, the book's area light among them, and
//! `environment.rs` for the sky), each answering `sample_li` (a
//! direction towards it from a shading point, the light along it and its density) and `power`
//! (what it is picked by), and the kinds a path can meet (a surface, the sky) `pdf_li` (the
//! density with which `sample_li` draws what the path met) and `radiance` (what the path sees)
//! too, the sky both in one look-up of its map. A point or a direction (a delta light) is
//! found by light sampling alone: its sample says so ([`LightSample::delta`]) and takes all
//! the weight, so such a kind has no `pdf_li` (pbrt's is 0) or `radiance` (black) that nothing
//! would ask. The light list of a world over the kinds ([`Emitters`]) is what the path
//! integrator asks, for light samples and for the densities and radiance of what its paths
//! meet; and the polished metal balls through which the sky's light is sampled onto the
//! surfaces they mirror ([`MirrorBall`]). Which light a vertex samples is the `LightSampler`'s
//! choice (`sampler.rs`): uniform, by power, or by a light tree (`bvh.rs`, over each light's
//! `light_bounds.rs`) that weighs where the vertex is.
//!
//! It sits above `scene` (a light of an emitting object samples that object's shape where the
//! object stands, and the light tree needs every light of the world at once) and below
//! `render` (the integrators ask it for light). The book's lights are not a second model here:
//! the kinds are built from the scene's own light values (`shading::Light`, below `scene` so
//! that the world holds them and the Whitted renderers and the rasterizer read them with the
//! books' meaning) and ask those values what the Whitted renderers ask (a spotlight's
//! fall-off, a directional light's direction, an area light's sides), reading them
//! physically.

mod area;
mod bvh;
mod directional;
mod emitters;
mod environment;
mod light_bounds;
mod mirror_ball;
mod pattern;
mod point;
mod sample;
mod sampler;
mod spot;

pub use area::AreaEmitter;
pub use directional::DirectionalEmitter;
pub use emitters::Emitters;
pub use environment::SkyEmitter;
pub use mirror_ball::{spread as mirror_spread, MirrorBall, MirrorBalls, MirrorPath};
pub use pattern::PatternEmitter;
pub use point::PointEmitter;
pub use sample::LightSample;
pub use spot::SpotEmitter;
