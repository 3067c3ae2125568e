//! Null-collision tracking through a medium (pbrt-v4's `SampleT_maj` and the two estimators
//! built on it, after Novák et al. 2014 and Miller et al. 2019): collisions are sampled
//! against a majorant σmaj ≥ σt, segment by segment along the ray (one segment for a
//! homogeneous medium or a cloud, the majorant grid's cells for a density grid), and each is a real
//! collision (absorption or scattering) or a null one by the caller's choice.
//!
//! Distances are sampled in one hero channel; the other channels' densities are carried as
//! ratios to the hero's (pbrt-v4's `r_u`, `r_l`), so that a medium whose colour varies is
//! tracked without bias: the path tracer chooses the hero uniformly and divides by the mean
//! ratio, the balance heuristic over the three channels (spectral MIS, Wilkie et al. 2014).

use super::majorant::{Dda, MajorantSegment};
use super::{beer, channel, Medium};
use crate::color::Color;
use crate::math::random::{Jitter, SplitMix64};
use crate::math::{Point3, Ray, Vec3};

/// What a medium is at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MediumPoint {
    /// Absorption coefficient.
    pub sigma_a: Color,
    /// Scattering coefficient.
    pub sigma_s: Color,
    /// Radiance given off per unit of absorption.
    pub emission: Color,
}

/// The majorant segments of a ray through a medium.
enum Segments<'m> {
    One(Option<MajorantSegment>),
    Grid(Dda<'m>),
}

impl Iterator for Segments<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            Segments::One(s) => s.take(),
            Segments::Grid(dda) => dda.next(),
        }
    }
}

/// Where the line `origin + t·direction` is inside the unit cube, within `[0, t_max]`.
fn unit_cube_span(origin: Point3, direction: Vec3, t_max: f64) -> Option<(f64, f64)> {
    let (mut near, mut far) = (0.0f64, t_max);
    for axis in 0..3 {
        let (o, d) = (origin[axis], direction[axis]);
        if d == 0.0 {
            if !(0.0..=1.0).contains(&o) {
                return None;
            }
            continue;
        }
        let (a, b) = ((0.0 - o) / d, (1.0 - o) / d);
        near = near.max(a.min(b));
        far = far.min(a.max(b));
    }
    (near < far).then_some((near, far))
}

impl Medium {
    /// The majorant segments of `ray` (whose direction is a unit vector) over `[0, t_max]`.
    fn segments(&self, ray: &Ray, t_max: f64) -> Segments<'_> {
        match self {
            Medium::Homogeneous(m) => Segments::One(Some(MajorantSegment {
                t_min: 0.0,
                t_max,
                sigma_maj: m.sigma_t(),
            })),
            Medium::Grid(m) => {
                let origin = m.to_unit(ray.origin);
                let direction = m.to_unit_vector(ray.direction);
                match unit_cube_span(origin, direction, t_max) {
                    Some((t0, t1)) => Segments::Grid(Dda::new(
                        &m.majorant,
                        m.sigma_a + m.sigma_s,
                        origin,
                        direction,
                        t0,
                        t1,
                    )),
                    None => Segments::One(None),
                }
            }
            Medium::Cloud(m) => Segments::One(m.span(ray.origin, ray.direction, t_max).map(
                |(t_min, t_max)| MajorantSegment {
                    t_min,
                    t_max,
                    sigma_maj: m.sigma_maj(),
                },
            )),
        }
    }

    /// What the medium is at the world point `p`.
    #[inline]
    pub fn at(&self, p: Point3) -> MediumPoint {
        match self {
            Medium::Homogeneous(m) => MediumPoint {
                sigma_a: m.sigma_a,
                sigma_s: m.sigma_s,
                emission: m.emission,
            },
            Medium::Grid(m) => {
                let (sigma_a, sigma_s, emission) = m.coefficients_at(m.to_unit(p));
                MediumPoint {
                    sigma_a,
                    sigma_s,
                    emission,
                }
            }
            Medium::Cloud(m) => {
                let (sigma_a, sigma_s) = m.coefficients_at(p);
                MediumPoint {
                    sigma_a,
                    sigma_s,
                    emission: Color::BLACK,
                }
            }
        }
    }
}

