//! `add: group`: `children`, each an item of its own, built inside the group's placement and
//! taking its material and `shadow:` unless they set their own.
//!
//! Separate because a group adds no object of its own: it hands its transform, motion,
//! material and shadow down to its children, and nests.

use super::nesting::{Builder, Inherited, MAX_GROUP_DEPTH};
use super::placement::Placement;
use crate::error::SceneError;
use crate::source::{Entry, Node};
use rayforge::Object;

/// Adds the objects of the group's children to `out`, each placed inside the group.
pub fn add_group<'n, 's>(
    builder: &mut Builder<'_, 'n, 's>,
    entries: &[Entry<'n, 's>],
    kind_node: &'n Node<'s>,
    placement: Placement<'n, 's>,
    inherited: &Inherited,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let source = builder.source;
    let children_node = entries
        .iter()
        .find(|e| e.name == "children")
        .map(|e| e.value)
        .ok_or_else(|| source.error(kind_node, "children", "a group needs `children:`"))?;
    if inherited.depth >= MAX_GROUP_DEPTH {
        return Err(source.error(
            kind_node,
            "add",
            format!("groups nest deeper than {MAX_GROUP_DEPTH} levels"),
        ));
    }
    let inside = Inherited {
        matrix: placement.world.matrix(),
        frame: inherited.frame,
        end_matrix: placement.world_end.matrix(),
        material: placement.material,
        casts_shadow: placement.casts_shadow,
        depth: inherited.depth + 1,
        media: placement.media,
    };
    for child in source.sequence(children_node, "children")? {
        add_child(builder, child, &inside, out)?;
    }
    Ok(())
}

/// Adds the objects of one child (an item with `add:`, perhaps naming a template) to `out`.
fn add_child<'n, 's>(
    builder: &mut Builder<'_, 'n, 's>,
    child: &'n Node<'s>,
    inside: &Inherited,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let source = builder.source;
    let child_entries = source.entries(child, "children")?;
    let child_kind = child_entries
        .iter()
        .find(|e| e.name == "add")
        .map(|e| e.value)
        .ok_or_else(|| source.error(child, "children", "each child needs `add:`"))?;
    builder.build_entries(child_entries, child_kind, inside, out)
}
