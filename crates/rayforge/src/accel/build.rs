//! Building the eight-wide hierarchy with the binned surface area heuristic.
//!
//! Each primitive becomes a [`PrimRef`]: its box in the hierarchy's `f32` frame (widened so
//! rounding can never make a ray miss it) with its index tucked into the spare fourth lane, 32
//! bytes that the build reads front to back and partitions in place. A node takes a range
//! of them and splits it in two with the SAH, then splits the child with the largest surface
//! until it has eight children (or the rest are cheaper as leaves); each child that is not a
//! leaf becomes a node the same way. Large subtrees are built on separate threads, and so
//! are the two halves of a large node's first split.
//!
//! The SAH chooses, among [`BINS`] candidate planes per axis, the split that minimises the
//! expected cost of a ray query, the area of each side times the work inside it. Leaves are
//! costed in whole blocks (a mesh tests four triangles at once, so three triangles cost as
//! much as four), which steers the build towards full blocks.
//!
//! A build may be given a stop flag (Ctrl-C, the page's cancel), looked at as each node is
//! begun: once it is set, every range not yet split becomes a stub and the build gives up
//! (`None`), so a hierarchy over tens of millions of primitives stops within one node's
//! split (a few passes over its range) instead of at its end. The flag is a relaxed load per
//! node, nothing per primitive; a build that is not stopped makes the very same tree.

use super::bvh::{leaf_blocks, leaf_reference, Bvh, Node, EMPTY, LEAF, MAX_DEPTH, WIDTH};
use super::bvh::{MAX_BLOCKS, MAX_LEAF_BLOCKS, NO_PRIMITIVE};
use super::pages;
use crate::math::{Aabb, Point3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use wide::f32x4;

/// Candidate split planes per axis.
const BINS: usize = 16;
/// Cost of entering a node relative to testing one block of primitives, for blocks of
/// several primitives tested at once (a mesh's packet of four triangles costs about as much
/// as four of a node's boxes)…
const PACKED_TRAVERSAL_COST: f32 = 1.5;
/// …and for primitives tested one by one (a world's objects: each test moves the ray into
/// the object's space and solves its shape, several times a node's box tests).
const SINGLE_TRAVERSAL_COST: f32 = 0.25;
/// Ranges of at least twice this many primitives choose their split from a sample this
/// large.
const SAMPLED: usize = 256;
/// Subtrees at least this large are built on their own thread.
const PARALLEL_MIN: usize = 8 * 1024;
/// Below this node depth the SAH chooses splits; deeper (only pathological input gets there)
/// ranges are halved, so no path can exceed [`MAX_DEPTH`] nodes: halving at least four ways
/// per node reaches a leaf within 16 more levels from 2^32 primitives. (Real scenes stay far
/// shallower: a million triangles make fewer than a dozen levels.)
const BALANCED_DEPTH: usize = MAX_DEPTH - 16;
/// Boxes are widened by this fraction of their largest coordinate (their distance from the
/// base point), far more than the rounding of the box, of a ray's origin near it and of the
/// slab test's arithmetic, all a few units of 2^-24 of that magnitude.
const RELATIVE_PAD: f32 = 1.0 / (1 << 20) as f32;
/// …and by this fraction of the whole hierarchy's size, so that boxes at the base point
/// (whose coordinates are near zero) still have some width.
const ABSOLUTE_PAD: f64 = 1.0 / (1u64 << 28) as f64;

/// A primitive's box in the build: minimum (with the primitive's index in the fourth lane)
/// and maximum.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PrimRef {
    min: f32x4,
    max: f32x4,
}

impl PrimRef {
    /// The primitive's index.
    #[inline]
    pub(crate) fn id(&self) -> u32 {
        self.min.as_array()[3].to_bits()
    }

    /// Twice its centre (the factor cancels in binning and saves a multiply).
    #[inline]
    fn centre2(&self) -> f32x4 {
        self.min + self.max
    }
}

/// The `f32` frame of a hierarchy: its base point and how much boxes are widened.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) base: Point3,
    absolute_pad: f32,
}