/// Samples tentative collisions along `ray` (a unit direction) over `[0, t_max]` against
/// the medium's majorants, in channel `hero`, from `u` for the first and `rng` for the rest.
/// At each, `collide(t, point, σmaj, T_maj, rng)` is called, `T_maj` being the majorant
/// transmittance since the last collision (or the ray's start); it returns whether tracking
/// goes on. Returns the majorant transmittance from the last collision to `t_max` where the
/// ray gets there, and white where `collide` stopped it.
pub fn sample_majorant(
    medium: &Medium,
    ray: &Ray,
    t_max: f64,
    mut u: f64,
    rng: &mut SplitMix64,
    hero: usize,
    mut collide: impl FnMut(f64, &MediumPoint, Color, Color, &mut SplitMix64) -> bool,
) -> Color {
    let mut t_maj = Color::WHITE;
    for segment in medium.segments(ray, t_max) {
        let sigma = channel(segment.sigma_maj, hero);
        if sigma <= 0.0 {
            t_maj = t_maj.hadamard(beer(segment.sigma_maj, segment.t_max - segment.t_min));
            continue;
        }
        let mut t_min = segment.t_min;
        loop {
            let t = t_min - (1.0 - u).ln() / sigma;
            u = rng.next_offset();
            if t >= segment.t_max {
                t_maj = t_maj.hadamard(beer(segment.sigma_maj, segment.t_max - t_min));
                break;
            }
            t_maj = t_maj.hadamard(beer(segment.sigma_maj, t - t_min));
            let point = medium.at(ray.position(t));
            if !collide(t, &point, segment.sigma_maj, t_maj, rng) {
                return Color::WHITE;
            }
            t_maj = Color::WHITE;
            t_min = t;
        }
    }
    t_maj
}

/// What a shadow ray has let through so far, with the ratios of the densities of the two
/// strategies that could have made the path to the hero channel's (see the module's
/// documentation): `t_ray` over the mean of `r_l` estimates the transmittance; a path
/// tracer weighs light sampling against delta-tracked paths by `r_l` against `r_u`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transmitted {
    /// The estimate's throughput.
    pub t_ray: Color,
    /// The unidirectional strategy's density ratios.
    pub r_u: Color,
    /// The light-sampling strategy's density ratios.
    pub r_l: Color,
}

impl Transmitted {
    /// Nothing attenuated yet.
    pub const CLEAR: Self = Self {
        t_ray: Color::WHITE,
        r_u: Color::WHITE,
        r_l: Color::WHITE,
    };
}

/// Below this estimated transmittance a ratio-tracked shadow ray plays Russian roulette.
const SHADOW_ROULETTE_BELOW: f64 = 0.05;
/// The chance such a shadow ray ends.
const SHADOW_ROULETTE_END: f64 = 0.75;

