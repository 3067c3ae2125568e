//! Chapter 7: the camera.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
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

#[test]
fn the_transformation_matrix_for_the_default_orientation() {
    let t = view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, -1.0),
        vector(0.0, 1.0, 0.0),
    );
    assert_matrix_approx(t, glam::DMat4::IDENTITY);
}

#[test]
fn a_view_transformation_matrix_looking_in_positive_z_direction() {
    let t = view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    );
    assert_matrix_approx(t, rayforge::math::scaling(-1.0, 1.0, -1.0));
}

#[test]
fn the_view_transformation_moves_the_world() {
    let t = view_transform(
        point(0.0, 0.0, 8.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    );
    assert_matrix_approx(t, rayforge::math::translation(0.0, 0.0, -8.0));
}

#[test]
fn an_arbitrary_view_transformation() {
    let t = view_transform(
        point(1.0, 3.0, 2.0),
        point(4.0, -2.0, 8.0),
        vector(1.0, 1.0, 0.0),
    );
    let expected = rayforge::math::matrix4([
        [-0.50709, 0.50709, 0.67612, -2.36643],
        [0.76772, 0.60609, 0.12122, -2.82843],
        [-0.35857, 0.59761, -0.71714, 0.00000],
        [0.00000, 0.00000, 0.00000, 1.00000],
    ]);
    assert_matrix_approx(t, expected);
}

#[test]
fn constructing_a_camera() {
    let c = Camera::new(160, 120, PI / 2.0);
    assert_eq!(c.hsize(), 160);
    assert_eq!(c.vsize(), 120);
    assert_eq!(c.field_of_view(), PI / 2.0);
    assert_eq!(c.transform().matrix(), glam::DMat4::IDENTITY);
}

#[test]
fn the_pixel_size_for_a_horizontal_canvas() {
    assert_approx(Camera::new(200, 125, PI / 2.0).pixel_size(), 0.01);
}

#[test]
fn the_pixel_size_for_a_vertical_canvas() {
    assert_approx(Camera::new(125, 200, PI / 2.0).pixel_size(), 0.01);
}

#[test]
fn constructing_a_ray_through_the_center_of_the_canvas() {
    let r = Camera::new(201, 101, PI / 2.0).ray_for_pixel(100, 50);
    assert_vec_approx(r.origin, point(0.0, 0.0, 0.0));
    assert_vec_approx(r.direction, vector(0.0, 0.0, -1.0));
}

#[test]
fn constructing_a_ray_through_a_corner_of_the_canvas() {
    let r = Camera::new(201, 101, PI / 2.0).ray_for_pixel(0, 0);
    assert_vec_approx(r.origin, point(0.0, 0.0, 0.0));
    assert_vec_approx(r.direction, vector(0.66519, 0.33259, -0.66851));
}

#[test]
fn constructing_a_ray_when_the_camera_is_transformed() {
    let c = Camera::new(201, 101, PI / 2.0).with_transform(
        rayforge::math::rotation_y(PI / 4.0) * rayforge::math::translation(0.0, -2.0, 5.0),
    );
    let r = c.ray_for_pixel(100, 50);
    let k = 2f64.sqrt() / 2.0;
    assert_vec_approx(r.origin, point(0.0, 2.0, -5.0));
    assert_vec_approx(r.direction, vector(k, 0.0, -k));
}
