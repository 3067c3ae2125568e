//! The bonus chapter "Bounding boxes and hierarchies": boxes for every shape, box arithmetic,
//! transformed boxes and ray–box tests. (The chapter's own `divide` builds the simple
//! median-split hierarchy; rayforge builds a binned-SAH BVH instead, tested in `bvh.rs`.)
// The book's expected values are kept exactly as printed.
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::math::{rotation_x, rotation_y, scaling, translation, Aabb};
use rayforge::{point, vector, Group, Node, Object, Point3, Ray, Shape, Vec3};
use std::f64::consts::PI;

const INF: f64 = f64::INFINITY;

fn aabb(min: (f64, f64, f64), max: (f64, f64, f64)) -> Aabb {
    Aabb::new(point(min.0, min.1, min.2), point(max.0, max.1, max.2))
}

#[test]
fn creating_an_empty_bounding_box() {
    let b = Aabb::EMPTY;
    assert_eq!(b.min, point(INF, INF, INF));
    assert_eq!(b.max, point(-INF, -INF, -INF));
}

#[test]
fn creating_a_bounding_box_with_volume() {
    let b = aabb((-1.0, -2.0, -3.0), (3.0, 2.0, 1.0));
    assert_eq!(b.min, point(-1.0, -2.0, -3.0));
    assert_eq!(b.max, point(3.0, 2.0, 1.0));
}

#[test]
fn adding_points_to_an_empty_bounding_box() {
    let mut b = Aabb::EMPTY;
    b.add_point(point(-5.0, 2.0, 0.0));
    b.add_point(point(7.0, 0.0, -3.0));
    assert_eq!(b.min, point(-5.0, 0.0, -3.0));
    assert_eq!(b.max, point(7.0, 2.0, 0.0));
}

