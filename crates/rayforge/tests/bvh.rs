//! The BVH: queries agree with a linear scan, and degenerate input builds and answers.
use proptest::prelude::*;
use rayforge::accel::{Bvh, NO_PRIMITIVE};
use rayforge::book::BookWorld;
use rayforge::math::{rotation_x, rotation_y, rotation_z, scaling, translation, Aabb};
use rayforge::scene::{WorldIndex, NO_OBJECT};
use rayforge::{hit, point, vector, Object, Ray, Shape, World};
use std::f64::consts::{FRAC_PI_2, PI};
use std::ops::ControlFlow;

fn world_of(objects: &[(u8, (f64, f64, f64), f64)]) -> World {
    let mut w = World::new();
    for &(kind, (x, y, z), size) in objects {
        let shape = match kind % 4 {
            0 => Shape::Sphere,
            1 => Shape::Cube,
            2 => Shape::Cylinder {
                minimum: -1.0,
                maximum: 1.0,
                closed: true,
            },
            _ => Shape::Plane,
        };
        w.objects.push(
            Object::new(shape).with_transform(translation(x, y, z) * scaling(size, size, size)),
        );
    }
    w
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The index finds the same nearest hit as testing every object (to rounding: a world of
    /// few objects finds a round ball's hits in world space, where the scan finds them in the
    /// ball's own).
    #[test]
    fn the_closest_hit_matches_a_linear_scan(
        objects in prop::collection::vec(
            (0u8..4, (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64), 0.1..3.0f64), 1..60),
        origin in (-15.0..15.0f64, -15.0..15.0f64, -15.0..15.0f64),
        direction in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
    ) {
        let d = vector(direction.0, direction.1, direction.2);
        prop_assume!(d.length() > 1e-3);
        let w = world_of(&objects);
        let index = WorldIndex::build(&w);
        let ray = Ray::new(point(origin.0, origin.1, origin.2), d.normalize());
        let expected = hit(&w.intersect(&ray));
        let found = index.closest_hit(&w, &ray);
        match (found, expected) {
            (Some(a), Some(b)) => {
                prop_assert!((a.t - b.t).abs() <= 1e-12 * b.t.abs().max(1.0), "{} against {}", a.t, b.t);
                prop_assert!(std::ptr::eq(a.object, b.object), "another object");
                the_normal_is_the_objects(&w, &index, &ray, &a)?;
            }
            (a, b) => prop_assert_eq!(a.is_some(), b.is_some()),
        }
    }
}

/// The index's normal at a hit (found with less work on flat surfaces and round balls) is
/// the object's own, to rounding.
fn the_normal_is_the_objects(
    w: &World,
    index: &WorldIndex,
    ray: &Ray,
    found: &rayforge::Intersection<'_>,
) -> Result<(), TestCaseError> {
    let at = ray.position(found.t);
    let own = found.object.normal_at_hit(at, found);
    let indexed = index.normal_at_hit(w, at, found);
    prop_assert!(
        (indexed - own).length() <= 1e-12,
        "{} against {}",
        indexed,
        own
    );
    Ok(())
}

/// A world of at most eight objects (tested without the hierarchy): rectangles lying in the
/// planes of the axes and round balls (tested outright in world space), rectangles turned
/// otherwise, and blocks.
fn few_world(objects: &[(u8, (f64, f64, f64), f64)]) -> World {
    let mut w = World::new();
    for &(kind, (x, y, z), size) in objects {
        let mut stretch = scaling(size, 1.0, 0.5 * size);
        let (shape, turn) = match kind % 6 {
            0 => (Shape::Rectangle, rotation_x(PI)),
            1 => (Shape::Rectangle, rotation_z(FRAC_PI_2)),
            2 => (Shape::Rectangle, rotation_x(-FRAC_PI_2)),
            3 => (Shape::Rectangle, rotation_y(0.4) * rotation_x(0.3)),
            4 => {
                stretch = scaling(size, size, size);
                (Shape::Sphere, rotation_y(0.5))
            }
            _ => (Shape::Cube, rotation_y(0.5)),
        };
        w.objects
            .push(Object::new(shape).with_transform(translation(x, y, z) * turn * stretch));
    }
    w
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// In a world of a few rectangles, balls and blocks, the index finds the nearest hit every
    /// object's own test finds (a rectangle along the axes or a ball is hit in world space, so
    /// the distance agrees to rounding), on the same object, at the distance the list of every
    /// crossing up to it gives it, and a shadow ray is blocked (by either search) where that
    /// hit lies before its end.
    #[test]
    fn a_few_rectangles_and_balls_are_hit_where_their_own_tests_hit_them(
        objects in prop::collection::vec(
            (0u8..6, (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64), 0.2..2.0f64), 1..9),
        origin in (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64),
        direction in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        reach in 0.1..10.0f64,
    ) {
        let d = vector(direction.0, direction.1, direction.2);
        prop_assume!(d.length() > 1e-3);
        let w = few_world(&objects);
        let index = WorldIndex::build(&w);
        let ray = Ray::new(point(origin.0, origin.1, origin.2), d.normalize());
        let expected = hit(&w.intersect(&ray)).map(|i| (i.t, i.object as *const Object));
        let actual = index.closest_hit(&w, &ray).map(|i| (i.t, i.object as *const Object));
        match (actual, expected) {
            (Some((a, p)), Some((b, q))) => {
                prop_assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{} against {}", a, b);
                prop_assert!(std::ptr::eq(p, q), "another object");
            }
            (a, b) => prop_assert_eq!(a.is_some(), b.is_some()),
        }
        // Refraction finds the hit in the list of every crossing up to it, by its distance.
        if let Some(found) = index.closest_hit(&w, &ray) {
            the_normal_is_the_objects(&w, &index, &ray, &found)?;
            let mut list = Vec::new();
            index.intersections_up_to(&w, &ray, found.t, &mut list);
            prop_assert!(list.iter().any(|i| i.same_as(&found)), "the hit is not in the list");
        }
        let first = expected.map(|(t, _)| t);
        let mut last = NO_OBJECT;
        let blocked = index.blocked(&w, &ray, 0.0, reach, &mut last, |object| {
            object.any_local_hit(&object.ray_to_object(&ray), 0.0, reach)
        });
        prop_assert_eq!(blocked, first.is_some_and(|t| t < reach));
        let shadowed = index.shadowed(&w, &ray, 0.0, reach, &mut last, |_| true);
        prop_assert_eq!(shadowed, blocked);
        let none_cast = index.shadowed(&w, &ray, 0.0, reach, &mut last, |_| false);
        prop_assert!(!none_cast);
    }
}

fn visit_all(bvh: &Bvh, ray: &Ray) -> Vec<u32> {
    let mut seen = Vec::new();
    bvh.traverse(
        ray.origin,
        ray.direction,
        f64::NEG_INFINITY,
        f64::INFINITY,
        |i, _| {
            seen.push(i);
            ControlFlow::Continue(())
        },
    );
    seen.sort_unstable();
    seen
}

#[test]
fn identical_boxes_build_a_leaf_and_are_all_found() {
    let boxes = vec![Aabb::new(point(-1.0, -1.0, -1.0), point(1.0, 1.0, 1.0)); 10_000];
    let bvh = Bvh::build(&boxes);
    let ray = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    assert_eq!(visit_all(&bvh, &ray).len(), 10_000);
}

#[test]
fn flat_boxes_are_found_by_rays_that_cross_their_plane() {
    // A grid of boxes with no thickness in z (the faces of a flat mesh).
    let boxes: Vec<Aabb> = (0..1000)
        .map(|i| {
            let (x, y) = ((i % 40) as f64, (i / 40) as f64);
            Aabb::new(point(x, y, 0.0), point(x + 1.0, y + 1.0, 0.0))
        })
        .collect();
    let bvh = Bvh::build(&boxes);
    let ray = Ray::new(point(10.5, 7.5, -3.0), vector(0.0, 0.0, 1.0));
    let seen = visit_all(&bvh, &ray);
    // The box under the ray is found; only its leaf's neighbours come along with it.
    assert!(seen.contains(&(7 * 40 + 10)), "{seen:?}");
    assert!(seen.len() <= 16, "{seen:?}");
}

#[test]
fn a_ray_parallel_to_an_axis_and_on_a_box_face_produces_no_nan_misses() {
    let boxes = vec![Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0))];
    let bvh = Bvh::build(&boxes);
    // Origin exactly on the x = 0 face, moving along z.
    let ray = Ray::new(point(0.0, 0.5, -5.0), vector(0.0, 0.0, 1.0));
    assert_eq!(visit_all(&bvh, &ray), [0]);
}

