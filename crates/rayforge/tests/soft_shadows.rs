//! The bonus chapter "Rendering soft shadows": area lights, their samples and jitter.
// The book's expected values are kept exactly as printed.
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::shading::{Jitter, Sequence};
use rayforge::{
    default_world, lighting, point, vector, AreaLight, Light, Material, Object, Point3, World,
};

/// The book's `is_shadowed(world, light_position, point)` rows.
fn occluded(light_position: Point3, p: Point3) -> bool {
    default_world().is_shadowed(light_position, p)
}

#[test]
fn is_shadowed_tests_for_occlusion_between_two_points_1() {
    assert!(!occluded(
        point(-10.0, -10.0, -10.0),
        point(-10.0, -10.0, 10.0)
    ));
}

#[test]
fn is_shadowed_tests_for_occlusion_between_two_points_2() {
    assert!(occluded(
        point(-10.0, -10.0, -10.0),
        point(10.0, 10.0, 10.0)
    ));
}

#[test]
fn is_shadowed_tests_for_occlusion_between_two_points_3() {
    assert!(!occluded(
        point(-10.0, -10.0, -10.0),
        point(-20.0, -20.0, -20.0)
    ));
}

#[test]
fn is_shadowed_tests_for_occlusion_between_two_points_4() {
    assert!(!occluded(
        point(-10.0, -10.0, -10.0),
        point(-5.0, -5.0, -5.0)
    ));
}

fn point_light_intensity(p: Point3) -> f64 {
    let w = default_world();
    w.intensity_at(&w.lights[0], p)
}

fn point_light_row(p: Point3, expected: f64) {
    assert_approx(point_light_intensity(p), expected);
}

scenario_rows! { point_light_row;
    point_lights_evaluate_the_light_intensity_at_a_given_point_1: point(0.0, 1.0001, 0.0), 1.0;
    point_lights_evaluate_the_light_intensity_at_a_given_point_2: point(-1.0001, 0.0, 0.0), 1.0;
    point_lights_evaluate_the_light_intensity_at_a_given_point_3: point(0.0, 0.0, -1.0001), 1.0;
    point_lights_evaluate_the_light_intensity_at_a_given_point_4: point(0.0, 0.0, 1.0001), 0.0;
    point_lights_evaluate_the_light_intensity_at_a_given_point_5: point(1.0001, 0.0, 0.0), 0.0;
    point_lights_evaluate_the_light_intensity_at_a_given_point_6: point(0.0, -1.0001, 0.0), 0.0;
    point_lights_evaluate_the_light_intensity_at_a_given_point_7: point(0.0, 0.0, 0.0), 0.0;
}

fn attenuated(intensity: f64, expected: rayforge::Color) {
    let mut w = default_world();
    w.lights = vec![Light::point(point(0.0, 0.0, -10.0), color(1.0, 1.0, 1.0))];
    let shape = &mut w.objects[0];
    shape.material.ambient = 0.1;
    shape.material.diffuse = 0.9;
    shape.material.specular = 0.0;
    shape.material.color = color(1.0, 1.0, 1.0);
    let pt = point(0.0, 0.0, -1.0);
    let eyev = vector(0.0, 0.0, -1.0);
    let normalv = vector(0.0, 0.0, -1.0);
    let result = lighting(
        &shape.material,
        shape,
        &w.lights[0],
        pt,
        eyev,
        normalv,
        intensity,
    );
    assert_color_approx(result, expected);
}

scenario_rows! { attenuated;
    lighting_uses_light_intensity_to_attenuate_color_1: 1.0, color(1.0, 1.0, 1.0);
    lighting_uses_light_intensity_to_attenuate_color_2: 0.5, color(0.55, 0.55, 0.55);
    lighting_uses_light_intensity_to_attenuate_color_3: 0.0, color(0.1, 0.1, 0.1);
}

#[test]
fn creating_an_area_light() {
    let light = AreaLight::new(
        point(0.0, 0.0, 0.0),
        vector(2.0, 0.0, 0.0),
        4,
        vector(0.0, 0.0, 1.0),
        2,
        color(1.0, 1.0, 1.0),
    );
    assert_eq!(light.corner, point(0.0, 0.0, 0.0));
    assert_vec_approx(light.uvec, vector(0.5, 0.0, 0.0));
    assert_eq!(light.usteps, 4);
    assert_vec_approx(light.vvec, vector(0.0, 0.0, 0.5));
    assert_eq!(light.vsteps, 2);
    assert_eq!(light.samples(), 8);
    assert_vec_approx(light.position(), point(1.0, 0.0, 0.5));
}

