//! Constructive solid geometry (chapter 16): union, intersection and difference of solids.
//!
//! A CSG object keeps every primitive below it (through nested CSGs and groups) in one flat
//! list of *leaves*, numbered depth first so that each operation covers a contiguous range:
//! its left operand's leaves, then its right's. Operations are stored in post-order. A ray
//! collects every leaf's hits, sorts them once, then each operation, innermost first, filters
//! the surviving hits in its range with the book's `intersection_allowed` rule — exactly the
//! book's recursive filtering, without recursion or per-level lists.
//!
//! Leaves carry their full world transform (a CSG object itself always has the identity), so a
//! leaf is the object that shades a hit: its normal, material and pattern.

use crate::geometry::LocalHit;
use crate::math::{Aabb, Point3, Ray, SingularTransform, Transform, Vec3};
use crate::scene::{Node, Object, Shape};
use smallvec::SmallVec;
use std::sync::Arc;

/// The set operation of a CSG node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CsgOperation {
    /// Everything in either operand.
    Union,
    /// Only what is in both operands.
    Intersection,
    /// What is in the left operand and not in the right.
    Difference,
    /// Everything not in its one operand (Fundamentals of Ray Tracing's `SetComplement`): the
    /// same surfaces, facing the other way. Useful inside another operation, as in
    /// `A ∩ ¬B`.
    Complement,
}

/// The book's `intersection_allowed(op, lhit, inl, inr)`: whether a hit on the left (`lhit`)
/// or right operand survives, given whether it lies inside the left (`inl`) and right (`inr`).
pub fn intersection_allowed(operation: CsgOperation, lhit: bool, inl: bool, inr: bool) -> bool {
    match operation {
        CsgOperation::Union => (lhit && !inr) || (!lhit && !inl),
        CsgOperation::Intersection => (lhit && inr) || (!lhit && inl),
        CsgOperation::Difference => (lhit && !inr) || (!lhit && inl),
        // Every surface of the operand bounds its complement.
        CsgOperation::Complement => true,
    }
}

/// One operation over the leaves `start..end`, of which `start..split` are its left operand.
#[derive(Debug, Clone, Copy, PartialEq)]
struct CsgNode {
    operation: CsgOperation,
    start: u32,
    split: u32,
    end: u32,
    /// Whether a ray coming from far away starts inside the left and the right operand
    /// (outside every bounded solid, inside a complement): the filter's first state.
    starts_inside: (bool, bool),
}

/// A CSG solid: its primitives (in world space) and its operations.
#[derive(Debug, Clone, PartialEq)]
pub struct Csg {
    leaves: Vec<Object>,
    /// Operations in post-order: the last is the root.
    nodes: Vec<CsgNode>,
    bounds: Aabb,
}

impl Csg {
    /// The book's `csg(operation, left, right)`. Operands may be shapes, groups or CSG objects.
    pub fn new(
        operation: CsgOperation,
        left: impl Into<Node>,
        right: impl Into<Node>,
    ) -> Result<Self, SingularTransform> {
        Self::build(operation, &left.into(), Some(&right.into()))
    }

    /// Everything outside `operand` (Fundamentals of Ray Tracing's set complement). The
    /// complement itself is unbounded, but its surfaces are its operand's: rays can only meet
    /// it there, so its box is the operand's.
    pub fn complement(operand: impl Into<Node>) -> Result<Self, SingularTransform> {
        Self::build(CsgOperation::Complement, &operand.into(), None)
    }