/// Transmittance along `ray` (a unit direction) over `[0, t_max]` through `medium`, folded
/// into `through`: exactly, by Beer–Lambert, in a homogeneous medium; by ratio tracking
/// against the majorant grid in a density grid (each tentative collision weighs the
/// estimate by σn/σmaj), with Russian roulette once what is left is small.
pub fn transmittance(
    medium: &Medium,
    ray: &Ray,
    t_max: f64,
    rng: &mut SplitMix64,
    hero: usize,
    through: &mut Transmitted,
) {
    if let Medium::Homogeneous(m) = medium {
        through.t_ray = through.t_ray.hadamard(beer(m.sigma_t(), t_max));
        return;
    }
    let u = rng.next_offset();
    let last = sample_majorant(
        medium,
        ray,
        t_max,
        u,
        rng,
        hero,
        |_, p, sigma_maj, t_maj, rng| {
            let sigma_n = clamp_zero(sigma_maj - p.sigma_a - p.sigma_s);
            let pdf = channel(t_maj, hero) * channel(sigma_maj, hero);
            through.t_ray = through.t_ray.hadamard(t_maj.hadamard(sigma_n)) * (1.0 / pdf);
            through.r_l = through.r_l.hadamard(t_maj.hadamard(sigma_maj)) * (1.0 / pdf);
            through.r_u = through.r_u.hadamard(t_maj.hadamard(sigma_n)) * (1.0 / pdf);
            let estimate = through.t_ray * (1.0 / super::average(through.r_l + through.r_u));
            if estimate.max_channel() < SHADOW_ROULETTE_BELOW {
                if rng.next_offset() < SHADOW_ROULETTE_END {
                    through.t_ray = Color::BLACK;
                } else {
                    through.t_ray = through.t_ray * (1.0 / (1.0 - SHADOW_ROULETTE_END));
                }
            }
            through.t_ray.max_channel() > 0.0
        },
    );
    let hero_t = channel(last, hero);
    if hero_t > 0.0 {
        let ratio = last * (1.0 / hero_t);
        through.t_ray = through.t_ray.hadamard(ratio);
        through.r_l = through.r_l.hadamard(ratio);
        through.r_u = through.r_u.hadamard(ratio);
    }
}

