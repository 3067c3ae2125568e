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
//! The tree is built top-down. Each cluster is cut where the two sides cost least by
//! [`LightBounds::cost`] (power × orientation × surface area, Conty Estevez and Kulla's
//! measure), trying [`BUCKETS`] cuts along each axis: bright lights, lights far apart and
//! lights facing apart then fall into different subtrees, where the walk's importance can
//! tell them apart. Where no cut costs anything (lights on one point or one line), or
//! deeper than [`BALANCED_FROM`] levels, a cluster is cut at the median of its lights'
//! centres along the axis where they spread most, so that no trail is longer than 64 bits.

use super::light_bounds::{LightBounds, NodeBounds};
use crate::math::{Aabb, Point3, Vec3};

/// How many cuts per axis the build tries on a cluster: evenly spaced over its lights'
/// centres (pbrt-v4 takes 12, as its BVH over shapes does).
const BUCKETS: usize = 12;

/// The depth from which clusters are cut at their median: each such cut halves the lights,
/// so the deepest trail is at most this plus `log2` of the (`u32`-numbered) lights, 64 bits.
const BALANCED_FROM: u32 = 32;

/// A node of the tree: a light, or two subtrees (the first right after the node).
#[derive(Debug, Clone)]
struct Node {
    bounds: NodeBounds,
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
                bounds: bounds.prepared(),
                kind: NodeKind::Leaf(*light),
            });
            return *bounds;
        }
        let middle = if depth < BALANCED_FROM {
            cheapest_cut(lights)
        } else {
            None
        }
        .unwrap_or_else(|| median_cut(lights));
        let at = self.nodes.len();
        self.nodes.push(Node {
            bounds: LightBounds::NONE.prepared(),
            kind: NodeKind::Inner(0),
        });
        let (first, second) = lights.split_at_mut(middle);
        let a = self.build(first, trail, depth + 1);
        let second_at = self.nodes.len() as u32;
        let b = self.build(second, trail | 1 << depth, depth + 1);
        let bounds = a.union(&b);
        self.nodes[at] = Node {
            bounds: bounds.prepared(),
            kind: NodeKind::Inner(second_at),
        };
        bounds
    }

    /// The total power of its lights.
    pub fn power(&self) -> f64 {
        self.nodes[0].bounds.power()
    }

    /// The share the first of the two children at `node` (an inner node whose second child
    /// is `second`) takes from `point` of normal `normal`. Where neither may light the point
    /// (a cluster's bounds are looser than its lights'), by their powers: every light keeps
    /// some probability, so that the picks' probabilities sum to 1 from every point.
    #[inline]
    fn first_share(&self, node: usize, second: usize, point: Point3, normal: Option<Vec3>) -> f64 {
        let (first, second) = (&self.nodes[node + 1].bounds, &self.nodes[second].bounds);
        let a = first.importance(point, normal);
        let b = second.importance(point, normal);
        let total = a + b;
        if total > 0.0 && total.is_finite() {
            a / total
        } else {
            first.power() / (first.power() + second.power())
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

/// The cut of `lights` (two or more) whose sides cost least (see the [module](self)):
/// reorders them so that the first side comes first and returns how many it holds; `None`
/// where every cut costs nothing or their centres all coincide.
fn cheapest_cut(lights: &mut [(u32, LightBounds)]) -> Option<usize> {
    let mut centres = Aabb::EMPTY;
    let mut whole = Aabb::EMPTY;
    for (_, b) in lights.iter() {
        centres.add_point(b.centroid());
        whole = whole.union(&b.bounds);
    }
    let (centre_extent, extent) = (centres.extent(), whole.extent());
    let longest = extent.max_element();
    // The best (cost, axis, first bucket of the second side).
    let mut best: Option<(f64, usize, usize)> = None;
    for axis in 0..3 {
        if centre_extent[axis] <= 0.0 {
            continue;
        }
        let bucket_of = |b: &LightBounds| {
            let at = (b.centroid()[axis] - centres.min[axis]) / centre_extent[axis];
            ((at * BUCKETS as f64) as usize).min(BUCKETS - 1)
        };
        let mut buckets = [LightBounds::NONE; BUCKETS];
        for (_, b) in lights.iter() {
            let k = bucket_of(b);
            buckets[k] = buckets[k].union(b);
        }
        let stretch = longest / extent[axis];
        // The first side's bounds for each cut, then the second's from the far end.
        let mut below = [LightBounds::NONE; BUCKETS];
        let mut running = LightBounds::NONE;
        for (k, bucket) in buckets.iter().enumerate() {
            below[k] = running;
            running = running.union(bucket);
        }
        let mut above = LightBounds::NONE;
        for cut in (1..BUCKETS).rev() {
            above = above.union(&buckets[cut]);
            if below[cut].power <= 0.0 || above.power <= 0.0 {
                continue;
            }
            let cost = below[cut].cost(stretch) + above.cost(stretch);
            if cost > 0.0 && cost.is_finite() && best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, cut));
            }
        }
    }
    let (_, axis, cut) = best?;
    let at = |b: &LightBounds| {
        let at = (b.centroid()[axis] - centres.min[axis]) / centre_extent[axis];
        ((at * BUCKETS as f64) as usize).min(BUCKETS - 1)
    };
    let mut first = 0;
    for i in 0..lights.len() {
        if at(&lights[i].1) < cut {
            lights.swap(i, first);
            first += 1;
        }
    }
    (0 < first && first < lights.len()).then_some(first)
}

