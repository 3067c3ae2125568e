//! Where one camera ray goes: the sample the render loop's sampler draws and the camera turns
//! into a ray ([`super::Camera::ray_for_sample`]).

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
