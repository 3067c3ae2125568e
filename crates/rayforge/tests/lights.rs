//! Chapter 6: lights.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
use rayforge::color::color;
use rayforge::{point, Light};

#[test]
fn a_point_light_has_a_position_and_intensity() {
    let intensity = color(1.0, 1.0, 1.0);
    let position = point(0.0, 0.0, 0.0);
    let light = Light::point(position, intensity);
    assert_eq!(light.position(), position);
    assert_eq!(light.intensity(), intensity);
}