fn book_light() -> AreaLight {
    AreaLight::new(
        point(0.0, 0.0, 0.0),
        vector(2.0, 0.0, 0.0),
        4,
        vector(0.0, 0.0, 1.0),
        2,
        color(1.0, 1.0, 1.0),
    )
}

fn point_on(u: u32, v: u32, expected: Point3) {
    let p = book_light().point_on_light(u, v, &mut Sequence::new(&[0.5]));
    assert_vec_approx(p, expected);
}

scenario_rows! { point_on;
    finding_a_single_point_on_an_area_light_1: 0, 0, point(0.25, 0.0, 0.25);
    finding_a_single_point_on_an_area_light_2: 1, 0, point(0.75, 0.0, 0.25);
    finding_a_single_point_on_an_area_light_3: 0, 1, point(0.25, 0.0, 0.75);
    finding_a_single_point_on_an_area_light_4: 2, 0, point(1.25, 0.0, 0.25);
    finding_a_single_point_on_an_area_light_5: 3, 1, point(1.75, 0.0, 0.75);
}

/// The area light of the intensity scenarios: 2×2 samples on a unit square at z = -5.
fn square_light() -> AreaLight {
    AreaLight::new(
        point(-0.5, -0.5, -5.0),
        vector(1.0, 0.0, 0.0),
        2,
        vector(0.0, 1.0, 0.0),
        2,
        color(1.0, 1.0, 1.0),
    )
}

fn area_intensity(light: AreaLight, jitter: &mut dyn Jitter, p: Point3) -> f64 {
    let w = default_world();
    light.fraction_visible(jitter, |sample| w.is_shadowed(sample, p))
}

fn area_row(p: Point3, expected: f64) {
    let w = default_world();
    assert_approx(w.intensity_at(&Light::Area(square_light()), p), expected);
}

scenario_rows! { area_row;
    the_area_light_intensity_function_1: point(0.0, 0.0, 2.0), 0.0;
    the_area_light_intensity_function_2: point(1.0, -1.0, 2.0), 0.25;
    the_area_light_intensity_function_3: point(1.5, 0.0, 2.0), 0.5;
    the_area_light_intensity_function_4: point(1.25, 1.25, 3.0), 0.75;
    the_area_light_intensity_function_5: point(0.0, 0.0, -2.0), 1.0;
}

fn jittered_point(u: u32, v: u32, expected: Point3) {
    let light = book_light().jittered();
    let p = light.point_on_light(u, v, &mut Sequence::new(&[0.3, 0.7]));
    assert_vec_approx(p, expected);
}

scenario_rows! { jittered_point;
    finding_a_single_point_on_a_jittered_area_light_1: 0, 0, point(0.15, 0.0, 0.35);
    finding_a_single_point_on_a_jittered_area_light_2: 1, 0, point(0.65, 0.0, 0.35);
    finding_a_single_point_on_a_jittered_area_light_3: 0, 1, point(0.15, 0.0, 0.85);
    finding_a_single_point_on_a_jittered_area_light_4: 2, 0, point(1.15, 0.0, 0.35);
    finding_a_single_point_on_a_jittered_area_light_5: 3, 1, point(1.65, 0.0, 0.85);
}

fn jittered_intensity(p: Point3, expected: f64) {
    let mut sequence = Sequence::new(&[0.7, 0.3, 0.9, 0.1, 0.5]);
    let fraction = area_intensity(square_light().jittered(), &mut sequence, p);
    assert_approx(fraction, expected);
}

scenario_rows! { jittered_intensity;
    the_area_light_with_jittered_samples_1: point(0.0, 0.0, 2.0), 0.0;
    the_area_light_with_jittered_samples_2: point(1.0, -1.0, 2.0), 0.5;
    the_area_light_with_jittered_samples_3: point(1.5, 0.0, 2.0), 0.75;
    the_area_light_with_jittered_samples_4: point(1.25, 1.25, 3.0), 0.75;
    the_area_light_with_jittered_samples_5: point(0.0, 0.0, -2.0), 1.0;
}

fn samples_area_light(pt: Point3, expected: rayforge::Color) {
    let light = Light::Area(square_light());
    let shape = Object::sphere().with_material(Material {
        ambient: 0.1,
        diffuse: 0.9,
        specular: 0.0,
        color: color(1.0, 1.0, 1.0),
        ..Material::default()
    });
    let eye = point(0.0, 0.0, -5.0);
    let eyev = (eye - pt).normalize();
    let normalv = vector(pt.x, pt.y, pt.z);
    let result = lighting(&shape.material, &shape, &light, pt, eyev, normalv, 1.0);
    assert_color_approx(result, expected);
}