/// Each channel at least 0.
#[inline]
pub fn clamp_zero(c: Color) -> Color {
    Color::new(c.red.max(0.0), c.green.max(0.0), c.blue.max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{point, vector, Aabb, Transform};
    use crate::media::{CloudMedium, DensityGrid, GridMedium, HenyeyGreenstein, Homogeneous};

    fn grey(s: f64) -> Color {
        Color::new(s, s, s)
    }

    /// A grid medium over [0, 2]³ whose density varies (a ramp along x times a bump).
    fn varied() -> Medium {
        let n = 12;
        let mut values = Vec::new();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let (fx, fy, fz) = (x as f32, y as f32, z as f32);
                    values.push(
                        0.2 + fx / 4.0 + ((fy - 6.0).powi(2) + (fz - 5.0).powi(2)).sqrt() / 8.0,
                    );
                }
            }
        }
        let density = DensityGrid::new([n, n, n], values).expect("grid");
        Medium::Grid(Box::new(
            GridMedium::new(
                grey(0.3),
                grey(0.5),
                Color::BLACK,
                HenyeyGreenstein::ISOTROPIC,
                density,
                Aabb::new(point(0.0, 0.0, 0.0), point(2.0, 2.0, 2.0)),
                Transform::IDENTITY,
            )
            .expect("medium"),
        ))
    }

    /// exp(−∫σt) along the ray, by the midpoint rule.
    fn optical_transmittance(medium: &Medium, ray: &Ray, t_max: f64) -> f64 {
        let steps = 20_000;
        let dt = t_max / steps as f64;
        let tau: f64 = (0..steps)
            .map(|i| {
                let p = medium.at(ray.position((i as f64 + 0.5) * dt));
                (p.sigma_a + p.sigma_s).red * dt
            })
            .sum();
        (-tau).exp()
    }

    /// Delta tracking's transmittance estimate: 1 where no real collision happens.
    fn delta_tracked(medium: &Medium, ray: &Ray, t_max: f64, rng: &mut SplitMix64) -> f64 {
        let mut stopped = false;
        let u = rng.next_offset();
        sample_majorant(medium, ray, t_max, u, rng, 0, |_, p, sigma_maj, _, rng| {
            let real = (p.sigma_a + p.sigma_s).red / sigma_maj.red;
            stopped = rng.next_offset() < real;
            !stopped
        });
        if stopped {
            0.0
        } else {
            1.0
        }
    }

    fn ratio_tracked(medium: &Medium, ray: &Ray, t_max: f64, rng: &mut SplitMix64) -> f64 {
        let mut through = Transmitted::CLEAR;
        transmittance(medium, ray, t_max, rng, 0, &mut through);
        through.t_ray.red / average(through.r_l)
    }

    use crate::media::average;

    /// Mean and standard error of `n` draws of `f`.
    fn mean(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let x = f();
            s += x;
            s2 += x * x;
        }
        let m = s / n as f64;
        (m, ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt())
    }

    fn rays() -> [(Ray, f64); 3] {
        [
            (Ray::new(point(-1.0, 0.5, 1.0), vector(1.0, 0.0, 0.0)), 4.0),
            (Ray::new(point(0.1, 0.1, 0.2), vector(0.6, 0.48, 0.64)), 2.5),
            (Ray::new(point(1.9, 1.7, 0.3), vector(-0.8, 0.0, 0.6)), 1.9),
        ]
    }

    #[test]
    fn ratio_and_delta_tracking_agree_with_the_optical_depth_through_a_grid() {
        let medium = varied();
        let mut rng = SplitMix64::new(11);
        for (ray, t_max) in rays() {
            let exact = optical_transmittance(&medium, &ray, t_max);
            let (ratio, ratio_se) = mean(40_000, || ratio_tracked(&medium, &ray, t_max, &mut rng));
            let (delta, delta_se) = mean(40_000, || delta_tracked(&medium, &ray, t_max, &mut rng));
            assert!(exact > 0.02 && exact < 0.9, "{exact}");
            let z_ratio = (ratio - exact) / ratio_se.max(1e-12);
            let z_delta = (delta - exact) / delta_se;
            assert!(
                z_ratio.abs() < 4.0,
                "ratio {ratio} ± {ratio_se} against {exact}"
            );
            assert!(
                z_delta.abs() < 4.0,
                "delta {delta} ± {delta_se} against {exact}"
            );
            let z = (ratio - delta) / (ratio_se * ratio_se + delta_se * delta_se).sqrt();
            assert!(z.abs() < 4.0, "ratio {ratio} against delta {delta}");
        }
    }

    /// pbrt-v4's cloud over [−1, 1]³ (its box [0, 1]³ scaled by 2 and moved), thin enough
    /// that light gets through.
    fn cloud() -> Medium {
        let world_from_medium =
            crate::math::translation(-1.0, -1.0, -1.0) * crate::math::scaling(2.0, 2.0, 2.0);
        Medium::Cloud(Box::new(
            CloudMedium::new(
                grey(0.2),
                Color::new(0.6, 0.9, 1.4),
                HenyeyGreenstein::ISOTROPIC,
                2.0,
                1.0,
                3.0,
                Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0)),
                Transform::try_new(world_from_medium).expect("invertible"),
            )
            .expect("cloud"),
        ))
    }

    #[test]
    fn ratio_and_delta_tracking_through_a_cloud_agree_with_its_optical_depth() {
        let medium = cloud();
        let mut rng = SplitMix64::new(17);
        let rays = [
            // Starting outside the box, through its dense base and out.
            (Ray::new(point(-2.0, -0.8, 0.1), vector(1.0, 0.0, 0.0)), 4.0),
            // Inside, upwards through the wisps.
            (Ray::new(point(0.1, -0.5, -0.2), vector(0.0, 0.8, 0.6)), 2.0),
            // Stopping short of the far side.
            (Ray::new(point(0.9, 0.3, -1.5), vector(-0.6, 0.0, 0.8)), 1.6),
        ];
        for (ray, t_max) in rays {
            // Red by delta tracking in red (the helpers' channel); every channel by ratio
            // tracking with the hero channel drawn at random, as the path tracer draws it.
            let exact = optical_transmittance(&medium, &ray, t_max);
            assert!(exact > 0.02 && exact < 0.98, "{exact}");
            let (delta, delta_se) = mean(40_000, || delta_tracked(&medium, &ray, t_max, &mut rng));
            assert!(
                (delta - exact).abs() < 4.0 * delta_se,
                "delta {delta} ± {delta_se} against {exact}"
            );
            let steps = 20_000;
            let dt = t_max / steps as f64;
            let mut tau = Color::BLACK;
            for i in 0..steps {
                let p = medium.at(ray.position((i as f64 + 0.5) * dt));
                tau += (p.sigma_a + p.sigma_s) * dt;
            }
            for c in 0..3 {
                let expected = (-channel(tau, c)).exp();
                let (m, se) = mean(40_000, || {
                    let hero = (rng.next_u64() % 3) as usize;
                    let mut through = Transmitted::CLEAR;
                    transmittance(&medium, &ray, t_max, &mut rng, hero, &mut through);
                    channel(through.t_ray, c) / average(through.r_l)
                });
                assert!(
                    (m - expected).abs() < 4.0 * se.max(1e-4),
                    "channel {c}: {m} ± {se} against {expected}"
                );
            }
        }
    }

    #[test]
    fn a_constant_grid_transmits_as_the_homogeneous_medium_does() {
        let density = DensityGrid::new([3, 4, 5], vec![2.0; 60]).expect("grid");
        let grid = Medium::Grid(Box::new(
            GridMedium::new(
                grey(0.1),
                grey(0.4),
                Color::BLACK,
                HenyeyGreenstein::ISOTROPIC,
                density,
                Aabb::new(point(-1.0, -1.0, -1.0), point(1.0, 1.0, 1.0)),
                Transform::IDENTITY,
            )
            .expect("medium"),
        ));
        let homogeneous = Medium::Homogeneous(Homogeneous {
            sigma_a: grey(0.2),
            sigma_s: grey(0.8),
            emission: Color::BLACK,
            phase: HenyeyGreenstein::ISOTROPIC,
        });
        let ray = Ray::new(point(-0.9, 0.2, -0.3), vector(0.8, 0.0, 0.6));
        let t = 1.5;
        let mut exact = Transmitted::CLEAR;
        let mut rng = SplitMix64::new(2);
        transmittance(&homogeneous, &ray, t, &mut rng, 0, &mut exact);
        assert!((exact.t_ray.red - (-1.5f64).exp()).abs() < 1e-12);
        let (ratio, se) = mean(20_000, || ratio_tracked(&grid, &ray, t, &mut rng));
        // A constant grid's majorant is its density: every tentative collision is real.
        let (delta, dse) = mean(20_000, || delta_tracked(&grid, &ray, t, &mut rng));
        assert!(
            (ratio - exact.t_ray.red).abs() < 4.0 * se.max(1e-3),
            "{ratio} ± {se}"
        );
        assert!(
            (delta - exact.t_ray.red).abs() < 4.0 * dse,
            "{delta} ± {dse}"
        );
    }

    #[test]
    fn a_chromatic_grid_is_unbiased_in_every_channel_whatever_the_hero() {
        let density = DensityGrid::new([2, 2, 2], vec![1.0, 0.5, 2.0, 1.5, 0.1, 1.0, 0.7, 0.3])
            .expect("grid");
        let medium = Medium::Grid(Box::new(
            GridMedium::new(
                Color::new(0.2, 0.8, 1.6),
                Color::new(0.1, 0.1, 0.4),
                Color::BLACK,
                HenyeyGreenstein::ISOTROPIC,
                density,
                Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0)),
                Transform::IDENTITY,
            )
            .expect("medium"),
        ));
        let ray = Ray::new(point(0.0, 0.3, 0.6), vector(1.0, 0.0, 0.0));
        let steps = 20_000;
        let dt = 1.0 / steps as f64;
        let mut tau = Color::BLACK;
        for i in 0..steps {
            let p = medium.at(ray.position((i as f64 + 0.5) * dt));
            tau += (p.sigma_a + p.sigma_s) * dt;
        }
        let exact = [(-tau.red).exp(), (-tau.green).exp(), (-tau.blue).exp()];
        let mut rng = SplitMix64::new(5);
        for (c, &expected) in exact.iter().enumerate() {
            let (m, se) = mean(60_000, || {
                let hero = (rng.next_u64() % 3) as usize;
                let mut through = Transmitted::CLEAR;
                transmittance(&medium, &ray, 1.0, &mut rng, hero, &mut through);
                channel(through.t_ray, c) / average(through.r_l)
            });
            assert!(
                (m - expected).abs() < 4.0 * se,
                "channel {c}: {m} ± {se} against {expected}"
            );
        }
    }
}
