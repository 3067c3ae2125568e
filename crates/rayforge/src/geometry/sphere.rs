//! The unit sphere (chapters 5 and 6), and its sampling: by area, and by the cone of directions
//! it subtends from a point outside it (see [`SubtendedCone`]).

use crate::math::{roots::solve_quadratic, sin_cos_turns, Frame, Point3, Ray, Vec3};
use std::f64::consts::PI;

/// The unit sphere's area.
pub const AREA: f64 = 4.0 * PI;

/// Both roots of `|o + t·d|² = 1`, tangent rays giving the same `t` twice (as the book expects).
#[inline]
pub fn intersect(ray: &Ray, mut hit: impl FnMut(f64)) {
    let a = ray.direction.length_squared();
    let b = 2.0 * ray.direction.dot(ray.origin);
    let c = ray.origin.length_squared() - 1.0;
    if let Some((t0, t1)) = solve_quadratic(a, b, c) {
        hit(t0);
        hit(t1);
    }
}

/// The normal of the unit sphere is the point itself.
pub fn normal_at(point: Point3) -> Vec3 {
    point
}

/// A point of the unit sphere uniformly by area, from `u` in [0, 1)², and its normal (the point
/// itself): `z` uniform in [−1, 1] (Archimedes' hat-box theorem) and the angle about z uniform.
pub fn sample_area([u, v]: [f64; 2]) -> (Point3, Vec3) {
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin, cos) = sin_cos_turns(v);
    let p = Point3::new(r * cos, r * sin, z);
    (p, p)
}

/// How far outside a sphere (relatively, in squared distance) a point must be for it to be
/// sampled by the cone it subtends: a path vertex on the sphere itself, which rounding puts a
/// hair inside or outside, is sampled by area either way, as light sampling and the density a
/// path that hits the sphere is told must agree on which way it was.
const OUTSIDE: f64 = 1e-6;

/// The cone of directions in which a sphere is seen from a point outside it, sampled uniformly:
/// every direction in it meets the sphere, so no sample is wasted on directions that miss, and a
/// small far lamp is sampled as well as a near one (by area, most of a sphere's points face away
/// from the point and the density per solid angle swings with the distance and slope of each).
///
/// The cone's half-angle θₘ has `sin θₘ = r / d` (`d` the distance to the centre), and its solid
/// angle is `2π (1 − cos θₘ)`. A direction at angle θ from the axis first meets the sphere at the
/// point whose angle α at the centre, from the axis back towards the viewer, has
/// `cos α = d sin²θ / r + cos θ · √(1 − d² sin²θ / r²)`, from the triangle of viewer, centre and
/// point: the point is placed on the sphere exactly, rather than by intersecting a ray.
#[derive(Debug, Clone, Copy)]
pub struct SubtendedCone {
    centre: Point3,
    radius: f64,
    /// Unit direction from the centre towards the viewer.
    back: Vec3,
    /// `sin² θₘ = r² / d²`.
    sin2_max: f64,
    /// `1 − cos θₘ`, worked out as `sin² θₘ / (1 + cos θₘ)`, which keeps its digits for a small
    /// far sphere where `1 − cos θₘ` would cancel.
    one_minus_cos_max: f64,
}

impl SubtendedCone {
    /// The cone in which the sphere of `radius` about `centre` is seen from `from`; `None` when
    /// `from` is inside it, or on it (within [`OUTSIDE`]).
    #[inline]
    pub fn seen_from(centre: Point3, radius: f64, from: Point3) -> Option<Self> {
        let back = from - centre;
        let d2 = back.length_squared();
        let r2 = radius * radius;
        if !(d2 > r2 * (1.0 + OUTSIDE) && d2.is_finite() && r2 > 0.0) {
            return None;
        }
        let sin2_max = r2 / d2;
        let one_minus_cos_max = sin2_max / (1.0 + (1.0 - sin2_max).sqrt());
        Some(Self {
            centre,
            radius,
            back: back / d2.sqrt(),
            sin2_max,
            one_minus_cos_max,
        })
    }

    /// The density per solid angle of every direction in the cone: one over its solid angle.
    #[inline]
    pub fn pdf(&self) -> f64 {
        1.0 / (2.0 * PI * self.one_minus_cos_max)
    }

    /// Whether `point` of the sphere is on the cap seen from the viewer, the only points
    /// [`sample`](Self::sample) gives (a ray that arrives elsewhere, on the far side, came
    /// through the sphere). The cap's edge, where the view grazes the sphere, is given a
    /// relative margin for rounding.
    #[inline]
    pub fn sees(&self, point: Point3) -> bool {
        let along = (point - self.centre).dot(self.back);
        // On the cap, the point's distance along `back` is at least r sin θₘ = r² / d.
        along >= self.radius * self.sin2_max.sqrt() * (1.0 - 1e-6)
    }

    /// A direction uniformly in the cone, from `u` in [0, 1)²: the point where it first meets
    /// the sphere, and the sphere's unit outward normal there.
    #[inline]
    pub fn sample(&self, [u, v]: [f64; 2]) -> (Point3, Vec3) {
        // cos θ uniform in [cos θₘ, 1], through m = 1 − cos θ (no cancellation near the axis).
        let m = u * self.one_minus_cos_max;
        let cos_theta = 1.0 - m;
        let sin2_theta = m * (2.0 - m);
        let sin_max = self.sin2_max.sqrt();
        let cos_alpha =
            sin2_theta / sin_max + cos_theta * (1.0 - (sin2_theta / self.sin2_max).min(1.0)).sqrt();
        let cos_alpha = cos_alpha.min(1.0);
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let (sin_phi, cos_phi) = sin_cos_turns(v);
        let normal = Frame::from_normal(self.back).to_world(Vec3::new(
            sin_alpha * cos_phi,
            sin_alpha * sin_phi,
            cos_alpha,
        ));
        (self.centre + normal * self.radius, normal)
    }
}
