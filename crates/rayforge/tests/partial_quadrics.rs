//! Light from pbrt-v4's cut quadrics, against answers known in closed form: a floor lit by a
//! glowing dome (a sphere cut at its equator) and by half a dome (also cut to half a turn),
//! rendered by the path tracer with light sampling on (the lamp drawn by area over what its
//! cut keeps) and off (found by scattering alone). Heights drawn over the whole sphere, as
//! pbrt-v4 draws a cut sphere's points, leave the dome a fifth and the half dome a third too
//! dark here.

mod path_support;

use path_support::render_counted;
use rayforge::geometry::PartialQuadric;
use rayforge::math::view_transform;
use rayforge::options::{PathOptions, Techniques};
use rayforge::shading::{EmissionSide, Material, Physical};
use rayforge::{point, vector, Camera, Color, Object, Shape, World};

/// Renders `world` through `camera` at `spp` samples per pixel; the mean and standard error of
/// the pixels' red channel.
fn mean_of(world: &World, camera: &Camera, spp: u64, next_event: bool) -> (f64, f64) {
    let options = PathOptions {
        max_depth: 4,
        techniques: Techniques {
            next_event,
            mis: next_event,
            ..Techniques::default()
        },
        ..PathOptions::default()
    };
    let canvas = render_counted(world, camera, spp, options).0.resolve();
    let values: Vec<f64> = (0..canvas.height())
        .flat_map(|y| (0..canvas.width()).map(move |x| (x, y)))
        .map(|(x, y)| canvas.pixel_at(x, y).red)
        .collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// A black lamp `lamp` glowing with radiance 1 inwards (its back), over a small white floor
/// disc at the origin facing +z, seen from just above by a camera looking down on the disc
/// alone.
fn lit_floor(lamp: PartialQuadric) -> (World, Camera) {
    let lamp = Object::new(Shape::Partial(Box::new(lamp))).with_material(Material {
        color: Color::BLACK,
        emission: Color::WHITE,
        emission_side: EmissionSide::Back,
        physical: Some(Physical::Diffuse),
        ..Material::DEFAULT
    });
    let floor = PartialQuadric::disk(0.0, 0.01, 0.0, 360.0).unwrap();
    let floor = Object::new(Shape::Partial(Box::new(floor))).with_material(Material {
        color: Color::WHITE,
        physical: Some(Physical::Diffuse),
        ..Material::DEFAULT
    });
    let world = World {
        objects: vec![lamp, floor],
        ..World::default()
    };
    let camera = Camera::new(6, 6, 0.1).with_transform(view_transform(
        point(0.0, 0.0, 0.05),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    (world, camera)
}

/// Whether `(mean, se)` is within four and a half standard errors (and the floor's own
/// offset from the centre, 0.1 % of the light) of `expected`.
fn agrees(found: (f64, f64), expected: f64) -> bool {
    (found.0 - expected).abs() <= 4.5 * found.1 + 2e-3 * expected
}

#[test]
fn a_floor_under_a_glowing_dome_reflects_its_radiance() {
    // The sphere of radius 10 above z = 0: every direction up from the floor meets it, so a
    // white floor sends back the dome's radiance, 1.
    let dome = PartialQuadric::sphere(10.0, 0.0, 10.0, 360.0).unwrap();
    let (world, camera) = lit_floor(dome);
    for next_event in [true, false] {
        let found = mean_of(&world, &camera, 256, next_event);
        assert!(agrees(found, 1.0), "next event {next_event}: {found:?}");
    }
}

#[test]
fn a_floor_under_half_a_dome_reflects_half_its_radiance() {
    // Cut to half a turn as well (φ from 0 to 180°: the +y side): from the floor's centre
    // the lamp fills the half of the sky with y > 0, which holds half the cosine-weighted
    // hemisphere: the floor sends back 1/2.
    let half = PartialQuadric::sphere(10.0, 0.0, 10.0, 180.0).unwrap();
    let (world, camera) = lit_floor(half);
    for next_event in [true, false] {
        let found = mean_of(&world, &camera, 512, next_event);
        assert!(agrees(found, 0.5), "next event {next_event}: {found:?}");
    }
}

#[test]
fn a_floor_under_a_glowing_ring_band_gets_the_bands_share() {
    // An open cylinder of radius 10 from z = 0 to z = 10, glowing inwards, swept a whole
    // turn: seen from the floor's centre it spans the zenith angles from 45° to 90°, which
    // hold `sin² 90° − sin² 45° = 1/2` of the cosine-weighted hemisphere.
    let band = PartialQuadric::cylinder(10.0, 0.0, 10.0, 360.0).unwrap();
    let (world, camera) = lit_floor(band);
    for next_event in [true, false] {
        let found = mean_of(&world, &camera, 512, next_event);
        assert!(agrees(found, 0.5), "next event {next_event}: {found:?}");
    }
}