#[test]
fn shadow_queries_stop_at_the_first_blocker() {
    let w = world_of(&[(0, (0.0, 0.0, 0.0), 1.0), (0, (0.0, 0.0, 5.0), 1.0)]);
    assert!(w.is_shadowed(point(0.0, 0.0, -10.0), point(0.0, 0.0, 10.0)));
    assert!(!w.is_shadowed(point(0.0, 5.0, -10.0), point(0.0, 5.0, 10.0)));
}

/// Large enough that the build splits the top nodes' halves on separate threads and
/// partitions the root's range in pieces (on a pool of three threads, so the pieces are
/// uneven): every box is still in the order exactly once, and a ray through each column of
/// boxes finds it.
#[test]
fn a_large_parallel_build_holds_every_box_once() {
    let side = 200;
    let boxes: Vec<Aabb> = (0..side * side)
        .map(|i| {
            let (x, y) = ((i % side) as f64, (i / side) as f64);
            Aabb::new(point(x, y, 0.0), point(x + 0.5, y + 0.5, 0.5))
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap();
    let bvh = pool.install(|| Bvh::build(&boxes));
    let mut order: Vec<u32> = bvh
        .order()
        .iter()
        .copied()
        .filter(|&p| p != NO_PRIMITIVE)
        .collect();
    order.sort_unstable();
    assert!(order.iter().copied().eq(0..(side * side) as u32));
    for i in (0..side * side).step_by(97) {
        let (x, y) = ((i % side) as f64 + 0.25, (i / side) as f64 + 0.25);
        let ray = Ray::new(point(x, y, -3.0), vector(0.0, 0.0, 1.0));
        assert_eq!(visit_all(&bvh, &ray), [i as u32]);
    }
}

#[test]
fn a_million_boxes_in_a_line_build_without_deep_recursion() {
    let boxes: Vec<Aabb> = (0..200_000)
        .map(|i| {
            let x = (i as f64).powf(1.5);
            Aabb::new(point(x, 0.0, 0.0), point(x + 0.5, 1.0, 1.0))
        })
        .collect();
    let bvh = Bvh::build(&boxes);
    let ray = Ray::new(point(-1.0, 0.5, 0.5), vector(1.0, 0.0, 0.0));
    assert_eq!(visit_all(&bvh, &ray).len(), 200_000);
}

/// The bonus chapter's "Intersecting ray+group doesn't test children if box is missed": the
/// BVH visits no primitive when the ray misses the root box.
#[test]
fn intersecting_ray_group_doesnt_test_children_if_box_is_missed() {
    let boxes = vec![Aabb::new(point(-1.0, -1.0, -1.0), point(1.0, 1.0, 1.0)); 3];
    let bvh = Bvh::build(&boxes);
    let ray = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 1.0, 0.0));
    assert!(visit_all(&bvh, &ray).is_empty());
}

