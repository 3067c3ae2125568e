//! Polished metal balls as a way for the sky's light to reach a surface: the reflection point
//! found directly, so that the sun's image in a mirror ball lights a diffuse surface by
//! next-event estimation instead of by the rare path that happens to bounce towards it.
//!
//! A path tracer finds light reflected by a perfect mirror onto a diffuse surface (a caustic)
//! only when the surface's own sampled direction meets the mirror just where the mirror shows
//! the light: for a small sun in a convex mirror, a tiny set of directions, so a few samples
//! carry enormous weights and the caustic stays speckled for thousands of samples. Manifold
//! next-event estimation (Hanika, Droske and Fascione, 2015) instead draws the light's
//! direction and solves for the point of the mirror that sends it to the surface. For a sphere
//! and a distant light the solution lies in the plane through the sphere's centre, the surface
//! point and the light's direction, so it is a root in one angle, bracketed and unique on the
//! part of the sphere the point sees (the reflected direction turns monotonically from straight
//! back to grazing as the reflection point moves out from the sphere's nearest point).
//!
//! The estimate needs how the mirror spreads directions: a pencil of rays of solid angle `dd`
//! leaving the surface point, reflected at distance `s` with incidence `i` by a convex sphere
//! of radius `R`, leaves as if from two virtual foci (Coddington's equations for a mirror, in
//! the plane of incidence and across it) and spans
//! `dω = dd · (1 + 2s / (R cos i)) · (1 + 2s cos i / R)`. It is 1 for a flat mirror and tends
//! to `4s² / R²` far away, where a ball spreads a parallel beam evenly over the whole sphere of
//! directions.
//!
//! Only balls that reflect the same everywhere qualify: a sphere placed by a similarity (no
//! stretch), standing still, of a smooth conductor with a plain colour and no bump map, that
//! does not glow. The path tracer weighs this strategy against the surface's BSDF sampling by
//! the power heuristic, which needs the same spread for a path that found the mirror by itself
//! ([`spread`]).
//!
//! A scene of many balls (a ball pit under a sky) would pay a solve per ball at every vertex.
//! So each ball has a share of the sky's light at a vertex ([`MirrorBall::share_from`]): its
//! reflectance `ρ` times the solid angle `Ω` it subtends, over π, what it adds to an even
//! sky's light there at most. Balls below a share are left to BSDF sampling, and of the rest
//! at most a few are solved, chosen in proportion to their shares ([`choose`]), each weighed
//! by one over how often it is chosen on average, the same factor in the density that MIS
//! weighs the BSDF's paths to the ball against.

use crate::color::Color;
use crate::math::{atan2_turns, sin_cos_turns, Point3, Vec3};
use crate::scene::{Object, Shape};
use crate::shading::bsdf::{fresnel, MIN_ALPHA};
use crate::shading::Physical;
use std::f64::consts::{PI, TAU};

/// A polished metal ball, in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct MirrorBall {
    /// Its index in the world's objects.
    pub object: u32,
    /// Its centre.
    pub centre: Point3,
    /// Its radius.
    pub radius: f64,
    /// Real part of the metal's index of refraction, per channel.
    eta: Color,
    /// Its extinction coefficient, per channel.
    k: Color,
    /// The colour that tints its reflection.
    tint: Color,
    /// Its reflectance at normal incidence, the largest channel: the `ρ` of its share.
    albedo: f64,
}

/// How a surface point sees a direction of the sky in a mirror ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorPath {
    /// The point of the ball that reflects the sky's direction to the surface point.
    pub point: Point3,
    /// The ball's outward normal there.
    pub normal: Vec3,
    /// The unit direction from the surface point to it.
    pub direction: Vec3,
    /// How far it is.
    pub distance: f64,
    /// The cosine of the angle of incidence there.
    pub cos_incidence: f64,
}

