//! Chapter 16: constructive solid geometry.
mod common;
use common::*;
use rayforge::book::BookWorld;
use rayforge::color::color;
use rayforge::geometry::LocalHit;
use rayforge::math::translation;
use rayforge::{
    hit, intersection_allowed, point, vector, Csg, CsgOperation, Group, Material, Object, Ray,
    Shape, World,
};
use smallvec::SmallVec;

use CsgOperation::{Difference, Intersection as Intersect, Union};

#[test]
fn csg_is_created_with_an_operation_and_two_shapes() {
    let s1 = Object::sphere();
    let s2 = Object::cube();
    let c = Csg::new(Union, s1.clone(), s2.clone()).unwrap();
    assert_eq!(c.operation(), Union);
    assert_eq!(c.left(), [s1]);
    assert_eq!(c.right(), [s2]);
}

/// Scenario outline "Evaluating the rule for a CSG operation": one test per example row.
macro_rules! rule_rows {
    ($($name:ident: $op:expr, $lhit:expr, $inl:expr, $inr:expr => $result:expr;)*) => {$(
        #[test]
        fn $name() {
            assert_eq!(intersection_allowed($op, $lhit, $inl, $inr), $result);
        }
    )*};
}

rule_rows! {
    evaluating_the_rule_for_a_csg_operation_union_1: Union, true, true, true => false;
    evaluating_the_rule_for_a_csg_operation_union_2: Union, true, true, false => true;
    evaluating_the_rule_for_a_csg_operation_union_3: Union, true, false, true => false;
    evaluating_the_rule_for_a_csg_operation_union_4: Union, true, false, false => true;
    evaluating_the_rule_for_a_csg_operation_union_5: Union, false, true, true => false;
    evaluating_the_rule_for_a_csg_operation_union_6: Union, false, true, false => false;
    evaluating_the_rule_for_a_csg_operation_union_7: Union, false, false, true => true;
    evaluating_the_rule_for_a_csg_operation_union_8: Union, false, false, false => true;
    evaluating_the_rule_for_a_csg_operation_intersection_1: Intersect, true, true, true => true;
    evaluating_the_rule_for_a_csg_operation_intersection_2: Intersect, true, true, false => false;
    evaluating_the_rule_for_a_csg_operation_intersection_3: Intersect, true, false, true => true;
    evaluating_the_rule_for_a_csg_operation_intersection_4: Intersect, true, false, false => false;
    evaluating_the_rule_for_a_csg_operation_intersection_5: Intersect, false, true, true => true;
    evaluating_the_rule_for_a_csg_operation_intersection_6: Intersect, false, true, false => true;
    evaluating_the_rule_for_a_csg_operation_intersection_7: Intersect, false, false, true => false;
    evaluating_the_rule_for_a_csg_operation_intersection_8: Intersect, false, false, false => false;
    evaluating_the_rule_for_a_csg_operation_difference_1: Difference, true, true, true => false;
    evaluating_the_rule_for_a_csg_operation_difference_2: Difference, true, true, false => true;
    evaluating_the_rule_for_a_csg_operation_difference_3: Difference, true, false, true => false;
    evaluating_the_rule_for_a_csg_operation_difference_4: Difference, true, false, false => true;
    evaluating_the_rule_for_a_csg_operation_difference_5: Difference, false, true, true => true;
    evaluating_the_rule_for_a_csg_operation_difference_6: Difference, false, true, false => true;
    evaluating_the_rule_for_a_csg_operation_difference_7: Difference, false, false, true => false;
    evaluating_the_rule_for_a_csg_operation_difference_8: Difference, false, false, false => false;
}

/// Scenario outline "Filtering a list of intersections": xs = 1:s1, 2:s2, 3:s1, 4:s2, where
/// s1 is the left leaf (0) and s2 the right (1).
fn filtered(operation: CsgOperation) -> Vec<f64> {
    let c = Csg::new(operation, Object::sphere(), Object::cube()).unwrap();
    let mut xs: SmallVec<[LocalHit; 16]> = [(1.0, 0), (2.0, 1), (3.0, 0), (4.0, 1)]
        .into_iter()
        .map(|(t, leaf)| LocalHit {
            t,
            leaf,
            ..LocalHit::default()
        })
        .collect();
    c.filter(&mut xs);
    xs.iter().map(|h| h.t).collect()
}

#[test]
fn filtering_a_list_of_intersections_union() {
    assert_eq!(filtered(Union), [1.0, 4.0]);
}

#[test]
fn filtering_a_list_of_intersections_intersection() {
    assert_eq!(filtered(Intersect), [2.0, 3.0]);
}

#[test]
fn filtering_a_list_of_intersections_difference() {
    assert_eq!(filtered(Difference), [1.0, 2.0]);
}

#[test]
fn a_ray_misses_a_csg_object() {
    let c = Object::csg(Union, Object::sphere(), Object::cube()).unwrap();
    let r = Ray::new(point(0.0, 2.0, -5.0), vector(0.0, 0.0, 1.0));
    assert!(c.intersections(&r).is_empty());
}

