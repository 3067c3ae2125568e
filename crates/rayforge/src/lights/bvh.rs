//! The light tree: a binary tree over the lights that have a place (not the sky or other
//! lights at infinity), each node holding the [`LightBounds`] of the lights below it.
//!
//! A light is picked for a shading point by walking down from the root, at each node going to
//! a child with probability proportional to the child's importance seen from the point; the
//! probabilities of the steps multiply into the light's. With many small lights this picks
//! the ones near the point and facing it, where picking by power alone spends most samples on
//! lights that give the point next to nothing. Multiple importance sampling needs the same
//! probability for a light a path hit: each light keeps its *bit trail* (which child was
//! taken at each level), so that [`LightBvh::probability`] retraces the walk from the root
//! without searching (the idea of pbrt-v4's `BVHLightSampler`, ch. 12.6).
//!
//! The tree is built top-down, splitting each cluster at the median of its lights' centres
//! along the axis where they spread most: it is balanced, so no trail is longer than
//! `log2(lights) + 1` bits (a `u64` holds any real scene's).

use super::light_bounds::LightBounds;
use crate::math::{Aabb, Point3, Vec3};

/// A node of the tree: a light, or two subtrees (the first right after the node).
#[derive(Debug, Clone)]
struct Node {
    bounds: LightBounds,
    /// The light's number (as given to [`LightBvh::new`]), or where the second child is.
    kind: NodeKind,
}

#[derive(Debug, Clone, Copy)]
enum NodeKind {
    Leaf(u32),
    /// The second child's index; the first is the next node.
    Inner(u32),
}

/// The tree (see the [module](self)).
#[derive(Debug, Clone)]
pub struct LightBvh {
    /// Depth first, each inner node followed by its first subtree.
    nodes: Vec<Node>,
    /// Per light number, its trail: bit `k` says which child the walk takes at depth `k`
    /// (1: the second). `None` for lights not in the tree.
    trails: Vec<Option<u64>>,
}

impl LightBvh {
    /// The tree over `lights`, each a light's number and bounds (`count`: how many numbers
    /// there are, in the tree or not); `None` when no light has any power.
    pub fn new(mut lights: Vec<(u32, LightBounds)>, count: usize) -> Option<Self> {
        lights.retain(|(_, b)| b.power > 0.0 && b.power.is_finite());
        if lights.is_empty() {
            return None;
        }
        let mut tree = Self {
            nodes: Vec::with_capacity(2 * lights.len()),
            trails: vec![None; count],
        };
        tree.build(&mut lights, 0, 0);
        Some(tree)
    }

    /// Adds the subtree over `lights`, whose root's trail so far is `trail` at `depth` bits;
    /// returns the bounds of its root.
    fn build(&mut self, lights: &mut [(u32, LightBounds)], trail: u64, depth: u32) -> LightBounds {
        if let [(light, bounds)] = lights {
            self.trails[*light as usize] = Some(trail);
            self.nodes.push(Node {
                bounds: *bounds,
                kind: NodeKind::Leaf(*light),
            });
            return *bounds;
        }
        let mut centres = Aabb::EMPTY;
        for (_, b) in lights.iter() {
            centres.add_point(b.centroid());
        }
        let extent = centres.extent();
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let middle = lights.len() / 2;
        lights.select_nth_unstable_by(middle, |a, b| {
            a.1.centroid()[axis].total_cmp(&b.1.centroid()[axis])
        });
        let at = self.nodes.len();
        self.nodes.push(Node {
            bounds: lights[0].1,
            kind: NodeKind::Inner(0),
        });
        let (first, second) = lights.split_at_mut(middle);
        let a = self.build(first, trail, depth + 1);
        let second_at = self.nodes.len() as u32;
        let b = self.build(second, trail | 1 << depth, depth + 1);
        let bounds = a.union(&b);
        self.nodes[at] = Node {
            bounds,
            kind: NodeKind::Inner(second_at),
        };
        bounds
    }

    /// The total power of its lights.
    pub fn power(&self) -> f64 {
        self.nodes[0].bounds.power
    }

    /// The share the first of the two children at `node` (an inner node whose second child
    /// is `second`) takes from `point` of normal `normal`. Where neither may light the point
    /// (a cluster's bounds are looser than its lights'), by their powers: every light keeps
    /// some probability, so that the picks' probabilities sum to 1 from every point.
    fn first_share(&self, node: usize, second: usize, point: Point3, normal: Option<Vec3>) -> f64 {
        let (first, second) = (&self.nodes[node + 1].bounds, &self.nodes[second].bounds);
        let a = first.importance(point, normal);
        let b = second.importance(point, normal);
        let total = a + b;
        if total > 0.0 && total.is_finite() {
            a / total
        } else {
            first.power / (first.power + second.power)
        }
    }

    /// Picks a light for `point` (of normal `normal`, where it has one) with `u` in [0, 1):
    /// its number, the probability of picking it, and `u` rescaled to [0, 1) for reuse.
    pub fn sample(&self, point: Point3, normal: Option<Vec3>, mut u: f64) -> (usize, f64, f64) {
        let mut node = 0;
        let mut probability = 1.0;
        loop {
            match self.nodes[node].kind {
                NodeKind::Leaf(light) => return (light as usize, probability, u),
                NodeKind::Inner(second) => {
                    let second = second as usize;
                    let share = self.first_share(node, second, point, normal);
                    if u < share {
                        u = (u / share).min(ONE_BELOW);
                        probability *= share;
                        node += 1;
                    } else {
                        u = ((u - share) / (1.0 - share)).min(ONE_BELOW);
                        probability *= 1.0 - share;
                        node = second;
                    }
                }
            }
        }
    }

