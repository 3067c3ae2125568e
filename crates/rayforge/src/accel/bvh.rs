//! A bounding volume hierarchy built with the binned surface area heuristic, flattened into an
//! array and traversed front to back with an explicit stack.
//!
//! The bonus chapter "Bounding boxes and hierarchies" splits groups in half by space; the SAH
//! instead chooses, among a few candidate planes per axis, the split that minimises the expected
//! cost of a ray query (the area of each side times the primitives in it). Both the build and the
//! traversal are iterative, so degenerate input (thousands of identical boxes, flat boxes) cannot
//! overflow the stack, and a query allocates nothing.

use crate::math::{Aabb, Point3};
use glam::DVec3;
use std::ops::ControlFlow;

/// One node of the flattened tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BvhNode {
    /// Box around everything below this node.
    pub bounds: Aabb,
    /// For a leaf, the first entry in the primitive order; for an interior node, the index of
    /// the second child (the first child always directly follows its parent).
    pub offset: u32,
    /// Number of primitives in a leaf; 0 marks an interior node.
    pub count: u32,
    /// The axis an interior node was split on (its children are visited nearest first).
    pub axis: u8,
}

/// A bounding volume hierarchy over primitives identified by their index.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
    order: Vec<u32>,
}

/// Candidate split planes per axis: 12 bins come within a few percent of a full sweep.
const BINS: usize = 12;
/// Ranges this small always become leaves.
const MIN_SPLIT: usize = 3;
/// Ranges larger than this are split even when the SAH prefers a leaf (keeps leaves short).
const MAX_LEAF: usize = 16;
/// Cost of descending into a node relative to intersecting one primitive.
const TRAVERSAL_COST: f64 = 1.0;
/// The deepest the tree may grow; a query's stack holds this many entries.
pub const MAX_DEPTH: usize = 64;

/// Subtrees at least this large are split in parallel (the two halves on different threads);
/// smaller ones are built on one thread, iteratively.
const PARALLEL_MIN: usize = 16 * 1024;

/// What the build reads: each primitive's box and centroid.
struct BuildInput<'a> {
    bounds: &'a [Aabb],
    centroids: &'a [Point3],
}

impl BuildInput<'_> {
    /// The nodes of the subtree over `items` (which start at `first` in the primitive order),
    /// laid out depth first with indices relative to the subtree's root.
    fn subtree(&self, items: &mut [u32], first: usize, depth: usize) -> Vec<BvhNode> {
        if items.len() < PARALLEL_MIN {
            return self.sequential(items, first, depth);
        }
        let node_bounds = self.union_of(items);
        let Some((axis, mid)) = choose_split(items, self.bounds, self.centroids, &node_bounds)
        else {
            return self.sequential(items, first, depth);
        };
        let (left, right) = items.split_at_mut(mid);
        let (left, right) = rayon::join(
            || self.subtree(left, first, depth + 1),
            || self.subtree(right, first + mid, depth + 1),
        );
        let mut nodes = Vec::with_capacity(1 + left.len() + right.len());
        nodes.push(BvhNode {
            bounds: node_bounds,
            offset: (1 + left.len()) as u32,
            count: 0,
            axis: axis as u8,
        });
        let base = 1 + left.len();
        append_shifted(&mut nodes, left, 1);
        append_shifted(&mut nodes, right, base);
        nodes
    }

    fn union_of(&self, items: &[u32]) -> Aabb {
        items
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.union(&self.bounds[i as usize]))
    }

    /// The subtree built on this thread with an explicit stack (no recursion).
    fn sequential(&self, items: &mut [u32], first: usize, depth: usize) -> Vec<BvhNode> {
        let mut nodes = Vec::with_capacity(2 * items.len() / MIN_SPLIT + 1);
        let mut stack = Vec::with_capacity(MAX_DEPTH);
        stack.push(Pending {
            parent: None,
            start: 0,
            end: items.len(),
            depth,
        });
        while let Some(job) = stack.pop() {
            let index = nodes.len();
            if let Some(parent) = job.parent {
                let parent: &mut BvhNode = &mut nodes[parent];
                parent.offset = index as u32;
            }
            let range = &mut items[job.start..job.end];
            let node_bounds = self.union_of(range);
            let split = if range.len() < MIN_SPLIT || job.depth + 1 >= MAX_DEPTH {
                None
            } else {
                choose_split(range, self.bounds, self.centroids, &node_bounds)
            };
            let (axis, count) = match split {
                Some((axis, mid)) => {
                    stack.push(Pending {
                        parent: Some(index),
                        start: job.start + mid,
                        end: job.end,
                        depth: job.depth + 1,
                    });
                    stack.push(Pending {
                        parent: None,
                        start: job.start,
                        end: job.start + mid,
                        depth: job.depth + 1,
                    });
                    (axis, 0)
                }
                None => (0, range.len()),
            };
            nodes.push(BvhNode {
                bounds: node_bounds,
                offset: if count > 0 {
                    (first + job.start) as u32
                } else {
                    0
                },
                count: count as u32,
                axis: axis as u8,
            });
        }
        nodes
    }
}

/// Appends a subtree's nodes placed at `base`: interior nodes' second-child indices move with
/// them (leaf offsets point into the primitive order and stay).
fn append_shifted(nodes: &mut Vec<BvhNode>, subtree: Vec<BvhNode>, base: usize) {
    nodes.extend(subtree.into_iter().map(|mut n| {
        if n.count == 0 {
            n.offset += base as u32;
        }
        n
    }));
}