    /// An operation over its operands (a complement has no right one).
    fn build(
        operation: CsgOperation,
        left: &Node,
        right: Option<&Node>,
    ) -> Result<Self, SingularTransform> {
        let mut csg = Csg {
            leaves: Vec::new(),
            nodes: Vec::new(),
            bounds: Aabb::EMPTY,
        };
        csg.add_operand(left)?;
        let split = csg.leaves.len() as u32;
        if let Some(right) = right {
            csg.add_operand(right)?;
        }
        let end = csg.leaves.len() as u32;
        let below = csg.nodes.len();
        let outside = |_: &Object| false;
        let starts_inside = (
            csg.range_inside(0, split, below, &outside),
            csg.range_inside(split, end, below, &outside),
        );
        csg.nodes.push(CsgNode {
            operation,
            start: 0,
            split,
            end,
            starts_inside,
        });
        csg.bounds = csg
            .leaves
            .iter()
            .fold(Aabb::EMPTY, |b, leaf| b.union(&leaf.bounds()));
        Ok(csg)
    }

    /// Appends an operand's leaves (and, for a nested CSG, its operations, re-based).
    fn add_operand(&mut self, node: &Node) -> Result<(), SingularTransform> {
        let objects = match node {
            Node::Object(object) => vec![Object::clone(object)],
            Node::Group(group) => group.flatten()?,
        };
        for object in objects {
            match &object.shape {
                Shape::Csg(inner) => {
                    let base = self.leaves.len() as u32;
                    let placed = inner.placed_by(&object.transform)?;
                    self.leaves.extend(placed.leaves);
                    self.nodes.extend(placed.nodes.iter().map(|n| CsgNode {
                        start: n.start + base,
                        split: n.split + base,
                        end: n.end + base,
                        ..*n
                    }));
                }
                _ => self.leaves.push(object),
            }
        }
        Ok(())
    }

    /// The same solid moved by `transform` (applied after its leaves' own transforms).
    pub fn placed_by(&self, transform: &Transform) -> Result<Self, SingularTransform> {
        self.placed_by_moving(transform, transform)
    }

    /// The same solid moving from `start` to `end` while the shutter is open (its primitives
    /// carry the motion).
    pub fn placed_by_moving(
        &self,
        start: &Transform,
        end: &Transform,
    ) -> Result<Self, SingularTransform> {
        let leaves = self
            .leaves
            .iter()
            .map(|leaf| leaf.placed_by_moving(start, end))
            .collect::<Result<Vec<_>, _>>()?;
        let bounds = leaves
            .iter()
            .fold(Aabb::EMPTY, |b, leaf| b.union(&leaf.bounds()));
        Ok(Self {
            leaves,
            nodes: self.nodes.clone(),
            bounds,
        })
    }

    /// The root operation.
    pub fn operation(&self) -> CsgOperation {
        self.nodes
            .last()
            .map_or(CsgOperation::Union, |n| n.operation)
    }

    /// The primitives, depth first: left operand's first.
    pub fn leaves(&self) -> &[Object] {
        &self.leaves
    }

    /// The primitives of the root's left operand.
    pub fn left(&self) -> &[Object] {
        let root = self.nodes.last().map_or(0, |n| n.split as usize);
        &self.leaves[..root]
    }

    /// The primitives of the root's right operand.
    pub fn right(&self) -> &[Object] {
        let root = self.nodes.last().map_or(0, |n| n.split as usize);
        &self.leaves[root..]
    }

    /// The box around every leaf.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The book's `includes(a, b)` for the root's operands: whether `object` is (by identity) a
    /// leaf of the left operand.
    pub fn left_includes(&self, object: &Object) -> bool {
        self.left().iter().any(|o| std::ptr::eq(o, object))
    }

    /// The book's `filter_intersections(csg, xs)` over leaf indices: `hits` sorted by `t`,
    /// each tagged with the leaf it is on; keeps the hits every operation allows.
    pub fn filter(&self, hits: &mut SmallVec<[LocalHit; 16]>) {
        for node in &self.nodes {
            let (mut inl, mut inr) = node.starts_inside;
            hits.retain(|h| {
                if h.leaf < node.start || h.leaf >= node.end {
                    return true;
                }
                let lhit = h.leaf < node.split;
                let allowed = intersection_allowed(node.operation, lhit, inl, inr);
                if lhit {
                    inl = !inl;
                } else {
                    inr = !inr;
                }
                allowed
            });
        }
    }

