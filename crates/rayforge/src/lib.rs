//! rayforge: a Whitted ray tracer built on *The Ray Tracer Challenge* (Jamis Buck) and its companions.
//!
//! The crate is the renderer only: it knows nothing of scene files (see `rayforge-scene`) or of the
//! command line (see `rayforge-cli`). Its API follows the book's names (`point`, `vector`,
//! `prepare_computations`, `shade_hit`, `color_at`, …) so the book's scenarios read naturally as tests.
//!
//! The pipeline: a [`World`] of [`Object`]s and [`Light`]s is seen through a [`Camera`]; the
//! [`render`](render::render) loop traces rays in parallel rows into a [`film`] of weighted
//! linear colours, which is developed ([`film::develop`]) into a [`Canvas`] for the encoders.
//! A second renderer, the [`raster`] module, draws the same world as triangles (a software
//! rasterizer after *Computer Graphics from Scratch*) into a film too. Canvas items
//! ([`draw2d`]) are drawn over the image of either.
#![deny(missing_docs)]
// Two modules may use `unsafe`: `accel::isa`, which calls the processor's vector instructions
// after checking at run time that it has them, and `accel::pages`, which asks the kernel for
// huge pages under the build's large buffers. Everything else is safe code.
#![deny(unsafe_code)]

pub mod accel;
pub mod camera;
pub mod canvas;
pub mod color;
pub mod draw2d;
pub mod film;
pub mod geometry;
pub mod math;
pub mod options;
pub mod raster;
pub mod render;
pub mod scene;
pub mod shading;

pub use camera::Camera;
pub use canvas::Canvas;
pub use color::Color;
pub use geometry::Shape;
pub use math::{point, vector, Matrix4, Point3, Ray, Transform, Vec3, EPSILON};
pub use scene::{
    default_world, hit, intersection_allowed, prepare_computations, schlick, Computations, Csg,
    CsgOperation, Group, Intersection, LightingModel, Node, Object, Tracer, World,
    DEFAULT_MAX_DEPTH,
};
pub use shading::{
    lighting, lighting_with, AreaLight, Light, Material, Pattern, PatternKind, PointLight,
    SpotLight,
};
