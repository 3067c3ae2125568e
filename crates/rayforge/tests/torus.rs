//! The torus and its quartic solver (Fundamentals of Ray Tracing, chapter 13; the next-steps
//! chapter of The Ray Tracer Challenge lists the torus as an extension).

use rayforge::geometry::toroidal_map;
use rayforge::math::roots::{evaluate, polynomial_roots_in, MAX_DEGREE};
use rayforge::{point, vector, Object, Ray, Shape};

/// The coefficients (lowest first) of the monic polynomial with these roots.
fn from_roots(roots: &[f64]) -> Vec<f64> {
    let mut c = vec![1.0];
    for &r in roots {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i + 1] += ci;
            next[i] -= r * ci;
        }
        c = next;
    }
    c
}

fn roots_in(c: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let mut out = [0.0; MAX_DEGREE];
    let n = polynomial_roots_in(c, lo, hi, &mut out);
    out[..n].to_vec()
}

fn assert_roots(found: &[f64], expected: &[f64], tolerance: f64) {
    assert_eq!(
        found.len(),
        expected.len(),
        "found {found:?}, expected {expected:?}"
    );
    for (f, e) in found.iter().zip(expected) {
        assert!(
            (f - e).abs() <= tolerance,
            "found {found:?}, expected {expected:?}"
        );
    }
}

#[test]
fn quartic_with_four_distinct_roots() {
    let c = from_roots(&[1.0, 2.0, 3.0, 4.0]);
    assert_roots(&roots_in(&c, -10.0, 10.0), &[1.0, 2.0, 3.0, 4.0], 1e-12);
}

#[test]
fn quartic_roots_are_limited_to_the_interval() {
    let c = from_roots(&[1.0, 2.0, 3.0, 4.0]);
    assert_roots(&roots_in(&c, 1.5, 3.5), &[2.0, 3.0], 1e-12);
}

#[test]
fn quartic_with_no_real_roots() {
    // (t² + 1)(t² + 4)
    let c = [4.0, 0.0, 5.0, 0.0, 1.0];
    assert!(roots_in(&c, -100.0, 100.0).is_empty());
}

#[test]
fn quartic_with_two_roots_a_millionth_apart() {
    let c = from_roots(&[-2.0, 1.0, 1.000001, 5.0]);
    assert_roots(
        &roots_in(&c, -10.0, 10.0),
        &[-2.0, 1.0, 1.000001, 5.0],
        1e-10,
    );
}

#[test]
fn quartic_with_a_double_root_reports_it_once() {
    let c = from_roots(&[-1.0, 2.0, 2.0, 3.0]);
    let found = roots_in(&c, -10.0, 10.0);
    // Rounding may split a double root into two neighbours or leave it single, never lose it.
    assert!(found.iter().any(|t| (t - 2.0).abs() < 1e-6), "{found:?}");
    assert!(found.iter().any(|t| (t + 1.0).abs() < 1e-12), "{found:?}");
    assert!(found.iter().any(|t| (t - 3.0).abs() < 1e-12), "{found:?}");
}

#[test]
fn quartic_with_roots_of_very_different_size() {
    let c = from_roots(&[-1000.0, 0.001, 0.002, 1000.0]);
    assert_roots(
        &roots_in(&c, -2000.0, 2000.0),
        &[-1000.0, 0.001, 0.002, 1000.0],
        1e-9,
    );
}

#[test]
fn cubic_and_quadratic_and_linear_cases() {
    assert_roots(
        &roots_in(&from_roots(&[-3.0, 0.5, 7.0]), -10.0, 10.0),
        &[-3.0, 0.5, 7.0],
        1e-12,
    );
    assert_roots(
        &roots_in(&[-6.0, 1.0, 1.0], -10.0, 10.0),
        &[-3.0, 2.0],
        1e-12,
    );
    assert_roots(&roots_in(&[-6.0, 2.0], -10.0, 10.0), &[3.0], 1e-12);
    // Leading zeros lower the degree.
    assert_roots(
        &roots_in(&[-6.0, 2.0, 0.0, 0.0, 0.0], -10.0, 10.0),
        &[3.0],
        1e-12,
    );
}

#[test]
fn every_root_found_is_a_root() {
    let c = from_roots(&[-1.3, -0.2, 0.7, 2.9]);
    let found = roots_in(&c, -10.0, 10.0);
    assert_eq!(found.len(), 4, "{found:?}");
    for t in found {
        assert!(
            evaluate(&c, t).abs() < 1e-12,
            "p({t}) = {}",
            evaluate(&c, t)
        );
    }
}

fn torus(major: f64, minor: f64) -> Shape {
    Shape::Torus { major, minor }
}

fn local_hits(shape: &Shape, ray: &Ray) -> Vec<f64> {
    let mut ts = Vec::new();
    shape.intersect(ray, |t| ts.push(t));
    ts.sort_by(f64::total_cmp);
    ts
}