/// A range of the primitives waiting to become a node; `parent` is patched with the node's
/// index when it is a second child.
struct Pending {
    parent: Option<usize>,
    start: usize,
    end: usize,
    depth: usize,
}

impl Bvh {
    /// Builds the hierarchy over `bounds`, one box per primitive. Boxes must be finite; empty
    /// boxes are left out of the tree.
    pub fn build(bounds: &[Aabb]) -> Self {
        let mut order: Vec<u32> = (0..bounds.len() as u32)
            .filter(|&i| !bounds[i as usize].is_empty())
            .collect();
        let centroids: Vec<Point3> = bounds.iter().map(Aabb::centroid).collect();
        let input = BuildInput {
            bounds,
            centroids: &centroids,
        };
        let nodes = if order.is_empty() {
            Vec::new()
        } else {
            input.subtree(&mut order, 0, 0)
        };
        Self { nodes, order }
    }

    /// The nodes, root first.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// The box around everything (empty when there are no primitives).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    /// The primitives of a leaf node.
    pub fn leaf_primitives(&self, node: &BvhNode) -> &[u32] {
        &self.order[node.offset as usize..(node.offset + node.count) as usize]
    }

    /// Visits every primitive whose leaf box the ray meets within `[t_min, t_max]`, nearest
    /// boxes first. `visit` receives the primitive and the current `t_max`, which it may lower
    /// once it has found a hit (pruning farther boxes), and may stop the walk with `Break`.
    #[inline]
    pub fn traverse(
        &self,
        origin: Point3,
        direction: DVec3,
        t_min: f64,
        mut t_max: f64,
        mut visit: impl FnMut(u32, &mut f64) -> ControlFlow<()>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = direction.recip();
        let negative = [direction.x < 0.0, direction.y < 0.0, direction.z < 0.0];
        let mut stack = [0u32; MAX_DEPTH];
        let mut top = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.bounds.hit_by(origin, inv, t_min, t_max).is_some() {
                if node.count > 0 {
                    for &prim in self.leaf_primitives(node) {
                        if visit(prim, &mut t_max).is_break() {
                            return;
                        }
                    }
                } else {
                    let (near, far) = if negative[node.axis as usize] {
                        (node.offset as usize, current + 1)
                    } else {
                        (current + 1, node.offset as usize)
                    };
                    stack[top] = far as u32;
                    top += 1;
                    current = near;
                    continue;
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            current = stack[top] as usize;
        }
    }
}

/// The SAH's best split of `items` as (axis, how many go left), after partitioning `items`
/// in place; `None` when a leaf is cheaper or no plane separates the centroids.
fn choose_split(
    items: &mut [u32],
    bounds: &[Aabb],
    centroids: &[Point3],
    node_bounds: &Aabb,
) -> Option<(usize, usize)> {
    let mut centroid_bounds = Aabb::EMPTY;
    for &i in items.iter() {
        centroid_bounds.add_point(centroids[i as usize]);
    }
    let extent = centroid_bounds.extent();
    let bin_of = |axis: usize, c: DVec3| -> usize {
        let f = (c[axis] - centroid_bounds.min[axis]) / extent[axis] * BINS as f64;
        // NaN and overflow both land in a valid bin.
        (f as usize).min(BINS - 1)
    };
    let usable = [0, 1, 2].map(|axis| extent[axis] > 0.0 && extent[axis].is_finite());
    // One pass bins every item on all three axes at once: the boxes and centroids are read
    // once instead of three times (the build's hottest loop).
    let mut counts = [[0usize; BINS]; 3];
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    for &i in items.iter() {
        let (c, b) = (centroids[i as usize], &bounds[i as usize]);
        for axis in 0..3 {
            if usable[axis] {
                let bin = bin_of(axis, c);
                counts[axis][bin] += 1;
                boxes[axis][bin] = boxes[axis][bin].union(b);
            }
        }
    }
    let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, first bin on the right)
    for axis in (0..3).filter(|&a| usable[a]) {
        let (counts, boxes) = (&counts[axis], &boxes[axis]);
        // Sweep from the right to know each suffix's area and count, then from the left.
        let mut right_cost = [0.0; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0usize);
        for b in (1..BINS).rev() {
            acc = acc.union(&boxes[b]);
            n += counts[b];
            right_cost[b] = acc.half_area() * n as f64;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0usize);
        for b in 1..BINS {
            acc = acc.union(&boxes[b - 1]);
            n += counts[b - 1];
            if n == 0 || n == items.len() {
                continue;
            }
            let cost = acc.half_area() * n as f64 + right_cost[b];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, b));
            }
        }
    }
    let (cost, axis, first_right) = best?;
    let area = node_bounds.half_area();
    let split_cost = TRAVERSAL_COST + cost / area;
    if split_cost >= items.len() as f64 && items.len() <= MAX_LEAF {
        return None;
    }
    let mut mid = 0;
    for k in 0..items.len() {
        if bin_of(axis, centroids[items[k] as usize]) < first_right {
            items.swap(k, mid);
            mid += 1;
        }
    }
    (mid > 0 && mid < items.len()).then_some((axis, mid))
}
