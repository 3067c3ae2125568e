//! Object templates: `add: NAME`, where NAME is a define whose value is itself an object,
//! expanded into the keys of the shape, group or model it stands for.
//!
//! Separate because expansion comes before any kind is read: the top-level dispatch, a group's
//! children and a CSG's operands all expand their items here first.

use super::kinds::{unknown_kind, ITEM_KINDS, SHAPE_KINDS};
use crate::defines::{is_reference, merge, Defines, Trail};
use crate::error::SceneError;
use crate::source::{Entry, Node, Source};

/// An `add:` item with any object templates expanded.
pub struct Expanded<'n, 's> {
    /// Its keys: the templates' merged with the item's own (`add:` names a shape kind).
    pub entries: Vec<Entry<'n, 's>>,
    /// Its transform lists in the order they apply: the innermost template's first, the
    /// item's own last.
    pub transforms: Vec<&'n Node<'s>>,
}

/// Expands an `add:` item whose kind names a template: `add: NAME` where NAME is a define
/// whose value is itself an object. The item's keys override the template's, except
/// `transform`, which composes (the template's placement first, then the item's).
///
/// The names of the templates expanded are left on `trail`: the caller truncates it once the
/// object is built, so that a template's children (or CSG operands) that instantiate the
/// template again are reported as a cycle rather than recursing forever.
pub fn expand_template<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    entries: Vec<Entry<'n, 's>>,
    kind: &'n Node<'s>,
    trail: &mut Trail<'n>,
) -> Result<Expanded<'n, 's>, SceneError> {
    let name = source.string(kind, "add")?;
    if SHAPE_KINDS.contains(&name) || ITEM_KINDS.contains(&name) || !is_reference(kind) {
        let transforms = entries
            .iter()
            .filter(|e| e.name == "transform")
            .map(|e| e.value)
            .collect();
        return Ok(Expanded {
            entries,
            transforms,
        });
    }
    if !defines.contains(name) {
        return Err(unknown_kind(source, kind, name));
    }
    let template = defines.mapping_entries(source, kind, "add", trail)?;
    // Stays on the trail while the object is built (see above).
    trail.push(name);
    let inner_kind = template
        .iter()
        .find(|e| e.name == "add")
        .map(|e| e.value)
        .ok_or_else(|| {
            source.error(
                kind,
                "add",
                format!(
                    "`{name}` is not a shape; expected one of: camera, light, {} or the name of a defined object",
                    SHAPE_KINDS.join(", ")
                ),
            )
        })?;
    let template_without_transform: Vec<_> = template
        .iter()
        .copied()
        .filter(|e| e.name != "transform")
        .collect();
    let mut expanded = expand_template(
        source,
        defines,
        template_without_transform,
        inner_kind,
        trail,
    )?;
    if let Some(t) = template.iter().find(|e| e.name == "transform") {
        expanded.transforms.push(t.value);
    }
    override_with(&mut expanded, entries);
    Ok(expanded)
}

/// The item's own keys over its template's: `transform` after the template's, every other key
/// in place of the template's (`add:`, which named the template, is dropped).
fn override_with<'n, 's>(expanded: &mut Expanded<'n, 's>, entries: Vec<Entry<'n, 's>>) {
    for e in entries {
        if e.name == "add" {
            continue;
        }
        if e.name == "transform" {
            expanded.transforms.push(e.value);
        } else {
            merge(&mut expanded.entries, e);
        }
    }
}
