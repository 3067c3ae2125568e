//! Fundamentals of Ray Tracing's optics model and the containment it relies on.
use rayforge::math::{scaling, translation};
use rayforge::scene::WorldIndex;
use rayforge::{
    point, vector, Color, CsgOperation, Light, LightingModel, Material, Object, Ray, Shape, Tracer,
    World,
};

fn optics_world(objects: Vec<Object>, lights: Vec<Light>) -> World {
    World {
        objects,
        lights,
        lighting: LightingModel::Optics,
        ..World::default()
    }
}

fn color_at(world: &World, ray: &Ray) -> Color {
    let index = WorldIndex::build(world);
    Tracer::new(world, &index).color_at(ray, 20)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn matte_light_falls_off_with_the_square_of_the_distance() {
    for d in [4.0, 9.0, 19.0] {
        let world = optics_world(
            vec![Object::sphere()],
            vec![Light::point(point(0.0, 0.0, -1.0 - d), Color::WHITE)],
        );
        let c = color_at(
            &world,
            &Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0)),
        );
        assert!(close(c.red, 1.0 / (d * d)), "at {d}: {c:?}");
    }
}

#[test]
fn matte_light_goes_with_the_cosine_of_incidence_and_the_light_colour() {
    let world = optics_world(
        vec![Object::plane().with_material(Material {
            color: Color::new(1.0, 0.5, 0.25),
            ..Material::default()
        })],
        vec![Light::point(
            point(3.0, 4.0, 0.0),
            Color::new(1.0, 1.0, 2.0),
        )],
    );
    let c = color_at(
        &world,
        &Ray::new(point(0.0, 1.0, 0.0), vector(0.0, -1.0, 0.0)),
    );
    // n·l̂ = 4/5, d² = 25.
    let k = 0.8 / 25.0;
    assert!(
        close(c.red, k) && close(c.green, 0.5 * k) && close(c.blue, 0.5 * k),
        "{c:?}"
    );
}

#[test]
fn gloss_reflects_one_mirror_ray() {
    // A mirror (gloss 1, no matte) facing a lit matte sphere shows the sphere.
    let mirror = Object::plane().with_material(Material {
        color: Color::BLACK,
        gloss: Color::WHITE,
        ..Material::default()
    });
    let ball = Object::sphere().with_transform(translation(0.0, 3.0, 0.0));
    let world = optics_world(
        vec![mirror, ball],
        vec![Light::point(point(0.0, 3.0, -5.0), Color::WHITE)],
    );
    // Down at 45° onto the mirror, bouncing to the ball's front.
    let seen_in_mirror = color_at(
        &world,
        &Ray::new(point(0.0, 3.0, -6.0), vector(0.0, -1.0, 1.0).normalize()),
    );
    let direct = color_at(
        &world,
        &Ray::new(point(0.0, 3.0, -6.0), vector(0.0, 0.0, 1.0)),
    );
    assert!(direct.red > 0.0);
    assert!(seen_in_mirror.red > 0.0, "{seen_in_mirror:?}");
}

#[test]
fn a_clear_solid_reflects_four_percent_head_on_and_lets_the_rest_through() {
    // Glass of index 1.5 in front of a white matte wall lit from the camera's side; looking
    // straight through the glass: at each face Fresnel keeps ((1.5 - 1)/(1.5 + 1))² = 4 %.
    let glass = Object::sphere().with_material(Material {
        opacity: 0.0,
        refractive_index: 1.5,
        ..Material::default()
    });
    let wall = Object::plane().with_transform(
        translation(0.0, 0.0, 5.0) * rayforge::math::rotation_x(-std::f64::consts::FRAC_PI_2),
    );
    let light = Light::point(point(0.0, 0.0, 4.0), Color::WHITE);
    let without = optics_world(vec![wall.clone()], vec![light.clone()]);
    let with = optics_world(vec![glass, wall], vec![light]);
    let ray = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let through = color_at(&with, &ray).red;
    let bare = color_at(&without, &ray).red;
    // The light sits between glass and wall (transparent solids cast full shadows). Two faces
    // each pass 96 %; the 4 % reflected back inside at the far face returns 4 % of itself at
    // the near one, and so on; the second round trip carries 0.96·0.04⁴ < 0.001 of the light
    // and is cut off: 0.96² · (1 + 0.04²).
    assert!(
        close(through, bare * 0.96 * 0.96 * (1.0 + 0.04 * 0.04)),
        "{through} vs {bare}"
    );
}

#[test]
fn containment_answers_for_each_solid() {
    let sphere = Object::sphere().with_transform(scaling(2.0, 2.0, 2.0));
    assert!(sphere.contains(point(1.9, 0.0, 0.0)));
    assert!(!sphere.contains(point(2.1, 0.0, 0.0)));
    let torus = Object::new(Shape::Torus {
        major: 3.0,
        minor: 1.0,
    });
    assert!(torus.contains(point(3.5, 0.0, 0.0)));
    assert!(!torus.contains(point(0.0, 0.0, 0.0)), "the hole");
    let cube = Object::cube();
    assert!(cube.contains(point(0.9, -0.9, 0.9)));
    assert!(!cube.contains(point(1.1, 0.0, 0.0)));
    let bitten = Object::csg(
        CsgOperation::Difference,
        Object::sphere(),
        Object::sphere().with_transform(translation(1.0, 0.0, 0.0)),
    )
    .unwrap();
    assert!(bitten.contains(point(-0.5, 0.0, 0.0)));
    assert!(!bitten.contains(point(0.5, 0.0, 0.0)), "in the bite");
}