impl Frame {
    /// The frame centred on `bounds` (the box around every primitive).
    pub(crate) fn around(bounds: &Aabb) -> Self {
        if bounds.is_empty() || !bounds.min.is_finite() || !bounds.max.is_finite() {
            return Self {
                base: Point3::ZERO,
                absolute_pad: 0.0,
            };
        }
        Self {
            base: bounds.centroid(),
            absolute_pad: (bounds.extent().max_element() * ABSOLUTE_PAD) as f32,
        }
    }

    /// The build's records of primitives `0..count`, `bounds(i)` giving the box of primitive
    /// `i` (`None` for one to leave out), made in parallel; those whose boxes do not fit in
    /// `f32` are left out too. (Each record is written in its place and the few left out are
    /// squeezed out afterwards: a filtering parallel collect would gather pieces and copy
    /// every record a second time.)
    pub(crate) fn prim_refs(
        &self,
        count: usize,
        bounds: impl Fn(usize) -> Option<(Point3, Point3)> + Sync,
    ) -> Vec<PrimRef> {
        let left_out = PrimRef {
            min: f32x4::splat(f32::from_bits(NO_PRIMITIVE)),
            max: f32x4::ZERO,
        };
        let mut refs: Vec<PrimRef> =
            pages::collect((0..count).into_par_iter().with_min_len(4096).map(|i| {
                bounds(i)
                    .and_then(|(min, max)| self.prim_ref(i as u32, min, max))
                    .unwrap_or(left_out)
            }));
        refs.retain(|r| r.id() != NO_PRIMITIVE);
        refs
    }

    /// The build's record of primitive `id` with box `min`..`max` (world or object units);
    /// `None` when the box does not fit in `f32` (such a primitive cannot be indexed).
    #[inline]
    pub(crate) fn prim_ref(&self, id: u32, min: Point3, max: Point3) -> Option<PrimRef> {
        let lo = (min - self.base).as_vec3();
        let hi = (max - self.base).as_vec3();
        let magnitude = lo.abs().max(hi.abs()).max_element();
        if !magnitude.is_finite() || magnitude > 1.0e30 {
            return None;
        }
        let pad = magnitude * RELATIVE_PAD + self.absolute_pad;
        Some(PrimRef {
            min: f32x4::new([lo.x - pad, lo.y - pad, lo.z - pad, f32::from_bits(id)]),
            max: f32x4::new([hi.x + pad, hi.y + pad, hi.z + pad, 0.0]),
        })
    }
}

/// Builds a hierarchy over boxes (empty ones and those too large for `f32` are left out);
/// `None` when `stop` was set before it was through.
pub(crate) fn from_boxes(bounds: &[Aabb], block: usize, stop: Option<&AtomicBool>) -> Option<Bvh> {
    let mut all = Aabb::EMPTY;
    for b in bounds.iter().filter(|b| !b.is_empty()) {
        all = all.union(b);
    }
    let frame = Frame::around(&all);
    let refs = frame.prim_refs(bounds.len(), |i| {
        let b = &bounds[i];
        (!b.is_empty()).then_some((b.min, b.max))
    });
    build(refs, block, frame, all, stop)
}

/// Builds a hierarchy over prepared primitive records; `bounds` is their exact box. `None`
/// when `stop` was set before the build was through (see the [module](self)).
pub(crate) fn build(
    mut refs: Vec<PrimRef>,
    block: usize,
    frame: Frame,
    bounds: Aabb,
    stop: Option<&AtomicBool>,
) -> Option<Bvh> {
    let block = block.clamp(1, 8).next_power_of_two();
    assert!(
        refs.len() < MAX_BLOCKS,
        "a hierarchy holds fewer than {MAX_BLOCKS} primitives"
    );
    if refs.is_empty() {
        return Some(Bvh {
            block,
            base: frame.base,
            ..Bvh::default()
        });
    }
    let builder = Builder {
        block,
        block_shift: block.next_power_of_two().trailing_zeros(),
        max_leaf: (MAX_LEAF_BLOCKS / 4).max(1) * block.max(2),
        traversal_cost: if block > 1 {
            PACKED_TRAVERSAL_COST
        } else {
            SINGLE_TRAVERSAL_COST
        },
        stop,
    };
    let info = Info::of(&refs);
    let mut nodes = pages::with_capacity(refs.len() / (2 * block));
    let root = builder.subtree(&mut refs, info, 0, 0, &mut nodes);
    if builder.stopped() {
        return None;
    }
    if root & LEAF != 0 {
        // Everything in one leaf: the root is still a node, with one child.
        let mut node = Node::EMPTY;
        info.bounds.write(&mut node, 0);
        node.child[0] = root;
        nodes.push(node);
    }
    let (nodes, order) = lay_out_leaves(nodes, &refs, block);
    Some(Bvh {
        depth: depth_of(&nodes),
        nodes,
        order,
        block,
        base: frame.base,
        bounds,
    })
}

