//! What items nested in groups and CSGs are built with: what they inherit from the groups
//! around them, how deep they may nest, and the builder handed down to them.
//!
//! Separate so that the readers of the kinds that nest (groups, CSG) can build their insides
//! without importing the object reader that dispatches to them: it hands itself down in
//! [`Builder::build`].

use super::templates::{expand_template, Expanded};
use crate::assets::Assets;
use crate::defines::{Defines, Trail};
use crate::error::SceneError;
use crate::media::MediaKeys;
use crate::source::{Entry, Node, Source};
use glam::DMat4;
use rayforge::{Material, Object};

/// Groups (and CSGs) may nest this deep, inline or through defined objects; deeper nesting is
/// certainly a generated or hostile file, and refusing it keeps the reader's recursion bounded
/// (an unoptimised build takes about 50 KiB of stack a level).
pub const MAX_GROUP_DEPTH: usize = 100;

/// What a shape inherits from the groups around it.
#[derive(Debug, Clone)]
pub struct Inherited {
    /// `world_from_parent`: every enclosing group's transform, composed.
    pub matrix: DMat4,
    /// The animation frame being built (0 for a still): `per-frame` steps apply this often.
    pub frame: u64,
    /// `world_from_parent` when the shutter closes (equal to `matrix` unless a group moves).
    pub end_matrix: DMat4,
    /// The nearest enclosing group's material, for children that set none.
    pub material: Option<Material>,
    /// False when an enclosing group has `shadow: false`.
    pub casts_shadow: bool,
    /// How many groups enclose this item.
    pub depth: usize,
    /// The nearest enclosing groups' `interior:`, `exterior:` and `material: interface`.
    pub media: MediaKeys,
}

impl Inherited {
    /// What a top-level item inherits: nothing.
    pub const TOP: Self = Self {
        matrix: DMat4::IDENTITY,
        frame: 0,
        end_matrix: DMat4::IDENTITY,
        material: None,
        casts_shadow: true,
        depth: 0,
        media: MediaKeys::NONE,
    };
}

/// Builds the objects of one expanded item into `out`, as the item inherits them.
pub type BuildObjects<'b, 'n, 's> = fn(
    &mut Builder<'b, 'n, 's>,
    &Expanded<'n, 's>,
    &Inherited,
    &mut Vec<Object>,
) -> Result<(), SceneError>;

/// What building one top-level item's objects reads from and writes to.
pub struct Builder<'b, 'n, 's> {
    /// The scene file.
    pub source: &'b Source<'s>,
    /// The defines read so far.
    pub defines: &'b Defines<'n, 's>,
    /// Models and images, read once each.
    pub assets: &'b mut Assets,
    /// The object templates being built (see `expand_template`): a template met again while
    /// it is on the trail is a cycle.
    pub trail: Trail<'n>,
    /// The object reader, which builds any item (and, through this, its insides).
    pub build: BuildObjects<'b, 'n, 's>,
}

impl<'n, 's> Builder<'_, 'n, 's> {
    /// Builds the objects of an item nested in a group or CSG into `out`.
    pub fn build(
        &mut self,
        item: &Expanded<'n, 's>,
        inside: &Inherited,
        out: &mut Vec<Object>,
    ) -> Result<(), SceneError> {
        let build = self.build;
        build(self, item, inside, out)
    }

    /// Builds the objects of a nested item given by its keys `entries` (whose `add:` is
    /// `kind`, perhaps naming a template) into `out`, keeping the trail of templates being
    /// built only while it is built.
    pub fn build_entries(
        &mut self,
        entries: Vec<Entry<'n, 's>>,
        kind: &'n Node<'s>,
        inside: &Inherited,
        out: &mut Vec<Object>,
    ) -> Result<(), SceneError> {
        let mark = self.trail.len();
        let item = expand_template(self.source, self.defines, entries, kind, &mut self.trail)?;
        self.build(&item, inside, out)?;
        self.trail.truncate(mark);
        Ok(())
    }
}