    /// The probability that [`sample`](Self::sample) picks light `light` for `point` (of
    /// normal `normal`): the walk down its trail, each step's share multiplied in; 0 for a
    /// light not in the tree.
    pub fn probability(&self, point: Point3, normal: Option<Vec3>, light: usize) -> f64 {
        let Some(Some(trail)) = self.trails.get(light) else {
            return 0.0;
        };
        let (mut node, mut depth, mut probability) = (0, 0, 1.0);
        while let NodeKind::Inner(second) = self.nodes[node].kind {
            let second = second as usize;
            let share = self.first_share(node, second, point, normal);
            if trail >> depth & 1 == 0 {
                probability *= share;
                node += 1;
            } else {
                probability *= 1.0 - share;
                node = second;
            }
            depth += 1;
        }
        probability
    }
}

/// The largest number below 1: a rescaled pick number stays in [0, 1).
const ONE_BELOW: f64 = 1.0 - f64::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::super::light_bounds::Cone;
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    /// Lamps on a grid, facing all ways, of differing powers.
    fn lamps(n: usize) -> Vec<(u32, LightBounds)> {
        (0..n)
            .map(|i| {
                let at = Point3::new((i % 7) as f64, (i / 7 % 5) as f64 * 0.5, (i / 35) as f64);
                let axis = [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::Y][i % 4];
                let cone = Cone {
                    axis,
                    theta_o: if i % 3 == 0 {
                        std::f64::consts::PI
                    } else {
                        0.0
                    },
                    theta_e: std::f64::consts::FRAC_PI_2,
                };
                let bounds = LightBounds {
                    bounds: Aabb::new(at, at + Vec3::splat(0.1)),
                    power: 1.0 + (i % 5) as f64,
                    cone,
                    two_sided: i % 5 == 0,
                };
                (i as u32, bounds)
            })
            .collect()
    }

    #[test]
    fn the_probabilities_from_any_point_sum_to_one() {
        let n = 77;
        let tree = LightBvh::new(lamps(n), n).unwrap();
        let mut random = SplitMix64::new(3);
        for _ in 0..200 {
            let mut r = || random.next_offset() * 8.0 - 1.0;
            let point = Point3::new(r(), r(), r());
            let normal = Vec3::new(r(), r(), r()).normalize();
            for normal in [None, Some(normal)] {
                let sum: f64 = (0..n).map(|i| tree.probability(point, normal, i)).sum();
                assert!((sum - 1.0).abs() < 1e-12, "{sum} at {point:?}");
            }
        }
    }

    #[test]
    fn a_pick_has_the_probability_the_tree_tells() {
        let n = 40;
        let tree = LightBvh::new(lamps(n), n).unwrap();
        let point = Point3::new(2.3, 0.4, 0.7);
        let normal = Some(Vec3::new(0.2, 1.0, -0.3).normalize());
        // Every pick number lands on one light, whose probability the walk reports; the pick
        // numbers in [0, 1) that land on a light span exactly its probability.
        let steps = 1 << 16;
        let mut span = vec![0.0; n];
        for k in 0..steps {
            let u = (k as f64 + 0.5) / steps as f64;
            let (light, p, rest) = tree.sample(point, normal, u);
            assert!((0.0..1.0).contains(&rest));
            assert!((p - tree.probability(point, normal, light)).abs() < 1e-12);
            span[light] += 1.0 / steps as f64;
        }
        for (light, &s) in span.iter().enumerate() {
            let p = tree.probability(point, normal, light);
            assert!(
                (s - p).abs() <= 2.0 / steps as f64 * 40.0,
                "{light}: {s} vs {p}"
            );
        }
    }

    #[test]
    fn random_picks_follow_the_probabilities_by_chi_square() {
        let n = 60;
        let tree = LightBvh::new(lamps(n), n).unwrap();
        let point = Point3::new(-0.5, 1.2, 0.4);
        let normal = Some(Vec3::new(0.0, 1.0, 0.0));
        let picks = 200_000;
        let mut counts = vec![0.0; n];
        let mut random = SplitMix64::new(11);
        for _ in 0..picks {
            let (light, _, _) = tree.sample(point, normal, random.next_offset());
            counts[light] += 1.0;
        }
        // Lights expected fewer than 5 times are pooled into one cell.
        let (mut chi2, mut cells, mut pool_e, mut pool_o) = (0.0, 0, 0.0, 0.0);
        for (light, &o) in counts.iter().enumerate() {
            let e = picks as f64 * tree.probability(point, normal, light);
            if e < 5.0 {
                pool_e += e;
                pool_o += o;
            } else {
                chi2 += (o - e) * (o - e) / e;
                cells += 1;
            }
        }
        if pool_e > 0.0 {
            chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            cells += 1;
        }
        // The 0.9999 quantile of chi-square with k = cells - 1 degrees of freedom, by
        // Wilson and Hilferty's cube-root approximation (z = 3.719).
        let k = (cells - 1) as f64;
        let limit = k * (1.0 - 2.0 / (9.0 * k) + 3.719 * (2.0 / (9.0 * k)).sqrt()).powi(3);
        assert!(
            chi2 < limit,
            "chi-square {chi2} over {limit} ({cells} cells)"
        );
    }
}
