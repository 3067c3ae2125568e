//! Normal perturbation (a chapter 17 "next step"): bumps tilt the shading normal only.
mod common;
use common::*;
use rayforge::shading::{Bump, BumpKind, Filter, Texture, UvMapping};
use rayforge::{point, prepare_computations, vector, Intersection, Material, Object, Ray};

fn bumpy_plane(kind: BumpKind) -> Object {
    Object::plane().with_material(Material {
        bump: Some(Box::new(Bump::new(kind))),
        ..Material::default()
    })
}

fn comps_at(plane: &Object, x: f64, z: f64) -> rayforge::Computations<'_> {
    let r = Ray::new(point(x, 1.0, z), vector(0.0, -1.0, 0.0));
    let i = Intersection::new(1.0, plane);
    prepare_computations(i, &r, &[i])
}

#[test]
fn waves_tilt_the_normal_but_not_the_surface() {
    let plane = bumpy_plane(BumpKind::Waves {
        amplitude: 0.3,
        wavelength: 2.0,
    });
    let c = comps_at(&plane, 0.5, 0.0);
    // At x = λ/4, z = 0 the ripple's gradient is along z only: cos(π/2)·sin(0) = 0 in x,
    // sin(π/2)·cos(0) = 1 in z.
    assert_vec_approx(c.normalv, vector(0.0, 1.0, 0.3).normalize());
    // The surface point and the shadow-ray start stay on the true normal.
    assert_vec_approx(c.point, point(0.5, 0.0, 0.0));
    assert!(c.over_point.y > 0.0 && c.over_point.x == 0.5 && c.over_point.z == 0.0);
}

#[test]
fn noise_bumps_vary_from_point_to_point_and_stay_unit_and_facing_out() {
    let plane = bumpy_plane(BumpKind::Noise { strength: 0.4 });
    let mut seen = Vec::new();
    for i in 0..50 {
        let c = comps_at(&plane, i as f64 * 0.37 + 0.1, i as f64 * 0.21 + 0.05);
        assert_approx(c.normalv.length(), 1.0);
        assert!(c.normalv.y > 0.5, "{:?}", c.normalv);
        seen.push(c.normalv);
    }
    assert!(seen.windows(2).any(|w| (w[0] - w[1]).length() > 1e-3));
}

#[test]
fn without_bumps_the_normal_is_the_surfaces() {
    let plane = Object::plane();
    assert_vec_approx(comps_at(&plane, 0.3, 0.7).normalv, vector(0.0, 1.0, 0.0));
}

/// A normal map of one pixel: every point gets the same tangent-space normal.
fn uniform_normal_map(red: f64, green: f64, blue: f64, mapping: UvMapping) -> BumpKind {
    let texture = Texture::new(
        1,
        1,
        vec![rayforge::Color::new(red, green, blue)],
        Filter::Nearest,
    )
    .unwrap();
    BumpKind::NormalMap {
        map: std::sync::Arc::new(texture),
        mapping,
        strength: 1.0,
    }
}

#[test]
fn a_flat_normal_map_leaves_the_normal_alone() {
    let plane = bumpy_plane(uniform_normal_map(0.5, 0.5, 1.0, UvMapping::Planar));
    let c = comps_at(&plane, 0.3, 0.7);
    assert_vec_approx(c.normalv, vector(0.0, 1.0, 0.0));
}

#[test]
fn a_normal_map_tilts_along_u_with_red_and_along_v_with_green() {
    // Planar mapping: u grows with x, v with z. Tangent-space (0.6, 0, 0.8) leans towards +x.
    let plane = bumpy_plane(uniform_normal_map(0.8, 0.5, 0.9, UvMapping::Planar));
    let c = comps_at(&plane, 0.3, 0.7);
    assert_vec_approx(c.normalv, vector(0.6, 0.8, 0.0));
    let plane = bumpy_plane(uniform_normal_map(0.5, 0.8, 0.9, UvMapping::Planar));
    let c = comps_at(&plane, 0.3, 0.7);
    assert_vec_approx(c.normalv, vector(0.0, 0.8, 0.6));
    // The surface itself does not move.
    assert_vec_approx(c.point, point(0.3, 0.0, 0.7));
}

#[test]
fn a_normal_map_on_a_sphere_follows_its_tangent_frame() {
    // On the sphere's equator facing -z, spherical u grows towards -x... whichever way it
    // grows, a red tilt leans the normal along the equator and keeps it unit length.
    let sphere = Object::sphere().with_material(Material {
        bump: Some(Box::new(Bump::new(uniform_normal_map(
            0.8,
            0.5,
            0.9,
            UvMapping::Spherical,
        )))),
        ..Material::default()
    });
    let r = Ray::new(point(0.0, 0.0, -5.0), vector(0.0, 0.0, 1.0));
    let i = Intersection::new(4.0, &sphere);
    let c = prepare_computations(i, &r, &[i]);
    assert_approx(c.normalv.length(), 1.0);
    assert_approx(c.normalv.y, 0.0);
    assert_approx(c.normalv.x.abs(), 0.6);
    assert_approx(c.normalv.z, -0.8);
}

#[test]
fn the_normal_map_follows_the_objects_transform() {
    use rayforge::math::rotation_z;
    // The plane turned a quarter turn about z is the yz plane facing -x; its u axis (object x)
    // now points along +y.
    let plane = bumpy_plane(uniform_normal_map(0.8, 0.5, 0.9, UvMapping::Planar))
        .with_transform(rotation_z(std::f64::consts::FRAC_PI_2));
    let r = Ray::new(point(-1.0, 0.3, 0.7), vector(1.0, 0.0, 0.0));
    let i = Intersection::new(1.0, &plane);
    let c = prepare_computations(i, &r, &[i]);
    assert_vec_approx(c.normalv, vector(-0.8, 0.6, 0.0));
}