    /// Every hit on the solid's surface, each tagged with its leaf (`LocalHit::leaf`).
    ///
    /// Takes the visitor as a trait object: leaves may be CSG solids themselves, and a generic
    /// visitor would make the compiler instantiate one copy per nesting level, forever.
    pub fn intersect(&self, ray: &Ray, hit: &mut dyn FnMut(LocalHit)) {
        let mut hits = self.leaf_hits(ray);
        hits.sort_unstable_by(|a, b| a.t.total_cmp(&b.t));
        self.filter(&mut hits);
        for h in hits {
            hit(h);
        }
    }

    /// Whether one of [`intersect`](Self::intersect)'s hits lies in `t_min <= t < t_max` (a
    /// shadow ray's span), with the sort and the filter skipped when none of the primitives'
    /// hits does: the filter only drops hits, so the answer is the same, and a shadow ray that
    /// passes by a solid's parts (or leaves its surface) costs their intersections alone.
    pub fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let within = |t: f64| t >= t_min && t < t_max;
        let mut hits = self.leaf_hits(ray);
        if !hits.iter().any(|h| within(h.t)) {
            return false;
        }
        hits.sort_unstable_by(|a, b| a.t.total_cmp(&b.t));
        self.filter(&mut hits);
        hits.iter().any(|h| within(h.t))
    }

    /// Every primitive's hits of `ray`, each tagged with its leaf, in no order and unfiltered.
    fn leaf_hits(&self, ray: &Ray) -> SmallVec<[LocalHit; 16]> {
        let mut hits: SmallVec<[LocalHit; 16]> = SmallVec::new();
        for (i, leaf) in self.leaves.iter().enumerate() {
            let local = leaf.ray_to_object(ray);
            let mut push = |mut h: LocalHit| {
                h.leaf = i as u32;
                hits.push(h);
            };
            leaf.shape.intersect_hits(&local, &mut push);
        }
        hits
    }

    /// Whether a point on the surface of leaf `leaf` is on the solid's surface: every
    /// operation above the leaf allows it (the book's `intersection_allowed`), given whether
    /// the point lies inside the other operand. This is the ray tracer's filter asked of a
    /// single point; the rasterizer keeps or drops the primitives' triangles by it.
    pub fn keeps_surface_point(&self, leaf: usize, point: Point3) -> bool {
        let leaf = leaf as u32;
        self.nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| n.start <= leaf && leaf < n.end)
            .all(|(k, n)| {
                let lhit = leaf < n.split;
                let inl = !lhit && self.range_contains(n.start, n.split, k, point);
                let inr = lhit && self.range_contains(n.split, n.end, k, point);
                intersection_allowed(n.operation, lhit, inl, inr)
            })
    }

    /// Whether `point` is inside the solid.
    pub fn contains_point(&self, point: Point3) -> bool {
        self.range_contains(0, self.leaves.len() as u32, self.nodes.len(), point)
    }

    /// Whether `point` is inside the operand made of leaves `start..end`.
    fn range_contains(&self, start: u32, end: u32, limit: usize, point: Point3) -> bool {
        self.range_inside(start, end, limit, &|leaf| leaf_contains(leaf, point))
    }

    /// Whether a place is inside the operand made of leaves `start..end`, given whether it is
    /// inside each leaf: the operations that span parts of it combine their operands; leaves
    /// side by side (a group) are a union.
    ///
    /// Only the operations before `limit` (in post-order, those below the one asking) are
    /// considered: a complement's operand spans the same leaves as the complement itself.
    fn range_inside(
        &self,
        start: u32,
        end: u32,
        limit: usize,
        leaf_inside: &dyn Fn(&Object) -> bool,
    ) -> bool {
        let mut at = start;
        let mut inside = false;
        while at < end {
            // The widest (and, among equals, outermost) operation that starts here and fits
            // in the range, else one leaf.
            let node = self.nodes[..limit.min(self.nodes.len())]
                .iter()
                .enumerate()
                .filter(|(_, n)| n.start == at && n.end <= end)
                .max_by_key(|(_, n)| n.end);
            let part = match node {
                Some((k, n)) => {
                    let (l, r) = (
                        self.range_inside(n.start, n.split, k, leaf_inside),
                        self.range_inside(n.split, n.end, k, leaf_inside),
                    );
                    at = n.end;
                    match n.operation {
                        CsgOperation::Union => l || r,
                        CsgOperation::Intersection => l && r,
                        CsgOperation::Difference => l && !r,
                        CsgOperation::Complement => !l,
                    }
                }
                _ => {
                    let leaf = &self.leaves[at as usize];
                    at += 1;
                    leaf_inside(leaf)
                }
            };
            inside |= part;
        }
        inside
    }

    /// The unit normal at a hit, from the leaf it is on.
    pub fn normal_at(&self, point: Point3, hit: &LocalHit) -> Vec3 {
        self.leaves
            .get(hit.leaf as usize)
            .map_or(Vec3::ZERO, |leaf| leaf.normal_at_local_hit(point, hit))
    }
}

