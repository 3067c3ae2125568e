//! The path tracer through participating media against answers known in closed form or by
//! numerical integration, at small sizes: Beer–Lambert through an absorbing medium (chromatic,
//! homogeneous and as a constant grid), a volumetric white furnace (albedo 1, isotropic and
//! Henyey–Greenstein g = ±0.7, chromatic), and single scattering of a point light in a thin
//! medium. Each compares the image's mean per channel with a z-test on the spread of its
//! pixels (every pixel of these scenes has the same expected value), at a fixed seed.

mod media_support;
mod path_support;

use media_support::{assert_means, homogeneous, medium_ball, single_scattering};
use path_support::render_counted;
use rayforge::film::Film;
use rayforge::math::{view_transform, Aabb, Transform};
use rayforge::media::{DensityGrid, Glow, GridMedium, HenyeyGreenstein, Media, Medium};
use rayforge::options::{PathOptions, Roulette, SampleAllocation, SamplerKind};
use rayforge::shading::{EnvironmentMap, Light, PointLight};
use rayforge::{point, vector, Camera, Color, World};
use std::sync::Arc;

fn render(world: &World, camera: &Camera, spp: u64, max_depth: u32) -> Film {
    let options = PathOptions {
        sampler: SamplerKind::Independent,
        max_depth,
        roulette: Roulette::Scale(1.0),
        allocation: SampleAllocation::Uniform,
        ..PathOptions::default()
    };
    render_counted(world, camera, spp, options).0
}

/// A camera at the centre of a sphere of radius 2 filled with `medium`, under a white sky:
/// every ray crosses 2 units of the medium.
fn inside_ball(medium: Medium) -> (World, Camera) {
    let mut world = World {
        background: Color::WHITE,
        media: Media::NONE,
        ..World::default()
    };
    let id = medium_ball(&mut world, medium, 2.0, [0.0; 3]);
    world.camera_medium = Some(id);
    let camera = Camera::new(8, 8, 1.5).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.3, 0.2, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    (world, camera)
}

const ABSORPTION: Color = Color::new(0.2, 0.6, 1.3);

fn attenuated() -> [f64; 3] {
    ABSORPTION.to_array().map(|s| (-2.0 * s).exp())
}

#[test]
fn an_absorbing_medium_lets_through_beer_lambert_in_every_channel() {
    // Albedo 0: exactly the attenuated sky, e^(−σa·2), whatever the channel's σa.
    let (world, camera) = inside_ball(homogeneous(ABSORPTION, Color::BLACK, 0.0));
    let film = render(&world, &camera, 64, 8);
    assert_means(&film, attenuated(), "homogeneous");
}

#[test]
fn a_constant_grid_attenuates_as_the_homogeneous_medium_does() {
    // Density 4 times a quarter of the coefficients, over a box around the ball.
    let density = DensityGrid::new([3, 2, 4], vec![4.0; 24]).expect("grid");
    let grid = GridMedium::new(
        ABSORPTION * 0.25,
        Color::BLACK,
        Color::BLACK,
        HenyeyGreenstein::ISOTROPIC,
        density,
        Aabb::new(point(-2.5, -2.5, -2.5), point(2.5, 2.5, 2.5)),
        Transform::IDENTITY,
    )
    .expect("medium");
    let (world, camera) = inside_ball(Medium::Grid(Box::new(grid)));
    let film = render(&world, &camera, 64, 8);
    assert_means(&film, attenuated(), "grid");
}