/// `dω / dd`: how much wider in solid angle a pencil of rays leaves a convex mirror ball of
/// radius `radius` than it arrived from a point `distance` away, meeting it with incidence
/// cosine `cos_incidence` (see the [module](self) documentation).
#[inline]
pub fn spread(distance: f64, cos_incidence: f64, radius: f64) -> f64 {
    let c = cos_incidence.max(1e-12);
    (1.0 + 2.0 * distance / (radius * c)) * (1.0 + 2.0 * distance * c / radius)
}

impl MirrorBall {
    /// `object` (the world's object `index`) as a mirror ball, if it is one (see the
    /// [module](self) documentation for what qualifies).
    pub fn of(object: &Object, index: u32) -> Option<Self> {
        let material = &object.material;
        let Some(Physical::Conductor {
            eta,
            k,
            alpha_u,
            alpha_v,
        }) = material.physical
        else {
            return None;
        };
        let plain = material.pattern.is_none()
            && material.texture.is_none()
            && material.bump.is_none()
            && material.metal_rough.is_none()
            && material.physical_patterns.is_none()
            && material.emission.max_channel() <= 0.0;
        if !matches!(object.shape, Shape::Sphere)
            || object.motion.is_some()
            || alpha_u >= MIN_ALPHA
            || alpha_v >= MIN_ALPHA
            || !plain
        {
            return None;
        }
        // A similarity: the images of three unit axes are orthogonal and of one length.
        let t = &object.transform;
        let (x, y, z) = (t.vector(Vec3::X), t.vector(Vec3::Y), t.vector(Vec3::Z));
        let radius = x.length();
        let tolerance = 1e-9 * radius * radius;
        let similar = (y.length_squared() - radius * radius).abs() <= tolerance
            && (z.length_squared() - radius * radius).abs() <= tolerance
            && x.dot(y).abs() <= tolerance
            && y.dot(z).abs() <= tolerance
            && z.dot(x).abs() <= tolerance;
        if !(similar && radius.is_finite() && radius > 0.0) {
            return None;
        }
        Some(Self::new(
            index,
            t.point(Point3::ZERO),
            radius,
            eta,
            k,
            material.color,
        ))
    }

    /// The ball of world object `object` at `centre`, of `radius`, of the metal of index
    /// `eta` and extinction `k`, tinted by `tint`.
    fn new(object: u32, centre: Point3, radius: f64, eta: Color, k: Color, tint: Color) -> Self {
        let albedo = tint.hadamard(fresnel::conductor(1.0, eta, k)).max_channel();
        Self {
            object,
            centre,
            radius,
            eta,
            k,
            tint,
            albedo,
        }
    }

    /// The ball's share of the sky's light at `point`, `ρ Ω / π`, where it is at least `cull`
    /// (see the [module](self) documentation); `None` below it, and from inside the ball.
    /// `Ω = 2π (1 − √(1 − x))` with `x = R² / d²`, the cone of directions towards the ball,
    /// is taken as `2π x / (1 + √(1 − x))`, which does not cancel for a far ball. As `Ω ≤ 2π
    /// x`, most balls of a large scene are left out by a product and a comparison.
    #[inline]
    pub fn share_from(&self, point: Point3, cull: f64) -> Option<f64> {
        let d2 = (self.centre - point).length_squared();
        let r2 = self.radius * self.radius;
        if d2.is_nan() || d2 <= r2 || 2.0 * self.albedo * r2 < cull * d2 {
            return None;
        }
        let x = r2 / d2;
        let share = self.albedo * 2.0 * x / (1.0 + (1.0 - x).sqrt());
        (share >= cull).then_some(share)
    }

    /// The share of light the ball reflects at incidence cosine `cos_incidence`: the conductor
    /// Fresnel reflectance, tinted, as its BSDF gives it.
    pub fn reflectance(&self, cos_incidence: f64) -> Color {
        self.tint
            .hadamard(fresnel::conductor(cos_incidence, self.eta, self.k))
    }

