//! `add: obj`: a Wavefront OBJ model (`file:`), its meshes added as objects with the file's
//! own materials unless the item gives one.
//!
//! Separate because a model is read from another file (through the scene's assets, once each)
//! and adds as many objects as the file has groups.

use super::motion::moving;
use super::placement::Placement;
use crate::assets::Assets;
use crate::error::SceneError;
use crate::source::{Entry, Node, Source};
use rayforge::Object;

/// Adds the meshes of the model that `file:` names, placed, to `out`.
pub fn add_model(
    source: &Source<'_>,
    assets: &mut Assets,
    entries: &[Entry<'_, '_>],
    kind_node: &Node<'_>,
    placement: Placement<'_, '_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let file = entries
        .iter()
        .find(|e| e.name == "file")
        .map(|e| e.value)
        .ok_or_else(|| source.error(kind_node, "file", "an obj needs `file:`"))?;
    let path = assets.resolve(source.string(file, "file")?);
    let meshes = assets.obj(&path).map_err(|e| {
        if e.path == path && e.span.is_none() {
            // The file itself could not be read: point at the `file:` that names it.
            source.error(file, "file", e.message)
        } else {
            e
        }
    })?;
    for (mesh, own_material) in meshes.iter() {
        let mut object = moving(
            Object::mesh(mesh.clone()),
            &placement.world,
            &placement.world_end,
        );
        // An explicit `material:` wins; then the file's own; then the group's.
        object.material = match (placement.material_explicit, own_material) {
            (false, Some(m)) => m.clone(),
            _ => placement.material.clone().unwrap_or_default(),
        };
        object.casts_shadow = placement.casts_shadow;
        source.spend(kind_node, "add")?;
        out.push(object);
    }
    Ok(())
}
