//! rayforge: a Whitted ray tracer built on *The Ray Tracer Challenge* (Jamis Buck) and its companions.
//!
//! The crate is the renderer only: it knows nothing of scene files (see `rayforge-scene`) or of the
//! command line (see `rayforge-cli`). Its API follows the book's names (`point`, `vector`,
//! `prepare_computations`, `shade_hit`, `color_at`, …) so the book's scenarios read naturally as tests.
//!
//! The pipeline: a [`World`] of [`Object`]s and [`Light`]s is seen through a [`Camera`]; the
//! [`render`](render::render) loop traces rays in parallel rows into a [`film`] of weighted
//! linear colours, each camera ray's colour found by the [integrator](render::integrator) of the
//! world's lighting model; the film is developed ([`film::develop`]) into a [`Canvas`] for the
//! encoders. A second renderer, the [`raster`] module, draws the same world as triangles (a
//! software rasterizer after *Computer Graphics from Scratch*) into a film too. Canvas items
//! ([`draw2d`]) are drawn over the image of either.
//!
//! The modules form layers, each using only its own layer and those below (checked by
//! `tests/layers.rs`):
//!
//! | layer | modules | what they hold |
//! |---|---|---|
//! | 0 | [`color`], [`math`] | colours; points, vectors, matrices, rays, random numbers |
//! | 1 | [`accel`], [`camera`], [`canvas`], [`film`], [`draw2d`], [`options`] | the BVH; cameras and their samples; images; films and their development; 2D drawing and canvas items; renderer options |
//! | 2 | [`geometry`] | primitive shapes in object space, meshes |
//! | 3 | [`shading`] | materials, patterns, textures, lights, each lighting model's local terms |
//! | 4 | [`scene`] | objects, the `Shape` enum, groups, CSG, intersections, the world, its index |
//! | 5 | [`lights`] | what gives off light, as the path tracer samples it; mirror balls |
//! | 6 | [`render`], [`raster`] | integrators, sampler and render loop; the rasterizer |
//! | 7 | [`book`] | the book's one-call entry points (`color_at`, `shade_hit`, …), used by tests |
//!
//! Inside the crate, modules name each other by their paths (`crate::scene::Object`), never by
//! the re-exports below, which are for users of the crate.
#![deny(missing_docs)]
// Two modules may use `unsafe`: `accel::isa`, which calls the processor's vector instructions
// after checking at run time that it has them, and `accel::pages`, which asks the kernel for
// huge pages under the build's large buffers. Everything else is safe code.
#![deny(unsafe_code)]

pub mod accel;
pub mod book;
pub mod camera;
pub mod canvas;
pub mod color;
pub mod draw2d;
pub mod film;
pub mod geometry;
pub mod lights;
pub mod math;
pub mod media;
pub mod options;
pub mod raster;
pub mod render;
pub mod scene;
pub mod shading;

pub use book::{lighting, BookMaterial, BookPattern, BookWorld, Tracer};
pub use camera::Camera;
pub use canvas::Canvas;
pub use color::Color;
pub use math::{point, vector, Matrix4, Point3, Ray, Transform, Vec3, EPSILON};
pub use render::DEFAULT_MAX_DEPTH;
pub use scene::{
    default_world, hit, intersection_allowed, prepare_computations, schlick, Computations, Csg,
    CsgOperation, Group, Intersection, LightingModel, Node, Object, Shape, World,
};
pub use shading::{
    lighting_with, AreaLight, Light, Material, Pattern, PatternKind, PointLight, SpotLight,
};