#[test]
fn a_ray_hits_a_csg_object() {
    let s1 = Object::sphere();
    let s2 = Object::sphere().with_transform(translation(0.0, 0.0, 0.5));
    let c = Object::csg(Union, s1.clone(), s2.clone()).unwrap();
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let xs = c.intersections(&r);
    assert_eq!(xs.len(), 2);
    assert_approx(xs[0].t, 4.0);
    assert_eq!(c.surface(xs[0].leaf), &s1);
    assert_approx(xs[1].t, 6.5);
    assert_eq!(c.surface(xs[1].leaf), &s2);
}

/// The book's `includes`: a leaf belongs to the left operand by identity.
#[test]
fn the_left_operand_includes_its_own_leaves_only() {
    let c = Csg::new(Union, Object::sphere(), Object::cube()).unwrap();
    assert!(c.left_includes(&c.leaves()[0]));
    assert!(!c.left_includes(&c.leaves()[1]));
    // A value-equal copy is not the same object.
    assert!(!c.left_includes(&Object::sphere()));
}

fn bore(transform: glam::DMat4) -> Object {
    Object::new(Shape::Cylinder {
        minimum: -2.0,
        maximum: 2.0,
        closed: true,
    })
    .with_transform(transform * rayforge::math::scaling(0.5, 1.0, 0.5))
}

