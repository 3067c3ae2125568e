//! Adaptive depth control and the shadow cache: speed-ups that must not change what the book's
//! model computes beyond what an 8-bit pixel can show (the bailout) or at all (the cache).
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::math::{scaling, translation};
use rayforge::scene::WorldIndex;
use rayforge::{point, vector, Color, Light, Material, Object, Point3, Ray, Tracer, World};

/// Two facing mirrors that reflect a tenth of the light, a lamp, and a sphere between them:
/// every camera ray bounces between the mirrors until the depth runs out.
fn hall_of_faint_mirrors() -> World {
    let mirror = Material {
        color: color(0.8, 0.8, 0.9),
        reflective: 0.1,
        ..Material::default()
    };
    let mut w = World::new();
    w.lights
        .push(Light::point(point(0.0, 5.0, 0.0), Color::WHITE));
    for z in [-5.0, 5.0] {
        w.objects.push(
            Object::cube()
                .with_transform(translation(0.0, 0.0, z) * scaling(10.0, 10.0, 0.1))
                .with_material(mirror.clone()),
        );
    }
    w.objects.push(Object::sphere().with_material(Material {
        reflective: 0.1,
        ..Material::default()
    }));
    w
}

fn trace(world: &World, bailout: f64, ray: &Ray, depth: u32) -> (Color, u64) {
    let index = WorldIndex::build(world);
    let mut tracer = Tracer::new(world, &index);
    tracer.set_bailout(bailout);
    let c = tracer.color_at(ray, depth);
    (c, tracer.rays_cast())
}

/// What the bailout leaves out only darkens, and by less than the bailout, in every channel.
fn assert_darker_by_less_than_the_bailout(exact: Color, quick: Color) {
    for (a, b) in [
        (exact.red, quick.red),
        (exact.green, quick.green),
        (exact.blue, quick.blue),
    ] {
        assert!(a >= b && a - b < 1.0 / 512.0, "{exact:?} vs {quick:?}");
    }
}

