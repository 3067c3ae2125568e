//! Chapter 10: patterns, and the chapter's "Putting it together" extras.
// The book's expected values are kept exactly as printed (0.70711, not FRAC_1_SQRT_2).
#![allow(clippy::approx_constant)]
mod common;
use common::*;
use rayforge::book::BookPattern;
use rayforge::color::color;
use rayforge::math::{rotation_y, scaling, translation};
use rayforge::{
    lighting, point, vector, Color, Light, Material, Object, Pattern, PatternKind, Transform,
};

const WHITE: Color = color(1.0, 1.0, 1.0);
const BLACK: Color = color(0.0, 0.0, 0.0);

#[test]
fn creating_a_stripe_pattern() {
    let pattern = Pattern::stripes(WHITE, BLACK);
    assert_eq!(
        pattern.kind,
        PatternKind::Stripes(vec![Pattern::solid(WHITE), Pattern::solid(BLACK)])
    );
}

#[test]
fn a_stripe_pattern_is_constant_in_y() {
    let pattern = Pattern::stripes(WHITE, BLACK);
    for y in [0.0, 1.0, 2.0] {
        assert_eq!(pattern.pattern_at(point(0.0, y, 0.0)), WHITE);
    }
}

#[test]
fn a_stripe_pattern_is_constant_in_z() {
    let pattern = Pattern::stripes(WHITE, BLACK);
    for z in [0.0, 1.0, 2.0] {
        assert_eq!(pattern.pattern_at(point(0.0, 0.0, z)), WHITE);
    }
}

#[test]
fn a_stripe_pattern_alternates_in_x() {
    let pattern = Pattern::stripes(WHITE, BLACK);
    for (x, expected) in [
        (0.0, WHITE),
        (0.9, WHITE),
        (1.0, BLACK),
        (-0.1, BLACK),
        (-1.0, BLACK),
        (-1.1, WHITE),
    ] {
        assert_eq!(pattern.pattern_at(point(x, 0.0, 0.0)), expected, "x = {x}");
    }
}

#[test]
fn lighting_with_a_pattern_applied() {
    let m = Material {
        pattern: Some(Box::new(Pattern::stripes(WHITE, BLACK))),
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        ..Material::default()
    };
    let eyev = vector(0.0, 0.0, -1.0);
    let normalv = vector(0.0, 0.0, -1.0);
    let light = Light::point(point(0.0, 0.0, -10.0), WHITE);
    let s = Object::sphere();
    let c1 = lighting(&m, &s, &light, point(0.9, 0.0, 0.0), eyev, normalv, 1.0);
    let c2 = lighting(&m, &s, &light, point(1.1, 0.0, 0.0), eyev, normalv, 1.0);
    assert_color_approx(c1, WHITE);
    assert_color_approx(c2, BLACK);
}

#[test]
fn stripes_with_an_object_transformation() {
    let object = Object::sphere().with_transform(scaling(2.0, 2.0, 2.0));
    let pattern = Pattern::stripes(WHITE, BLACK);
    assert_eq!(
        pattern.color_at_object(&object, point(1.5, 0.0, 0.0)),
        WHITE
    );
}

#[test]
fn stripes_with_a_pattern_transformation() {
    let object = Object::sphere();
    let pattern =
        Pattern::stripes(WHITE, BLACK).with_transform(Transform::new(scaling(2.0, 2.0, 2.0)));
    assert_eq!(
        pattern.color_at_object(&object, point(1.5, 0.0, 0.0)),
        WHITE
    );
}

#[test]
fn stripes_with_both_an_object_and_a_pattern_transformation() {
    let object = Object::sphere().with_transform(scaling(2.0, 2.0, 2.0));
    let pattern =
        Pattern::stripes(WHITE, BLACK).with_transform(Transform::new(translation(0.5, 0.0, 0.0)));
    assert_eq!(
        pattern.color_at_object(&object, point(2.5, 0.0, 0.0)),
        WHITE
    );
}

#[test]
fn the_default_pattern_transformation() {
    assert_eq!(Pattern::position().transform, Transform::IDENTITY);
}