#[test]
fn a_ray_along_a_diameter_hits_the_tube_four_times() {
    let t = torus(3.0, 1.0);
    let ray = Ray::new(point(-10.0, 0.0, 0.0), vector(1.0, 0.0, 0.0));
    assert_roots(&local_hits(&t, &ray), &[6.0, 8.0, 12.0, 14.0], 1e-9);
}

#[test]
fn a_ray_through_the_hole_misses() {
    let t = torus(3.0, 1.0);
    let ray = Ray::new(point(0.0, 10.0, 0.0), vector(0.0, -1.0, 0.0));
    assert!(local_hits(&t, &ray).is_empty());
}

#[test]
fn a_ray_down_through_the_tube_hits_its_top_and_bottom() {
    let t = torus(3.0, 1.0);
    let ray = Ray::new(point(3.0, 10.0, 0.0), vector(0.0, -2.0, 0.0));
    assert_roots(&local_hits(&t, &ray), &[4.5, 5.5], 1e-9);
}

#[test]
fn a_ray_outside_the_bounding_sphere_misses() {
    let t = torus(3.0, 1.0);
    let ray = Ray::new(point(-10.0, 0.0, 4.5), vector(1.0, 0.0, 0.0));
    assert!(local_hits(&t, &ray).is_empty());
}

#[test]
fn a_ray_from_a_million_units_away_keeps_its_precision() {
    let t = torus(3.0, 1.0);
    let ray = Ray::new(point(-1e6, 0.0, 0.0), vector(1.0, 0.0, 0.0));
    let expected = [1e6 - 4.0, 1e6 - 2.0, 1e6 + 2.0, 1e6 + 4.0];
    assert_roots(&local_hits(&t, &ray), &expected, 1e-8);
}

#[test]
fn a_ray_grazing_the_top_of_the_tube_hits_near_the_tangent_points() {
    let t = torus(3.0, 1.0);
    // Just below the top (y = r), the ray meets the tube in two close pairs around x = ±3.
    let ray = Ray::new(point(-10.0, 1.0 - 1e-8, 0.0), vector(1.0, 0.0, 0.0));
    let hits = local_hits(&t, &ray);
    assert_eq!(hits.len(), 4, "{hits:?}");
    for (h, centre) in hits.iter().zip([7.0, 7.0, 13.0, 13.0]) {
        assert!((h - centre).abs() < 1e-3, "{hits:?}");
    }
    // Each hit is on the surface.
    for h in hits {
        let p = ray.position(h);
        let radial = p.x.hypot(p.z) - 3.0;
        assert!((radial * radial + p.y * p.y - 1.0).abs() < 1e-7, "{p:?}");
    }
    // Just above, nothing.
    let above = Ray::new(point(-10.0, 1.0 + 1e-8, 0.0), vector(1.0, 0.0, 0.0));
    assert!(local_hits(&t, &above).is_empty());
}

#[test]
fn a_ray_grazing_the_outer_silhouette_hits_once_or_twice_close_to_the_tangent() {
    let t = torus(3.0, 1.0);
    let ray = Ray::new(point(-10.0, 0.0, 4.0 - 1e-9), vector(1.0, 0.0, 0.0));
    let hits = local_hits(&t, &ray);
    assert!(!hits.is_empty());
    for h in hits {
        assert!((h - 10.0).abs() < 1e-3, "{h}");
    }
}

#[test]
fn hits_on_a_transformed_torus_are_on_its_surface() {
    use rayforge::math::{rotation_x, scaling, translation};
    let object = Object::new(torus(1.0, 0.25))
        .with_transform(translation(1.0, 2.0, 3.0) * rotation_x(0.7) * scaling(2.0, 2.0, 2.0));
    let ray = Ray::new(point(3.0, 2.1, -20.0), vector(0.0, 0.001, 1.0));
    let xs = object.intersections(&ray);
    assert!(!xs.is_empty());
    for x in xs {
        let p = object.world_to_object(ray.position(x.t));
        let radial = p.x.hypot(p.z) - 1.0;
        assert!((radial * radial + p.y * p.y - 0.0625).abs() < 1e-9, "{p:?}");
    }
}

#[test]
fn normals_point_away_from_the_centre_circle() {
    let t = torus(3.0, 1.0);
    let cases = [
        (point(4.0, 0.0, 0.0), vector(1.0, 0.0, 0.0)),
        (point(2.0, 0.0, 0.0), vector(-1.0, 0.0, 0.0)),
        (point(0.0, 1.0, 3.0), vector(0.0, 1.0, 0.0)),
        (point(0.0, -1.0, -3.0), vector(0.0, -1.0, 0.0)),
        (
            point(3.0 + 0.5f64.sqrt(), 0.5f64.sqrt(), 0.0),
            vector(0.5f64.sqrt(), 0.5f64.sqrt(), 0.0),
        ),
    ];
    for (p, expected) in cases {
        let n = t.normal_at(p).normalize();
        assert!((n - expected).length() < 1e-9, "at {p:?}: {n:?}");
    }
}

