//! Chapter 6: lights.
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
