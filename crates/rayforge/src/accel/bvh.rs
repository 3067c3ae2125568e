//! An eight-wide bounding volume hierarchy with single-precision boxes, walked front to back.
//!
//! The bonus chapter "Bounding boxes and hierarchies" builds a binary tree of groups and tests
//! one box at a time. Here every node holds eight children's boxes side by side (all their
//! minimum x, then all their maximum x, …), so one set of eight-lane instructions tests a ray
//! against all eight at once; a node is 224 bytes (four cache lines), and the tree is a third
//! as deep as a binary one, so a ray makes fewer, cheaper steps. On a large mesh, whose
//! nodes do not fit in the caches, each step down is a wait on memory: fewer levels mean
//! fewer waits (eight children instead of four cut the growth of the time per ray from 1 k
//! to 10 M triangles by about a tenth, see `docs/performance.md`). Boxes are `f32`
//! relative to the centre of everything (see [`RayQuery`]), widened at build time so that
//! rounding can never make a ray miss a box it touches.
//!
//! Leaves hold primitives in blocks of [`Bvh::block`] slots of the primitive order (a mesh
//! uses blocks of four triangles, tested together; padding slots hold [`NO_PRIMITIVE`]).
//! The walk keeps an explicit stack of the children it has yet to visit with their entry
//! distances, so it never recurses, allocates nothing, and skips any child whose box starts
//! beyond the nearest hit found meanwhile.

use super::build;
use super::isa::{dispatch, Isa, Kernel, Lanes8};
use super::query::RayQuery;
use crate::math::{Aabb, Point3};
use glam::DVec3;
use std::ops::{ControlFlow, Range};
use std::sync::atomic::AtomicBool;

/// What a padding slot in the primitive order holds.
pub const NO_PRIMITIVE: u32 = u32::MAX;

/// Marks a child reference as a leaf.
pub(crate) const LEAF: u32 = 1 << 31;
/// An unused child slot (its box is empty, so no ray enters it).
pub(crate) const EMPTY: u32 = u32::MAX;
/// A leaf reference keeps its block count less one in the low bits.
pub(crate) const LEAF_COUNT_BITS: u32 = 4;
/// The most blocks a leaf may hold.
pub(crate) const MAX_LEAF_BLOCKS: usize = 1 << LEAF_COUNT_BITS;
/// The most blocks a hierarchy may hold (the leaf reference's remaining bits).
pub const MAX_BLOCKS: usize = 1 << (31 - LEAF_COUNT_BITS);

/// The longest path from the root to a leaf the builder makes (it switches to balanced
/// splits before a pathological input could go deeper); the walk's stack is sized by it.
pub(crate) const MAX_DEPTH: usize = 40;
/// Children per node: one lane each of an eight-lane vector, so a node's boxes are tested
/// together.
pub(crate) const WIDTH: usize = 8;
/// Stack entries a walk through a tree `depth` nodes deep needs: a node pushes all but one of
/// its children while visiting that one, and a node's children are copied to the stack a whole
/// [`WIDTH`] at a time (a fixed copy of two vector stores, where a copy of however many there
/// are would be a call to `memcpy`), so there is room for a whole node's worth past the top.
const fn stack_size(depth: usize) -> usize {
    (WIDTH - 1) * depth + WIDTH
}

/// One node: the boxes of up to [`WIDTH`] children, lane by lane, and what each child is.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct Node {
    /// The children's minimum x, y and z, then their maximum x, y and z: a ray picks
    /// the planes it enters and leaves by index (see [`RayQuery`]), without a branch.
    pub(crate) planes: [[f32; WIDTH]; 6],
    /// Each child: a node index, a leaf ([`LEAF`] set: first block and block count), or
    /// [`EMPTY`].
    pub(crate) child: [u32; WIDTH],
}

