//! Canvas items: lines and triangles a scene draws on the image itself, in the book's canvas
//! coordinates, rather than placing them in the 3D world. They are Computer Graphics from
//! Scratch's 2D stages (its chapters "Lines", "Filled triangles", "Shaded triangles" and
//! "Perspective projection"), drawn with the book's own functions ([`book2d`](super::book2d)).
//!
//! An [`Overlay`] is drawn over a finished image, whichever renderer made it: the items are
//! flat drawings on the canvas, which no ray meets and no depth buffer hides, so the ray tracer
//! and the rasterizer show them alike, on top of whatever the 3D scene drew, in the order the
//! scene lists them.

use super::book2d;
use crate::camera::Camera;
use crate::canvas::Canvas;
use crate::color::Color;
use glam::{DVec2, DVec3};

/// Where a corner of a canvas item is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CanvasPoint {
    /// A point on the canvas: the origin at its centre, x to the right, y up, in pixels of the
    /// canvas the scene's camera describes.
    Canvas(DVec2),
    /// A point in front of the eye, in the camera's own space (x to the right, y up, z
    /// forward; the eye at the origin), projected as the book's `ProjectVertex` does:
    /// `(x·d/z · Cw/Vw, y·d/z · Ch/Vh)` with the camera's canvas `Cw × Ch` and viewport
    /// `Vw × Vh` at distance `d` (a field-of-view camera's viewport is its view at distance 1).
    Projected(DVec3),
}

/// How a canvas triangle is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TriangleStyle {
    /// Its three sides (the book's `DrawWireframeTriangle`).
    Wireframe,
    /// Filled with its colour (`DrawFilledTriangle`).
    Filled,
    /// Filled with its colour times an intensity given at each corner and blended across
    /// (`DrawShadedTriangle`, the book's `h`).
    Shaded([f64; 3]),
}

/// One thing drawn on the canvas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CanvasItem {
    /// A line segment, both ends drawn (the book's `DrawLine`).
    Line {
        /// One end.
        from: CanvasPoint,
        /// The other end.
        to: CanvasPoint,
        /// Its colour.
        color: Color,
    },
    /// A triangle.
    Triangle {
        /// Its corners.
        points: [CanvasPoint; 3],
        /// Its colour.
        color: Color,
        /// Outline, fill or shaded fill.
        style: TriangleStyle,
    },
}

/// A scene's canvas items and the canvas size their canvas coordinates are given for.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overlay {
    items: Vec<CanvasItem>,
    width: usize,
    height: usize,
}

impl Overlay {
    /// Items whose canvas coordinates are pixels of a `width × height` canvas (the scene
    /// camera's).
    pub fn new(items: Vec<CanvasItem>, width: usize, height: usize) -> Self {
        Self {
            items,
            width,
            height,
        }
    }

    /// Whether there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The items, in drawing order.
    pub fn items(&self) -> &[CanvasItem] {
        &self.items
    }

    /// Draws every item, in order, over `canvas`, an image rendered through `camera`.
    ///
    /// When the image is not the size the items were given for (the command line's `--width`
    /// and `--height`), canvas coordinates are scaled with it, as the 3D scene is, so the
    /// drawing keeps its place in the picture; at the scene's own size they are used as they
    /// are, and the book's pixels come out exactly.
    pub fn draw(&self, canvas: &mut Canvas, camera: &Camera) {
        let (cw, ch) = (canvas.width() as f64, canvas.height() as f64);
        let scale = DVec2::new(
            if self.width > 0 {
                cw / self.width as f64
            } else {
                1.0
            },
            if self.height > 0 {
                ch / self.height as f64
            } else {
                1.0
            },
        );
        // The book's viewport: `Vw × Vh` at distance `d`.
        let (vw, vh, d) = match camera.viewport_of() {
            Some(v) => (v.width, v.height, v.distance),
            None => (
                camera.pixel_size() * camera.hsize() as f64,
                camera.pixel_size() * camera.vsize() as f64,
                1.0,
            ),
        };
        let place = |p: CanvasPoint| match p {
            CanvasPoint::Canvas(q) if scale == DVec2::ONE => q,
            CanvasPoint::Canvas(q) => q * scale,
            // `ProjectVertex` then `ViewportToCanvas`, operation for operation.
            CanvasPoint::Projected(v) => {
                DVec2::new(v.x * d / v.z * cw / vw, v.y * d / v.z * ch / vh)
            }
        };
        for item in &self.items {
            match *item {
                CanvasItem::Line { from, to, color } => {
                    book2d::draw_line(canvas, place(from), place(to), color)
                }
                CanvasItem::Triangle {
                    points,
                    color,
                    style,
                } => {
                    let points = points.map(place);
                    match style {
                        TriangleStyle::Wireframe => {
                            book2d::draw_wireframe_triangle(canvas, points, color)
                        }
                        TriangleStyle::Filled => {
                            book2d::draw_filled_triangle(canvas, points, color)
                        }
                        TriangleStyle::Shaded(h) => {
                            book2d::draw_shaded_triangle(canvas, points, h, color)
                        }
                    }
                }
            }
        }
    }
}
