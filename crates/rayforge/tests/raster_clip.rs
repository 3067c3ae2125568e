//! Clipping (the book's "Clipping" chapter): planes, bounding spheres, and triangles split at
//! a plane with their attributes interpolated at the new vertices.

use glam::DVec3;
use rayforge::math::view_transform;
use rayforge::raster::{clip_triangle, ClipPlane, ClipVertex, Projection, SphereSide};
use rayforge::{point, vector, Camera};

/// A vertex with an intensity attribute, as in the book's shaded triangles.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Shaded {
    p: DVec3,
    h: f64,
}

impl ClipVertex for Shaded {
    fn position(&self) -> DVec3 {
        self.p
    }
    fn lerp(&self, other: &Self, t: f64) -> Self {
        Shaded {
            p: self.p + (other.p - self.p) * t,
            h: self.h + (other.h - self.h) * t,
        }
    }
}

fn v(x: f64, y: f64, z: f64, h: f64) -> Shaded {
    Shaded {
        p: DVec3::new(x, y, z),
        h,
    }
}

fn near(z: f64) -> ClipPlane {
    ClipPlane::new(DVec3::Z, -z)
}

fn assert_vertex(actual: Shaded, expected: Shaded) {
    assert!(
        (actual.p - expected.p).length() < 1e-12 && (actual.h - expected.h).abs() < 1e-12,
        "{actual:?} != {expected:?}"
    );
}

#[test]
fn planes_are_normalised_and_give_signed_distances() {
    let plane = ClipPlane::new(DVec3::new(0.0, 0.0, 2.0), -2.0);
    assert_eq!(plane.normal, DVec3::Z);
    assert_eq!(plane.d, -1.0);
    assert_eq!(plane.signed_distance(DVec3::new(5.0, 5.0, 3.0)), 2.0);
    assert_eq!(plane.signed_distance(DVec3::new(0.0, 0.0, 0.0)), -1.0);
}

#[test]
fn bounding_spheres_are_inside_outside_or_crossing() {
    let plane = near(1.0);
    assert_eq!(
        plane.classify_sphere(DVec3::new(0.0, 0.0, 5.0), 2.0),
        SphereSide::Inside
    );
    assert_eq!(
        plane.classify_sphere(DVec3::new(0.0, 0.0, -5.0), 2.0),
        SphereSide::Outside
    );
    assert_eq!(
        plane.classify_sphere(DVec3::new(0.0, 0.0, 2.0), 2.0),
        SphereSide::Crossing
    );
}

#[test]
fn a_triangle_wholly_inside_or_outside_is_kept_or_dropped() {
    let tri = [
        v(0.0, 0.0, 2.0, 0.0),
        v(1.0, 0.0, 3.0, 0.0),
        v(0.0, 1.0, 4.0, 0.0),
    ];
    assert_eq!(clip_triangle(&[near(1.0)], tri).triangles(), [tri]);
    assert!(clip_triangle(&[near(5.0)], tri).triangles().is_empty());
}

#[test]
fn one_vertex_inside_leaves_one_smaller_triangle() {
    // A at z = 3 is in front of z = 1; B and C at z = -1 are behind: A B' C' with B', C' half
    // way along AB and AC, intensities half way too.
    let (a, b, c) = (
        v(0.0, 0.0, 3.0, 1.0),
        v(4.0, 0.0, -1.0, 0.0),
        v(0.0, 4.0, -1.0, 0.5),
    );
    let clipped = clip_triangle(&[near(1.0)], [a, b, c]);
    let t = clipped.triangles();
    assert_eq!(t.len(), 1);
    assert_vertex(t[0][0], a);
    assert_vertex(t[0][1], v(2.0, 0.0, 1.0, 0.5));
    assert_vertex(t[0][2], v(0.0, 2.0, 1.0, 0.75));
}

#[test]
fn two_vertices_inside_leave_two_triangles() {
    // A and B in front, C behind: A B A' and A' B B', A' on AC and B' on BC.
    let (a, b, c) = (
        v(0.0, 0.0, 2.0, 0.0),
        v(2.0, 0.0, 2.0, 1.0),
        v(0.0, 2.0, -2.0, 1.0),
    );
    let clipped = clip_triangle(&[near(1.0)], [a, b, c]);
    let t = clipped.triangles();
    assert_eq!(t.len(), 2);
    let a2 = v(0.0, 0.5, 1.0, 0.25);
    let b2 = v(1.5, 0.5, 1.0, 1.0);
    assert_vertex(t[0][0], a);
    assert_vertex(t[0][1], b);
    assert_vertex(t[0][2], a2);
    assert_vertex(t[1][0], a2);
    assert_vertex(t[1][1], b);
    assert_vertex(t[1][2], b2);
    // Whatever vertex comes first, the pieces are the same (rotated), wound the same way.
    let rotated = clip_triangle(&[near(1.0)], [c, a, b]);
    assert_eq!(rotated.triangles().len(), 2);
    for (p, q) in rotated.triangles().iter().zip(t) {
        let normal = |t: &[Shaded; 3]| (t[1].p - t[0].p).cross(t[2].p - t[0].p).normalize();
        assert!((normal(p) - normal(q)).length() < 1e-12);
    }
}

#[test]
fn the_pieces_cover_exactly_the_inside_part() {
    // Clip a triangle by two planes; the areas of the pieces add up to the inside area.
    let tri = [
        v(-4.0, -4.0, 5.0, 0.0),
        v(4.0, -4.0, 5.0, 0.0),
        v(0.0, 4.0, 5.0, 0.0),
    ];
    let left = ClipPlane::new(DVec3::X, 0.0); // x >= 0
    let bottom = ClipPlane::new(DVec3::Y, 0.0); // y >= 0
    let pieces = clip_triangle(&[left, bottom], tri);
    let area: f64 = pieces
        .triangles()
        .iter()
        .map(|t| (t[1].p - t[0].p).cross(t[2].p - t[0].p).length() / 2.0)
        .sum();
    // Inside x >= 0, y >= 0 the triangle is the one under y = 4 - 2x: area 4.
    assert!((area - 4.0).abs() < 1e-12, "{area}");
    for t in pieces.triangles() {
        for vtx in t {
            assert!(vtx.p.x >= -1e-12 && vtx.p.y >= -1e-12);
        }
    }
}

#[test]
fn the_cameras_clipping_planes_follow_its_field_of_view_and_aspect() {
    // 90° across a 200×100 image: the sides at 45°, the top and bottom at atan(1/2).
    let camera = Camera::new(200, 100, std::f64::consts::FRAC_PI_2).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    let projection = Projection::new(&camera, 0.5);
    let [n, l, r, b, t] = *projection.planes();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert_eq!(n.normal, DVec3::Z);
    assert_eq!(n.d, -0.5);
    assert!((l.normal - DVec3::new(s, 0.0, s)).length() < 1e-12);
    assert!((r.normal - DVec3::new(-s, 0.0, s)).length() < 1e-12);
    let k = 1.0 / 1.25f64.sqrt();
    assert!((b.normal - DVec3::new(0.0, k, 0.5 * k)).length() < 1e-12);
    assert!((t.normal - DVec3::new(0.0, -k, 0.5 * k)).length() < 1e-12);
    // A point on the left edge of the image at depth 2 projects to x = 0, mid-height.
    let p = projection.project(DVec3::new(-2.0, 0.0, 2.0));
    assert!((p.x - 0.0).abs() < 1e-9 && (p.y - 50.0).abs() < 1e-9);
}
