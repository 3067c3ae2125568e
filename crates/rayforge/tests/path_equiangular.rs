//! Equiangular sampling in homogeneous media (`Techniques::equiangular`) against answers
//! known in closed form, with and without MIS, and what it buys: single scattering of a point
//! light near the camera ray equals its integral whichever strategies run, a medium of albedo
//! 1 inside a glowing sphere (an area light that every strategy finds: light sampling from
//! distance-sampled and equiangular points, and the phase function meeting it) renders the
//! sphere's radiance, and the equiangular points cut the point light's noise by a measured
//! factor. Each compares an image's mean per channel with a z-test on the spread of its
//! pixels (every pixel of these scenes has the same expected value), at a fixed seed.

mod media_support;
mod path_support;

use media_support::{assert_means, channel_means, homogeneous, medium_ball, single_scattering};
use path_support::render_counted;
use rayforge::film::Film;
use rayforge::math::{scaling, view_transform};
use rayforge::media::Medium;
use rayforge::options::{PathOptions, Roulette, SampleAllocation, SamplerKind, Techniques};
use rayforge::shading::{EmissionSide, Light, Material, PointLight};
use rayforge::{point, vector, Camera, Color, Object, World};

fn render(
    world: &World,
    camera: &Camera,
    spp: u64,
    max_depth: u32,
    techniques: Techniques,
) -> Film {
    let options = PathOptions {
        sampler: SamplerKind::Independent,
        max_depth,
        roulette: Roulette::Scale(1.0),
        allocation: SampleAllocation::Uniform,
        techniques,
        ..PathOptions::default()
    };
    render_counted(world, camera, spp, options).0
}

const ON: Techniques = Techniques {
    equiangular: true,
    ..TECHNIQUES
};
const OFF: Techniques = Techniques {
    equiangular: false,
    ..TECHNIQUES
};
const TECHNIQUES: Techniques = Techniques {
    next_event: true,
    mis: true,
    roulette: true,
    glass_split: true,
    mirror_balls: true,
    mirror_ball_budget: rayforge::options::MirrorBallBudget { cap: 2, cull: 1e-3 },
    sphere_cones: true,
    equiangular: true,
    equiangular_lights: Techniques::DEFAULT_EQUIANGULAR_LIGHTS,
};

/// The camera looks along +z from the centre of a ball of radius 10 of thin chromatic medium;
/// a point light stands `offset` off the axis at z = 3. The expected single scattering per
/// channel, L = ∫ σs e^(−σt t) p(θ) I e^(−σt d) / d² dt.
fn point_light_in_fog(offset: f64) -> (World, Camera, [f64; 3]) {
    let (sigma_a, sigma_s, g) = (
        Color::new(0.05, 0.03, 0.01),
        Color::new(0.05, 0.1, 0.2),
        0.4,
    );
    let mut world = World::default();
    let id = medium_ball(&mut world, homogeneous(sigma_a, sigma_s, g), 10.0, [0.0; 3]);
    world.camera_medium = Some(id);
    let light = point(0.0, offset, 3.0);
    world.lights.push(Light::Point(PointLight {
        position: light,
        intensity: Color::WHITE,
        falloff: true,
    }));
    let camera = Camera::new(8, 8, 1e-4).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    let expected = single_scattering(sigma_a, sigma_s, g, light, 400_000);
    (world, camera, expected)
}

#[test]
fn single_scattering_of_a_close_point_light_matches_its_integral_with_every_strategy() {
    let (world, camera, expected) = point_light_in_fog(0.2);
    for (techniques, what) in [
        (ON, "equiangular with MIS"),
        (Techniques { mis: false, ..ON }, "equiangular alone"),
        (OFF, "distance sampling"),
    ] {
        let spp = if techniques.equiangular { 256 } else { 4096 };
        let film = render(&world, &camera, spp, 1, techniques);
        assert_means(&film, expected, what);
    }
}

#[test]
fn equiangular_points_cut_the_noise_of_a_close_point_light() {
    // The same samples per pixel with and without: the standard error of the image's mean
    // (the pixels' spread) falls by more than a factor of three (measured: see
    // docs/performance.md).
    let (world, camera, _) = point_light_in_fog(0.2);
    let on = channel_means(&render(&world, &camera, 256, 1, ON));
    let off = channel_means(&render(&world, &camera, 256, 1, OFF));
    for c in 0..3 {
        let ratio = off[c].1 / on[c].1;
        eprintln!(
            "channel {c}: standard error {} without, {} with: {ratio}",
            off[c].1, on[c].1
        );
        assert!(ratio > 3.0, "channel {c}: only {ratio} times less noise");
    }
}

/// A glowing sphere of radius 3 (radiance 1 inwards, sampled as an area light) around a
/// ball of radius 1.5 off its centre filled with a medium of albedo 1, seen from inside the
/// sphere: a furnace, where every pixel sees the sphere's 1 whatever the medium scatters.
fn glowing_furnace(medium: Medium) -> (World, Camera) {
    let mut world = World::default();
    let lamp = Object::sphere()
        .with_transform(scaling(3.0, 3.0, 3.0))
        .with_material(Material {
            emission: Color::WHITE,
            emission_side: EmissionSide::Back,
            color: Color::BLACK,
            specular: 0.0,
            ..Material::DEFAULT
        });
    world.objects.push(lamp);
    medium_ball(&mut world, medium, 1.5, [0.4, -0.3, 0.2]);
    let camera = Camera::new(8, 8, 0.6).with_transform(view_transform(
        point(0.0, 0.0, -2.8),
        point(0.3, -0.2, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (world, camera)
}

#[test]
fn a_medium_of_albedo_one_vanishes_in_a_glowing_furnace_with_every_strategy() {
    for g in [0.0, 0.7] {
        let (world, camera) =
            glowing_furnace(homogeneous(Color::BLACK, Color::new(0.8, 1.5, 3.0), g));
        for (techniques, what) in [
            (ON, "equiangular with MIS"),
            (Techniques { mis: false, ..ON }, "equiangular without MIS"),
            (OFF, "distance sampling"),
        ] {
            let film = render(&world, &camera, 1024, 1000, techniques);
            assert_means(&film, [1.0; 3], &format!("{what}, g = {g}"));
        }
    }
}
