//! Chapter 7: the camera.
mod common;
use common::*;
use rayforge::math::view_transform;
use rayforge::{default_world, point, vector, Camera, Color};
use std::f64::consts::PI;

#[test]
fn rendering_a_world_with_a_camera() {
    let w = default_world();
    let from = point(0.0, 0.0, -5.0);
    let to = point(0.0, 0.0, 0.0);
    let up = vector(0.0, 1.0, 0.0);
    let c = Camera::new(11, 11, PI / 2.0).with_transform(view_transform(from, to, up));
    let image = c.render(&w);
    assert_color_approx(image.pixel_at(5, 5), Color::new(0.38066, 0.47583, 0.2855));
}