impl Node {
    /// A node with no children.
    pub(crate) const EMPTY: Self = Self {
        planes: [
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [EMPTY; WIDTH],
    };

    /// Which children the ray enters within `[t_min, t_max]` (bit `i` for child `i`), and
    /// where it enters each.
    #[inline(always)]
    fn enter<I: Isa>(&self, isa: I, ray: &Slabs<I>, t_min: I::F8, t_max: I::F8) -> (u32, I::F8) {
        let mut near = t_min;
        let mut far = t_max;
        for axis in 0..3 {
            let entry = isa.load8(&self.planes[ray.entry_plane[axis]]);
            let exit = isa.load8(&self.planes[ray.exit_plane[axis]]);
            let (inv, offset) = (ray.inv_direction[axis], ray.origin_over_direction[axis]);
            near = near.max(entry.mul_sub(inv, offset));
            far = far.min(exit.mul_sub(inv, offset));
        }
        (near.le_bits(far), near)
    }
}

/// What the slab test needs of a [`RayQuery`], in every lane of the set's vectors (made once
/// per walk).
struct Slabs<I: Isa> {
    inv_direction: [I::F8; 3],
    origin_over_direction: [I::F8; 3],
    entry_plane: [usize; 3],
    exit_plane: [usize; 3],
}

impl<I: Isa> Slabs<I> {
    #[inline(always)]
    fn new(isa: I, q: &RayQuery) -> Self {
        Self {
            // Not `array::map`: see `RayQuery::new`.
            inv_direction: [
                isa.splat8(q.inv_direction[0]),
                isa.splat8(q.inv_direction[1]),
                isa.splat8(q.inv_direction[2]),
            ],
            origin_over_direction: [
                isa.splat8(q.origin_over_direction[0]),
                isa.splat8(q.origin_over_direction[1]),
                isa.splat8(q.origin_over_direction[2]),
            ],
            entry_plane: q.entry_plane,
            exit_plane: q.exit_plane,
        }
    }
}

/// Decodes a leaf reference into its first block and block count.
#[inline(always)]
pub(crate) fn leaf_blocks(reference: u32) -> (usize, usize) {
    let bits = reference & !LEAF;
    (
        (bits >> LEAF_COUNT_BITS) as usize,
        (bits & (MAX_LEAF_BLOCKS as u32 - 1)) as usize + 1,
    )
}

/// Encodes a leaf of `count` blocks starting at block `first`.
#[inline]
pub(crate) fn leaf_reference(first: usize, count: usize) -> u32 {
    debug_assert!((1..=MAX_LEAF_BLOCKS).contains(&count) && first < MAX_BLOCKS);
    LEAF | ((first as u32) << LEAF_COUNT_BITS) | (count as u32 - 1)
}

/// A bounding volume hierarchy over primitives identified by their index.
#[derive(Debug, Clone, PartialEq)]
pub struct Bvh {
    pub(crate) nodes: Vec<Node>,
    pub(crate) order: Vec<u32>,
    pub(crate) block: usize,
    pub(crate) base: Point3,
    pub(crate) bounds: Aabb,
    /// Nodes on the longest path from the root to a leaf (0 when empty): the walk's stack
    /// holds at most `WIDTH - 1` children per node on its path, so small trees get small stacks
    /// (clearing a stack sized for the deepest possible tree cost more than walking a small
    /// one).
    pub(crate) depth: usize,
}

impl Default for Bvh {
    fn default() -> Self {
        Self {
            nodes: Vec::new(),
            order: Vec::new(),
            block: 1,
            base: Point3::ZERO,
            bounds: Aabb::EMPTY,
            depth: 0,
        }
    }
}

impl Bvh {
    /// Builds the hierarchy over `bounds`, one box per primitive, one primitive per block.
    /// Boxes must be finite; empty boxes are left out of the tree.
    pub fn build(bounds: &[Aabb]) -> Self {
        build::from_boxes(bounds, 1, None).expect("a build without a stop flag is never stopped")
    }

    /// [`Bvh::build`] that gives up, `None`, once `stop` is set: looked at as each node is
    /// begun, so a hierarchy over millions of boxes stops within one node's split. Not
    /// stopped, the very tree [`Bvh::build`] makes.
    pub fn build_until(bounds: &[Aabb], stop: Option<&AtomicBool>) -> Option<Self> {
        build::from_boxes(bounds, 1, stop)
    }

    /// Builds the hierarchy with leaves made of blocks of `block` slots (1 to 8): a caller
    /// that tests several primitives at once lays them out by [`Bvh::order`].
    pub fn build_in_blocks(bounds: &[Aabb], block: usize) -> Self {
        build::from_boxes(bounds, block, None)
            .expect("a build without a stop flag is never stopped")
    }

    /// The nodes, root first.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The primitive order: leaves name their primitives by slots of this list, a block of
    /// [`Bvh::block`] slots at a time; padding slots hold [`NO_PRIMITIVE`].
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// How many slots make a block.
    pub fn block(&self) -> usize {
        self.block
    }

    /// The point the `f32` frame is centred on.
    pub fn base(&self) -> Point3 {
        self.base
    }

    /// The box around everything (empty when there are no primitives).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Bytes held on the heap by the nodes and the primitive order.
    pub fn heap_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.order.len() * 4
    }

    /// A ray prepared for [`Bvh::walk`].
    #[inline]
    pub fn query(&self, origin: Point3, direction: DVec3) -> RayQuery {
        RayQuery::new(self.base, origin, direction)
    }