/// Nodes on the longest path from the root down (children always follow their parents).
fn depth_of(nodes: &[Node]) -> usize {
    let mut depth = vec![0usize; nodes.len()];
    if let Some(root) = depth.first_mut() {
        *root = 1;
    }
    for (i, node) in nodes.iter().enumerate() {
        for &child in &node.child {
            if child != EMPTY && child & LEAF == 0 {
                depth[child as usize] = depth[i] + 1;
            }
        }
    }
    depth.into_iter().max().unwrap_or(0)
}

/// Gives each leaf its run of blocks in the primitive order (in the order the nodes list
/// them, so a subtree's primitives lie together), padding blocks with [`NO_PRIMITIVE`], and
/// turns the build's leaf references (which name ranges of `refs`) into block references.
fn lay_out_leaves(mut nodes: Vec<Node>, refs: &[PrimRef], block: usize) -> (Vec<Node>, Vec<u32>) {
    let mut order = pages::with_capacity(refs.len() + refs.len() / 4);
    for node in &mut nodes {
        for child in &mut node.child {
            if *child == EMPTY || *child & LEAF == 0 {
                continue;
            }
            let (start, count) = leaf_blocks(*child);
            let first_block = order.len() / block;
            order.extend(refs[start..start + count].iter().map(PrimRef::id));
            order.resize(order.len().div_ceil(block) * block, NO_PRIMITIVE);
            *child = leaf_reference(first_block, order.len() / block - first_block);
        }
    }
    (nodes, order)
}

/// An axis-aligned box in the build (the fourth lanes are meaningless).
#[derive(Debug, Clone, Copy)]
struct Box4 {
    min: f32x4,
    max: f32x4,
}

impl Box4 {
    const EMPTY: Self = Self {
        min: f32x4::splat(f32::INFINITY),
        max: f32x4::splat(f32::NEG_INFINITY),
    };

    #[inline(always)]
    fn grow(&mut self, min: f32x4, max: f32x4) {
        self.min = self.min.fast_min(min);
        self.max = self.max.fast_max(max);
    }

    #[inline(always)]
    fn add_point(&mut self, p: f32x4) {
        self.grow(p, p);
    }

    #[inline]
    fn union(&self, other: &Self) -> Self {
        Self {
            min: self.min.fast_min(other.min),
            max: self.max.fast_max(other.max),
        }
    }

    /// Half the surface area (the SAH's measure; the factor 2 cancels). Empty boxes have 0.
    #[inline]
    fn half_area(&self) -> f32 {
        let d = (self.max - self.min).fast_max(f32x4::ZERO).to_array();
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }

    /// Stores the box as child `slot` of `node`.
    fn write(&self, node: &mut Node, slot: usize) {
        let (min, max) = (self.min.to_array(), self.max.to_array());
        for axis in 0..3 {
            node.planes[axis][slot] = min[axis];
            node.planes[3 + axis][slot] = max[axis];
        }
    }
}

/// What the build knows of a range of primitives: their box and the box of their (doubled)
/// centres.
#[derive(Debug, Clone, Copy)]
struct Info {
    bounds: Box4,
    centres: Box4,
}

impl Info {
    const EMPTY: Self = Self {
        bounds: Box4::EMPTY,
        centres: Box4::EMPTY,
    };

    #[inline(always)]
    fn add(&mut self, r: &PrimRef) {
        self.bounds.grow(r.min, r.max);
        self.centres.add_point(r.centre2());
    }

    fn of(refs: &[PrimRef]) -> Self {
        if refs.len() >= 4 * PARALLEL_MIN {
            return refs
                .par_chunks(PARALLEL_MIN)
                .map(Self::of)
                .reduce(|| Self::EMPTY, |a, b| a.union(&b));
        }
        let mut info = Self::EMPTY;
        for r in refs {
            info.add(r);
        }
        info
    }

