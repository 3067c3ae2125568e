//! Chapter 5: intersections and hits (and, last, chapter 15's intersection with u and v).
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
use rayforge::{hit, Intersection, Object};

#[test]
fn an_intersection_encapsulates_t_and_object() {
    let s = Object::sphere();
    let i = Intersection::new(3.5, &s);
    assert_eq!(i.t, 3.5);
    assert!(std::ptr::eq(i.object, &s));
}

#[test]
fn aggregating_intersections() {
    let s = Object::sphere();
    let xs = [Intersection::new(1.0, &s), Intersection::new(2.0, &s)];
    assert_eq!(xs.len(), 2);
    assert_eq!(xs[0].t, 1.0);
    assert_eq!(xs[1].t, 2.0);
}

#[test]
fn the_hit_when_all_intersections_have_positive_t() {
    let s = Object::sphere();
    let i1 = Intersection::new(1.0, &s);
    let i2 = Intersection::new(2.0, &s);
    assert_eq!(hit(&[i2, i1]), Some(i1));
}

#[test]
fn the_hit_when_some_intersections_have_negative_t() {
    let s = Object::sphere();
    let i1 = Intersection::new(-1.0, &s);
    let i2 = Intersection::new(1.0, &s);
    assert_eq!(hit(&[i2, i1]), Some(i2));
}

#[test]
fn the_hit_when_all_intersections_have_negative_t() {
    let s = Object::sphere();
    let i1 = Intersection::new(-2.0, &s);
    let i2 = Intersection::new(-1.0, &s);
    assert_eq!(hit(&[i2, i1]), None);
}

#[test]
fn the_hit_is_always_the_lowest_nonnegative_intersection() {
    let s = Object::sphere();
    let i1 = Intersection::new(5.0, &s);
    let i2 = Intersection::new(7.0, &s);
    let i3 = Intersection::new(-3.0, &s);
    let i4 = Intersection::new(2.0, &s);
    assert_eq!(hit(&[i1, i2, i3, i4]), Some(i4));
}

#[test]
fn an_intersection_can_encapsulate_u_and_v() {
    let s = Object::triangle(
        rayforge::point(0.0, 1.0, 0.0),
        rayforge::point(-1.0, 0.0, 0.0),
        rayforge::point(1.0, 0.0, 0.0),
    );
    let i = Intersection::with_uv(3.5, &s, 0.2, 0.4);
    assert_eq!((i.u, i.v), (0.2, 0.4));
}