#[test]
fn the_medium_beyond_a_surface_is_the_first_solid_that_contains_it() {
    // A glass ball (1.5) inside a water ball (1.33) added first: leaving the glass into the
    // water bends less than leaving it into air would. Compare where a slanted ray lands.
    let water = Object::sphere()
        .with_transform(scaling(3.0, 3.0, 3.0))
        .with_material(Material {
            opacity: 0.0,
            refractive_index: 1.33,
            ..Material::default()
        });
    let glass = Object::sphere().with_material(Material {
        opacity: 0.0,
        refractive_index: 1.5,
        ..Material::default()
    });
    let water_first = optics_world(vec![water.clone(), glass.clone()], vec![]);
    let only_glass = optics_world(vec![glass], vec![]);
    // Both scenes are black without lights; the model must still run through containment
    // without panicking or recursing forever (depth 20, intensity cut-off).
    let ray = Ray::new(point(0.3, 0.2, -5.0), vector(0.0, 0.0, 1.0));
    assert_eq!(color_at(&water_first, &ray), Color::BLACK);
    assert_eq!(color_at(&only_glass, &ray), Color::BLACK);
}

/// The polyhedra: exact vertex sets, every edge the same length, every face facing out.
fn check_polyhedron(mesh: &rayforge::geometry::Mesh, vertices: usize, triangles: usize, edge: f64) {
    assert_eq!(mesh.positions().len(), vertices);
    assert_eq!(mesh.faces().len(), triangles);
    let object = Object::mesh(std::sync::Arc::new(mesh.clone()));
    for (i, face) in mesh.faces().enumerate() {
        let [a, b, c] = face.vertices.map(|v| mesh.positions()[v as usize]);
        let centre = (a + b + c) / 3.0;
        let hit = rayforge::geometry::LocalHit {
            face: i as u32,
            ..Default::default()
        };
        let normal = object.normal_at_local_hit(centre, &hit);
        assert!(normal.dot(centre) > 0.0, "face {i} faces in");
    }
    // Each vertex has neighbours at exactly the edge length and none nearer.
    for p in mesh.positions() {
        let nearest = mesh
            .positions()
            .iter()
            .filter(|q| (**q - *p).length() > 1e-9)
            .map(|q| (*q - *p).length())
            .fold(f64::INFINITY, f64::min);
        assert!(close(nearest, edge), "{nearest} vs {edge}");
    }
}

#[test]
fn the_icosahedron_has_twelve_vertices_and_twenty_faces() {
    check_polyhedron(&rayforge::geometry::icosahedron(), 12, 20, 2.0);
}

#[test]
fn the_dodecahedron_has_twenty_vertices_and_twelve_pentagons() {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    check_polyhedron(&rayforge::geometry::dodecahedron(), 20, 36, 2.0 / phi);
}

#[test]
fn a_thin_ring_is_hit_between_its_radii_and_holds_nothing() {
    let ring = Object::new(Shape::Ring {
        inner: 1.0,
        outer: 2.0,
    });
    let down = |x: f64| Ray::new(point(x, 5.0, 0.0), vector(0.0, -1.0, 0.0));
    assert!(ring.intersections(&down(0.5)).is_empty(), "the hole");
    assert_eq!(ring.intersections(&down(1.5)).len(), 1);
    assert!(ring.intersections(&down(2.5)).is_empty());
    assert!(!ring.contains(point(1.5, -1.0, 0.0)));
    assert!(!ring.contains(point(1.5, 0.0, 0.0)));
}

#[test]
fn a_thin_ring_is_lit_on_the_side_the_light_is() {
    // Lit from above, seen from above: bright; seen from below: the matte term is zero (the
    // light is on the other side of the surface).
    let ring = Object::new(Shape::Ring {
        inner: 0.0,
        outer: 2.0,
    });
    let world = optics_world(
        vec![ring],
        vec![Light::point(point(0.0, 3.0, 0.0), Color::WHITE)],
    );
    let above = color_at(
        &world,
        &Ray::new(point(0.0, 1.0, 0.5), vector(0.0, -1.0, 0.0)),
    );
    let below = color_at(
        &world,
        &Ray::new(point(0.0, -1.0, 0.5), vector(0.0, 1.0, 0.0)),
    );
    assert!(above.red > 0.0, "{above:?}");
    assert_eq!(below, Color::BLACK);
}

#[test]
fn the_surface_of_a_bite_faces_out_of_the_solid() {
    // A unit sphere with a bite (a sphere at x = 1.2) taken out, lit from +x: the bite's
    // surface is the inside of the smaller sphere, but it faces out of the solid, towards the
    // light, so the matte term lights it. Looking into the bite along -x.
    use rayforge::math::translation;
    let bitten = Object::csg(
        CsgOperation::Difference,
        Object::sphere(),
        Object::sphere().with_transform(translation(1.2, 0.0, 0.0)),
    )
    .unwrap();
    let world = optics_world(
        vec![bitten],
        vec![Light::point(point(5.0, 0.0, 0.0), Color::WHITE)],
    );
    let c = color_at(
        &world,
        &Ray::new(point(5.0, 0.0, 0.0), vector(-1.0, 0.0, 0.0)),
    );
    // The bite's deepest point is at x = 0.2, facing +x: n·l̂ = 1, d = 4.8.
    assert!(close(c.red, 1.0 / (4.8 * 4.8)), "{c:?}");
}
