//! Computer Graphics from Scratch's camera: a canvas of `Cw × Ch` pixels mapped onto a viewport
//! of `Vw × Vh` units at distance `d` in front of the eye, the eye at a position and turned by a
//! rotation matrix. Camera space has x to the right, y up and z forward.
//!
//! The book traces canvas point (x, y), x and y integers in `[-C/2, C/2)`, through viewport
//! point `(x·Vw/Cw, y·Vh/Ch, d)` and writes it to screen column `Cw/2 + x`, row `Ch/2 - y - 1`:
//! each pixel's ray goes through its lower-left corner, not its centre. The arithmetic below
//! repeats the book's operations in the book's order, so that its figures come out bit for bit.

use crate::math::{Point3, Vec3};
use glam::DMat3;

/// The viewport and the eye's placement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viewport {
    /// Viewport width `Vw`, in scene units.
    pub width: f64,
    /// Viewport height `Vh`.
    pub height: f64,
    /// Distance `d` from the eye to the viewport (the projection plane).
    pub distance: f64,
    /// Where the eye is.
    pub position: Point3,
    /// Rows of the matrix that turns camera-space directions into world space (the book's
    /// `camera.rotation`, applied to each ray's direction).
    pub rotation: [[f64; 3]; 3],
}

impl Viewport {
    /// The book's viewport: 1 × 1 at distance 1, the eye at the origin looking down +z.
    pub const BOOK: Self = Self {
        width: 1.0,
        height: 1.0,
        distance: 1.0,
        position: Point3::ZERO,
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// The rotation that looks from `from` towards `to` with `up` roughly up (the usual
    /// look-at form): its columns are the camera's right, up and forward directions. `None`
    /// when `up` is parallel to the line of sight or the eye looks at itself.
    pub fn look_at(from: Point3, to: Point3, up: Vec3) -> Option<[[f64; 3]; 3]> {
        let forward = (to - from).try_normalize()?;
        let right = up.cross(forward).try_normalize()?;
        let true_up = forward.cross(right);
        let m = DMat3::from_cols(right, true_up, forward).transpose();
        Some([
            m.x_axis.to_array(),
            m.y_axis.to_array(),
            m.z_axis.to_array(),
        ])
    }

    /// The ray's direction for canvas point (`x`, `y`) of a `canvas_width × canvas_height`
    /// canvas, unnormalised: it reaches the viewport at `t = 1`. The book's `CanvasToViewport`
    /// then its `MultiplyMV`, operation for operation.
    pub fn direction(&self, x: f64, y: f64, canvas_width: f64, canvas_height: f64) -> Vec3 {
        let v = [
            x * self.width / canvas_width,
            y * self.height / canvas_height,
            self.distance,
        ];
        let mut d = [0.0; 3];
        for (i, row) in self.rotation.iter().enumerate() {
            for (j, m) in row.iter().enumerate() {
                d[i] += v[j] * m;
            }
        }
        Vec3::from_array(d)
    }

    /// The canvas point whose ray a sample at image position (`px`, `py`) takes (pixels from
    /// the top-left corner, y down; a pixel's centre is at `+0.5`). The pixel's centre maps to
    /// the book's point for that pixel, its lower-left corner, so that one sample per pixel
    /// traces exactly the book's rays and supersampling spreads around them.
    pub fn canvas_point(px: f64, py: f64, canvas_width: f64, canvas_height: f64) -> (f64, f64) {
        let x = (px - 0.5) - canvas_width / 2.0;
        let y = canvas_height / 2.0 - (py + 0.5);
        (x, y)
    }

    /// The horizontal angle the viewport spans as seen from the eye.
    pub fn field_of_view(&self) -> f64 {
        2.0 * (self.width.max(self.height) / 2.0).atan2(self.distance)
    }
}