#[test]
fn assigning_a_transformation() {
    let pattern = Pattern::position().with_transform(Transform::new(translation(1.0, 2.0, 3.0)));
    assert_eq!(pattern.transform.matrix(), translation(1.0, 2.0, 3.0));
}

#[test]
fn a_pattern_with_an_object_transformation() {
    let shape = Object::sphere().with_transform(scaling(2.0, 2.0, 2.0));
    let c = Pattern::position().color_at_object(&shape, point(2.0, 3.0, 4.0));
    assert_color_approx(c, color(1.0, 1.5, 2.0));
}

#[test]
fn a_pattern_with_a_pattern_transformation() {
    let shape = Object::sphere();
    let pattern = Pattern::position().with_transform(Transform::new(scaling(2.0, 2.0, 2.0)));
    let c = pattern.color_at_object(&shape, point(2.0, 3.0, 4.0));
    assert_color_approx(c, color(1.0, 1.5, 2.0));
}

#[test]
fn a_pattern_with_both_an_object_and_a_pattern_transformation() {
    let shape = Object::sphere().with_transform(scaling(2.0, 2.0, 2.0));
    let pattern = Pattern::position().with_transform(Transform::new(translation(0.5, 1.0, 1.5)));
    let c = pattern.color_at_object(&shape, point(2.5, 3.0, 3.5));
    assert_color_approx(c, color(0.75, 0.5, 0.25));
}

/// SEED-NOTES.md erratum 6: the fraction is `x - floor(x)` (the seed's formula flips the sign).
#[test]
fn a_gradient_linearly_interpolates_between_colors() {
    let pattern = Pattern::gradient(WHITE, BLACK);
    assert_color_approx(pattern.pattern_at(point(0.0, 0.0, 0.0)), WHITE);
    assert_color_approx(
        pattern.pattern_at(point(0.25, 0.0, 0.0)),
        color(0.75, 0.75, 0.75),
    );
    assert_color_approx(
        pattern.pattern_at(point(0.5, 0.0, 0.0)),
        color(0.5, 0.5, 0.5),
    );
    assert_color_approx(
        pattern.pattern_at(point(0.75, 0.0, 0.0)),
        color(0.25, 0.25, 0.25),
    );
}

#[test]
fn a_ring_should_extend_in_both_x_and_z() {
    let pattern = Pattern::rings(WHITE, BLACK);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(1.0, 0.0, 0.0)), BLACK);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 1.0)), BLACK);
    // 0.708 = just slightly more than √2/2
    assert_eq!(pattern.pattern_at(point(0.708, 0.0, 0.708)), BLACK);
}

#[test]
fn checkers_should_repeat_in_x() {
    let pattern = Pattern::checkers(WHITE, BLACK);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(0.99, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(1.01, 0.0, 0.0)), BLACK);
}

#[test]
fn checkers_should_repeat_in_y() {
    let pattern = Pattern::checkers(WHITE, BLACK);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(0.0, 0.99, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(0.0, 1.01, 0.0)), BLACK);
}

#[test]
fn checkers_should_repeat_in_z() {
    let pattern = Pattern::checkers(WHITE, BLACK);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 0.99)), WHITE);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, 1.01)), BLACK);
}

// ---- The chapter's extras ("Putting it together") ----

#[test]
fn a_radial_gradient_blends_outward_from_the_y_axis() {
    let pattern = Pattern::radial_gradient(WHITE, BLACK);
    assert_color_approx(pattern.pattern_at(point(0.0, 5.0, 0.0)), WHITE);
    assert_color_approx(
        pattern.pattern_at(point(0.3, 0.0, 0.4)),
        color(0.5, 0.5, 0.5),
    );
    assert_color_approx(
        pattern.pattern_at(point(0.0, 0.0, 0.75)),
        color(0.25, 0.25, 0.25),
    );
    // It repeats every unit of radius.
    assert_color_approx(
        pattern.pattern_at(point(1.5, 0.0, 0.0)),
        color(0.5, 0.5, 0.5),
    );
}

