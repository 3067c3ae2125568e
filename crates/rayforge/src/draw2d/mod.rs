//! 2D drawing on a finished image, below both renderers: canvas items ([`Overlay`]) and the
//! book functions that draw them ([`book2d`]).
//!
//! Computer Graphics from Scratch draws lines and triangles straight on the canvas in its first
//! chapters; scenes use these as canvas items, drawn over the image of either renderer. They
//! share nothing with the rasterizer's 3D path, which has its own exact line and triangle
//! drawing (`raster::draw_line`, `raster::draw_filled_triangle`, with its coverage rule).

pub mod book2d;
mod overlay;

pub use overlay::{CanvasItem, CanvasPoint, Overlay, TriangleStyle};
