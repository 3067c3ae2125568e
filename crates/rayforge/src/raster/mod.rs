//! A second renderer: a software rasterizer after *Computer Graphics from Scratch*, part II.
//!
//! The ray tracer asks, for every pixel, which surface it sees; the rasterizer asks, for every
//! triangle, which pixels it covers. It draws the same [`World`](crate::scene::World) through the same
//! [`Camera`](crate::camera::Camera), so the two images line up pixel for pixel, but it can only draw
//! triangles: every analytic shape is tessellated first ([`tessellate()`]).
//!
//! The pipeline, one file per stage:
//!
//! 1. [`mod@tessellate`]: shapes become triangle meshes in object space (the book's models).
//! 2. `instance`: each object becomes an instance: its mesh, its 4×4 transform composed with the
//!    camera's ([`Projection`]), and a bounding sphere that accepts or rejects it whole against
//!    the five clipping planes.
//! 3. `vertex`: every vertex is moved into view space and projected, once, in parallel.
//! 4. `bin`: every triangle is clipped ([`clip_triangle`]: split, never dropped), back-face culled
//!    and sorted into the screen tiles its bounding box touches, in parallel chunks of fixed size.
//! 5. `tile`: each tile fills a depth buffer on 1/z and a triangle id per pixel with the
//!    fixed-point edge functions of [`edge`], then shades each visible pixel once (`shade`):
//!    flat, Gouraud or Phong, with the scene's materials and lights through the ray tracer's own
//!    [`lighting_with`](crate::shading::lighting_with), and textures (image textures, mapped patterns
//!    and cube maps, `surface`) read perspective-correctly with nearest, bilinear or trilinear
//!    (MIP-mapped) filtering (`mipmap`). Phong pixels of plain surfaces under point lights are
//!    shaded a few at a time in vector lanes, to the same bits (`lanes`).
//!
//! The 2D drawing functions of the book's first chapters ([`draw_line`], [`interpolate`],
//! [`draw_wireframe_triangle`], [`draw_filled_triangle`], [`draw_shaded_triangle`]) work on any
//! [`Canvas`](crate::canvas::Canvas) and share the coverage rule of the 3D path. [`mod@book2d`]
//! (in [`draw2d`](crate::draw2d), below both renderers) holds the book's own versions,
//! approximations and all, to the pixel; scenes draw with them through canvas items
//! ([`Overlay`]), over the image of either renderer.
//!
//! What a rasterizer cannot show: shadows, reflection and refraction need rays, so surfaces are
//! lit as if nothing stood between them and each light, mirrors and glass look like the opaque
//! Phong surface under them, area lights act as a point light at their centre, and focal blur
//! and anti-aliasing are not done.
//!
//! Every pixel's result depends only on the ordered list of triangles covering it, and that
//! order is the scene's (objects in order, faces in order), whichever thread bins or draws them:
//! the image is the same bytes for any thread count.

mod bin;
pub mod clip;
pub mod edge;
mod fill;
mod instance;
mod lanes;
mod lighting;
mod line;
mod mipmap;
mod projection;
mod render;
mod shade;
mod surface;
pub mod tessellate;
mod tile;
mod vertex;

pub use clip::{clip_triangle, ClipPlane, ClipVertex, Clipped, SphereSide};
pub use fill::{draw_filled_triangle, draw_shaded_triangle};
pub use line::{draw_line, draw_wireframe_triangle, interpolate, Interpolate};
pub use mipmap::MipChain;
// Canvas items and the options are below both renderers; here too, for users of the rasterizer.
pub use crate::draw2d::{book2d, CanvasItem, CanvasPoint, Overlay, TriangleStyle};
pub use crate::options::{RasterOptions, Shading, TextureFilter};
pub use projection::Projection;
pub use render::{
    render, render_film, render_film_observed, render_rows_into, render_with_stats, RasterError,
    RasterStats, Rasterizer,
};
pub use tessellate::{face_count, generate_sphere, refine, tessellate, Faces, Tessellation};
