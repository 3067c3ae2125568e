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

/// Computer Graphics from Scratch's lights under the Phong model.
#[test]
fn an_ambient_light_adds_only_the_ambient_term() {
    let m = rayforge::Material::default();
    let object = rayforge::Object::sphere();
    let light = rayforge::Light::Ambient(rayforge::color::color(0.5, 0.5, 0.5));
    let c = rayforge::lighting(
        &m,
        &object,
        &light,
        rayforge::point(0.0, 0.0, -1.0),
        rayforge::vector(0.0, 0.0, -1.0),
        rayforge::vector(0.0, 0.0, -1.0),
        1.0,
    );
    // colour 1 × intensity 0.5 × ambient 0.1
    assert!(
        (c.red - 0.05).abs() < 1e-12 && c.red == c.green && c.green == c.blue,
        "{c:?}"
    );
}

#[test]
fn a_directional_light_shades_like_a_point_light_infinitely_far_away() {
    let m = rayforge::Material::default();
    let object = rayforge::Object::sphere();
    let eye = rayforge::vector(0.0, 0.0, -1.0);
    let normal = rayforge::vector(0.0, 0.0, -1.0);
    let p = rayforge::point(0.0, 0.0, -1.0);
    let directional = rayforge::Light::Directional(rayforge::shading::DirectionalLight {
        towards: rayforge::vector(0.0, 3.0, -3.0),
        intensity: rayforge::Color::WHITE,
    });
    let far = rayforge::Light::point(rayforge::point(0.0, 1e9, -1e9), rayforge::Color::WHITE);
    let a = rayforge::lighting(&m, &object, &directional, p, eye, normal, 1.0);
    let b = rayforge::lighting(&m, &object, &far, p, eye, normal, 1.0);
    assert!((a.red - b.red).abs() < 1e-6, "{a:?} vs {b:?}");
    // 0.1 ambient + 0.9·cos 45° diffuse, no highlight towards the eye.
    assert!(
        (a.red - (0.1 + 0.9 * std::f64::consts::FRAC_1_SQRT_2)).abs() < 1e-4,
        "{a:?}"
    );
}

/// Computer Graphics from Scratch's intensity with every light visible (the rasterizer's).
#[test]
fn the_unshadowed_cgfs_intensity_sums_ambient_diffuse_and_specular() {
    use rayforge::shading::unshadowed_intensity;
    use rayforge::shading::DirectionalLight;
    let lights = [
        Light::Ambient(color(0.2, 0.2, 0.2)),
        Light::Directional(DirectionalLight {
            towards: rayforge::vector(0.0, 2.0, 0.0),
            intensity: color(0.5, 0.5, 0.5),
        }),
    ];
    let up = rayforge::vector(0.0, 1.0, 0.0);
    // Matte: 0.2 + 0.5 · (n·l / |n||l|) = 0.7.
    let matte = unshadowed_intensity(&lights, point(0.0, 0.0, 0.0), up, up, -1.0);
    assert!((matte.red - 0.7).abs() < 1e-12, "{matte:?}");
    // Seen along the mirror direction, a shiny surface adds 0.5 · 1^s.
    let shiny = unshadowed_intensity(&lights, point(0.0, 0.0, 0.0), up, up, 10.0);
    assert!((shiny.red - 1.2).abs() < 1e-12, "{shiny:?}");
}
