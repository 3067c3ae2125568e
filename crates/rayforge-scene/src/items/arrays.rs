//! `add: array`: many copies of one object (`of:`, a defined object or an item) on a grid of
//! `count` copies a side, `step` apart, each copy perhaps with its own colour (`colors:`).
//!
//! Separate because it is how a scene places thousands of instances without an item each:
//! the copied object is read once, and each copy is that object moved (a mesh is shared, not
//! copied), so a copy costs an object's worth of memory and no YAML at all.

use super::nesting::{Builder, Inherited, MAX_GROUP_DEPTH};
use super::placement::Placement;
use crate::error::SceneError;
use crate::material::color;
use crate::source::{as_str, Entry, Node};
use glam::{DMat4, DVec3};
use rayforge::{Color, Object, Transform};

/// Adds the copies of the array's object to `out`, each placed inside the array.
pub fn add_array<'n, 's>(
    builder: &mut Builder<'_, 'n, 's>,
    entries: &[Entry<'n, 's>],
    kind_node: &'n Node<'s>,
    placement: Placement<'n, 's>,
    inherited: &Inherited,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let source = builder.source;
    let find = |key: &str| entries.iter().find(|e| e.name == key);
    let of = find("of").ok_or_else(|| source.error(kind_node, "of", "an array needs `of:`"))?;
    if inherited.depth >= MAX_GROUP_DEPTH {
        return Err(source.error(
            kind_node,
            "add",
            format!("groups nest deeper than {MAX_GROUP_DEPTH} levels"),
        ));
    }
    let count = match find("count") {
        Some(e) => counts(builder, e.value)?,
        None => return Err(source.error(kind_node, "count", "an array needs `count:`")),
    };
    let step = match find("step") {
        Some(e) => DVec3::from_array(source.triple(e.value, "step")?),
        None => DVec3::ZERO,
    };
    let colors = match find("colors") {
        Some(e) => {
            let list = source.sequence(e.value, "colors")?;
            if list.is_empty() {
                return Err(source.error(e.value, "colors", "`colors` needs at least one colour"));
            }
            list.iter()
                .map(|c| color(source, c, "colors"))
                .collect::<Result<Vec<Color>, _>>()?
        }
        None => Vec::new(),
    };

    // The object, read once in the array's own space: its material and shadow inherited from
    // the array as a group's children inherit them.
    let element = {
        let inside = Inherited {
            matrix: DMat4::IDENTITY,
            frame: inherited.frame,
            end_matrix: DMat4::IDENTITY,
            material: placement.material.clone(),
            casts_shadow: placement.casts_shadow,
            depth: inherited.depth + 1,
            media: placement.media,
        };
        let mut parts = Vec::new();
        let item_entries = match as_str(of.value) {
            Some(_) => vec![Entry {
                name: "add",
                key: of.key,
                value: of.value,
            }],
            None => source.entries(of.value, "of")?,
        };
        let item_kind = item_entries
            .iter()
            .find(|e| e.name == "add")
            .map(|e| e.value)
            .ok_or_else(|| source.error(of.value, "of", "the array's `of:` needs `add:`"))?;
        builder.build_entries(item_entries, item_kind, &inside, &mut parts)?;
        parts
    };

    let singular = || {
        source.error(
            placement.placed_at,
            "step",
            "a copy of the array is placed by a singular transform",
        )
    };
    let mut index = 0usize;
    for z in 0..count[2] {
        for y in 0..count[1] {
            for x in 0..count[0] {
                // A copy spends even when the object has no parts (an empty group), so
                // that no count loops unbounded.
                source.spend(kind_node, "count")?;
                let offset =
                    DMat4::from_translation(step * DVec3::new(x as f64, y as f64, z as f64));
                let start = Transform::try_new(placement.world.matrix() * offset);
                let end = Transform::try_new(placement.world_end.matrix() * offset);
                let (Ok(start), Ok(end)) = (start, end) else {
                    return Err(singular());
                };
                for part in &element {
                    source.spend(kind_node, "count")?;
                    let mut copy = part
                        .placed_by_moving(&start, &end)
                        .map_err(|_| singular())?;
                    if let Some(c) = colors.get(index % colors.len().max(1)) {
                        copy.material.color = *c;
                    }
                    out.push(copy);
                }
                index += 1;
            }
        }
    }
    Ok(())
}

/// `count:`: one whole number (copies along x) or three (along x, y and z), each at least 1.
fn counts(builder: &Builder<'_, '_, '_>, node: &Node<'_>) -> Result<[u64; 3], SceneError> {
    let source = builder.source;
    if as_str(node).is_none() && source.number(node, "count").is_ok() {
        return Ok([source.integer(node, "count", 1)?, 1, 1]);
    }
    let items = source.sequence(node, "count")?;
    if items.len() != 3 {
        return Err(source.error(
            node,
            "count",
            format!(
                "expected one whole number or three, found a list of {}",
                items.len()
            ),
        ));
    }
    let mut out = [0; 3];
    for (slot, item) in out.iter_mut().zip(items) {
        *slot = source.integer(item, "count", 1)?;
    }
    Ok(out)
}