/// Nested CSG: (sphere ∩ cube) − (bore ∪ bore), filtered innermost first.
#[test]
fn nested_csg_objects_filter_level_by_level() {
    let rounded_cube = Object::csg(
        Intersect,
        Object::sphere().with_transform(rayforge::math::scaling(1.3, 1.3, 1.3)),
        Object::cube(),
    )
    .unwrap();
    let bores = Object::csg(
        Union,
        bore(glam::DMat4::IDENTITY),
        bore(rayforge::math::rotation_x(std::f64::consts::FRAC_PI_2)),
    )
    .unwrap();
    let c = Object::csg(Difference, rounded_cube, bores).unwrap();
    // Straight down the z bore: nothing is left to hit.
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    assert!(c.intersections(&r).is_empty());
    // Beside both bores (and inside the sphere's rounding): the cube's faces at z = ±1.
    let r = Ray::new(point(0.7, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let ts: Vec<f64> = c.intersections(&r).iter().map(|i| i.t).collect();
    assert_eq!(ts.len(), 2, "{ts:?}");
    assert_approx(ts[0], 4.0);
    assert_approx(ts[1], 6.0);
    // Across the y bore along x (y = 0.7 stays clear of the z bore): the cube's faces and the
    // bore's wall on both sides.
    let r = Ray::new(point(-5.0, 0.7, 0.0), vector(1.0, 0.0, 0.0));
    let ts: Vec<f64> = c.intersections(&r).iter().map(|i| i.t).collect();
    assert_eq!(ts.len(), 4, "{ts:?}");
    assert_approx(ts[1], 4.5);
    assert_approx(ts[2], 5.5);
}

/// A group as an operand: its children all count as that side (the book's `includes`).
#[test]
fn a_group_can_be_an_operand() {
    let pair = Group::new()
        .with_child(Object::sphere().with_transform(translation(-3.0, 0.0, 0.0)))
        .with_child(Object::sphere().with_transform(translation(3.0, 0.0, 0.0)));
    let c = Csg::new(
        Difference,
        pair,
        Object::cube()
            .with_transform(translation(3.0, 0.0, 0.0) * rayforge::math::scaling(1.5, 1.5, 1.5)),
    )
    .unwrap();
    assert_eq!(c.left().len(), 2);
    assert_eq!(c.right().len(), 1);
    let c = Object::new(Shape::Csg(std::sync::Arc::new(c)));
    // The left sphere is whole; the right one is inside the cube and removed.
    let hits = |x: f64| {
        c.intersections(&Ray::new(point(x, 0.0, -5.0), vector(0.0, 0.0, 1.0)))
            .len()
    };
    assert_eq!(hits(-3.0), 2);
    assert_eq!(hits(3.0), 0);
}

/// Each hit is shaded by the primitive it is on: its material and normal.
#[test]
fn a_csg_hit_is_shaded_by_the_primitive_it_is_on() {
    let red = Object::sphere().with_material(Material {
        color: color(1.0, 0.0, 0.0),
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        ..Material::default()
    });
    let blue_cube = Object::cube()
        .with_transform(translation(0.0, 0.0, 1.5))
        .with_material(Material {
            color: color(0.0, 0.0, 1.0),
            ambient: 1.0,
            diffuse: 0.0,
            specular: 0.0,
            ..Material::default()
        });
    // The cube minus the sphere: from the front, the ray first meets the sphere's far side
    // carved into the cube (a red dimple), seen through the cube's removed front.
    let c = Object::csg(Difference, blue_cube, red).unwrap();
    let w = World {
        objects: vec![c],
        lights: vec![rayforge::Light::point(
            point(0.0, 0.0, -10.0),
            color(1.0, 1.0, 1.0),
        )],
        ..World::default()
    };
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let h = hit(&w.intersect(&r)).unwrap();
    assert_approx(h.t, 6.0);
    assert_color_approx(w.color_at(&r, 5), color(1.0, 0.0, 0.0));
    // Off to the side the cube's own face shows.
    let r = Ray::new(point(0.9, 0.9, -5.0), vector(0.0, 0.0, 1.0));
    assert_color_approx(w.color_at(&r, 5), color(0.0, 0.0, 1.0));
}

/// A transformed CSG solid moves its primitives: normals and bounds follow.
#[test]
fn a_transformed_csg_object_places_its_primitives() {
    let c = Object::csg(Union, Object::sphere(), Object::cube())
        .unwrap()
        .with_transform(translation(10.0, 0.0, 0.0));
    assert_eq!(c.transform.matrix(), glam::DMat4::IDENTITY);
    let b = c.bounds();
    assert_vec_approx(b.min, point(9.0, -1.0, -1.0));
    let r = Ray::new(point(10.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let xs = c.intersections(&r);
    assert_eq!(xs.len(), 2);
    assert_approx(xs[0].t, 4.0);
    assert_vec_approx(
        c.normal_at_hit(r.position(xs[0].t), &xs[0]),
        vector(0.0, 0.0, -1.0),
    );
}

/// Fundamentals of Ray Tracing's set complement.
#[test]
fn a_complement_keeps_every_surface_of_its_operand() {
    use rayforge::{intersection_allowed, CsgOperation};
    for (l, i, r) in [
        (true, true, true),
        (false, false, false),
        (true, false, true),
    ] {
        assert!(intersection_allowed(CsgOperation::Complement, l, i, r));
    }
    let outside = rayforge::Object::complement(rayforge::Object::sphere()).unwrap();
    let ray = rayforge::Ray::new(
        rayforge::point(0.0, 0.0, -5.0),
        rayforge::vector(0.0, 0.0, 1.0),
    );
    let ts: Vec<f64> = outside.intersections(&ray).iter().map(|x| x.t).collect();
    assert_eq!(ts.len(), 2);
    assert!(!outside.contains(rayforge::point(0.0, 0.0, 0.0)));
    assert!(outside.contains(rayforge::point(0.0, 0.0, 3.0)));
}

#[test]
fn an_intersection_with_a_complement_is_a_difference() {
    use rayforge::math::translation;
    use rayforge::{CsgOperation, Object};
    let bite = || Object::sphere().with_transform(translation(0.7, 0.2, 0.0));
    let difference = Object::csg(CsgOperation::Difference, Object::sphere(), bite()).unwrap();
    let complement = Object::complement(bite()).unwrap();
    let crossed = Object::csg(CsgOperation::Intersection, Object::sphere(), complement).unwrap();
    for i in 0..40 {
        let y = -1.2 + i as f64 * 0.06;
        let ray = rayforge::Ray::new(
            rayforge::point(-3.0, y, 0.1),
            rayforge::vector(1.0, 0.05, 0.0),
        );
        let ts = |o: &Object| -> Vec<f64> {
            let mut t: Vec<f64> = o.intersections(&ray).iter().map(|x| x.t).collect();
            t.sort_by(f64::total_cmp);
            t
        };
        assert_eq!(ts(&difference), ts(&crossed), "ray at y = {y}");
    }
}

/// The inside tests by formula (`Shape::contains_point`) give what the parity of the surfaces
/// ahead of the point gives (the ray cast they replace), away from the surface.
#[test]
fn inside_tests_by_formula_agree_with_the_parity_of_the_surfaces_ahead() {
    use rayforge::Shape;
    let shapes = [
        Shape::Sphere,
        Shape::Cube,
        Shape::Plane,
        Shape::Cylinder {
            minimum: -0.5,
            maximum: 1.5,
            closed: true,
        },
        Shape::Torus {
            major: 1.0,
            minor: 0.4,
        },
        Shape::Torus {
            major: 0.5,
            minor: 0.8,
        },
    ];
    let direction = vector(0.267_261_24, 0.801_783_73, 0.534_522_48);
    // A fixed scatter of points over [-2, 2)³.
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
    };
    for shape in &shapes {
        let mut compared = 0;
        for _ in 0..2000 {
            let p = point(next(), next(), next());
            let mut crossings = Vec::new();
            shape.intersect(&Ray::new(p, direction), |t| crossings.push(t));
            // Points within rounding of the surface may go either way.
            if crossings.iter().any(|t| t.abs() < 1e-6) {
                continue;
            }
            let parity = crossings.iter().filter(|&&t| t > 0.0).count() % 2 == 1;
            assert_eq!(shape.contains_point(p), Some(parity), "{shape:?} at {p:?}");
            compared += 1;
        }
        assert!(compared > 1900, "{shape:?}: {compared}");
    }
}
