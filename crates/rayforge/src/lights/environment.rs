//! The sky as the path tracer reads it: the world's environment maps, their radiance summed,
//! importance-sampled by luminance ([`EnvironmentMap`]), else the background as light of
//! constant radiance from every direction. A constant sky is found only by the paths that
//! escape: sampling the BSDF follows a uniform sky as well as light sampling could (perfectly,
//! for a diffuse surface), and a white furnace then has no variance at all.
//!
//! A world may have several maps (a pbrt-v4 scene's several image `infinite` lights): the sky
//! is then their sum, one light of the light list, whose draw picks a map by its power (its
//! mean luminance, what the light samplers pick lights at infinity by) and follows that map's
//! own sampling; the density of a direction is the mixture of every map's, weighed by those
//! picks (what a light sampler picking each map by power apart would give, for the price of
//! one entry), and the radiance along it the sum, so each map is sampled where it is bright
//! and the estimate stays unbiased however the maps overlap.

use super::sample::LightSample;
use crate::color::Color;
use crate::math::distribution::Distribution1D;
use crate::math::Vec3;
use crate::shading::{EnvironmentMap, SkyDraw};
use std::f64::consts::PI;
use std::sync::Arc;

/// The sky of a world: its maps, summed, or the constant background.
#[derive(Debug, Clone)]
pub struct SkyEmitter {
    /// The sky when there is no environment map.
    background: Color,
    /// The maps (the world's `environment` first), their radiance summed.
    maps: Vec<Arc<EnvironmentMap>>,
    /// Which map a draw follows, by each one's mean luminance, where there are several.
    choice: Option<Distribution1D>,
}

impl SkyEmitter {
    /// The sky of a world with `background` and, if it has any, the environment maps `maps`
    /// (which then replace the background).
    pub(super) fn new(background: Color, maps: Vec<Arc<EnvironmentMap>>) -> Self {
        let choice = if maps.len() > 1 {
            let powers: Vec<f64> = maps
                .iter()
                .map(|m| m.average_radiance().luminance().max(0.0))
                .collect();
            Distribution1D::new(&powers).ok()
        } else {
            None
        };
        Self {
            background,
            maps,
            choice,
        }
    }

    /// Whether the sky is made of maps (else it is the constant background).
    pub(super) fn has_maps(&self) -> bool {
        !self.maps.is_empty()
    }

    /// A direction towards the sky from the numbers `u` (see [`EnvironmentMap::sample`]): the
    /// unit world direction, the sky's radiance along it (every map's) and its density per
    /// solid angle (the mixture of the maps' densities, by their picks); `None` for a constant
    /// sky or an empty draw. Every draw of a [`SkyDraw`] goes through it.
    #[inline]
    pub fn draw(&self, u: [f64; 2]) -> Option<(Vec3, Color, f64)> {
        let Some(choice) = &self.choice else {
            return self.maps.first()?.sample(u);
        };
        let (map, _, u0) = choice.sample_discrete_reused(u[0]);
        let (direction, _, _) = self.maps[map].sample([u0, u[1]])?;
        let (radiance, pdf) = self.radiance_and_pdf_li(direction);
        (pdf > 0.0).then_some((direction, radiance, pdf))
    }

    /// A direction towards the sky from the draw `sky` (made there if no one has made it yet),
    /// the radiance along it, and its solid-angle density times `probability`, the chance the
    /// sky was picked; `None` for a constant sky, which is not sampled, or an empty draw.
    #[inline]
    pub fn sample_li(&self, sky: &mut SkyDraw, probability: f64) -> Option<LightSample> {
        let (direction, radiance, pdf) = sky.of(|u| self.draw(u))?;
        Some(LightSample {
            direction,
            distance: f64::INFINITY,
            radiance,
            pdf: probability * pdf,
            delta: false,
        })
    }

    /// The radiance of the sky along `direction` (what a path that escapes sees).
    #[inline]
    pub fn radiance(&self, direction: Vec3) -> Color {
        match self.maps.as_slice() {
            [] => self.background,
            [map] => map.radiance(direction),
            maps => maps
                .iter()
                .fold(Color::BLACK, |sum, map| sum + map.radiance(direction)),
        }
    }

    /// The radiance along `direction` (as [`radiance`](Self::radiance)) and the solid-angle
    /// density with which [`sample_li`](Self::sample_li) draws it, before the sky's pick: the
    /// map's, in the one look-up both take, or the mixture of the maps' (the background and 0
    /// for a constant sky, which is not sampled).
    #[inline]
    pub fn radiance_and_pdf_li(&self, direction: Vec3) -> (Color, f64) {
        let Some(choice) = &self.choice else {
            return match self.maps.first() {
                Some(map) => map.radiance_and_pdf(direction),
                None => (self.background, 0.0),
            };
        };
        let mut sum = (Color::BLACK, 0.0);
        for (index, map) in self.maps.iter().enumerate() {
            let (radiance, pdf) = map.radiance_and_pdf(direction);
            sum.0 += radiance;
            sum.1 += choice.probability(index) * pdf;
        }
        sum
    }