impl Object {
    /// Whether `point` (in world space) is inside the solid: a CSG solid by its operations,
    /// any other shape by the parity of its surfaces ahead of the point (see `leaf_contains`).
    /// Open surfaces pick a side: below a plane counts as inside.
    pub fn contains(&self, point: Point3) -> bool {
        match &self.shape {
            Shape::Csg(csg) => csg.contains_point(self.world_to_object(point)),
            shape if !shape.has_volume() => false,
            _ => leaf_contains(self, point),
        }
    }

    /// The primitive whose material fills the solid at `point`: for a CSG solid the first of
    /// its primitives that contains the point, for any other the object itself.
    pub fn surface_containing(&self, point: Point3) -> &Object {
        match &self.shape {
            Shape::Csg(csg) => csg
                .leaves()
                .iter()
                .find(|leaf| leaf.contains(point))
                .unwrap_or(self),
            _ => self,
        }
    }

    /// Everything outside `operand`, as an object (see [`Csg::complement`]).
    pub fn complement(operand: impl Into<Node>) -> Result<Self, SingularTransform> {
        Ok(Self::new(Shape::Csg(Arc::new(Csg::complement(operand)?))))
    }

    /// The book's `csg(operation, left, right)` as an object.
    pub fn csg(
        operation: CsgOperation,
        left: impl Into<Node>,
        right: impl Into<Node>,
    ) -> Result<Self, SingularTransform> {
        Ok(Self::new(Shape::Csg(Arc::new(Csg::new(
            operation, left, right,
        )?))))
    }
}

/// Whether `point` is inside a primitive: by its formula where it has one
/// ([`Shape::contains_point`]), else when an odd number of its surfaces lie ahead along a
/// fixed, skewed direction (the parity the ray tracer's filter keeps along every ray). For open
/// surfaces this picks a side: below a plane, for instance, counts as inside.
fn leaf_contains(leaf: &Object, point: Point3) -> bool {
    // The same instant as the ray below (`Ray::new` casts at time 0).
    if let Some(inside) = leaf
        .shape
        .contains_point(leaf.world_to_object_at(point, 0.0))
    {
        return inside;
    }
    let direction = Vec3::new(0.267_261_24, 0.801_783_73, 0.534_522_48);
    let ray = leaf.ray_to_object(&Ray::new(point, direction));
    let mut crossings = 0u32;
    let tolerance = 1e-9 * (1.0 + point.length());
    leaf.shape.intersect(&ray, |t| {
        if t > tolerance {
            crossings += 1;
        }
    });
    crossings % 2 == 1
}
