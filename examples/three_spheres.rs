//! Builds chapter 7's scene in Rust code with the book's API and renders it to `three_spheres.ppm`.
//!
//! Scene data from *The Ray Tracer Challenge* (Jamis Buck), chapter 7, "Putting It Together".
//! Run with `cargo run --release -p rayforge --example three_spheres`.

use rayforge::math::{rotation_x, rotation_y, scaling, translation, view_transform};
use rayforge::{point, vector, Camera, Color, Light, Material, Object, World};
use std::f64::consts::FRAC_PI_2 as HALF_PI;
use std::f64::consts::FRAC_PI_3;
use std::f64::consts::FRAC_PI_4;

fn main() -> std::io::Result<()> {
    let wall = Material {
        color: Color::new(1.0, 0.9, 0.9),
        specular: 0.0,
        ..Material::DEFAULT
    };
    let floor = Object::sphere()
        .with_transform(scaling(10.0, 0.01, 10.0))
        .with_material(wall.clone());
    let left_wall = Object::sphere()
        .with_transform(
            translation(0.0, 0.0, 5.0)
                * rotation_y(-FRAC_PI_4)
                * rotation_x(HALF_PI)
                * scaling(10.0, 0.01, 10.0),
        )
        .with_material(wall.clone());
    let right_wall = Object::sphere()
        .with_transform(
            translation(0.0, 0.0, 5.0)
                * rotation_y(FRAC_PI_4)
                * rotation_x(HALF_PI)
                * scaling(10.0, 0.01, 10.0),
        )
        .with_material(wall);
    let sphere = |transform, color| {
        Object::sphere()
            .with_transform(transform)
            .with_material(Material {
                color,
                diffuse: 0.7,
                specular: 0.3,
                ..Material::DEFAULT
            })
    };
    let world = World {
        objects: vec![
            floor,
            left_wall,
            right_wall,
            sphere(translation(-0.5, 1.0, 0.5), Color::new(0.1, 1.0, 0.5)),
            sphere(
                translation(1.5, 0.5, -0.5) * scaling(0.5, 0.5, 0.5),
                Color::new(0.5, 1.0, 0.1),
            ),
            sphere(
                translation(-1.5, 0.33, -0.75) * scaling(0.33, 0.33, 0.33),
                Color::new(1.0, 0.8, 0.1),
            ),
        ],
        lights: vec![Light::point(point(-10.0, 10.0, -10.0), Color::WHITE)],
        background: Color::BLACK,
        ..World::default()
    };
    let camera = Camera::new(400, 200, FRAC_PI_3).with_transform(view_transform(
        point(0.0, 1.5, -5.0),
        point(0.0, 1.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let canvas = camera.render(&world);
    std::fs::write("three_spheres.ppm", canvas.to_ppm())?;
    println!(
        "wrote three_spheres.ppm ({}×{})",
        canvas.width(),
        canvas.height()
    );
    Ok(())
}
