//! Chapters 7 to 12, as properties: what the book's scenarios check at a few chosen points must
//! hold for random transforms, rays and points (acne offsets, transform invariance, unit normals,
//! Fresnel bounds, camera rays, patterns that move with their objects).
use glam::DMat4;
use proptest::prelude::*;
use rayforge::book::{BookPattern, BookWorld};
use rayforge::color::color;
use rayforge::math::{
    rotation_x, rotation_y, rotation_z, scaling, shearing, translation, view_transform,
};
use rayforge::{
    hit, point, prepare_computations, schlick, vector, Camera, Color, Intersection, Light,
    Material, Object, Pattern, PatternKind, Point3, Ray, Transform, Vec3, World,
};
use std::f64::consts::PI;

/// The chapter 7 to 12 primitives: 0 sphere, 1 cube, 2 plane.
fn object(kind: u8) -> Object {
    match kind {
        0 => Object::sphere(),
        1 => Object::cube(),
        _ => Object::plane(),
    }
}

/// A random invertible transform: scale (mirrors included), a mild shear, three rotations and
/// a translation. The shear's coefficients stay within ±0.3, which keeps its determinant above
/// 0.67; the scales stay at least 0.3 in size.
fn invertible_transform() -> impl Strategy<Value = DMat4> {
    (
        prop::array::uniform3(0.3..3.0f64),
        prop::array::uniform3(any::<bool>()),
        prop::array::uniform6(-0.3..0.3f64),
        prop::array::uniform3(-PI..PI),
        prop::array::uniform3(-5.0..5.0f64),
    )
        .prop_map(|(size, mirror, shear, angle, offset)| {
            let sign = |m: bool| if m { -1.0 } else { 1.0 };
            translation(offset[0], offset[1], offset[2])
                * rotation_x(angle[0])
                * rotation_y(angle[1])
                * rotation_z(angle[2])
                * shearing(shear[0], shear[1], shear[2], shear[3], shear[4], shear[5])
                * scaling(
                    size[0] * sign(mirror[0]),
                    size[1] * sign(mirror[1]),
                    size[2] * sign(mirror[2]),
                )
        })
}

/// A unit direction (from a random vector that is not too short to normalise).
fn direction() -> impl Strategy<Value = Vec3> {
    prop::array::uniform3(-1.0..1.0f64)
        .prop_map(|[x, y, z]| vector(x, y, z))
        .prop_filter("too short to normalise", |v| v.length() > 0.1)
        .prop_map(Vec3::normalize)
}

/// An object-space ray that certainly crosses the shape, far from grazing it: it passes through
/// a point at least 0.5 inside the sphere or cube (or through the plane at no less than about 6°),
/// starting 5 units before that point, outside the sphere and cube.
fn crossing_ray(kind: u8, target: [f64; 3], d: Vec3) -> Option<Ray> {
    let q = if kind == 2 {
        if d.y.abs() < 0.1 {
            return None;
        }
        point(target[0] * 10.0, 0.0, target[2] * 10.0)
    } else {
        point(target[0], target[1], target[2])
    };
    Some(Ray::new(q - d * 5.0, d))
}

