//! The path tracer through participating media against answers known in closed form or by
//! numerical integration, at small sizes: Beer–Lambert through an absorbing medium (chromatic,
//! homogeneous and as a constant grid), a volumetric white furnace (albedo 1, isotropic and
//! Henyey–Greenstein g = ±0.7, chromatic), and single scattering of a point light in a thin
//! medium; and pbrt-v4's cloud, pixel by pixel, against its transmittance by quadrature.
//! Where every pixel has the same expected value, the image's mean per channel is compared
//! by a z-test on the spread of its pixels; the cloud's pixels differ, and each is judged on
//! the spread of its own passes. All at a fixed seed.

mod media_support;
mod path_support;

use media_support::{assert_means, homogeneous, medium_ball, single_scattering};
use path_support::{render_counted, render_samples};
use rayforge::film::Film;
use rayforge::math::{scaling, translation, view_transform, Aabb, Ray, Transform};
use rayforge::media::{
    CloudMedium, DensityGrid, Glow, GridMedium, HenyeyGreenstein, Media, Medium, MediumInterface,
};
use rayforge::options::{PathOptions, Roulette, SampleAllocation, SamplerKind};
use rayforge::shading::{EnvironmentMap, Light, PointLight};
use rayforge::{point, vector, Camera, Color, Object, World};
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

/// pbrt-v4's cloud over the world box [−1, 1]³ (its unit cube scaled by 2 and moved), a pure
/// absorber of σa `sigma_a` where its density is 1.
fn absorbing_cloud(sigma_a: Color) -> CloudMedium {
    let transform =
        Transform::try_new(translation(-1.0, -1.0, -1.0) * scaling(2.0, 2.0, 2.0)).expect("moves");
    CloudMedium::new(
        sigma_a,
        Color::BLACK,
        HenyeyGreenstein::ISOTROPIC,
        1.0,
        1.0,
        2.0,
        Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0)),
        transform,
    )
    .expect("cloud")
}

/// The transmittance of `cloud` along `ray` (a unit direction), per channel: its optical
/// depth integrated by the midpoint rule in `steps` steps over the ray's stretch in the box.
fn cloud_transmittance(cloud: &CloudMedium, ray: &Ray, steps: usize) -> [f64; 3] {
    let Some((t0, t1)) = cloud.span(ray.origin, ray.direction, f64::INFINITY) else {
        return [1.0; 3];
    };
    let dt = (t1 - t0) / steps as f64;
    let depth: f64 = (0..steps)
        .map(|i| {
            let p = ray.position(t0 + (i as f64 + 0.5) * dt);
            cloud.density_at(cloud.transform.inverse_point(p)) * dt
        })
        .sum();
    cloud.sigma_a.to_array().map(|s| (-s * depth).exp())
}

/// A pixel's expected value under a white sky: the transmittance averaged over the pixel (the
/// box filter draws its samples uniformly there), by an `n` × `n` grid of rays.
fn expected_pixel(
    cloud: &CloudMedium,
    camera: &Camera,
    px: usize,
    py: usize,
    n: usize,
    steps: usize,
) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for i in 0..n {
        for j in 0..n {
            let x = px as f64 + (i as f64 + 0.5) / n as f64;
            let y = py as f64 + (j as f64 + 0.5) / n as f64;
            let t = cloud_transmittance(cloud, &camera.ray_through(x, y), steps);
            for c in 0..3 {
                sum[c] += t[c] / (n * n) as f64;
            }
        }
    }
    sum
}

#[test]
fn a_cloud_lets_through_the_transmittance_of_its_density_pixel_by_pixel() {
    // A camera looks through an absorbing cloud in an index-matched cube at a white sky:
    // each pixel's expected value is the transmittance along its rays, e^(−σa ∫ density),
    // which the cloud's density gives by fine numerical integration, independently of the
    // tracker (majorant, null collisions, the hero channel and its ratios). The pixels
    // differ, so each is judged on its own standard error, taken from the spread of the
    // means of `PASSES` disjoint ranges of samples, rendered apart.
    const PASSES: u64 = 32;
    const SPP: u64 = 32;
    let cloud = absorbing_cloud(Color::new(0.5, 0.8, 1.2));
    let mut world = World {
        background: Color::WHITE,
        ..World::default()
    };
    let id = world
        .media
        .add(Medium::Cloud(Box::new(cloud.clone())))
        .expect("id");
    let mut cube = Object::cube().with_transform(scaling(1.01, 1.01, 1.01));
    cube.media = Some(MediumInterface {
        inside: Some(id),
        outside: None,
        index_matched: true,
    });
    world.objects.push(cube);
    let camera = Camera::new(6, 6, 0.5).with_transform(view_transform(
        point(0.3, 0.1, 4.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let options = PathOptions {
        sampler: SamplerKind::Independent,
        max_depth: 8,
        roulette: Roulette::Scale(1.0),
        allocation: SampleAllocation::Uniform,
        ..PathOptions::default()
    };
    let passes: Vec<_> = (0..PASSES)
        .map(|k| {
            render_samples(&world, &camera, k * SPP..(k + 1) * SPP, options)
                .0
                .resolve()
        })
        .collect();
    let (w, h) = (camera.hsize(), camera.vsize());
    let (mut residual, mut variance, mut lowest, mut highest) =
        ([0.0; 3], [0.0; 3], 1.0f64, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            // The quadrature's own error: how far a grid of half the rays and steps strays.
            let fine = expected_pixel(&cloud, &camera, x, y, 8, 512);
            let coarse = expected_pixel(&cloud, &camera, x, y, 4, 256);
            for c in 0..3 {
                let values: Vec<f64> = passes
                    .iter()
                    .map(|p| p.pixel_at(x, y).to_array()[c])
                    .collect();
                let n = values.len() as f64;
                let mean = values.iter().sum::<f64>() / n;
                let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
                let se = (var / n).sqrt();
                let quadrature = (fine[c] - coarse[c]).abs();

                let tolerance = 5.0 * (se * se + quadrature * quadrature).sqrt();
                assert!(
                    (mean - fine[c]).abs() <= tolerance,
                    "pixel ({x}, {y}) channel {c}: {mean} ± {se}, expected {} (quadrature {quadrature})",
                    fine[c]
                );
                assert!(
                    se < 0.1 * fine[c].max(1e-2),
                    "pixel ({x}, {y}) channel {c} too noisy to judge: {se}"
                );
                residual[c] += mean - fine[c];
                variance[c] += se * se + quadrature * quadrature;
                lowest = lowest.min(fine[c]);
                highest = highest.max(fine[c]);
            }
        }
    }
    // The whole image's bias, far tighter than any one pixel's.
    for c in 0..3 {
        assert!(
            residual[c].abs() <= 4.0 * variance[c].sqrt(),
            "channel {c}: the pixels stray by {} in all, ± {}",
            residual[c],
            variance[c].sqrt()
        );
    }
    // A cloud, not a slab: the pixels see very different depths of it.
    assert!(highest - lowest > 0.3, "{lowest} to {highest}");
}