    /// Where the ball reflects light arriving from the far direction `towards` (unit, pointing
    /// away from the ball to where the light comes from) into the point `from`: `None` when
    /// `from` is inside or on the ball, or when no point of the ball that `from` sees sends
    /// that direction to it (it lies beyond the grazing reflections, behind the ball).
    pub fn reflection_towards(&self, from: Point3, towards: Vec3) -> Option<MirrorPath> {
        let r = self.radius;
        let offset = from - self.centre;
        let d = offset.length();
        if d.is_nan() || d <= r * (1.0 + 1e-9) || !towards.is_finite() {
            return None;
        }
        // The plane of the centre, the point and the direction: e1 towards the point, e2
        // towards the direction's side. In it the normal is (cos α, sin α), α from 0 (the
        // nearest point) to the edge the point sees, acos(R / d).
        let e1 = offset / d;
        let along = towards.dot(e1);
        let across = towards - e1 * along;
        let side = across.length();
        let omega = [along, side];
        let e2 = if side > 1e-12 {
            across / side
        } else if along > 0.0 {
            // Straight back along the axis: the nearest point reflects it.
            return Some(self.path(from, e1));
        } else {
            return None;
        };
        // At the point of normal angle α the reflected direction has angle ψ(α) = 2α + β(α),
        // β the angle at the ball's point between the centre's line and the surface point
        // (tan β = R sin α / (d − R cos α)). ψ rises from 0 at α = 0 to π/2 + edge at the edge
        // of what the point sees, α = acos(R / d); ω's angle φ in (0, π] is reached once, if
        // below that. `ahead(α)` is sin(φ − ψ) times the distance to the surface point, which
        // needs no inverse trigonometry: positive before the root, negative after it.
        // acos(R / d), and the sine of it, by the crate's arctangent (libm's `acos` and
        // `atan2` were 3 % of an environment-lit render).
        let (cos_edge, sin_edge) = (r / d, (1.0 - (r / d) * (r / d)).max(0.0).sqrt());
        let edge = TAU * atan2_turns(sin_edge, cos_edge);
        let (cos_phi, sin_phi) = (omega[0], omega[1]);
        let ahead = |alpha: f64| {
            let (sin, cos) = sin_cos_turns(alpha / TAU);
            let (sin_2a, cos_2a) = (2.0 * sin * cos, cos * cos - sin * sin);
            // sin(φ − 2α) and cos(φ − 2α), then sin(φ − 2α − β)·L with cos β·L = d − R cos α
            // and sin β·L = R sin α.
            let sin_rest = sin_phi * cos_2a - cos_phi * sin_2a;
            let cos_rest = cos_phi * cos_2a + sin_phi * sin_2a;
            let length_squared = d * d + r * r - 2.0 * d * r * cos;
            let value = sin_rest * (d - r * cos) - cos_rest * r * sin;
            // ψ'(α) = 2 + β'(α), β' = R (d cos α − R) / L².
            let slope = 2.0 + r * (d * cos - r) / length_squared;
            (value / length_squared.sqrt(), slope)
        };
        // Behind the ball: φ is not below ψ(edge) = π/2 + edge, whose cosine is −sin(edge).
        // (Both sides are finite: `towards` is, and R / d lies in (0, 1).)
        if cos_phi <= -sin_edge {
            return None;
        }
        // Newton's method on φ − ψ (read as its sine, so a far step falls short rather than
        // overshooting), kept within a bracket that shrinks with every value seen; from the
        // bisector of the point's direction and ω (right for a far point), three steps reach
        // the limit of precision.
        let (mut lo, mut hi) = (0.0, edge);
        let mut alpha = (PI * atan2_turns(side, along)).clamp(0.0, edge);
        for _ in 0..60 {
            let (value, slope) = ahead(alpha);
            if value == 0.0 || value.is_nan() {
                break;
            }
            if value > 0.0 {
                lo = alpha;
            } else {
                hi = alpha;
            }
            let newton = alpha + value / slope;
            let in_bracket = (lo..=hi).contains(&newton);
            let next = if in_bracket { newton } else { 0.5 * (lo + hi) };
            let step = (next - alpha).abs();
            alpha = next;
            // A Newton step leaves an error of about its square times ψ''/ψ' (at most of the
            // order of 1/edge²): below 10⁻⁸·edge, the point is as good as the arithmetic. (A
            // bisection's step says nothing of the error, only the bracket does.)
            if (in_bracket && step <= 1e-8 * edge) || hi - lo <= 1e-15 * edge {
                break;
            }
        }
        let (sin, cos) = sin_cos_turns(alpha / TAU);
        Some(self.path(from, e1 * cos + e2 * sin))
    }

