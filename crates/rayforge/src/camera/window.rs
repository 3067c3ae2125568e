//! Where the image lies on the camera's canvas: by default centred on the camera's axis with
//! square pixels, or any rectangle of it (pbrt's `screenwindow`, or a frame aspect ratio
//! other than the image's), which moves the image off the axis or stretches its pixels.

/// A rectangle of the canvas the image spans, in the canvas's units (a pinhole's canvas one
/// unit in front of the eye, an orthographic camera's at the camera), x towards the image's
/// right and y up as the image is seen: pbrt's screen window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenWindow {
    /// Where the image's left edge lies.
    pub x_min: f64,
    /// Where its right edge lies.
    pub x_max: f64,
    /// Where its bottom edge lies.
    pub y_min: f64,
    /// Where its top edge lies.
    pub y_max: f64,
}

impl ScreenWindow {
    /// The window centred on the axis, `half_width` by `half_height` each side.
    pub fn centred(half_width: f64, half_height: f64) -> Self {
        Self {
            x_min: -half_width,
            x_max: half_width,
            y_min: -half_height,
            y_max: half_height,
        }
    }

    /// Whether the window has finite edges and is not empty across or down (edges in
    /// either order: the wrong order mirrors the image, as pbrt-v4 has it).
    pub fn is_valid(&self) -> bool {
        [self.x_min, self.x_max, self.y_min, self.y_max]
            .iter()
            .all(|v| v.is_finite())
            && self.x_max != self.x_min
            && self.y_max != self.y_min
    }
}

/// The canvas point of image point `(x, y)` (pixels from the top-left corner) as the camera
/// works it out for every ray: `(left − x · step_x, top − y · step_y)` in its own space,
/// whose +x is the image's left. Kept as these four numbers (not the window) so that the
/// centred camera's point is the book's `half_width − x · pixel_size` to the bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Grid {
    pub left: f64,
    pub top: f64,
    pub step_x: f64,
    pub step_y: f64,
}

impl Grid {
    /// The book's grid: centred, square pixels of `pixel_size`.
    pub fn centred(half_width: f64, half_height: f64, pixel_size: f64) -> Self {
        Self {
            left: half_width,
            top: half_height,
            step_x: pixel_size,
            step_y: pixel_size,
        }
    }

    /// The grid of `window` over `hsize × vsize` pixels.
    pub fn of(window: &ScreenWindow, hsize: usize, vsize: usize) -> Self {
        Self {
            // The camera's +x is the image's left: the image's left edge, at x_min to the
            // right, is −x_min in its space.
            left: -window.x_min,
            top: window.y_max,
            step_x: (window.x_max - window.x_min) / hsize as f64,
            step_y: (window.y_max - window.y_min) / vsize as f64,
        }
    }

    /// The canvas point of image point `(x, y)`.
    #[inline]
    pub fn point(&self, x: f64, y: f64) -> (f64, f64) {
        (self.left - x * self.step_x, self.top - y * self.step_y)
    }
}