/// Cuts `lights` (two or more) at the median of their centres along the axis where they
/// spread most: reorders them so that the lower half comes first and returns its size.
fn median_cut(lights: &mut [(u32, LightBounds)]) -> usize {
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
    middle
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

    /// A lamp of power `power` facing down at `at`, 0.2 across.
    fn lamp_at(at: Point3, power: f64) -> LightBounds {
        LightBounds {
            bounds: Aabb::new(at, at + Vec3::new(0.2, 0.0, 0.2)),
            power,
            cone: Cone {
                axis: -Vec3::Y,
                theta_o: 0.0,
                theta_e: std::f64::consts::FRAC_PI_2,
            },
            two_sided: false,
        }
    }

    #[test]
    fn the_cheapest_cut_parts_two_far_groups_of_lamps() {
        // Eight lamps near x = 0 and eight near x = 50, shuffled: the root's two subtrees
        // are the two groups, the near group then taking nearly every pick.
        let lights: Vec<(u32, LightBounds)> = (0..16)
            .map(|i| {
                let x = if i % 2 == 0 { 0.0 } else { 50.0 } + (i / 2) as f64 * 0.3;
                (i, lamp_at(Point3::new(x, 2.0, (i % 3) as f64), 1.0))
            })
            .collect();
        let tree = LightBvh::new(lights, 16).unwrap();
        let near: f64 = (0..16)
            .step_by(2)
            .map(|i| tree.probability(Point3::new(1.0, 0.0, 1.0), Some(Vec3::Y), i))
            .sum();
        assert!(near > 0.99, "{near}");
        let NodeKind::Inner(second) = tree.nodes[0].kind else {
            panic!("a leaf at the root");
        };
        // Each subtree holds one group: eight leaves, 15 nodes.
        assert_eq!(second, 16);
    }

    #[test]
    fn lamps_in_a_line_of_ever_brighter_ones_keep_trails_within_64_bits() {
        // Costs that cut the brightest lamp off one at a time would make a tree as deep as
        // the lamps are many; past `BALANCED_FROM` levels the cuts halve, so 300 lamps fit.
        let n = 300;
        let lights: Vec<(u32, LightBounds)> = (0..n)
            .map(|i| {
                (
                    i,
                    lamp_at(Point3::new(i as f64, 1.0, 0.0), 1.2f64.powi(i as i32)),
                )
            })
            .collect();
        let tree = LightBvh::new(lights, n as usize).unwrap();
        let point = Point3::new(150.0, 0.0, 0.0);
        let sum: f64 = (0..n as usize)
            .map(|i| tree.probability(point, Some(Vec3::Y), i))
            .sum();
        assert!((sum - 1.0).abs() < 1e-9, "{sum}");
        // And lamps at one point (no cut costs anything) are halved too.
        let same: Vec<(u32, LightBounds)> = (0..100)
            .map(|i| (i, lamp_at(Point3::ZERO, 1.0 + i as f64)))
            .collect();
        let tree = LightBvh::new(same, 100).unwrap();
        let sum: f64 = (0..100).map(|i| tree.probability(point, None, i)).sum();
        assert!((sum - 1.0).abs() < 1e-9, "{sum}");
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