    fn union(&self, other: &Self) -> Self {
        Self {
            bounds: self.bounds.union(&other.bounds),
            centres: self.centres.union(&other.centres),
        }
    }
}

/// The bins of the SAH along the three axes: per bin, the box of the primitives whose
/// centres fall in it, and how many.
#[derive(Debug, Clone, Copy)]
struct Bins<const N: usize> {
    bounds: [[Box4; N]; 3],
    counts: [[u32; N]; 3],
}

impl<const N: usize> Bins<N> {
    const EMPTY: Self = Self {
        bounds: [[Box4::EMPTY; N]; 3],
        counts: [[0; N]; 3],
    };

    #[inline(always)]
    fn add(&mut self, bins: [i32; 4], r: &PrimRef) {
        for (axis, &bin) in bins.iter().take(3).enumerate() {
            let b = bin as usize;
            self.bounds[axis][b].grow(r.min, r.max);
            self.counts[axis][b] += 1;
        }
    }

    fn merge(mut self, other: &Self) -> Self {
        for axis in 0..3 {
            for i in 0..N {
                self.bounds[axis][i] = self.bounds[axis][i].union(&other.bounds[axis][i]);
                self.counts[axis][i] += other.counts[axis][i];
            }
        }
        self
    }

    /// Counts the primitives into the bins along all three axes in one pass. Large ranges
    /// put alternate primitives in two sets of bins, merged at the end: neighbouring
    /// primitives usually share a bin, and one set would make each update wait for the
    /// previous one's store.
    fn fill(refs: &[PrimRef], binning: &Binning) -> Self {
        let mut even = Self::EMPTY;
        if refs.len() < 256 {
            for r in refs {
                even.add(binning.bins_of(r), r);
            }
            return even;
        }
        let mut odd = Self::EMPTY;
        let mut pairs = refs.chunks_exact(2);
        for pair in &mut pairs {
            even.add(binning.bins_of(&pair[0]), &pair[0]);
            odd.add(binning.bins_of(&pair[1]), &pair[1]);
        }
        for r in pairs.remainder() {
            even.add(binning.bins_of(r), r);
        }
        even.merge(&odd)
    }

    /// The cheapest split plane by the SAH, leaves costed in blocks by `blocks`; `None` if
    /// every plane leaves one side empty.
    fn best_split(
        &self,
        n: usize,
        binning: &Binning,
        blocks: impl Fn(u32) -> f32,
    ) -> Option<Split> {
        let scale = binning.scale.to_array();
        let mut best: Option<Split> = None;
        for (axis, &scale) in scale.iter().take(3).enumerate() {
            if scale == 0.0 {
                continue;
            }
            let (bounds, counts) = (&self.bounds[axis], &self.counts[axis]);
            // Right to left for each suffix's cost, then left to right.
            let mut right_cost = [0f32; N];
            let (mut acc, mut count) = (Box4::EMPTY, 0u32);
            for b in (1..N).rev() {
                acc = acc.union(&bounds[b]);
                count += counts[b];
                right_cost[b] = acc.half_area() * blocks(count);
            }
            let (mut acc, mut count) = (Box4::EMPTY, 0u32);
            for b in 1..N {
                acc = acc.union(&bounds[b - 1]);
                count += counts[b - 1];
                if count == 0 || count as usize == n {
                    continue;
                }
                let cost = acc.half_area() * blocks(count) + right_cost[b];
                if best.is_none_or(|s| cost < s.cost) {
                    best = Some(Split {
                        axis,
                        first_right: b as i32,
                        cost,
                    });
                }
            }
        }
        best
    }
}

/// How primitives' centres map to bins along each axis.
#[derive(Debug, Clone, Copy)]
struct Binning {
    origin: f32x4,
    scale: f32x4,
    /// How many bins (fewer for small ranges, whose sweep would otherwise cost more than
    /// their binning).
    count: usize,
}

