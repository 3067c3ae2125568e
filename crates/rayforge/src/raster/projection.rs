//! The camera as the rasterizer needs it (the book's "Perspective projection" and "Describing
//! and rendering a scene" chapters): a 4×4 transform from world to view space, the viewport,
//! and the five clipping planes of the camera's actual field of view.
//!
//! View space is the book's: the eye at the origin looking down +z, x to the right of the image
//! and y up. rayforge's camera space looks down -z with +x to the *left* of the image (the
//! view transform's first row is the "left" vector), so view space is camera space turned half
//! a turn about y. Projection inverts [`Camera::ray_through`]: the point a camera ray through a
//! pixel centre meets projects back to that pixel centre, so the two renderers line up.

use super::clip::ClipPlane;
use crate::camera::Camera;
use glam::{DAffine3, DMat4, DVec2, DVec3};

/// A camera ready for rasterizing.
#[derive(Debug, Clone, PartialEq)]
pub struct Projection {
    world_to_view: DAffine3,
    view_to_world: DAffine3,
    eye: DVec3,
    half_width: f64,
    half_height: f64,
    pixel_size: f64,
    width: usize,
    height: usize,
    planes: [ClipPlane; 5],
}

impl Projection {
    /// The projection of `camera`, with the near plane `near` units in front of the eye.
    pub fn new(camera: &Camera, near: f64) -> Self {
        let pixel_size = camera.pixel_size();
        let half_width = pixel_size * camera.hsize() as f64 / 2.0;
        let half_height = pixel_size * camera.vsize() as f64 / 2.0;
        // Camera space to the book's view space: x and z change sign (half a turn about y).
        let turn = DMat4::from_diagonal(glam::DVec4::new(-1.0, 1.0, -1.0, 1.0));
        let world_to_view = DAffine3::from_mat4(turn * camera.transform().matrix());
        let view_to_world = world_to_view.inverse();
        let near = if near.is_finite() && near > 0.0 {
            near
        } else {
            1e-3
        };
        // The sides pass through the eye and the viewport's edges at z = 1: x = ±half_width,
        // y = ±half_height. Normals point inwards.
        let planes = [
            ClipPlane::new(DVec3::Z, -near),
            ClipPlane::new(DVec3::new(1.0, 0.0, half_width), 0.0),
            ClipPlane::new(DVec3::new(-1.0, 0.0, half_width), 0.0),
            ClipPlane::new(DVec3::new(0.0, 1.0, half_height), 0.0),
            ClipPlane::new(DVec3::new(0.0, -1.0, half_height), 0.0),
        ];
        Self {
            world_to_view,
            view_to_world,
            eye: view_to_world.transform_point3(DVec3::ZERO),
            half_width,
            half_height,
            pixel_size,
            width: camera.hsize(),
            height: camera.vsize(),
            planes,
        }
    }

    /// The camera transform as a 4×4 matrix from world to view space.
    pub fn world_to_view(&self) -> DMat4 {
        DMat4::from(self.world_to_view)
    }

    /// The affine form of [`Projection::world_to_view`].
    pub(crate) fn world_to_view_affine(&self) -> &DAffine3 {
        &self.world_to_view
    }

    /// A view-space point back in world space.
    #[inline]
    pub fn view_to_world(&self, p: DVec3) -> DVec3 {
        self.view_to_world.transform_point3(p)
    }

    /// Where the eye is, in world space.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The clipping planes in view space: near, left, right, bottom, top.
    pub fn planes(&self) -> &[ClipPlane; 5] {
        &self.planes
    }

    /// Image width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The perspective projection of a view-space point (z > 0) to pixel coordinates: the
    /// book's `x' = x·d/z` on the viewport at `d = 1`, then viewport to canvas (pixel `(0, 0)`
    /// spans `[0, 1) × [0, 1)`, y down).
    #[inline]
    pub fn project(&self, p: DVec3) -> DVec2 {
        let inv_z = 1.0 / p.z;
        DVec2::new(
            (self.half_width + p.x * inv_z) / self.pixel_size,
            (self.half_height - p.y * inv_z) / self.pixel_size,
        )
    }
}
