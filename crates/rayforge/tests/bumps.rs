//! Normal perturbation (a chapter 17 "next step"): bumps tilt the shading normal only.
mod common;
use common::*;
use rayforge::shading::{Bump, BumpKind};
use rayforge::{point, prepare_computations, vector, Intersection, Material, Object, Ray};

fn bumpy_plane(kind: BumpKind) -> Object {
    Object::plane().with_material(Material {
        bump: Some(Bump::new(kind)),
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
