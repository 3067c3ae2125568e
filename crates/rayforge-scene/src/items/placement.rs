//! Placement: where an object goes when the shutter opens and closes (its transform lists,
//! `per-frame`, `motion`, `velocity`, and every enclosing group's transform), its material and
//! whether it casts shadows.
//!
//! Separate because every kind of object is placed alike, before its kind's reader builds it.

use super::motion::{motion_end, per_frame};
use super::nesting::{Builder, Inherited};
use super::templates::Expanded;
use crate::defines::{Defines, Trail};
use crate::error::SceneError;
use crate::material::{checked, material};
use crate::media::{medium_named, MediaKeys, INTERFACE};
use crate::source::as_str;
use crate::source::{Entry, Node, Source};
use crate::transform::transform_list;
use glam::DMat4;
use rayforge::{Material, Transform};

/// Where an item goes and how it looks, from its keys and what it inherits.
pub struct Placement<'n, 's> {
    /// Where errors about the placement point: the item's last transform list, else its `add:`.
    pub placed_at: &'n Node<'s>,
    /// World from the item's own space when the shutter opens.
    pub world: Transform,
    /// World from the item's own space when the shutter closes.
    pub world_end: Transform,
    /// The item's `material:`, else the nearest enclosing group's.
    pub material: Option<Material>,
    /// Whether the item itself gives `material:` (an OBJ model's own materials yield to it).
    pub material_explicit: bool,
    /// False when the item or an enclosing group has `shadow: false`.
    pub casts_shadow: bool,
    /// The media it bounds: its own `interior:`, `exterior:` and `material: interface`,
    /// else the nearest enclosing group's.
    pub media: MediaKeys,
}

/// Places an expanded item whose `add:` is `kind_node`, inside what it inherits.
pub fn place<'n, 's>(
    builder: &mut Builder<'_, 'n, 's>,
    item: &Expanded<'n, 's>,
    kind_node: &'n Node<'s>,
    inherited: &Inherited,
) -> Result<Placement<'n, 's>, SceneError> {
    let (source, defines) = (builder.source, builder.defines);
    let entries = &item.entries;
    let own = own_transform(source, defines, &item.transforms)?;
    let placed_at = item.transforms.last().copied().unwrap_or(kind_node);
    checked(source, placed_at, own)?;
    let own = per_frame(source, defines, entries, own, inherited.frame)?;
    let world = checked(source, placed_at, inherited.matrix * own)?;
    let world_end = match motion_end(source, defines, entries, own)? {
        Some((node, end)) => checked(source, node, inherited.end_matrix * end)?,
        None => checked(source, placed_at, inherited.end_matrix * own)?,
    };
    let (material_here, casts_shadow, media) = looks(builder, entries, inherited)?;
    Ok(Placement {
        placed_at,
        world,
        world_end,
        material_explicit: material_here.is_some(),
        material: material_here.or_else(|| inherited.material.clone()),
        casts_shadow,
        media,
    })
}

/// The item's transform lists composed, in the order they apply.
fn own_transform<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    transforms: &[&'n Node<'s>],
) -> Result<DMat4, SceneError> {
    let mut own = DMat4::IDENTITY;
    for t in transforms.iter().copied() {
        own = transform_list(source, defines, t, &mut Trail::new())? * own;
    }
    Ok(own)
}

/// The item's own `material:`, if any, whether it casts shadows (`shadow:`, and what it
/// inherits) and the media it bounds, read in the order the keys are written.
fn looks<'n, 's>(
    builder: &mut Builder<'_, 'n, 's>,
    entries: &[Entry<'n, 's>],
    inherited: &Inherited,
) -> Result<(Option<Material>, bool, MediaKeys), SceneError> {
    let source = builder.source;
    let mut material_here = None;
    let mut casts_shadow = inherited.casts_shadow;
    let mut media = inherited.media;
    for e in entries {
        match e.name {
            "interior" => {
                media.interior = Some(medium_named(source, builder.defines, e.value, "interior")?)
            }
            "exterior" => {
                media.exterior = Some(medium_named(source, builder.defines, e.value, "exterior")?)
            }
            // A boundary between media only (pbrt-v4's `interface` material).
            "material" if as_str(e.value) == Some(INTERFACE) => media.index_matched = true,
            "material" => {
                media.index_matched = false;
                material_here = Some(material(
                    source,
                    builder.defines,
                    builder.assets,
                    e.value,
                    &Material::DEFAULT,
                )?)
            }
            "shadow" => casts_shadow &= source.boolean(e.value, "shadow")?,
            _ => {}
        }
    }
    Ok((material_here, casts_shadow, media))
}