#[test]
fn a_nested_pattern_evaluates_each_cell_in_its_sub_patterns_space() {
    let red = color(1.0, 0.0, 0.0);
    let green = color(0.0, 1.0, 0.0);
    // Checkers of 2-unit cells; the first cells hold stripes along x, the second hold stripes
    // turned a quarter turn (so they change along z). Sub-patterns live in the checkers' space,
    // so each is scaled by one half to show 1-unit stripes in the world.
    let half = scaling(0.5, 0.5, 0.5);
    let along_x = Pattern::stripes(red, green).with_transform(Transform::new(half));
    let along_z = Pattern::stripes(WHITE, BLACK).with_transform(Transform::new(
        rotation_y(std::f64::consts::FRAC_PI_2) * half,
    ));
    let checkers = Pattern::new(PatternKind::Checkers(vec![along_x, along_z]))
        .with_transform(Transform::new(scaling(2.0, 2.0, 2.0)));
    let object = Object::sphere();
    // The first cell: stripes along x.
    assert_eq!(checkers.color_at_object(&object, point(0.5, 0.0, 0.5)), red);
    assert_eq!(
        checkers.color_at_object(&object, point(1.5, 0.0, 0.5)),
        green
    );
    // The next cell along x: the turned stripes change with z, not x.
    assert_eq!(
        checkers.color_at_object(&object, point(2.5, 0.0, 0.5)),
        BLACK
    );
    assert_eq!(
        checkers.color_at_object(&object, point(3.5, 0.0, 0.5)),
        BLACK
    );
    assert_eq!(
        checkers.color_at_object(&object, point(2.5, 0.0, 1.5)),
        WHITE
    );
}

#[test]
fn a_blended_pattern_averages_its_patterns() {
    let a = Pattern::stripes(WHITE, BLACK);
    let b = Pattern::stripes(WHITE, BLACK)
        .with_transform(Transform::new(rotation_y(std::f64::consts::FRAC_PI_2)));
    let blended = Pattern::new(PatternKind::Blended(vec![a, b]));
    assert_color_approx(blended.pattern_at(point(0.5, 0.0, -0.5)), WHITE);
    assert_color_approx(
        blended.pattern_at(point(1.5, 0.0, -0.5)),
        color(0.5, 0.5, 0.5),
    );
    assert_color_approx(blended.pattern_at(point(1.5, 0.0, 0.5)), BLACK);
}

#[test]
fn a_perturbed_pattern_with_scale_zero_is_its_inner_pattern() {
    let inner = Pattern::stripes(WHITE, BLACK);
    let perturbed = Pattern::new(PatternKind::Perturbed {
        pattern: Box::new(inner.clone()),
        scale: 0.0,
    });
    for x in [-1.3, -0.2, 0.4, 0.99, 1.7] {
        let p = point(x, 0.3, -0.7);
        assert_eq!(perturbed.pattern_at(p), inner.pattern_at(p));
    }
}

#[test]
fn a_perturbed_pattern_moves_points_by_bounded_deterministic_noise() {
    let perturbed = Pattern::new(PatternKind::Perturbed {
        pattern: Box::new(Pattern::position()),
        scale: 0.2,
    });
    let mut moved = false;
    for i in 0..200 {
        let p = point(i as f64 * 0.137, i as f64 * -0.071, i as f64 * 0.029);
        let c = perturbed.pattern_at(p);
        let q = point(c.red, c.green, c.blue);
        // Each noise lookup interpolates (convexly) between corner terms g·d, where every
        // gradient g has two ±1 components and every offset d is within 1 per axis: |noise| ≤ 2,
        // so the point moves at most 2 × 0.2 per axis. (In practice the noise peaks just above 1.)
        assert!(
            (q - p).abs().max_element() <= 2.0 * 0.2 + 1e-12,
            "{p:?} moved to {q:?}"
        );
        moved |= (q - p).length() > 1e-3;
        assert_eq!(perturbed.pattern_at(p), c, "noise must be deterministic");
    }
    assert!(moved, "the perturbation must move points");
}

