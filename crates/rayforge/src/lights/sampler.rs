//! How next-event estimation picks the one light it samples at a path vertex, chosen per scene
//! ([`LightSamplerKind`]): uniformly, by power, or by a light tree that also weighs where the
//! vertex is and which way it faces ([`LightBvh`]).
//!
//! Whatever picks, multiple importance sampling must be told the probability of picking a
//! light *from the vertex the path left*, for a light the path met by scattering: that is
//! [`LightSampler::probability`], which for the tree depends on that vertex (its point and
//! normal) just as the pick did.

use super::bvh::LightBvh;
use super::light_bounds::LightBounds;
use crate::math::{Distribution1D, Point3, Vec3};
use crate::options::LightSamplerKind;

/// Marks a light that is not one of the tree's apart-sampled lights.
const IN_TREE: u32 = u32::MAX;

/// A light sampler over a list of lights (numbered as the list is).
#[derive(Debug, Clone)]
pub(crate) enum LightSampler {
    /// Each of `count` lights with probability `1 / count`.
    Uniform { count: usize },
    /// In proportion to each light's power.
    Power(Distribution1D),
    /// The lights with a place by the tree; those at infinity (the sky, directional light,
    /// infinite planes, and lights that do not fall off with distance, whose importance no
    /// distance bounds) apart: `apart` picks among them and the tree as a whole by power,
    /// the tree being its last entry.
    Bvh {
        tree: Option<LightBvh>,
        apart: Distribution1D,
        /// The apart lights' numbers, in `apart`'s order.
        apart_lights: Vec<u32>,
        /// Per light number, its place in `apart`, or [`IN_TREE`].
        apart_of: Vec<u32>,
    },
}

impl LightSampler {
    /// The sampler of kind `kind` over lights of powers `power` and tree bounds `bounds`
    /// (`None`: a light at infinity); `None` when no light has any power.
    pub fn new(
        kind: LightSamplerKind,
        power: &[f64],
        bounds: &[Option<LightBounds>],
    ) -> Option<Self> {
        let by_power = Distribution1D::new(power)
            .ok()
            .filter(|d| d.integral() > 0.0)?;
        let placed = bounds.iter().filter(|b| b.is_some()).count();
        let kind = match kind {
            LightSamplerKind::Auto if placed >= LightSamplerKind::TREE_FROM => {
                LightSamplerKind::Bvh
            }
            LightSamplerKind::Auto => LightSamplerKind::Power,
            kind => kind,
        };
        Some(match kind {
            LightSamplerKind::Uniform => Self::Uniform { count: power.len() },
            LightSamplerKind::Power | LightSamplerKind::Auto => Self::Power(by_power),
            LightSamplerKind::Bvh => {
                let placed: Vec<(u32, LightBounds)> = bounds
                    .iter()
                    .enumerate()
                    .filter_map(|(i, b)| Some((i as u32, (*b)?)))
                    .collect();
                let tree = LightBvh::new(placed, power.len());
                let mut apart_of = vec![IN_TREE; power.len()];
                let mut apart_lights = Vec::new();
                let mut weights = Vec::new();
                for (i, b) in bounds.iter().enumerate() {
                    if b.is_none() {
                        apart_of[i] = apart_lights.len() as u32;
                        apart_lights.push(i as u32);
                        weights.push(power[i]);
                    }
                }
                weights.push(tree.as_ref().map_or(0.0, LightBvh::power));
                let apart = Distribution1D::new(&weights)
                    .ok()
                    .filter(|d| d.integral() > 0.0)?;
                Self::Bvh {
                    tree,
                    apart,
                    apart_lights,
                    apart_of,
                }
            }
        })
    }

    /// Picks a light for `point` (of normal `normal`, where the vertex has one) with `u` in
    /// [0, 1): its number, the probability of picking it, and what is left of `u` (uniform in
    /// [0, 1) again, for the light's own choices). `None` where no light may light the point.
    #[inline]
    pub fn sample(&self, point: Point3, normal: Option<Vec3>, u: f64) -> Option<(usize, f64, f64)> {
        match self {
            Self::Uniform { count } => {
                let scaled = u * *count as f64;
                let light = (scaled as usize).min(count - 1);
                Some((
                    light,
                    1.0 / *count as f64,
                    (scaled - light as f64).clamp(0.0, 1.0),
                ))
            }
            Self::Power(pick) => Some(pick.sample_discrete_reused(u)),
            Self::Bvh {
                tree,
                apart,
                apart_lights,
                ..
            } => {
                let (entry, chance, rest) = apart.sample_discrete_reused(u);
                match apart_lights.get(entry) {
                    Some(&light) => Some((light as usize, chance, rest)),
                    None => {
                        let (light, p, rest) = tree.as_ref()?.sample(point, normal, rest);
                        Some((light, chance * p, rest))
                    }
                }
            }
        }
    }

    /// The probability with which [`sample`](Self::sample) picks light number `light` for
    /// `point` (of normal `normal`).
    #[inline]
    pub fn probability(&self, point: Point3, normal: Option<Vec3>, light: usize) -> f64 {
        match self {
            Self::Uniform { count } => 1.0 / *count as f64,
            Self::Power(pick) => pick.probability(light),
            Self::Bvh {
                tree,
                apart,
                apart_of,
                apart_lights,
            } => match apart_of.get(light) {
                Some(&IN_TREE) => tree.as_ref().map_or(0.0, |tree| {
                    apart.probability(apart_lights.len()) * tree.probability(point, normal, light)
                }),
                Some(&entry) => apart.probability(entry as usize),
                None => 0.0,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::light_bounds::Cone;
    use super::*;
    use crate::math::Aabb;

    fn lamp(x: f64) -> Option<LightBounds> {
        let at = Point3::new(x, 1.0, 0.0);
        Some(LightBounds {
            bounds: Aabb::new(at, at),
            power: 1.0 + x.abs(),
            cone: Cone::EVERYWHERE,
            two_sided: false,
        })
    }

    #[test]
    fn every_sampler_picks_with_the_probability_it_tells_and_they_sum_to_one() {
        let bounds = [lamp(0.0), None, lamp(2.0), lamp(-3.0), None, lamp(5.0)];
        let power = [1.0, 4.0, 3.0, 4.0, 0.5, 6.0];
        for kind in [
            LightSamplerKind::Uniform,
            LightSamplerKind::Power,
            LightSamplerKind::Bvh,
        ] {
            let sampler = LightSampler::new(kind, &power, &bounds).unwrap();
            let point = Point3::new(1.0, 0.0, 0.3);
            let normal = Some(Vec3::Y);
            let sum: f64 = (0..power.len())
                .map(|i| sampler.probability(point, normal, i))
                .sum();
            assert!((sum - 1.0).abs() < 1e-12, "{kind:?}: {sum}");
            let steps = 1 << 14;
            let mut span = vec![0.0; power.len()];
            for k in 0..steps {
                let u = (k as f64 + 0.5) / steps as f64;
                let (light, p, rest) = sampler.sample(point, normal, u).unwrap();
                assert!((0.0..=1.0).contains(&rest));
                assert!((p - sampler.probability(point, normal, light)).abs() < 1e-12);
                span[light] += 1.0 / steps as f64;
            }
            for (light, s) in span.into_iter().enumerate() {
                let p = sampler.probability(point, normal, light);
                assert!((s - p).abs() < 1e-3, "{kind:?} light {light}: {s} vs {p}");
            }
        }
    }
}
