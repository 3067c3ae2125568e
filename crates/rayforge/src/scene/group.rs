//! Groups (chapter 14): shapes that move together, flattened into world objects before
//! rendering.
//!
//! The book gives every shape a parent pointer and walks up the chain to convert points and
//! normals. rayforge bakes the chain instead: flattening a group multiplies each child's
//! transform by its ancestors' (`parent * child`, the parent first, as the validation notebook
//! warns), so the renderer sees flat objects with their full world transform and never walks a
//! hierarchy per ray. The results are the same: `world_to_object` and `normal_to_world` of a
//! flattened child equal the book's recursive versions.

use crate::math::{Aabb, Motion, SingularTransform, Transform};
use crate::scene::Object;

/// A node of a scene tree: a shape, or a group of nodes.
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    /// A shape with its own transform (relative to its parent). Boxed: an object is far larger
    /// than a group header.
    Object(Box<Object>),
    /// A group with its own transform (relative to its parent).
    Group(Box<Group>),
}

/// The book's `group()`: children that share a transform.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Group {
    /// `parent_from_group` (when the shutter opens, for a group that moves).
    pub transform: Transform,
    /// `parent_from_group` when the shutter closes, for a group that moves (motion blur).
    pub motion_end: Option<Transform>,
    /// The shapes and groups inside, each placed relative to the group.
    pub children: Vec<Node>,
}

impl Group {
    /// An empty group with the identity transform.
    pub fn new() -> Self {
        Self::default()
    }

    /// The same group placed by `matrix`.
    ///
    /// # Panics
    /// When the matrix is singular; use [`Transform::try_new`] for user input.
    pub fn with_transform(mut self, matrix: glam::DMat4) -> Self {
        self.transform = Transform::new(matrix);
        self
    }

    /// The book's `add_child(group, shape)`.
    pub fn add_child(&mut self, child: impl Into<Node>) {
        self.children.push(child.into());
    }

    /// The same group with one more child.
    pub fn with_child(mut self, child: impl Into<Node>) -> Self {
        self.add_child(child);
        self
    }

    /// Every shape in the group, with its transform composed with all of its ancestors'
    /// (this group's included), in depth-first order.
    ///
    /// Walks the tree with an explicit stack, so arbitrarily deep nesting cannot overflow.
    pub fn flatten(&self) -> Result<Vec<Object>, SingularTransform> {
        let mut out = Vec::new();
        // Each entry carries its parent's placement when the shutter opens and closes (the
        // same twice unless something above it moves).
        let placement = (self.transform, self.end_transform());
        let mut stack: Vec<(&Node, (Transform, Transform))> =
            self.children.iter().rev().map(|c| (c, placement)).collect();
        while let Some((node, (start, end))) = stack.pop() {
            match node {
                Node::Object(object) => out.push(object.placed_by_moving(&start, &end)?),
                Node::Group(group) => {
                    let placement = (
                        start.then_after(&group.transform)?,
                        end.then_after(&group.end_transform())?,
                    );
                    stack.extend(group.children.iter().rev().map(|c| (c, placement)));
                }
            }
        }
        Ok(out)
    }
}

impl Node {
    /// The box around the node in its parent's space (the book's `parent_space_bounds_of`).
    pub fn bounds(&self) -> Aabb {
        match self {
            Node::Object(object) => object.bounds(),
            Node::Group(group) => group.bounds(),
        }
    }
}

impl Group {
    /// The box around every child, in the group's own space (the book's `bounds_of(group)`).
    pub fn local_bounds(&self) -> Aabb {
        self.children
            .iter()
            .fold(Aabb::EMPTY, |b, child| b.union(&child.bounds()))
    }

    /// The box around the group in its parent's space (over its whole motion, if it moves).
    pub fn bounds(&self) -> Aabb {
        match self.motion_end {
            None => self.local_bounds().transform(&self.transform),
            Some(end) => Motion::new(self.transform, end).bounds(&self.local_bounds()),
        }
    }

    /// Where the group is when the shutter closes.
    fn end_transform(&self) -> Transform {
        self.motion_end.unwrap_or(self.transform)
    }

    /// The book's `partition_children(group)`: splits the group's box in half along its longest
    /// axis and moves out the children that fit entirely in one half, returning (left, right);
    /// children that straddle the split stay.
    pub fn partition_children(&mut self) -> (Vec<Node>, Vec<Node>) {
        let (left_box, right_box) = self.local_bounds().split();
        let (mut left, mut right, mut stay) = (Vec::new(), Vec::new(), Vec::new());
        for child in std::mem::take(&mut self.children) {
            let b = child.bounds();
            if left_box.contains_box(&b) {
                left.push(child);
            } else if right_box.contains_box(&b) {
                right.push(child);
            } else {
                stay.push(child);
            }
        }
        self.children = stay;
        (left, right)
    }

    /// The book's `make_subgroup(group, children)`: adds a new group holding `children`.
    pub fn make_subgroup(&mut self, children: Vec<Node>) {
        self.add_child(Group {
            children,
            ..Group::default()
        });
    }

    /// The book's `divide(group, threshold)`: the bonus chapter's simple hierarchy, which
    /// partitions any group of at least `threshold` children into subgroups, recursively.
    ///
    /// Rendering does not need it (flattened objects get a surface-area-heuristic BVH); it
    /// exists for code that builds scene trees with the book's API. It recurses once per level
    /// of the tree, which the scene reader caps at 256.
    pub fn divide(&mut self, threshold: usize) {
        if threshold <= self.children.len() {
            let (left, right) = self.partition_children();
            if !left.is_empty() {
                self.make_subgroup(left);
            }
            if !right.is_empty() {
                self.make_subgroup(right);
            }
        }
        for child in &mut self.children {
            if let Node::Group(group) = child {
                group.divide(threshold);
            }
        }
    }
}

impl From<Object> for Node {
    fn from(object: Object) -> Self {
        Node::Object(Box::new(object))
    }
}

impl From<Group> for Node {
    fn from(group: Group) -> Self {
        Node::Group(Box::new(group))
    }
}