    /// Visits, nearest first, the leaves whose boxes the ray enters within `[t_min, t_max]`
    /// (query distances). `visit` receives the leaf's slots of [`Bvh::order`] and the current
    /// `t_max`, which it lowers when it finds a hit (so farther boxes are skipped), and may
    /// stop the walk with `Break`. Runs inside a [`Kernel`] (hence always inlined).
    #[inline(always)]
    pub(crate) fn walk<I: Isa>(
        &self,
        isa: I,
        query: &RayQuery,
        t_min: f32,
        t_max: f32,
        visit: impl FnMut(Range<usize>, &mut f32) -> ControlFlow<()>,
    ) {
        match self.depth {
            0 => {}
            1..=3 => self.walk_with::<I, { stack_size(3) }>(isa, query, t_min, t_max, visit),
            4..=9 => self.walk_with::<I, { stack_size(9) }>(isa, query, t_min, t_max, visit),
            _ => self.walk_with::<I, { stack_size(MAX_DEPTH) }>(isa, query, t_min, t_max, visit),
        }
    }

    /// [`Bvh::walk`] with a stack of `N` entries (at least [`stack_size`] of the depth).
    #[inline(always)]
    fn walk_with<I: Isa, const N: usize>(
        &self,
        isa: I,
        query: &RayQuery,
        t_min: f32,
        mut t_max: f32,
        mut visit: impl FnMut(Range<usize>, &mut f32) -> ControlFlow<()>,
    ) {
        let slabs = Slabs::new(isa, query);
        let t_min8 = isa.splat8(t_min);
        let mut stack = [(0u32, 0f32); N];
        let mut top = 0usize;
        let mut current = 0u32;
        loop {
            if current & LEAF != 0 {
                let (first, count) = leaf_blocks(current);
                let slots = first * self.block..(first + count) * self.block;
                if visit(slots, &mut t_max).is_break() {
                    return;
                }
            } else {
                let node = &self.nodes[current as usize];
                let (mut mask, near) = node.enter(isa, &slabs, t_min8, isa.splat8(t_max));
                if mask != 0 {
                    let near = near.to_array();
                    // The nearest entered child is visited next; the others wait on the
                    // stack, farthest deepest.
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        current = node.child[first];
                        continue;
                    }
                    let mut pending = [(0u32, 0f32); WIDTH];
                    pending[0] = (node.child[first], near[first]);
                    let mut n = 1;
                    while mask != 0 {
                        let i = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        // Insertion into the (at most WIDTH) entries, sorted far to near.
                        let entry = (node.child[i], near[i]);
                        let mut k = n;
                        while k > 0 && pending[k - 1].1 < entry.1 {
                            pending[k] = pending[k - 1];
                            k -= 1;
                        }
                        pending[k] = entry;
                        n += 1;
                    }
                    stack[top..top + WIDTH].copy_from_slice(&pending);
                    top += n - 1;
                    current = pending[n - 1].0;
                    continue;
                }
            }
            // Back to the nearest child still waiting whose box starts before the nearest hit.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let (reference, near) = stack[top];
                if near <= t_max {
                    current = reference;
                    break;
                }
            }
        }
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
        t_max: f64,
        visit: impl FnMut(u32, &mut f64) -> ControlFlow<()>,
    ) {
        dispatch(Traverse {
            bvh: self,
            query: self.query(origin, direction),
            t_min,
            t_max,
            visit,
        });
    }
}

/// [`Bvh::traverse`] as a [`Kernel`].
struct Traverse<'a, F> {
    bvh: &'a Bvh,
    query: RayQuery,
    t_min: f64,
    t_max: f64,
    visit: F,
}

impl<F: FnMut(u32, &mut f64) -> ControlFlow<()>> Kernel for Traverse<'_, F> {
    type Output = ();

    #[inline(always)]
    fn run<I: Isa>(self, isa: I) {
        let Self {
            bvh,
            query,
            t_min,
            mut t_max,
            mut visit,
        } = self;
        let (lower, upper) = (query.t_below(t_min), query.t_above(t_max));
        bvh.walk(
            isa,
            &query,
            lower,
            upper,
            #[inline(always)]
            |slots, limit| {
                for &primitive in &bvh.order[slots] {
                    if primitive == NO_PRIMITIVE {
                        continue;
                    }
                    let before = t_max;
                    let flow = visit(primitive, &mut t_max);
                    if t_max != before {
                        *limit = query.t_above(t_max);
                    }
                    flow?;
                }
                ControlFlow::Continue(())
            },
        );
    }
}