    /// What the light samplers pick it by: the maps' mean radiance over the scene's
    /// cross-section `disc`; 0 for a constant sky, which is not sampled.
    pub fn power(&self, disc: f64) -> f64 {
        self.maps
            .iter()
            .map(|map| map.average_radiance().luminance() * PI * disc)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::stats::chi_square_p_value;
    use glam::DMat3;

    /// Three maps of three layouts, each with a sun of its own, turned apart: a sky of their
    /// sum.
    fn three_skies() -> SkyEmitter {
        let mut rng = SplitMix64::new(4);
        let mut texels = |n: usize, sun: usize, bright: f64| {
            let mut t: Vec<Color> = (0..n)
                .map(|_| Color::new(rng.next_offset(), rng.next_offset(), 0.5))
                .collect();
            t[sun] = Color::new(bright, bright, bright);
            t
        };
        let equirect = EnvironmentMap::new(8, 5, texels(40, 9, 30.0), 1.0).unwrap();
        let lat_long = EnvironmentMap::lat_long(8, 4, texels(32, 20, 60.0), 0.5)
            .unwrap()
            .with_frame(DMat3::from_rotation_x(0.7))
            .unwrap();
        let equal_area = EnvironmentMap::equal_area(4, 4, texels(16, 5, 20.0), 2.0)
            .unwrap()
            .with_frame(DMat3::from_rotation_y(2.0))
            .unwrap();
        SkyEmitter::new(
            Color::BLACK,
            vec![Arc::new(equirect), Arc::new(lat_long), Arc::new(equal_area)],
        )
    }

    /// The direction of `(φ, θ)`, +z the pole.
    fn direction(phi: f64, theta: f64) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// `∫ f dω` over the cell of `(φ, θ)` from `(p0, t0)` to `(p1, t1)`, by the midpoint rule
    /// on an `n × n` grid.
    fn integrate(
        f: &impl Fn(Vec3) -> f64,
        (p0, p1): (f64, f64),
        (t0, t1): (f64, f64),
        n: usize,
    ) -> f64 {
        let (dp, dt) = ((p1 - p0) / n as f64, (t1 - t0) / n as f64);
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let theta = t0 + (j as f64 + 0.5) * dt;
                sum += f(direction(p0 + (i as f64 + 0.5) * dp, theta)) * theta.sin();
            }
        }
        sum * dp * dt
    }

    #[test]
    fn several_maps_sum_their_radiance_and_their_mixed_density_integrates_to_one() {
        let sky = three_skies();
        let pdf = |d: Vec3| sky.radiance_and_pdf_li(d).1;
        let total = integrate(&pdf, (0.0, 2.0 * PI), (0.0, PI), 600);
        assert!((total - 1.0).abs() < 1e-2, "{total}");
        let mut rng = SplitMix64::new(9);
        for _ in 0..200 {
            let d = direction(2.0 * PI * rng.next_offset(), PI * rng.next_offset());
            let want = sky.maps.iter().fold(Color::BLACK, |s, m| s + m.radiance(d));
            assert_eq!(sky.radiance(d), want);
            assert_eq!(sky.radiance_and_pdf_li(d).0, want);
        }
        let each: f64 = sky
            .maps
            .iter()
            .map(|m| m.average_radiance().luminance())
            .sum();
        assert!((sky.power(1.0) - each * PI).abs() < 1e-12);
    }

    #[test]
    fn draws_from_several_maps_follow_the_mixed_density() {
        let sky = three_skies();
        let (columns, rows) = (12, 6);
        let n = 200_000;
        let mut counts = vec![0u64; columns * rows];
        let mut rng = SplitMix64::new(17);
        // The sky's light over the sphere by importance: ∫ L dω = 4π × the sum of averages.
        let (mut sum, mut sum_sq) = (0.0, 0.0);
        for _ in 0..n {
            let mut draw = SkyDraw::new([rng.next_offset(), rng.next_offset()]);
            let sample = sky.sample_li(&mut draw, 0.5).expect("a direction");
            let (radiance, pdf) = sky.radiance_and_pdf_li(sample.direction);
            assert_eq!(radiance, sample.radiance);
            assert!((0.5 * pdf - sample.pdf).abs() <= 1e-12 * pdf);
            let d = sample.direction;
            let theta = d.z.clamp(-1.0, 1.0).acos();
            let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
            let c = ((phi / (2.0 * PI) * columns as f64) as usize).min(columns - 1);
            let r = ((theta / PI * rows as f64) as usize).min(rows - 1);
            counts[r * columns + c] += 1;
            let value = radiance.green / pdf;
            sum += value;
            sum_sq += value * value;
        }
        let pdf = |d: Vec3| sky.radiance_and_pdf_li(d).1;
        let expected: Vec<f64> = (0..columns * rows)
            .map(|i| {
                let (c, r) = ((i % columns) as f64, (i / columns) as f64);
                let phi = (
                    2.0 * PI * c / columns as f64,
                    2.0 * PI * (c + 1.0) / columns as f64,
                );
                let theta = (PI * r / rows as f64, PI * (r + 1.0) / rows as f64);
                integrate(&pdf, phi, theta, 60)
            })
            .collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}");
        let mean = sum / n as f64;
        let se = ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt();
        let want: f64 = sky
            .maps
            .iter()
            .map(|m| 4.0 * PI * m.average_radiance().green)
            .sum();
        assert!((mean - want).abs() < 4.0 * se, "{mean} ± {se} vs {want}");
    }

    #[test]
    fn one_map_is_drawn_as_the_map_draws_and_no_map_is_the_background() {
        let map = Arc::new(EnvironmentMap::lat_long(4, 2, vec![Color::WHITE; 8], 1.0).unwrap());
        let sky = SkyEmitter::new(Color::new(5.0, 5.0, 5.0), vec![map.clone()]);
        let u = [0.3, 0.8];
        assert_eq!(sky.draw(u), map.sample(u));
        assert_eq!(sky.radiance(Vec3::X), Color::WHITE);
        let constant = SkyEmitter::new(Color::new(5.0, 5.0, 5.0), Vec::new());
        assert_eq!(constant.radiance(Vec3::X), Color::new(5.0, 5.0, 5.0));
        assert_eq!(constant.radiance_and_pdf_li(Vec3::X).1, 0.0);
        assert_eq!(constant.power(1.0), 0.0);
        assert!(constant.draw(u).is_none());
    }
}
