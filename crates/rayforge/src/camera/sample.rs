//! Where one camera ray goes: the sample the render loop's sampler draws and the camera turns
//! into a ray ([`super::Camera::ray_for_sample`]), and that ray with its weight.

use crate::math::Ray;

/// A camera's ray for one sample and the weight its radiance is recorded with: 1 for every
/// camera but a realistic one, whose lens system passes more light to some film points
/// than to others (pbrt-v4's `CameraRay`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraRay {
    /// The ray, in the world.
    pub ray: Ray,
    /// What its radiance is multiplied by.
    pub weight: f64,
}

impl CameraRay {
    /// `ray` of weight 1.
    pub fn unweighted(ray: Ray) -> Self {
        Self { ray, weight: 1.0 }
    }
}

/// Where one camera ray goes: a point of the image, a point of the lens and an instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSample {
    /// Horizontal image position in pixels (0 is the left edge of the image).
    pub x: f64,
    /// Vertical image position in pixels (0 is the top edge).
    pub y: f64,
    /// Point of the lens, each coordinate in [0, 1) (0.5, 0.5 is its centre).
    pub lens_u: f64,
    /// See `lens_u`.
    pub lens_v: f64,
    /// Instant, as a fraction of the shutter interval in [0, 1) (0.5 is its middle).
    pub time: f64,
}

impl CameraSample {
    /// Through image point (`x`, `y`), from the lens's centre, half way through the shutter.
    pub fn centred(x: f64, y: f64) -> Self {
        Self {
            x,
            y,
            lens_u: 0.5,
            lens_v: 0.5,
            time: 0.5,
        }
    }
}