#[test]
fn a_sphere_has_a_bounding_box() {
    assert_eq!(
        Shape::Sphere.bounds(),
        aabb((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    );
}

#[test]
fn a_plane_has_a_bounding_box() {
    assert_eq!(
        Shape::Plane.bounds(),
        aabb((-INF, 0.0, -INF), (INF, 0.0, INF))
    );
}

#[test]
fn a_cube_has_a_bounding_box() {
    assert_eq!(
        Shape::Cube.bounds(),
        aabb((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    );
}

#[test]
fn an_unbounded_cylinder_has_a_bounding_box() {
    assert_eq!(
        Shape::CYLINDER.bounds(),
        aabb((-1.0, -INF, -1.0), (1.0, INF, 1.0))
    );
}

#[test]
fn a_bounded_cylinder_has_a_bounding_box() {
    let s = Shape::Cylinder {
        minimum: -5.0,
        maximum: 3.0,
        closed: false,
    };
    assert_eq!(s.bounds(), aabb((-1.0, -5.0, -1.0), (1.0, 3.0, 1.0)));
}

#[test]
fn an_unbounded_cone_has_a_bounding_box() {
    assert_eq!(
        Shape::CONE.bounds(),
        aabb((-INF, -INF, -INF), (INF, INF, INF))
    );
}

#[test]
fn a_bounded_cone_has_a_bounding_box() {
    let s = Shape::Cone {
        minimum: -5.0,
        maximum: 3.0,
        closed: false,
    };
    assert_eq!(s.bounds(), aabb((-5.0, -5.0, -5.0), (5.0, 3.0, 5.0)));
}

#[test]
fn a_triangle_has_a_bounding_box() {
    let t = Object::triangle(
        point(-3.0, 7.0, 2.0),
        point(6.0, 2.0, -4.0),
        point(2.0, -1.0, -1.0),
    );
    assert_eq!(t.shape.bounds(), aabb((-3.0, -1.0, -4.0), (6.0, 7.0, 2.0)));
}

#[test]
fn adding_one_bounding_box_to_another() {
    let b1 = aabb((-5.0, -2.0, 0.0), (7.0, 4.0, 4.0));
    let b2 = aabb((8.0, -7.0, -2.0), (14.0, 2.0, 8.0));
    assert_eq!(b1.union(&b2), aabb((-5.0, -7.0, -2.0), (14.0, 4.0, 8.0)));
}

#[test]
fn checking_to_see_if_a_box_contains_a_given_point() {
    let b = aabb((5.0, -2.0, 0.0), (11.0, 4.0, 7.0));
    for (p, expected) in [
        ((5.0, -2.0, 0.0), true),
        ((11.0, 4.0, 7.0), true),
        ((8.0, 1.0, 3.0), true),
        ((3.0, 0.0, 3.0), false),
        ((8.0, -4.0, 3.0), false),
        ((8.0, 1.0, -1.0), false),
        ((13.0, 1.0, 3.0), false),
        ((8.0, 5.0, 3.0), false),
        ((8.0, 1.0, 8.0), false),
    ] {
        assert_eq!(b.contains_point(point(p.0, p.1, p.2)), expected, "{p:?}");
    }
}

#[test]
fn checking_to_see_if_a_box_contains_a_given_box() {
    let b = aabb((5.0, -2.0, 0.0), (11.0, 4.0, 7.0));
    for (min, max, expected) in [
        ((5.0, -2.0, 0.0), (11.0, 4.0, 7.0), true),
        ((6.0, -1.0, 1.0), (10.0, 3.0, 6.0), true),
        ((4.0, -3.0, -1.0), (10.0, 3.0, 6.0), false),
        ((6.0, -1.0, 1.0), (12.0, 5.0, 8.0), false),
    ] {
        assert_eq!(b.contains_box(&aabb(min, max)), expected, "{min:?} {max:?}");
    }
}

#[test]
fn transforming_a_bounding_box() {
    let b = aabb((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0));
    let t = rayforge::Transform::new(rotation_x(PI / 4.0) * rotation_y(PI / 4.0));
    let b2 = b.transform(&t);
    assert_vec_approx(b2.min, point(-1.4142, -1.7071, -1.7071));
    assert_vec_approx(b2.max, point(1.4142, 1.7071, 1.7071));
}

#[test]
fn querying_a_shapes_bounding_box_in_its_parents_space() {
    let s = Object::sphere().with_transform(translation(1.0, -3.0, 5.0) * scaling(0.5, 2.0, 4.0));
    let b = s.bounds();
    assert_vec_approx(b.min, point(0.5, -5.0, 1.0));
    assert_vec_approx(b.max, point(1.5, -1.0, 9.0));
}

#[test]
fn a_group_has_a_bounding_box_that_contains_its_children() {
    let s = Object::sphere().with_transform(translation(2.0, 5.0, -3.0) * scaling(2.0, 2.0, 2.0));
    let c = Object::new(Shape::Cylinder {
        minimum: -2.0,
        maximum: 2.0,
        closed: false,
    })
    .with_transform(translation(-4.0, -1.0, 4.0) * scaling(0.5, 1.0, 0.5));
    let g = Group::new().with_child(s).with_child(c);
    let b = g
        .flatten()
        .unwrap()
        .iter()
        .fold(Aabb::EMPTY, |b, o| b.union(&o.bounds()));
    assert_vec_approx(b.min, point(-4.5, -3.0, -5.0));
    assert_vec_approx(b.max, point(4.0, 7.0, 4.5));
}

/// An infinite box transformed by a rotation stays infinite, never NaN.
#[test]
fn transforming_an_infinite_box_gives_no_nan() {
    let b = Shape::Plane
        .bounds()
        .transform(&rayforge::Transform::new(rotation_x(0.3)));
    assert!(!b.min.is_nan() && !b.max.is_nan());
    assert_eq!(b.min.x, -INF);
}

fn hits(b: &Aabb, origin: Point3, direction: Vec3) -> bool {
    b.intersects(&Ray::new(origin, direction.normalize()))
}

#[test]
fn intersecting_a_ray_with_a_bounding_box_at_the_origin() {
    let b = aabb((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0));
    for (o, d, expected) in [
        ((5.0, 0.5, 0.0), (-1.0, 0.0, 0.0), true),
        ((-5.0, 0.5, 0.0), (1.0, 0.0, 0.0), true),
        ((0.5, 5.0, 0.0), (0.0, -1.0, 0.0), true),
        ((0.5, -5.0, 0.0), (0.0, 1.0, 0.0), true),
        ((0.5, 0.0, 5.0), (0.0, 0.0, -1.0), true),
        ((0.5, 0.0, -5.0), (0.0, 0.0, 1.0), true),
        ((0.0, 0.5, 0.0), (0.0, 0.0, 1.0), true),
        ((-2.0, 0.0, 0.0), (2.0, 4.0, 6.0), false),
        ((0.0, -2.0, 0.0), (6.0, 2.0, 4.0), false),
        ((0.0, 0.0, -2.0), (4.0, 6.0, 2.0), false),
        ((2.0, 0.0, 2.0), (0.0, 0.0, -1.0), false),
        ((0.0, 2.0, 2.0), (0.0, -1.0, 0.0), false),
        ((2.0, 2.0, 0.0), (-1.0, 0.0, 0.0), false),
    ] {
        let r = hits(&b, point(o.0, o.1, o.2), vector(d.0, d.1, d.2));
        assert_eq!(r, expected, "{o:?} {d:?}");
    }
}

#[test]
fn intersecting_a_ray_with_a_non_cubic_bounding_box() {
    let b = aabb((5.0, -2.0, 0.0), (11.0, 4.0, 7.0));
    for (o, d, expected) in [
        ((15.0, 1.0, 2.0), (-1.0, 0.0, 0.0), true),
        ((-5.0, -1.0, 4.0), (1.0, 0.0, 0.0), true),
        ((7.0, 6.0, 5.0), (0.0, -1.0, 0.0), true),
        ((9.0, -5.0, 6.0), (0.0, 1.0, 0.0), true),
        ((8.0, 2.0, 12.0), (0.0, 0.0, -1.0), true),
        ((6.0, 0.0, -5.0), (0.0, 0.0, 1.0), true),
        ((8.0, 1.0, 3.5), (0.0, 0.0, 1.0), true),
        ((9.0, -1.0, -8.0), (2.0, 4.0, 6.0), false),
        ((8.0, 3.0, -4.0), (6.0, 2.0, 4.0), false),
        ((9.0, -1.0, -2.0), (4.0, 6.0, 2.0), false),
        ((4.0, 0.0, 9.0), (0.0, 0.0, -1.0), false),
        ((8.0, 6.0, -1.0), (0.0, -1.0, 0.0), false),
        ((12.0, 5.0, 4.0), (-1.0, 0.0, 0.0), false),
    ] {
        let r = hits(&b, point(o.0, o.1, o.2), vector(d.0, d.1, d.2));
        assert_eq!(r, expected, "{o:?} {d:?}");
    }
}

#[test]
fn splitting_a_perfect_cube() {
    let (l, r) = aabb((-1.0, -4.0, -5.0), (9.0, 6.0, 5.0)).split();
    assert_eq!(l, aabb((-1.0, -4.0, -5.0), (4.0, 6.0, 5.0)));
    assert_eq!(r, aabb((4.0, -4.0, -5.0), (9.0, 6.0, 5.0)));
}

#[test]
fn splitting_an_x_wide_box() {
    let (l, r) = aabb((-1.0, -2.0, -3.0), (9.0, 5.5, 3.0)).split();
    assert_eq!(l, aabb((-1.0, -2.0, -3.0), (4.0, 5.5, 3.0)));
    assert_eq!(r, aabb((4.0, -2.0, -3.0), (9.0, 5.5, 3.0)));
}

#[test]
fn splitting_a_y_wide_box() {
    let (l, r) = aabb((-1.0, -2.0, -3.0), (5.0, 8.0, 3.0)).split();
    assert_eq!(l, aabb((-1.0, -2.0, -3.0), (5.0, 3.0, 3.0)));
    assert_eq!(r, aabb((-1.0, 3.0, -3.0), (5.0, 8.0, 3.0)));
}

#[test]
fn splitting_a_z_wide_box() {
    let (l, r) = aabb((-1.0, -2.0, -3.0), (5.0, 3.0, 7.0)).split();
    assert_eq!(l, aabb((-1.0, -2.0, -3.0), (5.0, 3.0, 2.0)));
    assert_eq!(r, aabb((-1.0, -2.0, 2.0), (5.0, 3.0, 7.0)));
}

#[test]
fn a_csg_shape_has_a_bounding_box_that_contains_its_children() {
    let left = Object::sphere();
    let right = Object::sphere().with_transform(translation(2.0, 3.0, 4.0));
    let shape = rayforge::Object::csg(rayforge::CsgOperation::Difference, left, right).unwrap();
    let b = shape.bounds();
    assert_vec_approx(b.min, point(-1.0, -1.0, -1.0));
    assert_vec_approx(b.max, point(3.0, 4.0, 5.0));
}

fn sphere_at(x: f64, y: f64, z: f64) -> Object {
    Object::sphere().with_transform(translation(x, y, z))
}

fn as_group(node: &Node) -> &Group {
    match node {
        Node::Group(g) => g,
        Node::Object(o) => panic!("expected a group, found {o:?}"),
    }
}

#[test]
fn partitioning_a_groups_children() {
    let (s1, s2, s3) = (
        sphere_at(-2.0, 0.0, 0.0),
        sphere_at(2.0, 0.0, 0.0),
        Object::sphere(),
    );
    let mut g = Group::new()
        .with_child(s1.clone())
        .with_child(s2.clone())
        .with_child(s3.clone());
    let (left, right) = g.partition_children();
    assert_eq!(g.children, [Node::from(s3)]);
    assert_eq!(left, [Node::from(s1)]);
    assert_eq!(right, [Node::from(s2)]);
}

#[test]
fn creating_a_sub_group_from_a_list_of_children() {
    let (s1, s2) = (Object::sphere(), Object::sphere());
    let mut g = Group::new();
    g.make_subgroup(vec![Node::from(s1.clone()), Node::from(s2.clone())]);
    assert_eq!(g.children.len(), 1);
    assert_eq!(
        as_group(&g.children[0]).children,
        [Node::from(s1), Node::from(s2)]
    );
}

#[test]
fn subdividing_a_group_partitions_its_children() {
    let s1 = sphere_at(-2.0, -2.0, 0.0);
    let s2 = sphere_at(-2.0, 2.0, 0.0);
    let s3 = Object::sphere().with_transform(scaling(4.0, 4.0, 4.0));
    let mut g = Group::new()
        .with_child(s1.clone())
        .with_child(s2.clone())
        .with_child(s3.clone());
    g.divide(1);
    assert_eq!(g.children[0], Node::from(s3));
    let subgroup = as_group(&g.children[1]);
    assert_eq!(subgroup.children.len(), 2);
    assert_eq!(as_group(&subgroup.children[0]).children, [Node::from(s1)]);
    assert_eq!(as_group(&subgroup.children[1]).children, [Node::from(s2)]);
}

#[test]
fn subdividing_a_group_with_too_few_children() {
    let s1 = sphere_at(-2.0, 0.0, 0.0);
    let s2 = sphere_at(2.0, 1.0, 0.0);
    let s3 = sphere_at(2.0, -1.0, 0.0);
    let subgroup = Group::new()
        .with_child(s1.clone())
        .with_child(s2.clone())
        .with_child(s3.clone());
    let s4 = Object::sphere();
    let mut g = Group::new().with_child(subgroup).with_child(s4.clone());
    g.divide(3);
    let subgroup = as_group(&g.children[0]);
    assert_eq!(g.children[1], Node::from(s4));
    assert_eq!(subgroup.children.len(), 2);
    assert_eq!(as_group(&subgroup.children[0]).children, [Node::from(s1)]);
    assert_eq!(
        as_group(&subgroup.children[1]).children,
        [Node::from(s2), Node::from(s3)]
    );
}

#[test]
fn subdividing_a_primitive_does_nothing_to_its_flattened_objects() {
    // A group of one primitive below the threshold stays as it is.
    let mut g = Group::new().with_child(Object::sphere());
    let before = g.clone();
    g.divide(2);
    assert_eq!(g, before);
}

#[test]
fn a_divided_group_renders_the_same_objects() {
    let mut g = Group::new();
    for i in 0..20 {
        g.add_child(sphere_at(i as f64 * 0.7 - 7.0, (i % 3) as f64, 0.0));
    }
    let before = g.flatten().unwrap();
    g.divide(4);
    let after = g.flatten().unwrap();
    assert_eq!(before.len(), after.len());
    for o in &before {
        assert!(after.contains(o));
    }
}

/// The book's "A test shape has (arbitrary) bounds": every shape reports object-space bounds;
/// with no `test_shape` in rayforge, a unit cube stands in for it.
#[test]
fn a_test_shape_has_arbitrary_bounds() {
    let b = Shape::Cube.bounds();
    assert_eq!(b.min, point(-1.0, -1.0, -1.0));
    assert_eq!(b.max, point(1.0, 1.0, 1.0));
}

/// The book's "Subdividing a CSG shape subdivides its children". A rayforge CSG keeps its
/// operands as flat lists of primitives (its own hierarchy is the operation tree), so dividing
/// the groups before building the CSG must leave each side's primitives where they were.
#[test]
fn subdividing_a_csg_shape_subdivides_its_children() {
    let (s1, s2) = (sphere_at(-1.5, 0.0, 0.0), sphere_at(1.5, 0.0, 0.0));
    let (s3, s4) = (sphere_at(0.0, 0.0, -1.5), sphere_at(0.0, 0.0, 1.5));
    let mut left = Group::new().with_child(s1.clone()).with_child(s2.clone());
    let mut right = Group::new().with_child(s3.clone()).with_child(s4.clone());
    left.divide(1);
    right.divide(1);
    assert_eq!(
        as_group(&left.children[0]).children,
        [Node::from(s1.clone())]
    );
    assert_eq!(
        as_group(&left.children[1]).children,
        [Node::from(s2.clone())]
    );
    assert_eq!(
        as_group(&right.children[0]).children,
        [Node::from(s3.clone())]
    );
    assert_eq!(
        as_group(&right.children[1]).children,
        [Node::from(s4.clone())]
    );
    let csg = rayforge::Csg::new(rayforge::CsgOperation::Difference, left, right).unwrap();
    assert_eq!(csg.left(), [s1, s2]);
    assert_eq!(csg.right(), [s3, s4]);
}