/// A ball of radius 1 filled with `medium` seen from outside under a white sky.
fn furnace(medium: Medium) -> (World, Camera) {
    let mut world = World {
        background: Color::WHITE,
        ..World::default()
    };
    medium_ball(&mut world, medium, 1.0, [0.0; 3]);
    let camera = Camera::new(8, 8, 0.45).with_transform(view_transform(
        point(0.0, 0.0, 4.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (world, camera)
}

#[test]
fn a_medium_of_albedo_one_vanishes_in_the_white_furnace() {
    // It loses nothing: whatever it scatters, every pixel is the sky's 1.
    for g in [0.0, 0.7, -0.7] {
        let (world, camera) = furnace(homogeneous(Color::BLACK, Color::new(2.0, 2.0, 2.0), g));
        let film = render(&world, &camera, 256, 1000);
        assert_means(&film, [1.0; 3], &format!("g = {g}"));
    }
}

#[test]
fn a_chromatic_medium_of_albedo_one_vanishes_in_the_white_furnace() {
    // σs differs by channel: tracked in one hero channel, weighed over all three.
    let (world, camera) = furnace(homogeneous(Color::BLACK, Color::new(0.5, 2.0, 5.0), 0.3));
    let film = render(&world, &camera, 256, 1000);
    assert_means(&film, [1.0; 3], "chromatic");
}

#[test]
fn a_chromatic_medium_vanishes_under_a_sampled_sky() {
    // A uniform environment map of 1 is a light that next-event estimation samples: the
    // light found by sampling it and by the phase function are weighed against each other,
    // channel by channel, and still add up to 1.
    let (mut world, camera) = furnace(homogeneous(Color::BLACK, Color::new(0.5, 2.0, 5.0), 0.5));
    let sky = EnvironmentMap::new(8, 4, vec![Color::WHITE; 32], 1.0).expect("sky");
    world.environment = Some(Arc::new(sky));
    let film = render(&world, &camera, 256, 1000);
    assert_means(&film, [1.0; 3], "sampled sky");
}

#[test]
fn single_scattering_of_a_point_light_matches_its_integral() {
    // The camera looks along +z from the centre of a ball of radius 10 of thin medium; a
    // point light stands 1 off the axis at z = 3. One bounce: the light scattered once
    // towards the camera, L = ∫ σs e^(−σt t) p(θ) E(d) e^(−σt d) dt with E = π I / d².
    // A chromatic medium: each channel has its own integral.
    let (sigma_a, sigma_s, g) = (
        Color::new(0.05, 0.03, 0.01),
        Color::new(0.05, 0.1, 0.2),
        0.4,
    );
    let mut world = World::default();
    let id = medium_ball(&mut world, homogeneous(sigma_a, sigma_s, g), 10.0, [0.0; 3]);
    world.camera_medium = Some(id);
    let light = point(0.0, 1.0, 3.0);
    world.lights.push(Light::Point(PointLight {
        position: light,
        intensity: Color::WHITE,
        falloff: true,
    }));
    let camera = Camera::new(4, 4, 1e-4).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    let expected = single_scattering(sigma_a, sigma_s, g, light, 200_000);
    let film = render(&world, &camera, 1024, 1);
    assert_means(&film, expected, "single scattering");
}

#[test]
fn an_emitting_grid_gives_its_light_less_what_it_absorbs() {
    // A pure absorber (σa = 0.5 where the density is 1) glowing with Le = (1, 0.5, 0.25)
    // times a grid of factors 2: along 2 units from the camera, L = 2 Le (1 − e^(−σa·2)).
    let density = DensityGrid::new([2, 2, 2], vec![1.0; 8]).expect("grid");
    let factors = DensityGrid::new([3, 1, 2], vec![2.0; 6]).expect("grid");
    let le = Color::new(1.0, 0.5, 0.25);
    let grid = GridMedium::new(
        Color::new(0.5, 0.5, 0.5),
        Color::BLACK,
        Color::BLACK,
        HenyeyGreenstein::ISOTROPIC,
        density,
        Aabb::new(point(-2.5, -2.5, -2.5), point(2.5, 2.5, 2.5)),
        Transform::IDENTITY,
    )
    .expect("medium")
    .with_glow(Glow::Scaled {
        radiance: le,
        scale: factors,
    });
    let (mut world, camera) = inside_ball(Medium::Grid(Box::new(grid)));
    world.background = Color::BLACK;
    let film = render(&world, &camera, 256, 8);
    let expected = le.to_array().map(|c| 2.0 * c * (1.0 - (-1.0f64).exp()));
    assert_means(&film, expected, "emitting grid");
}