fn sorted_ts(xs: &[Intersection<'_>]) -> Vec<f64> {
    let mut ts: Vec<f64> = xs.iter().map(|i| i.t).collect();
    ts.sort_by(f64::total_cmp);
    ts
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Chapter 8's acne: a ray leaving a hit from `over_point` along the normal never meets the
    /// surface again ahead of it. The three shapes are convex (or flat), so leaving along the
    /// outward normal there is nothing ahead at any distance; a hit at a tiny positive `t` would
    /// be the surface shadowing itself. Nor does the lone object shadow a light straight above.
    #[test]
    fn a_ray_leaving_over_point_along_the_normal_never_rehits_the_surface(
        kind in 0u8..3,
        m in invertible_transform(),
        target in prop::array::uniform3(-0.5..0.5f64),
        d in direction(),
    ) {
        let Some(local) = crossing_ray(kind, target, d) else {
            return Ok(());
        };
        let w = World {
            objects: vec![object(kind).with_transform(m)],
            ..World::default()
        };
        let shape = &w.objects[0];
        let ray = local.transform(m);
        let xs = w.intersect(&ray);
        let h = hit(&xs);
        prop_assert!(h.is_some(), "a ray through the inside must hit: {xs:?}");
        let comps = prepare_computations(h.unwrap(), &ray, &xs);
        // The ray starts outside the sphere and cube; a plane seen from below counts as inside
        // and turns its normal to face the eye, which is the side the ray leaves by.
        prop_assert!(kind == 2 || !comps.inside);
        let leaving = Ray::new(comps.over_point, comps.normalv);
        let again = shape.intersections(&leaving);
        prop_assert!(
            again.iter().all(|i| i.t <= 0.0),
            "re-hit at {:?}", sorted_ts(&again)
        );
        let light = comps.over_point + comps.normalv * 10.0;
        prop_assert!(!w.is_shadowed(light, comps.over_point));
    }

    /// Chapter 11's `under_point` starts refracted rays inside the solid: a ray from it leaves
    /// a sphere or cube exactly once ahead.
    #[test]
    fn the_under_point_lies_inside_the_solid(
        kind in 0u8..2,
        m in invertible_transform(),
        target in prop::array::uniform3(-0.5..0.5f64),
        d in direction(),
    ) {
        let shape = object(kind).with_transform(m);
        let ray = crossing_ray(kind, target, d).unwrap().transform(m);
        let xs = shape.intersections(&ray);
        let comps = prepare_computations(hit(&xs).unwrap(), &ray, &xs);
        // Keep clear of the cube's edges, where a nudge of EPSILON may legitimately cross into
        // the neighbouring face's slab.
        let on_face = shape.world_to_object(comps.point).abs();
        prop_assume!(kind == 0 || {
            let mut sorted = on_face.to_array();
            sorted.sort_by(f64::total_cmp);
            sorted[1] < 0.999
        });
        let inward = Ray::new(comps.under_point, -comps.normalv);
        let ahead = shape.intersections(&inward).iter().filter(|i| i.t > 0.0).count();
        prop_assert_eq!(ahead, 1);
    }

    /// Chapter 9's shape abstraction: moving the ray and the object by the same invertible
    /// transform changes no `t` (both meet the shape in the same object space).
    #[test]
    fn intersections_survive_transforming_the_ray_and_the_object_together(
        kind in 0u8..3,
        m in invertible_transform(),
        extra in invertible_transform(),
        target in prop::array::uniform3(-0.5..0.5f64),
        d in direction(),
    ) {
        let Some(local) = crossing_ray(kind, target, d) else {
            return Ok(());
        };
        let ray = local.transform(m);
        let shape = object(kind).with_transform(m);
        let moved = object(kind).with_transform(extra * m);
        let ts = sorted_ts(&shape.intersections(&ray));
        let moved_ts = sorted_ts(&moved.intersections(&ray.transform(extra)));
        prop_assert_eq!(ts.len(), if kind == 2 { 1 } else { 2 });
        prop_assert_eq!(ts.len(), moved_ts.len());
        for (a, b) in ts.iter().zip(&moved_ts) {
            prop_assert!((a - b).abs() < 1e-7 * (1.0 + a.abs()), "{ts:?} vs {moved_ts:?}");
        }
    }

    /// Chapters 5, 9 and 12: every intersection found, near or far, hit or not, lies on the
    /// surface: |p| = 1 on the sphere, the largest |coordinate| = 1 on the cube, y = 0 on the
    /// plane (in object space), for any ray at all.
    #[test]
    fn every_intersection_lies_on_the_surface(
        kind in 0u8..3,
        m in invertible_transform(),
        origin in prop::array::uniform3(-3.0..3.0f64),
        d in direction(),
    ) {
        let shape = object(kind).with_transform(m);
        let local = Ray::new(point(origin[0], origin[1], origin[2]), d);
        let ray = local.transform(m);
        for i in shape.intersections(&ray) {
            let p = shape.world_to_object(ray.position(i.t));
            let off_surface = match kind {
                0 => p.length() - 1.0,
                1 => p.abs().max_element() - 1.0,
                _ => p.y,
            };
            prop_assert!(off_surface.abs() < 1e-9, "t = {} gives {p:?}", i.t);
        }
    }

    /// Chapter 9's `normal_at`: after the inverse-transpose the normal is unit length,
    /// perpendicular to the transformed surface and on the outer side of it.
    #[test]
    fn normals_are_unit_length_perpendicular_and_outward(
        kind in 0u8..3,
        m in invertible_transform(),
        face in 0usize..3,
        positive in any::<bool>(),
        coords in prop::array::uniform3(-0.95..0.95f64),
        u in direction(),
    ) {
        // An object-space point on the surface, the outward direction there and two tangents.
        let (p, outward, tangents) = match kind {
            0 => {
                let (t1, t2) = u.any_orthonormal_pair();
                (u, u, [t1, t2])
            }
            1 => {
                let mut axes = [Vec3::X, Vec3::Y, Vec3::Z];
                axes.rotate_left(face);
                let normal = if positive { axes[0] } else { -axes[0] };
                let p = normal + axes[1] * coords[1] + axes[2] * coords[2];
                (p, normal, [axes[1], axes[2]])
            }
            _ => (point(coords[0] * 10.0, 0.0, coords[2] * 10.0), Vec3::Y, [Vec3::X, Vec3::Z]),
        };
        let shape = object(kind).with_transform(m);
        let t = Transform::new(m);
        let n = shape.normal_at(t.point(p));
        prop_assert!((n.length() - 1.0).abs() < 1e-9, "|n| = {}", n.length());
        for tangent in tangents {
            let along = t.vector(tangent);
            prop_assert!(n.dot(along).abs() < 1e-9 * along.length(), "n = {n:?}, tangent {along:?}");
        }
        prop_assert!(n.dot(t.vector(outward)) > 0.0);
    }

    /// Chapter 11's Schlick approximation: entering glass (n1 = 1, n2 = 1.5) from outside, the
    /// reflectance lies between r0 = ((1 - 1.5) / 2.5)² = 0.04 (head on) and 1 (grazing).
    #[test]
    fn the_reflectance_entering_glass_lies_between_r0_and_one(
        m in invertible_transform(),
        target in prop::array::uniform3(-0.5..0.5f64),
        d in direction(),
    ) {
        let shape = Object::glass_sphere().with_transform(m);
        let ray = crossing_ray(0, target, d).unwrap().transform(m);
        let xs = shape.intersections(&ray);
        let comps = prepare_computations(hit(&xs).unwrap(), &ray, &xs);
        prop_assert_eq!((comps.n1, comps.n2), (1.0, 1.5));
        let reflectance = schlick(&comps);
        prop_assert!((0.04 - 1e-12..=1.0).contains(&reflectance), "{reflectance}");
    }

    /// Chapter 11's Schlick approximation with n1 > n2: light leaving glass along the refracted
    /// ray (so at the refracted angle, inside) is reflected as much as light entering it, which is
    /// why the book switches to cos(θt) when n1 > n2.
    #[test]
    fn the_reflectance_is_the_same_entering_and_leaving_glass(
        m in invertible_transform(),
        target in prop::array::uniform3(-0.5..0.5f64),
        d in direction(),
    ) {
        let shape = Object::glass_sphere().with_transform(m);
        let ray = crossing_ray(0, target, d).unwrap().transform(m);
        let xs = shape.intersections(&ray);
        let entering = prepare_computations(hit(&xs).unwrap(), &ray, &xs);
        // Snell's law, as the book's refracted_color computes it.
        let n_ratio = entering.n1 / entering.n2;
        let cos_i = entering.eyev.dot(entering.normalv);
        let cos_t = (1.0 - n_ratio * n_ratio * (1.0 - cos_i * cos_i)).sqrt();
        let refracted =
            (entering.normalv * (n_ratio * cos_i - cos_t) - entering.eyev * n_ratio).normalize();
        // Back out along the refracted ray, from just inside the glass to the same point.
        let back = Ray::new(entering.point + refracted * 1e-3, -refracted);
        let back_xs = shape.intersections(&back);
        let leaving_hit = hit(&back_xs).unwrap();
        prop_assert!((leaving_hit.t - 1e-3).abs() < 1e-9);
        let leaving = prepare_computations(leaving_hit, &back, &back_xs);
        prop_assert_eq!((leaving.n1, leaving.n2), (1.5, 1.0));
        let (a, b) = (schlick(&entering), schlick(&leaving));
        prop_assert!((a - b).abs() < 1e-9, "entering {a}, leaving {b}");
    }

    /// Chapter 11's recursion limit: with no recursion left, a surface that is both mirror and
    /// glass gives neither a reflected nor a refracted colour, and `color_at` is the surface alone.
    #[test]
    fn no_recursion_left_means_no_reflected_or_refracted_color(
        m in invertible_transform(),
        target in prop::array::uniform3(-0.5..0.5f64),
        d in direction(),
    ) {
        let shiny = Material {
            reflective: 0.8,
            transparency: 0.8,
            refractive_index: 1.5,
            ..Material::default()
        };
        let w = World {
            objects: vec![
                Object::sphere().with_transform(m).with_material(shiny),
                Object::plane().with_transform(translation(0.0, -30.0, 0.0)),
            ],
            lights: vec![Light::point(point(-10.0, 10.0, -10.0), Color::WHITE)],
            ..World::default()
        };
        let ray = crossing_ray(0, target, d).unwrap().transform(m);
        let xs = w.intersect(&ray);
        let h = hit(&xs).unwrap();
        prop_assert!(std::ptr::eq(h.object, &w.objects[0]));
        let comps = prepare_computations(h, &ray, &xs);
        prop_assert_eq!(w.reflected_color(&comps, 0), Color::BLACK);
        prop_assert_eq!(w.refracted_color(&comps, 0), Color::BLACK);
        prop_assert_eq!(w.color_at(&ray, 0), w.shade_hit(&comps, 0));
    }

    /// Chapter 7's camera: every ray starts at the eye with a unit direction, and the middle
    /// pixel of an odd-sized canvas looks straight at `to`.
    #[test]
    fn camera_rays_start_at_the_eye_and_the_middle_one_looks_at_the_target(
        from in prop::array::uniform3(-10.0..10.0f64),
        forward in direction(),
        up in direction(),
        half_size in (1usize..60, 1usize..60),
        fov in 0.2..3.0f64,
        pixel in (0.0..1.0f64, 0.0..1.0f64),
    ) {
        prop_assume!(forward.cross(up).length() > 0.1);
        let from = point(from[0], from[1], from[2]);
        let to = from + forward * 3.0;
        let (hsize, vsize) = (2 * half_size.0 + 1, 2 * half_size.1 + 1);
        let c = Camera::new(hsize, vsize, fov).with_transform(view_transform(from, to, up));
        let middle = c.ray_for_pixel(hsize / 2, vsize / 2);
        prop_assert!((middle.origin - from).length() < 1e-9);
        prop_assert!((middle.direction - forward).length() < 1e-9, "{:?}", middle.direction);
        let px = ((pixel.0 * hsize as f64) as usize).min(hsize - 1);
        let py = ((pixel.1 * vsize as f64) as usize).min(vsize - 1);
        let r = c.ray_for_pixel(px, py);
        prop_assert!((r.origin - from).length() < 1e-9);
        prop_assert!((r.direction.length() - 1.0).abs() < 1e-9);
        // Every ray passes through the canvas one unit in front of the eye: it heads forward.
        prop_assert!(r.direction.dot(forward) > 0.0);
    }

    /// Chapter 10's `pattern_at_shape`: a pattern follows its object, so the colour at a moved
    /// point on the moved object is the colour at the original point (kept away from the cell
    /// walls, where rounding may pick either side).
    #[test]
    fn a_pattern_moves_with_its_object(
        m in invertible_transform(),
        coords in prop::array::uniform3(-4.0..4.0f64),
    ) {
        let p = point(coords[0], coords[1], coords[2]);
        // The stripes are half a unit wide, so the walls lie on every multiple of one half.
        let fraction = p * 2.0 - (p * 2.0).floor();
        prop_assume!(fraction.min_element() > 1e-6 && fraction.max_element() < 1.0 - 1e-6);
        let red = color(1.0, 0.0, 0.0);
        let pattern = Pattern::new(PatternKind::Checkers(vec![
            Pattern::stripes(Color::WHITE, Color::BLACK)
                .with_transform(Transform::new(scaling(0.5, 0.5, 0.5))),
            Pattern::solid(red),
        ]));
        let expected = pattern.pattern_at(p);
        let object = Object::sphere().with_transform(m);
        prop_assert_eq!(pattern.color_at_object(&object, Transform::new(m).point(p)), expected);
    }

    /// Chapter 10's perturbed pattern: the point moves by the noise times the scale, and the
    /// noise is bounded: each lookup interpolates convexly between corner terms g·d whose
    /// gradients g have two ±1 components and whose offsets d are within 1 per axis, so
    /// |noise| ≤ 2. It is also deterministic: the same point always gives the same colour.
    #[test]
    fn a_perturbed_pattern_moves_points_by_at_most_twice_its_scale(
        coords in prop::array::uniform3(-100.0..100.0f64),
        scale in 0.0..1.0f64,
    ) {
        let p = point(coords[0], coords[1], coords[2]);
        let perturbed = Pattern::new(PatternKind::Perturbed {
            pattern: Box::new(Pattern::position()),
            scale,
        });
        let c = perturbed.pattern_at(p);
        let moved: Point3 = point(c.red, c.green, c.blue);
        prop_assert!((moved - p).abs().max_element() <= 2.0 * scale + 1e-9);
        prop_assert_eq!(perturbed.pattern_at(p), c);
    }
}