    /// The path from `from` to the point of the ball with outward normal `normal`.
    fn path(&self, from: Point3, normal: Vec3) -> MirrorPath {
        let point = self.centre + normal * self.radius;
        let to = point - from;
        let distance = to.length();
        let direction = to / distance;
        MirrorPath {
            point,
            normal,
            direction,
            distance,
            cos_incidence: (-direction.dot(normal)).max(0.0),
        }
    }
}

/// `cap` choices among balls of `shares` (which sum to `total`), made systematically with
/// probability in proportion to each share from the one number `u` in [0, 1): `cap` points
/// `(i + u) · total / cap` along the shares laid end to end, each choosing the ball it falls
/// in. `chosen` is called, in the order of `shares`, with each chosen ball's index in
/// `shares` and its weight: how many points it took over how many it takes on average
/// (`cap × share / total`), so that the sum over the chosen of weight × a ball's light has
/// the sum over all of them as its mean. Systematic choice spreads the points evenly: a
/// ball whose mean is at least one is always chosen, and no ball's count is ever more than
/// one away from its mean.
pub fn choose(shares: &[f64], total: f64, cap: u32, u: f64, mut chosen: impl FnMut(usize, f64)) {
    let step = total / f64::from(cap);
    // The next point, and how many have been placed.
    let (mut next, mut placed) = (u * step, 0);
    let mut end = 0.0;
    for (i, &share) in shares.iter().enumerate() {
        end += share;
        let mut taken = 0u32;
        // The last ball takes every point left, whatever rounding did to the running sum.
        let last = i + 1 == shares.len();
        while placed < cap && (next < end || last) {
            taken += 1;
            placed += 1;
            next = (f64::from(placed) + u) * step;
        }
        if taken > 0 {
            let expected = f64::from(cap) * share / total;
            chosen(i, f64::from(taken) / expected);
        }
    }
}