impl Binning {
    /// Bins across `centres` for `n` primitives; `None` when the centres coincide on every
    /// axis.
    fn across(centres: &Box4, n: usize) -> Option<Self> {
        let count = if n <= 16 {
            4
        } else if n <= 64 {
            8
        } else {
            BINS
        };
        let extent = (centres.max - centres.min).to_array();
        // Just under `count` bins per extent: the largest centre lands in the last bin.
        let per_unit = extent.map(|e| {
            if e > 0.0 && e.is_finite() {
                count as f32 * 0.999_99 / e
            } else {
                0.0
            }
        });
        if per_unit[..3].iter().all(|&s| s == 0.0) {
            return None;
        }
        Some(Self {
            origin: centres.min,
            scale: f32x4::new([per_unit[0], per_unit[1], per_unit[2], 0.0]),
            count,
        })
    }

    /// The bin of a primitive on each axis. Clamping in floating point first keeps a NaN or
    /// a rounding overshoot in range (`fast_max` picks 0 over a NaN).
    #[inline(always)]
    fn bins_of(&self, r: &PrimRef) -> [i32; 4] {
        let f = (r.centre2() - self.origin) * self.scale;
        f.fast_max(f32x4::ZERO)
            .fast_min(f32x4::splat(self.count as f32 - 1.0))
            .fast_trunc_int()
            .to_array()
    }
}

/// A split found by the SAH: the axis, the first bin on the right and the estimated cost.
#[derive(Debug, Clone, Copy)]
struct Split {
    axis: usize,
    first_right: i32,
    cost: f32,
}

/// A range of the build's records waiting to become a child of a node.
#[derive(Clone, Copy)]
struct Pending {
    start: usize,
    end: usize,
    info: Info,
    /// The SAH prefers this range as a leaf.
    leaf: bool,
}

impl Pending {
    const EMPTY: Self = Self {
        start: 0,
        end: 0,
        info: Info::EMPTY,
        leaf: true,
    };
}

struct Builder<'s> {
    block: usize,
    /// `log2(block)`: blocks are counted with a shift.
    block_shift: u32,
    max_leaf: usize,
    /// The SAH's cost of a node, in blocks.
    traversal_cost: f32,
    /// Looked at as each node is begun (see the [module](self)).
    stop: Option<&'s AtomicBool>,
}