#[test]
fn without_a_bailout_every_bounce_up_to_the_depth_is_traced() {
    let w = hall_of_faint_mirrors();
    let ray = Ray::new(point(3.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let (_, shallow) = trace(&w, 0.0, &ray, 2);
    let (_, deep) = trace(&w, 0.0, &ray, 10);
    // Each bounce adds a reflected ray and its shadow ray.
    assert_eq!(deep - shallow, 8 * 2);
}

#[test]
fn rays_below_the_bailout_are_not_traced_and_change_the_colour_by_less_than_it() {
    let w = hall_of_faint_mirrors();
    let ray = Ray::new(point(3.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let (exact, all) = trace(&w, 0.0, &ray, 10);
    let (quick, fewer) = trace(&w, 1.0 / 512.0, &ray, 10);
    // 0.1² is above 1/512, 0.1³ below: the camera ray and two bounces, each with its shadow ray.
    assert_eq!(fewer, 3 * 2);
    assert!(fewer < all);
    assert_darker_by_less_than_the_bailout(exact, quick);
}

#[test]
fn the_bailout_leaves_strong_reflections_alone() {
    // A half-mirror's reflections weigh 0.5, 0.25, …: with the bailout at 1/512, eight bounces
    // are still traced.
    let mut w = hall_of_faint_mirrors();
    for o in &mut w.objects {
        o.material.reflective = 0.5;
    }
    let ray = Ray::new(point(3.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let (exact, _) = trace(&w, 0.0, &ray, 8);
    let (quick, _) = trace(&w, 1.0 / 512.0, &ray, 8);
    assert_eq!(exact, quick);
}

/// Shadow rays try the last blocker of their light first: the answer never changes, whatever
/// the order of the points (in and out of shadows, from light to light).
#[test]
fn remembering_the_last_blocker_never_changes_a_shadow() {
    let mut w = World::new();
    w.lights
        .push(Light::point(point(-10.0, 10.0, -10.0), Color::WHITE));
    w.lights
        .push(Light::point(point(10.0, 8.0, -3.0), Color::WHITE));
    for i in 0..12 {
        let x = (i % 4) as f64 * 2.5 - 4.0;
        let z = (i / 4) as f64 * 2.5 - 2.0;
        w.objects
            .push(Object::sphere().with_transform(translation(x, 1.0, z) * scaling(0.8, 0.8, 0.8)));
    }
    let index = WorldIndex::build(&w);
    let mut tracer = Tracer::new(&w, &index);
    let mut shadowed = 0;
    for k in 0..4000 {
        let a = k as f64 * 0.754_877_666;
        let p: Point3 = point((a * 7.3).sin() * 7.0, 0.0, (a * 3.1).cos() * 6.0);
        for light in &w.lights {
            let cached = tracer.intensity_at(light, p);
            let plain = if w.is_shadowed(light.position(), p) {
                0.0
            } else {
                1.0
            };
            assert_eq!(cached, plain, "point {p:?}");
            shadowed += usize::from(plain == 0.0);
        }
    }
    assert!(shadowed > 500, "the test needs shadows: {shadowed}");
}

/// Lights behind a surface cast no shadow ray (they add only their ambient term, shadowed or
/// not): the colours are those of the book's `lighting` with `is_shadowed` asked for every
/// light, to the bit, and fewer rays are cast.
#[test]
fn lights_behind_the_surface_cast_no_shadow_ray_and_change_nothing() {
    let mut w = World::new();
    w.lights
        .push(Light::point(point(-10.0, 10.0, -10.0), Color::WHITE));
    w.lights
        .push(Light::point(point(10.0, -8.0, 3.0), color(0.3, 0.4, 0.5)));
    w.objects.push(Object::sphere().with_material(Material {
        color: color(0.9, 0.5, 0.2),
        specular: 0.6,
        ..Material::default()
    }));
    w.objects.push(
        Object::sphere().with_transform(translation(-2.0, 2.0, -2.0) * scaling(0.5, 0.5, 0.5)),
    );
    let index = WorldIndex::build(&w);
    let mut tracer = Tracer::new(&w, &index);
    let (mut hits, mut behind) = (0, 0);
    for k in 0..2000 {
        let a = k as f64 * 0.754_877_666;
        let origin = point((a * 7.3).sin() * 6.0, (a * 2.9).cos() * 6.0, -8.0);
        let ray = Ray::new(origin, (point(0.0, 0.0, 0.0) - origin).normalize());
        let xs = w.objects[0].intersections(&ray);
        let Some(h) = rayforge::hit(&xs) else {
            continue;
        };
        hits += 1;
        let comps = rayforge::prepare_computations(h, &ray, &xs);
        let before = tracer.rays_cast();
        let shaded = tracer.shade_hit(&comps, 0);
        let cast = tracer.rays_cast() - before;
        let mut book = Color::BLACK;
        for light in &w.lights {
            let shadowed = w.is_shadowed(light.position(), comps.over_point);
            book += rayforge::book::lighting(
                &comps.surface.material,
                comps.surface,
                light,
                comps.over_point,
                comps.eyev,
                comps.normalv,
                if shadowed { 0.0 } else { 1.0 },
            );
        }
        assert_eq!(shaded, book, "ray {ray:?}");
        behind += w.lights.len() as u64 - cast;
    }
    assert!(
        hits > 1000 && behind > 500,
        "{hits} hits, {behind} lights behind"
    );
}

/// A shadow ray whose light is too faint, at the weight of the ray that hit, to move the pixel
/// by the bailout is not cast either: the light counts as blocked there.
#[test]
fn shadow_rays_too_faint_to_show_are_left_out() {
    let mut w = hall_of_faint_mirrors();
    // At most 0.034 of this light reaches the eye from a mirror: enough for the camera ray
    // (weight 1) and the first bounce (0.1), not the second (0.01: 0.00034 < 1/512).
    w.lights
        .push(Light::point(point(0.0, -5.0, 0.0), color(0.02, 0.02, 0.02)));
    let ray = Ray::new(point(3.0, 0.0, 0.0), vector(0.0, 0.0, 1.0));
    let (exact, _) = trace(&w, 0.0, &ray, 10);
    let (quick, fewer) = trace(&w, 1.0 / 512.0, &ray, 10);
    // Three rays (the camera's and two bounces), each with the lamp's shadow ray, and the
    // faint light's for the first two only.
    assert_eq!(fewer, 3 + 3 + 2);
    assert_darker_by_less_than_the_bailout(exact, quick);
}

/// On glass that both reflects and refracts, Schlick's reflectance is part of each ray's
/// weight: a reflection that brings 4 % of a faint mirror's light is below the bailout, though
/// the mirror's own reflectivity is not.
#[test]
fn the_fresnel_share_counts_in_the_weight_of_glass_rays() {
    let glass = |reflective: f64| {
        let mut w = World::new();
        w.lights
            .push(Light::point(point(-10.0, 10.0, -10.0), Color::WHITE));
        w.objects.push(Object::sphere().with_material(Material {
            reflective,
            transparency: 0.9,
            refractive_index: 1.5,
            ..Material::default()
        }));
        w
    };
    // Head on, Schlick's reflectance is ((1 - 1.5) / (1 + 1.5))² = 0.04.
    let ray = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let faint = glass(0.04); // 0.04 × 0.04 = 0.0016 < 1/512
    let (exact, all) = trace(&faint, 0.0, &ray, 1);
    let (quick, fewer) = trace(&faint, 1.0 / 512.0, &ray, 1);
    assert_eq!(all - fewer, 1, "the reflected ray is left out");
    assert_darker_by_less_than_the_bailout(exact, quick);
    let stronger = glass(0.1); // 0.1 × 0.04 = 0.004 ≥ 1/512
    assert_eq!(
        trace(&stronger, 0.0, &ray, 1).1,
        trace(&stronger, 1.0 / 512.0, &ray, 1).1
    );
}

/// A shadow ray is weighed by how much its light can change the colour, either way: a
/// material that subtracts light (a negative coefficient, which scenes may give) counts by
/// its magnitude.
#[test]
fn a_lights_weight_is_the_most_it_can_change_the_colour() {
    use rayforge::shading::most_light;
    let light = Light::point(point(0.0, 5.0, 0.0), color(0.5, 1.0, 0.25));
    let surface = color(0.8, 0.4, 1.0);
    let plain = Material {
        diffuse: 0.5,
        specular: 0.25,
        ..Material::default()
    };
    // diffuse: the largest of 0.4, 0.4, 0.25, times 0.5; specular: 1.0 × 0.25.
    assert!((most_light(&plain, surface, &light) - 0.45).abs() < 1e-12);
    let darkening = Material {
        diffuse: -0.5,
        specular: -0.25,
        ..plain.clone()
    };
    assert!((most_light(&darkening, surface, &light) - 0.45).abs() < 1e-12);
    assert_eq!(
        most_light(&plain, surface, &Light::Ambient(Color::WHITE)),
        0.0
    );
}
