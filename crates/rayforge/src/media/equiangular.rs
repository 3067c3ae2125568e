//! Equiangular sampling of distances along a ray (Kulla and Fajardo 2012, "Importance
//! Sampling Techniques for Path Tracing in Participating Media"): a point along the ray is
//! drawn with a density proportional to `1 / r²`, `r` being its distance to a light's place
//! (an anchor), so that the angle it makes with the anchor is uniform. The light a thin medium
//! scatters from a small lamp falls off as `1 / r²`; sampling distances by the medium's
//! transmittance alone puts few points near the lamp, where most of that light is, and the
//! image speckles. The path tracer draws one such point per ray segment through a homogeneous
//! medium and weighs it against the transmittance-sampled scattering by multiple importance
//! sampling, so the image stays unbiased whichever strategy finds the light.
//!
//! With several lights the point is drawn toward one of a few anchors (the most powerful
//! lights that have a place: 8 unless the render asks for another count, up to
//! [`MAX_ANCHORS`]), chosen in proportion to their power: the density
//! is the mixture over the anchors, a function of the ray and the point only (never of the
//! light point later sampled), which is what lets MIS weigh a phase-sampled path that finds
//! a lamp against it.

use crate::math::{Point3, Vec3};
use crate::options::Techniques;
use std::f64::consts::FRAC_PI_2;

/// The most lights distances can be drawn towards: the size of the fixed arrays an
/// [`Anchors`] and a ray's [`Equiangular`] hold, so that no ray allocates; a render's own
/// count ([`Techniques::equiangular_lights`], 8 by default) is at most this.
pub const MAX_ANCHORS: usize = Techniques::MAX_EQUIANGULAR_LIGHTS as usize;

/// The nearest a ray may pass an anchor, relative to the anchor's distance from the ray's
/// origin (and at least [`MIN_OFFSET`]): a ray through the anchor itself would make the
/// density's integral diverge, so it is drawn as if passing this close (still a density that
/// integrates to 1, which the weights read back exactly).
const MIN_RELATIVE_OFFSET: f64 = 1e-6;
/// The nearest a ray may pass an anchor in absolute terms.
const MIN_OFFSET: f64 = 1e-9;

/// The places distances are drawn towards, each with its share of the draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Anchors {
    places: [Point3; MAX_ANCHORS],
    /// Each place's probability of being chosen (summing to 1 over the first `len`).
    shares: [f64; MAX_ANCHORS],
    len: usize,
}

impl Default for Anchors {
    fn default() -> Self {
        Self::NONE
    }
}

impl Anchors {
    /// No anchor: equiangular sampling does not run.
    pub const NONE: Self = Self {
        places: [Point3::ZERO; MAX_ANCHORS],
        shares: [0.0; MAX_ANCHORS],
        len: 0,
    };

    /// The `count` most powerful of `lights` (each a place and a power; those of no power, or
    /// of a place or power that is not finite, left out), chosen by power; `count` is held to
    /// [`MAX_ANCHORS`].
    pub fn of_lights(lights: impl IntoIterator<Item = (Point3, f64)>, count: usize) -> Self {
        let mut kept: Vec<(Point3, f64)> = lights
            .into_iter()
            .filter(|(p, w)| p.is_finite() && w.is_finite() && *w > 0.0)
            .collect();
        // Stable: equal powers keep the lights' order, so the choice is the same every run.
        kept.sort_by(|a, b| b.1.total_cmp(&a.1));
        kept.truncate(count.min(MAX_ANCHORS));
        let total: f64 = kept.iter().map(|(_, w)| w).sum();
        let mut anchors = Self::NONE;
        if !(total > 0.0 && total.is_finite()) {
            return anchors;
        }
        for (i, (p, w)) in kept.iter().enumerate() {
            anchors.places[i] = *p;
            anchors.shares[i] = w / total;
        }
        anchors.len = kept.len();
        anchors
    }

    /// Whether there is none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The distance sampler of the ray from `origin` along unit `direction` over
    /// `[0, t_max]` (`t_max` may be infinite); `None` without anchors or an empty range.
    pub fn along(&self, origin: Point3, direction: Vec3, t_max: f64) -> Option<Equiangular> {
        if self.len == 0 || t_max.is_nan() || t_max <= 0.0 {
            return None;
        }
        let mut sampler = Equiangular {
            spans: [Span::EMPTY; MAX_ANCHORS],
            shares: self.shares,
            len: self.len,
            t_max,
        };
        for i in 0..self.len {
            sampler.spans[i] = Span::new(origin, direction, t_max, self.places[i]);
        }
        Some(sampler)
    }
}