/// "Intersecting ray+group tests children if box is hit".
#[test]
fn intersecting_ray_group_tests_children_if_box_is_hit() {
    let boxes = vec![Aabb::new(point(-1.0, -1.0, -1.0), point(1.0, 1.0, 1.0)); 3];
    let bvh = Bvh::build(&boxes);
    let ray = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    assert_eq!(visit_all(&bvh, &ray), [0, 1, 2]);
}

/// A build given a stop flag (Ctrl-C, a server's cancel): set, the hierarchy, a mesh and a
/// world's index give up; clear, they are the very ones made without a flag (the same
/// nodes, order and hits: no image changes).
#[test]
fn a_build_gives_up_at_its_stop_flag_and_is_otherwise_the_same() {
    use rayforge::geometry::{Mesh, MeshError, MeshFace};
    use std::sync::atomic::AtomicBool;
    let (clear, set) = (AtomicBool::new(false), AtomicBool::new(true));
    let boxes: Vec<Aabb> = (0..20_000)
        .map(|i| {
            let (x, y, z) = ((i % 30) as f64, ((i / 30) % 30) as f64, (i / 900) as f64);
            Aabb::new(point(x, y, z), point(x + 1.5, y + 0.5, z + 2.0))
        })
        .collect();
    let plain = Bvh::build(&boxes);
    assert_eq!(Bvh::build_until(&boxes, Some(&clear)), Some(plain.clone()));
    assert_eq!(Bvh::build_until(&boxes, None), Some(plain));
    assert_eq!(Bvh::build_until(&boxes, Some(&set)), None);

    // A stack of 1000 triangles, one a thousandth behind the other.
    let positions: Vec<_> = (0..3000)
        .map(|i| {
            let z = (i / 3) as f64 * 1e-3;
            [point(0.0, 0.0, z), point(1.0, 0.0, z), point(0.0, 1.0, z)][i % 3]
        })
        .collect();
    let faces: Vec<MeshFace> = (0..1000u32)
        .map(|f| MeshFace {
            vertices: [3 * f, 3 * f + 1, 3 * f + 2],
            normals: None,
            texcoords: None,
        })
        .collect();
    let build =
        |stop| Mesh::with_texcoords_until(positions.clone(), vec![], vec![], faces.clone(), stop);
    let mesh = Mesh::new(positions.clone(), vec![], faces.clone()).unwrap();
    let ray = Ray::new(point(0.2, 0.3, -5.0), vector(0.0, 0.0, 1.0));
    let stopless = build(Some(&clear)).unwrap();
    assert!(mesh.closest_hit(&ray, 0.0, f64::INFINITY).is_some());
    assert_eq!(
        stopless.closest_hit(&ray, 0.0, f64::INFINITY),
        mesh.closest_hit(&ray, 0.0, f64::INFINITY)
    );
    assert_eq!(build(Some(&set)).unwrap_err(), MeshError::Stopped);

    let world = world_of(&[(0, (0.0, 0.0, 0.0), 1.0), (1, (3.0, 0.0, 0.0), 1.0)]);
    assert!(WorldIndex::build_until(&world, Some(&set)).is_none());
    assert!(WorldIndex::build_until(&world, Some(&clear)).is_some());
}