#[test]
fn stripes_with_three_colors_cycle_through_them() {
    let red = color(1.0, 0.0, 0.0);
    let pattern = Pattern::new(PatternKind::Stripes(vec![
        Pattern::solid(WHITE),
        Pattern::solid(BLACK),
        Pattern::solid(red),
    ]));
    assert_eq!(pattern.pattern_at(point(0.5, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(1.5, 0.0, 0.0)), BLACK);
    assert_eq!(pattern.pattern_at(point(2.5, 0.0, 0.0)), red);
    assert_eq!(pattern.pattern_at(point(3.5, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(-0.5, 0.0, 0.0)), red);
}

#[test]
fn rings_with_three_colors_cycle_through_them() {
    let red = color(1.0, 0.0, 0.0);
    let pattern = Pattern::new(PatternKind::Rings(vec![
        Pattern::solid(WHITE),
        Pattern::solid(BLACK),
        Pattern::solid(red),
    ]));
    assert_eq!(pattern.pattern_at(point(0.5, 0.0, 0.0)), WHITE);
    assert_eq!(pattern.pattern_at(point(0.0, 0.0, -1.5)), BLACK);
    // Radius 2.5: (1.5, 2.0) is a 3-4-5 triangle scaled by one half.
    assert_eq!(pattern.pattern_at(point(1.5, 7.0, 2.0)), red);
    assert_eq!(pattern.pattern_at(point(-3.5, 0.0, 0.0)), WHITE);
}

#[test]
fn checkers_with_three_colors_cycle_through_them() {
    let red = color(1.0, 0.0, 0.0);
    let pattern = Pattern::new(PatternKind::Checkers(vec![
        Pattern::solid(WHITE),
        Pattern::solid(BLACK),
        Pattern::solid(red),
    ]));
    assert_eq!(pattern.pattern_at(point(0.5, 0.5, 0.5)), WHITE);
    assert_eq!(pattern.pattern_at(point(1.5, 0.5, 0.5)), BLACK);
    assert_eq!(pattern.pattern_at(point(1.5, 1.5, 0.5)), red);
    assert_eq!(pattern.pattern_at(point(1.5, 1.5, 1.5)), WHITE);
    // Cell sum -1 wraps round to the last colour.
    assert_eq!(pattern.pattern_at(point(-0.5, 0.5, 0.5)), red);
}

#[test]
fn a_gradient_between_nested_patterns_blends_their_colors() {
    let red = color(1.0, 0.0, 0.0);
    let green = color(0.0, 1.0, 0.0);
    let pattern = Pattern::new(PatternKind::Gradient(
        Box::new(Pattern::solid(WHITE)),
        Box::new(Pattern::stripes(red, green)),
    ));
    // A quarter of the way across each unit: 3/4 white + 1/4 of whichever stripe is there.
    assert_color_approx(
        pattern.pattern_at(point(0.25, 0.0, 0.0)),
        color(1.0, 0.75, 0.75),
    );
    assert_color_approx(
        pattern.pattern_at(point(1.25, 0.0, 0.0)),
        color(0.75, 1.0, 0.75),
    );
}

#[test]
fn a_perturbed_patterns_offset_grows_linearly_with_its_scale() {
    let perturbed = |scale| {
        Pattern::new(PatternKind::Perturbed {
            pattern: Box::new(Pattern::position()),
            scale,
        })
    };
    let (small, large) = (perturbed(0.1), perturbed(0.3));
    let mut largest: f64 = 0.0;
    for i in 0..50 {
        let p = point(
            i as f64 * 0.291 - 3.0,
            i as f64 * 0.113,
            2.0 - i as f64 * 0.057,
        );
        let offset = |pattern: &Pattern| {
            let c = pattern.pattern_at(p);
            point(c.red, c.green, c.blue) - p
        };
        // The noise is read at the unperturbed point, so only its scale differs.
        assert_vec_approx(offset(&large), offset(&small) * 3.0);
        largest = largest.max(offset(&large).abs().max_element());
    }
    assert!(largest > 0.01, "the noise must move the points");
}