/// One anchor seen from a ray: where along it the anchor is nearest (`delta`), how near
/// (`offset`), and the angles under which the range's ends are seen from it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Span {
    delta: f64,
    offset: f64,
    theta_a: f64,
    theta_b: f64,
}

impl Span {
    const EMPTY: Self = Self {
        delta: 0.0,
        offset: 1.0,
        theta_a: 0.0,
        theta_b: 0.0,
    };

    fn new(origin: Point3, direction: Vec3, t_max: f64, anchor: Point3) -> Self {
        let to = anchor - origin;
        let delta = to.dot(direction);
        let floor = (MIN_RELATIVE_OFFSET * to.length()).max(MIN_OFFSET);
        let offset = (to - direction * delta).length().max(floor);
        let theta_a = (-delta / offset).atan();
        let theta_b = if t_max.is_finite() {
            ((t_max - delta) / offset).atan()
        } else {
            FRAC_PI_2
        };
        Self {
            delta,
            offset,
            theta_a,
            theta_b,
        }
    }

    /// The density of `t` (within the range).
    #[inline]
    fn pdf(&self, t: f64) -> f64 {
        let angle = self.theta_b - self.theta_a;
        if angle <= 0.0 {
            return 0.0;
        }
        let x = t - self.delta;
        self.offset / (angle * (self.offset * self.offset + x * x))
    }

    /// The distance whose angle is the share `u` of the way from `theta_a` to `theta_b`.
    #[inline]
    fn sample(&self, u: f64) -> f64 {
        let theta = self.theta_a + u * (self.theta_b - self.theta_a);
        self.delta + self.offset * theta.tan()
    }
}

/// Distances along one ray drawn towards the anchors (see the [module](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Equiangular {
    spans: [Span; MAX_ANCHORS],
    shares: [f64; MAX_ANCHORS],
    len: usize,
    t_max: f64,
}

impl Equiangular {
    /// A distance in `[0, t_max]` from two numbers in [0, 1): the first chooses the anchor,
    /// the second the angle; with its density ([`pdf`](Self::pdf)).
    pub fn sample(&self, u_anchor: f64, u: f64) -> (f64, f64) {
        let mut chosen = self.len - 1;
        let mut below = 0.0;
        for i in 0..self.len {
            below += self.shares[i];
            if u_anchor < below {
                chosen = i;
                break;
            }
        }
        let t = self.spans[chosen].sample(u).clamp(0.0, self.t_max);
        (t, self.pdf(t))
    }

    /// The density (per unit length) with which [`sample`](Self::sample) draws `t`: the
    /// anchors' mixture; 0 outside `[0, t_max]`.
    pub fn pdf(&self, t: f64) -> f64 {
        if !(0.0..=self.t_max).contains(&t) {
            return 0.0;
        }
        (0..self.len)
            .map(|i| self.shares[i] * self.spans[i].pdf(t))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{point, vector};

    /// The χ² statistic of `n` draws over `bins` equal bins of `[0, t_max]` against the
    /// density integrated numerically over each bin.
    fn chi_square(sampler: &Equiangular, t_max: f64, bins: usize, n: usize) -> (f64, usize) {
        let mut rng = SplitMix64::new(7);
        let mut counts = vec![0usize; bins];
        for _ in 0..n {
            let (t, pdf) = sampler.sample(rng.next_offset(), rng.next_offset());
            assert!((0.0..=t_max).contains(&t), "t = {t}");
            assert!((pdf - sampler.pdf(t)).abs() <= 1e-12 * pdf.max(1.0));
            counts[((t / t_max * bins as f64) as usize).min(bins - 1)] += 1;
        }
        let width = t_max / bins as f64;
        let mut chi = 0.0;
        let mut used = 0;
        for (b, &count) in counts.iter().enumerate() {
            let steps = 400;
            let p: f64 = (0..steps)
                .map(|s| {
                    let t = (b as f64 + (s as f64 + 0.5) / steps as f64) * width;
                    sampler.pdf(t) * width / steps as f64
                })
                .sum();
            let expected = p * n as f64;
            if expected >= 5.0 {
                chi += (count as f64 - expected).powi(2) / expected;
                used += 1;
            }
        }
        (chi, used - 1)
    }

    #[test]
    fn the_density_integrates_to_one_over_the_range() {
        let anchors = Anchors::of_lights(
            [(point(0.3, 1.0, 2.0), 1.0), (point(-1.0, 0.1, 7.0), 3.0)],
            8,
        );
        let s = anchors
            .along(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0), 10.0)
            .expect("sampler");
        let steps = 200_000;
        let dt = 10.0 / steps as f64;
        let total: f64 = (0..steps).map(|i| s.pdf((i as f64 + 0.5) * dt) * dt).sum();
        assert!((total - 1.0).abs() < 1e-4, "{total}");
        assert_eq!(s.pdf(-0.1), 0.0);
        assert_eq!(s.pdf(10.1), 0.0);
    }