impl Builder<'_> {
    /// Whether the stop flag is set.
    #[inline]
    fn stopped(&self) -> bool {
        self.stop.is_some_and(|s| s.load(Ordering::Relaxed))
    }

    /// Blocks needed for `n` primitives.
    #[inline]
    fn blocks(&self, n: u32) -> f32 {
        ((n + self.block as u32 - 1) >> self.block_shift) as f32
    }

    /// Splits `refs` into the children of one node, written to `out` (as many as it holds,
    /// at most [`WIDTH`]) with ranges counted from `offset`: how many there are. The child
    /// with the largest surface is split until `out` is full or every child is better as a
    /// leaf; a range large enough to be built in parallel is first split in two, and each
    /// half fills half of `out` on its own thread (otherwise the top of the tree, three
    /// passes over every primitive, would run on one thread).
    fn children(
        &self,
        refs: &mut [PrimRef],
        info: Info,
        offset: usize,
        depth: usize,
        out: &mut [Pending],
    ) -> usize {
        let n = refs.len();
        let whole = Pending {
            start: offset,
            end: offset + n,
            info,
            leaf: false,
        };
        if out.len() >= 2 && n >= PARALLEL_MIN {
            let Some((mid, left, right)) = self.split(refs, &info, depth) else {
                out[0] = Pending {
                    leaf: true,
                    ..whole
                };
                return 1;
            };
            let (left_refs, right_refs) = refs.split_at_mut(mid);
            let half = out.len() / 2;
            let (left_out, right_out) = out.split_at_mut(half);
            let (l, r) = rayon::join(
                || self.children(left_refs, left, offset, depth, left_out),
                || self.children(right_refs, right, offset + mid, depth, right_out),
            );
            out.copy_within(half..half + r, l);
            return l + r;
        }
        out[0] = whole;
        let mut count = 1;
        while count < out.len() {
            let Some(pick) = (0..count).filter(|&i| !out[i].leaf).max_by(|&a, &b| {
                let area = |i: usize| out[i].info.bounds.half_area();
                area(a).total_cmp(&area(b))
            }) else {
                break;
            };
            let child = out[pick];
            let range = child.start - offset..child.end - offset;
            match self.split(&mut refs[range], &child.info, depth) {
                None => out[pick].leaf = true,
                Some((mid, left, right)) => {
                    out.copy_within(pick + 1..count, pick + 2);
                    out[pick] = Pending {
                        end: child.start + mid,
                        info: left,
                        ..child
                    };
                    out[pick + 1] = Pending {
                        start: child.start + mid,
                        info: right,
                        ..child
                    };
                    count += 1;
                }
            }
        }
        count
    }

    /// Builds the subtree over `refs` (which start at `first` in the whole array), appending
    /// its nodes to `out` (the subtree's root first) and returning the reference to its root:
    /// a node index in `out`, or a leaf (naming its range of `refs`) when the whole range is
    /// one.
    fn subtree(
        &self,
        refs: &mut [PrimRef],
        info: Info,
        first: usize,
        depth: usize,
        out: &mut Vec<Node>,
    ) -> u32 {
        let n = refs.len();
        if self.stopped() {
            // A stub in place of the range: the build is given up (`build` returns `None`).
            return leaf_reference(first, 1);
        }
        let mut children = [Pending::EMPTY; WIDTH];
        let count = self.children(refs, info, 0, depth, &mut children);
        let children = &children[..count];
        if count == 1 {
            return leaf_reference(first, n);
        }
        let index = out.len();
        out.push(Node::EMPTY);
        let mut node = Node::EMPTY;
        for (slot, child) in children.iter().enumerate() {
            child.info.bounds.write(&mut node, slot);
            if child.leaf {
                node.child[slot] = leaf_reference(first + child.start, child.end - child.start);
            }
        }
        if n >= PARALLEL_MIN {
            // Each child's subtree on its own thread, into its own list, then moved here.
            let mut parts: Vec<(usize, &mut [PrimRef], Pending)> = Vec::with_capacity(WIDTH);
            let mut rest = refs;
            let mut at = 0;
            for (slot, child) in children.iter().enumerate() {
                let (part, tail) = rest.split_at_mut(child.end - at);
                at = child.end;
                rest = tail;
                if !child.leaf {
                    parts.push((slot, part, *child));
                }
            }
            let built: Vec<(usize, u32, Vec<Node>)> = parts
                .into_par_iter()
                .map(|(slot, part, child)| {
                    // About one node per eight blocks: a guess that saves most regrowth.
                    let mut nodes = pages::with_capacity(part.len() / (8 * self.block));
                    let root =
                        self.subtree(part, child.info, first + child.start, depth + 1, &mut nodes);
                    (slot, root, nodes)
                })
                .collect();
            for (slot, root, nodes) in built {
                let base = out.len() as u32;
                out.extend(nodes.into_iter().map(|mut node| {
                    for c in &mut node.child {
                        if *c != EMPTY && *c & LEAF == 0 {
                            *c += base;
                        }
                    }
                    node
                }));
                node.child[slot] = if root & LEAF == 0 { root + base } else { root };
            }
        } else {
            for (slot, child) in children.iter().enumerate() {
                if !child.leaf {
                    let part = &mut refs[child.start..child.end];
                    node.child[slot] =
                        self.subtree(part, child.info, first + child.start, depth + 1, out);
                }
            }
        }
        out[index] = node;
        index as u32
    }

    /// Splits `refs` in two, partitioning them in place: how many go left and both sides'
    /// infos. `None` when the range is better as a leaf.
    fn split(
        &self,
        refs: &mut [PrimRef],
        info: &Info,
        depth: usize,
    ) -> Option<(usize, Info, Info)> {
        let n = refs.len();
        if n <= self.block.min(self.max_leaf) || n <= 1 {
            return None;
        }
        let halve = |refs: &mut [PrimRef]| {
            (n > self.max_leaf).then(|| {
                let mid = (n / 2).div_ceil(self.block) * self.block;
                let mid = mid.clamp(1, n - 1);
                (mid, Info::of(&refs[..mid]), Info::of(&refs[mid..]))
            })
        };
        if depth >= BALANCED_DEPTH {
            return halve(refs);
        }
        let Some(binning) = Binning::across(&info.centres, n) else {
            return halve(refs);
        };
        let blocks = |count| self.blocks(count);
        let best = match binning.count {
            4 => Bins::<4>::fill(refs, &binning).best_split(n, &binning, blocks),
            8 => Bins::<8>::fill(refs, &binning).best_split(n, &binning, blocks),
            _ if n < 2 * SAMPLED => {
                Bins::<BINS>::fill(refs, &binning).best_split(n, &binning, blocks)
            }
            _ => {
                // A large range's split is chosen from an even sample of it: the SAH's
                // estimate barely changes, and the top levels (which visit every primitive)
                // cost one pass each, the partition, instead of two.
                let stride = n / SAMPLED;
                let sample: Vec<PrimRef> = refs.iter().step_by(stride).copied().collect();
                Bins::<BINS>::fill(&sample, &binning).best_split(sample.len(), &binning, blocks)
            }
        };
        let Some(best) = best else {
            return halve(refs);
        };
        let area = info.bounds.half_area().max(f32::MIN_POSITIVE);
        let split_cost = self.traversal_cost + best.cost / area;
        if n <= self.max_leaf && self.blocks(n as u32) <= split_cost {
            return None;
        }
        let (mid, left, right) = partition(refs, &binning, best);
        if mid == 0 || mid == n {
            return halve(refs);
        }
        Some((mid, left, right))
    }
}