#[test]
fn a_spindle_torus_has_outward_normals_on_its_apple_and_its_lemon() {
    // R = 1, r = 2: the apple reaches x = 3, the lemon (swept by the tube's far side) x = 1.
    let (major, minor) = (1.0, 2.0);
    let t = torus(major, minor);
    // The surface's equation f(p) = (|p|² + R² − r²)² − 4R²(x² + z²), negative inside the solid.
    let f = |p: rayforge::math::Point3| {
        let e = p.length_squared() + major * major - minor * minor;
        e * e - 4.0 * major * major * (p.x * p.x + p.z * p.z)
    };
    let cases = [
        // On the apple's equator, outwards.
        (point(3.0, 0.0, 0.0), vector(1.0, 0.0, 0.0)),
        // On the lemon's equator: the solid is outside the lemon, so the normal points in.
        (point(1.0, 0.0, 0.0), vector(-1.0, 0.0, 0.0)),
        (point(0.0, 0.0, -1.0), vector(0.0, 0.0, 1.0)),
    ];
    for (p, expected) in cases {
        assert!(f(p).abs() < 1e-9, "{p:?} is on the surface");
        let n = t.normal_at(p).normalize();
        assert!((n - expected).length() < 1e-9, "at {p:?}: {n:?}");
    }
    // Anywhere on the lemon (tube angle φ past acos(−R/r)) and the apple, the normal is the
    // direction of the equation's gradient, out of the solid.
    for k in 1..40 {
        let phi = k as f64 * std::f64::consts::TAU / 40.0;
        // The tube's circle about the centre-circle point (0.6, 0, 0.8)·R; ρ < 0 is the lemon.
        let rho = major + minor * phi.cos();
        let p = point(rho * 0.6, minor * phi.sin(), rho * 0.8);
        let h = 1e-6;
        let gradient = vector(
            f(p + vector(h, 0.0, 0.0)) - f(p - vector(h, 0.0, 0.0)),
            f(p + vector(0.0, h, 0.0)) - f(p - vector(0.0, h, 0.0)),
            f(p + vector(0.0, 0.0, h)) - f(p - vector(0.0, 0.0, h)),
        );
        if gradient.length() < 1e-6 {
            continue;
        }
        let n = t.normal_at(p).normalize();
        assert!(
            (n - gradient.normalize()).length() < 1e-5,
            "at φ = {phi}: {n:?} against the gradient {:?}",
            gradient.normalize()
        );
    }
}

#[test]
fn bounds_of_a_torus() {
    let b = torus(3.0, 1.0).bounds();
    assert_eq!(b.min, point(-4.0, -1.0, -4.0));
    assert_eq!(b.max, point(4.0, 1.0, 4.0));
}

#[test]
fn toroidal_mapping_goes_around_the_axis_and_the_tube() {
    let cases = [
        (point(0.0, 0.0, 4.0), (0.5, 0.0)),
        (point(4.0, 0.0, 0.0), (0.25, 0.0)),
        (point(0.0, 1.0, 3.0), (0.5, 0.25)),
        (point(0.0, 0.0, 2.0), (0.5, 0.5)),
        (point(0.0, -1.0, 3.0), (0.5, 0.75)),
    ];
    for (p, (u, v)) in cases {
        let (mu, mv) = toroidal_map(p, 3.0);
        assert!(
            (mu - u).abs() < 1e-9 && (mv - v).abs() < 1e-9,
            "{p:?}: ({mu}, {mv})"
        );
    }
}

#[test]
fn quartic_whose_odd_term_is_tiny_keeps_its_four_roots() {
    // Nearly symmetric roots: the resolvent's largest root is then small and found mostly by
    // its polish.
    let c = from_roots(&[-2.0, -1.0, 1.0, 2.0 + 1e-9]);
    assert_roots(
        &roots_in(&c, -10.0, 10.0),
        &[-2.0, -1.0, 1.0, 2.0 + 1e-9],
        1e-12,
    );
    // And exactly symmetric ones: a biquadratic.
    let c = from_roots(&[-2.0, -1.0, 1.0, 2.0]);
    assert_roots(&roots_in(&c, -10.0, 10.0), &[-2.0, -1.0, 1.0, 2.0], 1e-12);
}

#[test]
fn cubic_with_one_real_root() {
    // (t − 2)(t² + 1)
    assert_roots(
        &roots_in(&[-2.0, 1.0, -2.0, 1.0], -10.0, 10.0),
        &[2.0],
        1e-12,
    );
}