    #[test]
    fn one_anchor_gives_its_closed_form_density() {
        // Anchor 1 off the axis at z = 3, range [0, 10]: p(t) = D / ((θb − θa)(D² + (t − Δ)²)).
        let anchors = Anchors::of_lights([(point(0.0, 1.0, 3.0), 2.0)], 8);
        let s = anchors
            .along(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0), 10.0)
            .expect("sampler");
        let angle = (7.0f64).atan() - (-3.0f64).atan();
        for t in [0.0, 1.0, 3.0, 9.5] {
            let expected = 1.0 / (angle * (1.0 + (t - 3.0) * (t - 3.0)));
            assert!((s.pdf(t) - expected).abs() < 1e-12, "{t}");
        }
        // The angle of a draw is uniform: the share u of the way lands at its tangent.
        let (t, _) = s.sample(0.0, 0.5);
        let theta = (-3.0f64).atan() + 0.5 * angle;
        assert!((t - (3.0 + theta.tan())).abs() < 1e-12);
    }

    #[test]
    fn draws_follow_the_density_by_chi_square() {
        // Two anchors, one close to the ray: the mixture's draws against its density. With
        // 49 degrees of freedom, 99.9 % of χ² values lie below 85.4.
        let anchors = Anchors::of_lights(
            [(point(0.0, 0.05, 2.0), 1.0), (point(0.5, 2.0, 6.0), 1.0)],
            8,
        );
        let s = anchors
            .along(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0), 8.0)
            .expect("sampler");
        let (chi, dof) = chi_square(&s, 8.0, 50, 200_000);
        assert!(dof >= 40, "{dof}");
        assert!(chi < 85.4, "χ² = {chi} over {dof} degrees of freedom");
    }

    #[test]
    fn an_infinite_range_and_a_ray_through_the_anchor_keep_a_proper_density() {
        let anchors = Anchors::of_lights([(point(0.0, 0.0, 2.0), 1.0)], 8);
        let s = anchors
            .along(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0), f64::INFINITY)
            .expect("sampler");
        let mut rng = SplitMix64::new(3);
        for _ in 0..1000 {
            let (t, pdf) = s.sample(rng.next_offset(), rng.next_offset());
            assert!(t >= 0.0 && t.is_finite() && pdf.is_finite() && pdf > 0.0);
        }
    }

    #[test]
    fn anchors_are_the_most_powerful_lights_chosen_by_power() {
        let lights = || (0..40).map(|i| (point(i as f64, 0.0, 0.0), i as f64));
        let anchors = Anchors::of_lights(lights(), 8);
        assert_eq!(anchors.len, 8);
        assert_eq!(anchors.places[0], point(39.0, 0.0, 0.0));
        let total: f64 = (32..40).map(|i| i as f64).sum();
        assert!((anchors.shares[0] - 39.0 / total).abs() < 1e-15);
        // Another count, other anchors: the three most powerful only, their shares renewed.
        let three = Anchors::of_lights(lights(), 3);
        assert_eq!(three.len, 3);
        assert_eq!(
            three.places[..3],
            [39.0, 38.0, 37.0].map(|x| point(x, 0.0, 0.0))
        );
        assert!((three.shares[2] - 37.0 / 114.0).abs() < 1e-15);
        // More than the arrays hold is held to them.
        assert_eq!(Anchors::of_lights(lights(), 1000).len, MAX_ANCHORS);
        assert!(Anchors::of_lights([(point(0.0, 0.0, 0.0), 0.0)], 8).is_empty());
        assert!(Anchors::NONE
            .along(point(0.0, 0.0, 0.0), vector(0.0, 0.0, 1.0), 1.0)
            .is_none());
    }
}
