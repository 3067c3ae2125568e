//! Motion blur (chapter 17's "next steps"): a shutter interval on the camera, objects that move
//! while it is open, each ray cast at its own instant.

use rayforge::math::{rotation_y, scaling, translation, Motion};
use rayforge::render::{render, RenderOptions, Sampling};
use rayforge::{
    point, vector, Camera, Color, Group, Light, Material, Object, Ray, Transform, World,
};
use std::f64::consts::FRAC_PI_2;

fn close(a: glam::DVec3, b: glam::DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn a_motion_starts_and_ends_at_its_two_transforms() {
    let start = Transform::new(translation(1.0, 2.0, 3.0));
    let end = Transform::new(translation(5.0, 2.0, 3.0) * rotation_y(1.0));
    let motion = Motion::new(start, end);
    assert_eq!(motion.at(0.0), start);
    assert_eq!(motion.at(1.0), end);
    // Times outside the interval hold the nearer end.
    assert_eq!(motion.at(-3.0), start);
    assert_eq!(motion.at(7.0), end);
}

#[test]
fn a_translation_is_interpolated_linearly() {
    let motion = Motion::new(
        Transform::new(translation(0.0, 0.0, 0.0)),
        Transform::new(translation(4.0, -2.0, 0.0)),
    );
    let p = motion.at(0.25).point(point(0.0, 0.0, 0.0));
    assert!(close(p, point(1.0, -0.5, 0.0)), "{p:?}");
}

#[test]
fn a_rotation_turns_without_shrinking() {
    // Averaging the matrices of 0° and 90° would put (1, 0, 0) at (0.5, 0, -0.5), at distance
    // 0.71 from the axis; the decomposed motion turns it by 45°.
    let motion = Motion::new(Transform::IDENTITY, Transform::new(rotation_y(FRAC_PI_2)));
    let p = motion.at(0.5).point(point(1.0, 0.0, 0.0));
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(close(p, point(h, 0.0, -h)), "{p:?}");
}

#[test]
fn a_spin_about_an_objects_own_centre_keeps_the_centre_still() {
    let at = translation(3.0, 0.0, 0.0);
    let motion = Motion::new(
        Transform::new(at * scaling(2.0, 1.0, 1.0)),
        Transform::new(at * rotation_y(FRAC_PI_2) * scaling(2.0, 1.0, 1.0)),
    );
    for i in 0..=10 {
        let t = i as f64 / 10.0;
        let centre = motion.at(t).point(point(0.0, 0.0, 0.0));
        assert!(close(centre, point(3.0, 0.0, 0.0)), "at {t}: {centre:?}");
        // The stretched axis keeps its length as it turns.
        let tip = motion.at(t).point(point(1.0, 0.0, 0.0)) - centre;
        assert!((tip.length() - 2.0).abs() < 1e-9, "at {t}: {tip:?}");
    }
}

/// A motion between fixed transforms interpolates only its middle: an off-centre point of
/// an instance turning about its origin swings along the arc (staying at its distance),
/// where interpolating the products would cut the chord; its own inner placement rides
/// along, and the bounds still cover every instant.
#[test]
fn a_motion_between_fixed_transforms_interpolates_only_the_middle() {
    let inner = Transform::new(translation(2.0, 0.0, 0.0) * scaling(0.5, 0.5, 0.5));
    let outer = Transform::new(translation(0.0, 3.0, 0.0) * scaling(2.0, 1.0, 1.0));
    let (start, end) = (Transform::IDENTITY, Transform::new(rotation_y(FRAC_PI_2)));
    let motion = Motion::after(&start, &end, &inner).unwrap();
    assert_eq!(motion.at(0.0), start.then_after(&inner).unwrap());
    assert_eq!(motion.at(1.0), end.then_after(&inner).unwrap());
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let mid = motion.at(0.5).point(point(0.0, 0.0, 0.0));
    assert!(close(mid, point(2.0 * h, 0.0, -2.0 * h)), "{mid:?}");
    // The products' interpolation would put it on the chord, nearer the axis.
    let chord = Motion::new(
        start.then_after(&inner).unwrap(),
        end.then_after(&inner).unwrap(),
    );
    let cut = chord.at(0.5).point(point(0.0, 0.0, 0.0));
    assert!(cut.length() < 1.9, "{cut:?}");
    let placed = motion.placed_by(&outer).unwrap();
    let p = placed.at(0.5).point(point(0.0, 0.0, 0.0));
    assert!(close(p, point(4.0 * h, 3.0, -2.0 * h)), "{p:?}");
    assert_eq!(placed.at(1.0), outer.then_after(&motion.at(1.0)).unwrap());
    let local = rayforge::math::Aabb::new(point(-1.0, -1.0, -1.0), point(1.0, 1.0, 1.0));
    let bounds = placed.bounds(&local);
    for i in 0..=200 {
        let at = placed.at(i as f64 / 200.0);
        for corner in [
            point(-1.0, -1.0, -1.0),
            point(1.0, 1.0, 1.0),
            point(1.0, -1.0, 1.0),
        ] {
            let q = at.point(corner);
            assert!(
                bounds.min.cmple(q).all() && q.cmple(bounds.max).all(),
                "{q:?} {bounds:?}"
            );
        }
    }
}

#[test]
fn a_scale_is_interpolated_linearly() {
    let motion = Motion::new(
        Transform::new(scaling(1.0, 1.0, 1.0)),
        Transform::new(scaling(3.0, 3.0, 3.0)),
    );
    let p = motion.at(0.5).point(point(1.0, 1.0, 1.0));
    assert!(close(p, point(2.0, 2.0, 2.0)), "{p:?}");
}

#[test]
fn the_bounds_of_a_moving_object_cover_its_whole_path() {
    let object = Object::cube().placed_by_moving(
        &Transform::new(translation(0.0, 0.0, 0.0)),
        &Transform::new(translation(10.0, 0.0, 0.0) * rotation_y(2.5) * scaling(1.0, 2.0, 0.5)),
    );
    let object = object.unwrap();
    let bounds = object.bounds();
    let motion = object.motion.as_ref().expect("it moves");
    for i in 0..=1000 {
        let t = i as f64 / 1000.0;
        let at = rayforge::math::Aabb::new(point(-1.0, -1.0, -1.0), point(1.0, 1.0, 1.0))
            .transform(&motion.at(t));
        assert!(
            bounds.contains_box(&at),
            "at {t}: {at:?} is outside {bounds:?}"
        );
    }
    // And they are not absurdly large.
    assert!(bounds.max.x < 12.5 && bounds.min.x > -1.5, "{bounds:?}");
}

#[test]
fn a_ray_meets_a_moving_sphere_where_it_is_at_the_rays_instant() {
    let sphere = Object::sphere()
        .placed_by_moving(
            &Transform::IDENTITY,
            &Transform::new(translation(4.0, 0.0, 0.0)),
        )
        .unwrap();
    let ray =
        |x: f64, time: f64| Ray::new(point(x, 0.0, -5.0), vector(0.0, 0.0, 1.0)).at_time(time);
    assert_eq!(sphere.intersections(&ray(0.0, 0.0)).len(), 2);
    assert!(sphere.intersections(&ray(0.0, 1.0)).is_empty());
    assert_eq!(sphere.intersections(&ray(2.0, 0.5)).len(), 2);
    assert_eq!(sphere.intersections(&ray(4.0, 1.0)).len(), 2);
    // The normal is taken where the sphere is at the hit's instant.
    let xs = sphere.intersections(&ray(2.0, 0.5));
    let hit = xs.iter().min_by(|a, b| a.t.total_cmp(&b.t)).unwrap();
    let p = ray(2.0, 0.5).position(hit.t);
    assert!(close(sphere.normal_at_hit(p, hit), vector(0.0, 0.0, -1.0)));
}

#[test]
fn a_moving_group_moves_its_children() {
    let mut group = Group::new();
    group.add_child(Object::sphere().with_transform(translation(0.0, 1.0, 0.0)));
    group.motion_end = Some(Transform::new(translation(3.0, 0.0, 0.0)));
    let objects = group.flatten().unwrap();
    let ray =
        |x: f64, time: f64| Ray::new(point(x, 1.0, -5.0), vector(0.0, 0.0, 1.0)).at_time(time);
    assert_eq!(objects[0].intersections(&ray(0.0, 0.0)).len(), 2);
    assert_eq!(objects[0].intersections(&ray(3.0, 1.0)).len(), 2);
    assert!(objects[0].intersections(&ray(3.0, 0.0)).is_empty());
}

/// A white sphere sliding from x = -1.5 to x = 1.5 in front of a black background.
fn sliding_sphere(shutter: (f64, f64)) -> (World, Camera) {
    let sphere = Object::sphere()
        .with_material(Material {
            ambient: 1.0,
            diffuse: 0.0,
            specular: 0.0,
            ..Material::DEFAULT
        })
        .placed_by_moving(
            &Transform::new(translation(-1.5, 0.0, 0.0) * scaling(0.5, 0.5, 0.5)),
            &Transform::new(translation(1.5, 0.0, 0.0) * scaling(0.5, 0.5, 0.5)),
        )
        .unwrap();
    let world = World {
        objects: vec![sphere],
        lights: vec![Light::point(point(0.0, 0.0, -10.0), Color::WHITE)],
        background: Color::BLACK,
        ..World::default()
    };
    let camera = Camera::new(41, 11, 1.2)
        .with_transform(rayforge::math::view_transform(
            point(0.0, 0.0, -5.0),
            point(0.0, 0.0, 0.0),
            vector(0.0, 1.0, 0.0),
        ))
        .with_shutter(shutter.0, shutter.1);
    (world, camera)
}

fn middle_row(world: &World, camera: &Camera, sampling: Sampling) -> Vec<f64> {
    let options = RenderOptions {
        sampling,
        ..RenderOptions::default()
    };
    let (canvas, _) = render(camera, world, &options);
    (0..canvas.width())
        .map(|x| canvas.pixel_at(x, canvas.height() / 2).red)
        .collect()
}

#[test]
fn one_sample_per_pixel_shows_the_object_half_way_through_the_shutter() {
    let (world, camera) = sliding_sphere((0.0, 1.0));
    let row = middle_row(&world, &camera, Sampling::Centre);
    assert_eq!(row[20], 1.0, "the sphere is at the centre at time 0.5");
    assert_eq!(row[2], 0.0);
    assert_eq!(row[38], 0.0);
}

#[test]
fn many_samples_smear_a_moving_object_along_its_path() {
    let (world, camera) = sliding_sphere((0.0, 1.0));
    let row = middle_row(&world, &camera, Sampling::Stratified { per_side: 8 });
    // Along the whole path the sphere covers each point for only part of the shutter time:
    // intermediate values everywhere between the two ends, no pixel fully white.
    let streak: Vec<f64> = row[10..31].to_vec();
    assert!(streak.iter().all(|&v| v > 0.05 && v < 0.8), "{row:?}");
    assert_eq!(row[0], 0.0);
    assert_eq!(row[40], 0.0);
}

#[test]
fn a_closed_shutter_interval_freezes_the_motion() {
    let (world, camera) = sliding_sphere((0.0, 0.0));
    let row = middle_row(&world, &camera, Sampling::Stratified { per_side: 4 });
    // At time 0 the sphere is at x = -1.5: sharp, white at its centre, nothing at x = 0.
    let centre_at_start = row.iter().position(|&v| v == 1.0).expect("a sharp sphere");
    assert!(centre_at_start < 16, "{row:?}");
    assert_eq!(row[20], 0.0);
    assert!(row.iter().all(|&v| v == 0.0 || v > 0.2), "{row:?}");
}

#[test]
fn a_moving_object_casts_its_shadow_where_it_is_at_the_instant() {
    // The blocker is between the light and the point at time 0 and has moved away at time 1.
    let blocker = Object::sphere()
        .placed_by_moving(
            &Transform::new(translation(0.0, 5.0, 0.0)),
            &Transform::new(translation(10.0, 5.0, 0.0)),
        )
        .unwrap();
    let world = World {
        objects: vec![blocker],
        lights: vec![Light::point(point(0.0, 10.0, 0.0), Color::WHITE)],
        background: Color::BLACK,
        ..World::default()
    };
    let index = rayforge::scene::WorldIndex::build(&world);
    let mut tracer = rayforge::Tracer::new(&world, &index);
    assert!(tracer.is_shadowed_at(point(0.0, 10.0, 0.0), point(0.0, 0.0, 0.0), 0.0));
    assert!(!tracer.is_shadowed_at(point(0.0, 10.0, 0.0), point(0.0, 0.0, 0.0), 1.0));
}