/// The mean number of times ball of `share` is solved at a vertex where `qualifying` balls
/// have a share of at least the cull, together `total`, and at most `cap` are solved: 1 when
/// all of them are, else `cap × share / total` ([`choose`]). The density of the mirror-ball
/// sampling's directions towards the ball is the sky's, narrowed by the spread, times this.
#[inline]
pub fn expected_solves(share: f64, qualifying: usize, total: f64, cap: u32) -> f64 {
    if qualifying <= cap as usize {
        1.0
    } else {
        f64::from(cap) * share / total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{Transform, EPSILON};
    use crate::shading::Material;
    use glam::DMat4;
    use std::f64::consts::PI;

    fn ball(centre: Point3, radius: f64) -> MirrorBall {
        let (eta, k) = (Color::new(1.6, 0.9, 0.5), Color::new(9.2, 6.3, 4.8));
        MirrorBall::new(0, centre, radius, eta, k, Color::WHITE)
    }

    #[test]
    fn a_balls_share_is_its_reflectance_times_its_solid_angle_over_pi() {
        let mirror = ball(Point3::ZERO, 0.5);
        let albedo = mirror.reflectance(1.0).max_channel();
        for d in [0.6, 1.0, 3.0, 40.0, 1e4] {
            let x: f64 = 0.25 / (d * d);
            let cone = 2.0 * PI * (1.0 - (1.0 - x).sqrt());
            let share = mirror.share_from(Point3::new(0.0, d, 0.0), 0.0).unwrap();
            let expected = albedo * cone / PI;
            // The cone's form cancels far away: compare loosely there.
            let tolerance = if d > 100.0 { 1e-6 } else { 1e-12 };
            assert!(
                (share - expected).abs() <= tolerance * expected,
                "{d}: {share}"
            );
        }
        // Far balls are left out below the cull, near ones kept; none from inside.
        let far = Point3::new(0.0, 40.0, 0.0);
        let share = mirror.share_from(far, 0.0).unwrap();
        assert!(mirror.share_from(far, share * 1.001).is_none());
        assert_eq!(mirror.share_from(far, share), Some(share));
        assert!(mirror.share_from(Point3::new(0.0, 0.3, 0.0), 0.0).is_none());
    }

    #[test]
    fn systematic_choice_takes_each_ball_as_often_as_its_share_says() {
        let shares = [0.5, 0.05, 0.2, 0.01, 0.9, 0.3, 0.04];
        let total: f64 = shares.iter().sum();
        for cap in [1, 2, 3, 5] {
            let n = 10_000;
            let mut counts = [0.0; 7];
            let mut weights = [0.0; 7];
            for j in 0..n {
                let u = (j as f64 + 0.5) / n as f64;
                let mut placed = 0;
                choose(&shares, total, cap, u, |i, w| {
                    let expected = expected_solves(shares[i], shares.len(), total, cap);
                    let taken = w * expected;
                    assert!((taken - taken.round()).abs() < 1e-9);
                    placed += taken.round() as u32;
                    counts[i] += taken;
                    weights[i] += w;
                });
                assert_eq!(placed, cap);
            }
            for i in 0..7 {
                let expected = cap as f64 * shares[i] / total;
                assert!((counts[i] / n as f64 - expected).abs() < 1e-3, "{cap} {i}");
                // The weight's mean is 1: every ball's light counts at its full size.
                assert!((weights[i] / n as f64 - 1.0).abs() < 2e-3, "{cap} {i}");
            }
        }
    }

    fn unit_on_sphere(rng: &mut SplitMix64) -> Vec3 {
        let z = 1.0 - 2.0 * rng.next_offset();
        let phi = TAU * rng.next_offset();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    #[test]
    fn the_reflection_point_sends_the_direction_to_the_point() {
        let mirror = ball(Point3::new(0.3, -0.2, 1.0), 0.7);
        let mut rng = SplitMix64::new(5);
        let (mut found, mut tries) = (0, 0);
        while tries < 20_000 {
            tries += 1;
            let from = mirror.centre + unit_on_sphere(&mut rng) * (0.71 + 5.0 * rng.next_offset());
            let towards = unit_on_sphere(&mut rng);
            let Some(path) = mirror.reflection_towards(from, towards) else {
                continue;
            };
            found += 1;
            // On the ball, seen from the front, reflecting the ray into `towards`.
            assert!(((path.point - mirror.centre).length() - 0.7).abs() < 1e-12);
            assert!(path.cos_incidence > 0.0);
            let d = path.direction;
            let reflected = d - path.normal * (2.0 * d.dot(path.normal));
            assert!(
                (reflected - towards).length() < 1e-12,
                "{reflected} vs {towards} from {from}"
            );
            // The point is the first the ray meets (the near side of the ball).
            let oc = from - mirror.centre;
            let b = oc.dot(d);
            let c = oc.length_squared() - 0.7 * 0.7;
            let near = -b - (b * b - c).max(0.0).sqrt();
            assert!((near - path.distance).abs() < 1e-9 * path.distance.max(1.0));
        }
        // Most directions are reachable: all but those behind the ball.
        assert!(found > 10_000, "{found}");
        // From inside the ball, or on it, there is none.
        assert!(mirror
            .reflection_towards(mirror.centre + Vec3::X * 0.5, Vec3::Y)
            .is_none());
    }

    #[test]
    fn directions_behind_the_ball_are_not_reflected() {
        let mirror = ball(Point3::ZERO, 1.0);
        let from = Point3::new(0.0, 0.0, 3.0);
        // Straight away from the point, through the ball: no reflection reaches it.
        assert!(mirror.reflection_towards(from, -Vec3::Z).is_none());
        // Straight back: the nearest point.
        let path = mirror.reflection_towards(from, Vec3::Z).unwrap();
        assert!((path.point - Point3::new(0.0, 0.0, 1.0)).length() < 1e-12);
        assert!((path.distance - 2.0).abs() < 1e-12);
        assert!((path.cos_incidence - 1.0).abs() < 1e-12);
    }

    /// Every direction from a point that meets the ball leaves it reflected; together they
    /// cover the cap of directions around the axis out to the grazing reflection. So the
    /// spread, integrated over the directions towards the ball, is that cap's solid angle.
    #[test]
    fn the_spread_integrates_to_the_solid_angle_of_the_reflections() {
        for (distance, radius) in [(3.0, 1.0), (1.2, 1.0), (40.0, 0.5)] {
            let mirror = ball(Point3::ZERO, radius);
            let from = Point3::new(0.0, 0.0, distance);
            // Directions towards the ball: a cone of half-angle β about −Z, by the midpoint
            // rule in cos and azimuth (the integrand does not depend on the azimuth).
            let beta = (radius / distance).asin();
            let n = 20_000;
            let mut total = 0.0;
            for i in 0..n {
                let cos = 1.0 - (1.0 - beta.cos()) * (i as f64 + 0.5) / n as f64;
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let d = Vec3::new(sin, 0.0, -cos);
                let oc = from - mirror.centre;
                let b = oc.dot(d);
                let c = oc.length_squared() - radius * radius;
                let disc = b * b - c;
                if disc < 0.0 {
                    continue;
                }
                let s = -b - disc.sqrt();
                let normal = (from + d * s - mirror.centre) / radius;
                total += spread(s, -d.dot(normal), radius);
            }
            total *= 2.0 * PI * (1.0 - beta.cos()) / n as f64;
            let expected = 2.0 * PI * (1.0 + beta.cos());
            assert!(
                (total - expected).abs() < 2e-3 * expected,
                "{distance}, {radius}: {total} vs {expected}"
            );
        }
        // A flat mirror does not spread.
        assert!((spread(2.0, 0.6, 1e12) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn only_still_plain_polished_metal_balls_qualify() {
        let metal = Material {
            physical: Some(Physical::Conductor {
                eta: Color::new(1.6, 0.9, 0.5),
                k: Color::new(9.2, 6.3, 4.8),
                alpha_u: 0.0,
                alpha_v: 0.0,
            }),
            ..Material::DEFAULT
        };
        let placed = Transform::new(
            DMat4::from_translation(Vec3::new(1.0, 2.0, 3.0))
                * DMat4::from_rotation_y(0.4)
                * DMat4::from_scale(Vec3::splat(0.5)),
        );
        let mut sphere = Object::sphere();
        sphere.material = metal.clone();
        sphere.transform = placed;
        let found = MirrorBall::of(&sphere, 7).expect("a mirror ball");
        assert_eq!(found.object, 7);
        assert!((found.centre - Point3::new(1.0, 2.0, 3.0)).length() < EPSILON);
        assert!((found.radius - 0.5).abs() < 1e-12);
        // Stretched, rough, of another material or another shape: not one.
        let mut stretched = sphere.clone();
        stretched.transform = Transform::new(DMat4::from_scale(Vec3::new(1.0, 2.0, 1.0)));
        assert!(MirrorBall::of(&stretched, 0).is_none());
        let mut rough = sphere.clone();
        rough.material.physical = Some(Physical::Conductor {
            eta: Color::WHITE,
            k: Color::WHITE,
            alpha_u: 0.2,
            alpha_v: 0.2,
        });
        assert!(MirrorBall::of(&rough, 0).is_none());
        let mut diffuse = sphere.clone();
        diffuse.material.physical = Some(Physical::Diffuse);
        assert!(MirrorBall::of(&diffuse, 0).is_none());
        let mut cube = Object::cube();
        cube.material = metal;
        assert!(MirrorBall::of(&cube, 0).is_none());
        // Its reflectance is the conductor's Fresnel term.
        let f = found.reflectance(0.5);
        assert_eq!(
            f,
            fresnel::conductor(0.5, Color::new(1.6, 0.9, 0.5), Color::new(9.2, 6.3, 4.8))
        );
    }
}