scenario_rows! { samples_area_light;
    lighting_samples_the_area_light_1: point(0.0, 0.0, -1.0), color(0.9965, 0.9965, 0.9965);
    lighting_samples_the_area_light_2: point(0.0, 0.7071, -0.7071), color(0.6232, 0.6232, 0.6232);
}

/// Soft shadows render the same with any thread count: the jitter is seeded per pixel.
#[test]
fn jittered_renders_do_not_depend_on_the_thread_count() {
    let mut w = World::new();
    w.objects.push(Object::plane());
    w.objects
        .push(Object::sphere().with_transform(rayforge::math::translation(0.0, 1.0, 0.0)));
    w.lights.push(Light::Area(
        AreaLight::new(
            point(-1.0, 4.0, -1.0),
            vector(2.0, 0.0, 0.0),
            4,
            vector(0.0, 0.0, 2.0),
            4,
            color(1.0, 1.0, 1.0),
        )
        .jittered(),
    ));
    let camera = rayforge::Camera::new(24, 16, 1.0).with_transform(rayforge::math::view_transform(
        point(0.0, 3.0, -5.0),
        point(0.0, 0.5, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let render_on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| camera.render(&w))
    };
    assert_eq!(render_on(1), render_on(3));
}

/// A sphere above a floor, lit by `light`: the middle row of a small image of the floor (its
/// brightness across the shadow).
fn shadow_row(light: Light, sphere_casts_shadow: bool) -> Vec<f64> {
    let mut w = World::new();
    w.objects.push(Object::plane().with_material(Material {
        ambient: 0.0,
        specular: 0.0,
        ..Material::default()
    }));
    let mut sphere = Object::sphere().with_transform(
        rayforge::math::translation(0.0, 1.5, 0.0) * rayforge::math::scaling(0.5, 0.5, 0.5),
    );
    sphere.casts_shadow = sphere_casts_shadow;
    // The camera looks down at the floor from below the sphere, so the middle row of the image
    // shows only the floor and the shadow on it.
    w.objects.push(sphere);
    w.lights.push(light);
    let camera = rayforge::Camera::new(61, 3, 0.9).with_transform(rayforge::math::view_transform(
        point(0.0, 0.9, -3.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let canvas = camera.render(&w);
    (0..canvas.width())
        .map(|x| canvas.pixel_at(x, 1).red)
        .collect()
}

fn area_light_above() -> Light {
    Light::Area(AreaLight::new(
        point(-1.0, 4.0, -1.0),
        vector(2.0, 0.0, 0.0),
        8,
        vector(0.0, 0.0, 2.0),
        8,
        color(1.0, 1.0, 1.0),
    ))
}

#[test]
fn an_area_light_casts_a_shadow_with_a_penumbra() {
    let row = shadow_row(area_light_above(), true);
    let lit = row.iter().cloned().fold(0.0, f64::max);
    let darkest = row.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(darkest < 0.25 * lit, "an umbra: {row:?}");
    // Between the umbra and the lit floor, a gradual penumbra of several distinct levels.
    let mut levels: Vec<u32> = row
        .iter()
        .filter(|&&v| v > darkest + 0.05 * lit && v < 0.95 * lit)
        .map(|v| (v * 1000.0) as u32)
        .collect();
    levels.sort_unstable();
    levels.dedup();
    assert!(levels.len() >= 6, "a penumbra: {row:?}");
}

#[test]
fn a_point_light_casts_a_hard_shadow() {
    let row = shadow_row(
        Light::point(point(0.0, 4.0, 0.0), color(1.0, 1.0, 1.0)),
        true,
    );
    // Each pixel is either in shadow (no light at all: the floor has no ambient term) or lit.
    let shadowed = row.iter().filter(|&&v| v == 0.0).count();
    assert!(shadowed > 0 && shadowed < row.len(), "{row:?}");
}

#[test]
fn objects_that_cast_no_shadow_let_every_kind_of_light_through() {
    let spot = rayforge::SpotLight::new(
        point(0.0, 4.0, 0.0),
        vector(0.0, -1.0, 0.0),
        1.2,
        0.0,
        color(1.0, 1.0, 1.0),
    )
    .unwrap();
    for light in [
        Light::point(point(0.0, 4.0, 0.0), color(1.0, 1.0, 1.0)),
        area_light_above(),
        Light::Spot(spot),
    ] {
        let with = shadow_row(light.clone(), true);
        let without = shadow_row(light, false);
        assert!(with.iter().any(|&v| v < 0.05), "a shadow: {with:?}");
        assert!(without.iter().all(|&v| v > 0.1), "no shadow: {without:?}");
    }
}