/// Moves the primitives left of the split plane to the front: how many there are, and both
/// sides' infos (gathered in the same pass). A range too large for the caches is cut into a
/// piece per thread, the pieces partitioned side by side, and the misplaced middle swapped
/// across (a quarter of the range, on average): otherwise the root's split, a pass over every
/// primitive, would leave all but one thread waiting.
fn partition(refs: &mut [PrimRef], binning: &Binning, split: Split) -> (usize, Info, Info) {
    partition_in_pieces(refs, binning, split, rayon::current_num_threads())
}

/// [`partition`] in (about) `pieces` pieces.
fn partition_in_pieces(
    refs: &mut [PrimRef],
    binning: &Binning,
    split: Split,
    pieces: usize,
) -> (usize, Info, Info) {
    if pieces < 2 || refs.len() < 4 * PARALLEL_MIN {
        return partition_alone(refs, binning, split);
    }
    let half = refs.len() / 2;
    let (front, back) = refs.split_at_mut(half);
    let ((front_left, front_l, front_r), (back_left, back_l, back_r)) = rayon::join(
        || partition_in_pieces(front, binning, split, pieces / 2),
        || partition_in_pieces(back, binning, split, pieces - pieces / 2),
    );
    // [front's left | front's right | back's left | back's right]: swapping the shorter of
    // the two middle runs with the far end of the other brings every left one to the front.
    let front_right = half - front_left;
    let moved = front_right.min(back_left);
    let (a, b) = refs[front_left..half + back_left].split_at_mut(front_right);
    let (a, b) = (&mut a[..moved], &mut b[back_left - moved..]);
    a.par_chunks_mut(PARALLEL_MIN)
        .zip(b.par_chunks_mut(PARALLEL_MIN))
        .for_each(|(x, y)| x.swap_with_slice(y));
    (
        front_left + back_left,
        front_l.union(&back_l),
        front_r.union(&back_r),
    )
}

/// [`partition`] on one thread.
fn partition_alone(refs: &mut [PrimRef], binning: &Binning, split: Split) -> (usize, Info, Info) {
    // The bin on the split's axis alone, computed exactly as `bins_of` computes it.
    let axis = split.axis;
    let (origin, scale) = (
        binning.origin.as_array()[axis],
        binning.scale.as_array()[axis],
    );
    let last = binning.count as f32 - 1.0;
    let goes_left = |r: &PrimRef| {
        let centre2 = r.min.as_array()[axis] + r.max.as_array()[axis];
        // Truncating f (at least 0) gives a bin below `first_right` exactly when f is.
        ((centre2 - origin) * scale).max(0.0).min(last) < split.first_right as f32
    };
    let (mut left, mut right) = (Info::EMPTY, Info::EMPTY);
    let (mut l, mut r) = (0, refs.len());
    loop {
        while l < r && goes_left(&refs[l]) {
            left.add(&refs[l]);
            l += 1;
        }
        while l < r && !goes_left(&refs[r - 1]) {
            right.add(&refs[r - 1]);
            r -= 1;
        }
        if l >= r {
            break;
        }
        refs.swap(l, r - 1);
        left.add(&refs[l]);
        right.add(&refs[r - 1]);
        l += 1;
        r -= 1;
    }
    (l, left, right)
}
