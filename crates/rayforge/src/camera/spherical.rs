//! A spherical camera's directions (pbrt-v4's `spherical` camera): every direction about the
//! eye, laid out on the image by an equal-area octahedral map or an equirectangular one.
//!
//! The layout is pbrt-v4's, so that its scenes render as it renders them, and an equal-area
//! image of the world is an environment map its infinite light reads back: the image point
//! `(u, v)` (each 0 to 1 across and down) goes to pbrt's direction, which is then swapped
//! y for z (pbrt's maps keep their pole on z, its cameras look along z with y up), and turned
//! into this crate's camera space by negating x and z (pbrt's camera looks down its +z with
//! +x to the image's right, this crate's down −z with +x to the image's left).
//! - **Equirectangular**: θ = π v from the pole, φ = 2π u, pbrt's direction
//!   `(sin θ cos φ, sin θ sin φ, cos θ)`: the top row looks up (+y), the bottom row down, the
//!   image's centre along pbrt's −x (this crate's +x), a quarter in from the left along the
//!   camera's forward axis.
//! - **Equal area**: Clarberg's octahedral map (pbrt-v4's `EqualAreaSquareToSphere`), the image
//!   point first folded back into the square as pbrt-v4's `WrapEqualAreaSquare` folds one a
//!   filter has pushed past an edge; the image's centre looks up, its corners down.

use crate::math::{equal_area_square_to_sphere, Vec3};
use std::f64::consts::PI;

/// How a spherical camera lays the directions about it on the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SphericalMapping {
    /// Clarberg's equal-area octahedral map (pbrt-v4's default): each pixel the same solid
    /// angle.
    EqualArea,
    /// Longitude across, latitude down.
    Equirectangular,
}

impl SphericalMapping {
    /// The direction (unit, in the camera's space) of image point `(u, v)`, each a fraction
    /// of the image's width and height.
    pub fn direction(self, u: f64, v: f64) -> Vec3 {
        let pbrt = match self {
            Self::Equirectangular => {
                let (theta, phi) = (PI * v, 2.0 * PI * u);
                let sin_theta = theta.sin().clamp(-1.0, 1.0);
                Vec3::new(
                    sin_theta * phi.cos(),
                    sin_theta * phi.sin(),
                    theta.cos().clamp(-1.0, 1.0),
                )
            }
            Self::EqualArea => {
                let (u, v) = wrap_equal_area_square(u, v);
                equal_area_square_to_sphere(u, v)
            }
        };
        // pbrt swaps y and z, then its camera space becomes this crate's: x and z negated.
        Vec3::new(-pbrt.x, pbrt.z, -pbrt.y)
    }
}

/// A point past the unit square's edges folded back into it, as the equal-area map continues
/// across them (pbrt-v4's `WrapEqualAreaSquare`): across u = 0 or 1, mirrored in u and in v
/// about 0.5; across v = 0 or 1, mirrored in v and in u about 0.5.
fn wrap_equal_area_square(mut u: f64, mut v: f64) -> (f64, f64) {
    if u < 0.0 {
        u = -u;
        v = 1.0 - v;
    } else if u > 1.0 {
        u = 2.0 - u;
        v = 1.0 - v;
    }
    if v < 0.0 {
        u = 1.0 - u;
        v = -v;
    } else if v > 1.0 {
        u = 1.0 - u;
        v = 2.0 - v;
    }
    (u, v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every direction is a unit vector, and a point just past an edge of the equal-area
    /// square looks where the map continues: next to the point just inside.
    #[test]
    fn the_equal_area_map_continues_across_its_edges() {
        for (u, v) in [(-0.001, 0.3), (1.001, 0.7), (0.2, -0.001), (0.6, 1.001)] {
            let outside = SphericalMapping::EqualArea.direction(u, v);
            let inside =
                SphericalMapping::EqualArea.direction(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
            assert!((outside.length() - 1.0).abs() < 1e-12);
            assert!((outside - inside).length() < 0.01, "{u}, {v}");
        }
    }
}
