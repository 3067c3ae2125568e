//! Fundamentals of Ray Tracing's optics model through the rasterizer: the matte term under
//! every light, the automatic exposure of the whole image, and no rays (no gloss, no
//! refraction, no shadows).

use rayforge::math::{scaling, translation, view_transform};
use rayforge::raster::{self, RasterOptions};
use rayforge::{
    point, vector, Camera, Canvas, Color, Light, LightingModel, Material, Object, World,
};

fn camera() -> Camera {
    Camera::new(48, 48, 0.8).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ))
}

/// A matte sphere and a smaller one beside it, lit by a dim light: the raw matte light is a
/// few thousandths, which only the exposure brings up to a visible image.
fn world(second: Material) -> World {
    let matte = Material {
        color: Color::new(0.9, 0.6, 0.3),
        ..Material::DEFAULT
    };
    World {
        objects: vec![
            Object::sphere().with_material(matte),
            Object::sphere()
                .with_transform(translation(1.6, 0.8, -0.5) * scaling(0.4, 0.4, 0.4))
                .with_material(second),
        ],
        lights: vec![Light::point(
            point(-4.0, 5.0, -6.0),
            Color::new(0.2, 0.2, 0.2),
        )],
        lighting: LightingModel::Optics,
        ..World::default()
    }
}

fn rasterized(world: &World) -> Canvas {
    let options = RasterOptions {
        sphere_divisions: 128,
        ..RasterOptions::default()
    };
    raster::render(&camera(), world, &options).expect("within the triangle budget")
}

fn brightest(canvas: &Canvas) -> f64 {
    canvas
        .pixels()
        .iter()
        .map(|c| c.max_channel())
        .fold(0.0, f64::max)
}

#[test]
fn the_optics_model_rasterizes_as_the_ray_tracer_traces_matte_solids() {
    let w = world(Material {
        color: Color::new(0.3, 0.5, 0.9),
        ..Material::DEFAULT
    });
    let traced = camera().render(&w);
    let drawn = rasterized(&w);
    // Both exposed: the brightest channel is full.
    assert_eq!(brightest(&traced), 1.0);
    assert_eq!(brightest(&drawn), 1.0);
    // Away from the silhouettes (where the tessellation differs by a pixel) every channel
    // agrees within two steps of 255: the same matte term, exposed the same way.
    let mut compared = 0;
    for y in 1..47 {
        for x in 1..47 {
            let inside = |c: &Canvas| {
                (-1..=1).all(|dy: i64| {
                    (-1..=1).all(|dx: i64| {
                        let p = c.pixel_at((x as i64 + dx) as usize, (y as i64 + dy) as usize);
                        p != Color::BLACK
                    })
                })
            };
            if !(inside(&traced) && inside(&drawn)) {
                continue;
            }
            let (a, b) = (traced.pixel_at(x, y), drawn.pixel_at(x, y));
            for (p, q) in a.to_array().into_iter().zip(b.to_array()) {
                assert!(
                    (p - q).abs() <= 2.0 / 255.0 + 1e-12,
                    "({x}, {y}): {a:?} vs {b:?}"
                );
            }
            compared += 1;
        }
    }
    assert!(compared > 250, "{compared}");
}

#[test]
fn gloss_needs_rays_the_rasterizer_does_not_cast() {
    // A glossy second sphere would mirror the first in the ray tracer; rasterized, it shows its
    // matte part only, exactly as without gloss.
    let glossy = Material {
        color: Color::new(0.3, 0.5, 0.9),
        gloss: Color::new(0.8, 0.8, 0.8),
        ..Material::DEFAULT
    };
    let plain = Material {
        gloss: Color::BLACK,
        ..glossy.clone()
    };
    assert_eq!(rasterized(&world(glossy)), rasterized(&world(plain)));
}

#[test]
fn opacity_scales_the_matte_light() {
    // Half opaque, the second sphere sends back half the matte light of an opaque one (its
    // transparent half would need a refracted ray). It is greyer than the first sphere, which
    // sets the exposure of both images alike.
    let grey = Material {
        color: Color::new(0.5, 0.5, 0.5),
        ..Material::DEFAULT
    };
    let opaque = rasterized(&world(grey.clone()));
    let half = rasterized(&world(Material {
        opacity: 0.5,
        ..grey
    }));
    let mut compared = 0;
    for y in 0..48 {
        // The second sphere lies right of column 38.
        for x in 39..48 {
            let (a, b) = (opaque.pixel_at(x, y), half.pixel_at(x, y));
            if a == Color::BLACK {
                continue;
            }
            // Exposure truncates to steps of 1/255: half of a step may be lost.
            assert!((b.red - a.red / 2.0).abs() <= 1.0 / 255.0, "{a:?} vs {b:?}");
            compared += 1;
        }
    }
    assert!(compared > 30, "{compared}");
}

#[test]
fn under_the_optics_model_a_solid_is_lit_only_from_outside() {
    // The eye and the light inside a large sphere: its inner surface faces away from its
    // outward normal, which the model lights by, so it stays dark, as the ray tracer draws it.
    // Under Phong the rasterizer lights the side that faces the eye.
    let room = Object::sphere().with_transform(scaling(10.0, 10.0, 10.0));
    let mut w = World {
        objects: vec![room],
        lights: vec![Light::point(point(0.0, 2.0, -2.0), Color::WHITE)],
        lighting: LightingModel::Optics,
        ..World::default()
    };
    let optics = rasterized(&w);
    assert!(optics.pixels().iter().all(|&c| c == Color::BLACK));
    assert!(camera()
        .render(&w)
        .pixels()
        .iter()
        .all(|&c| c == Color::BLACK));
    w.lighting = LightingModel::Phong;
    assert!(brightest(&rasterized(&w)) > 0.1);
}
