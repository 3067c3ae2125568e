//! `add: obj`, `add: gltf` and `add: ply`: a Wavefront OBJ, glTF 2.0 or PLY model (`file:`),
//! its meshes added as objects with the file's own materials unless the item gives one (a PLY
//! file has none: its mesh takes the item's material, or the enclosing group's).
//!
//! Separate because a model is read from another file (through the scene's assets, once each)
//! and adds as many objects as the file has groups or mesh primitives.

use super::motion::moving;
use super::placement::Placement;
use crate::assets::Assets;
use crate::error::SceneError;
use crate::gltf::GLTF_TO_BOOK;
use crate::source::{Entry, Node, Source};
use rayforge::{Object, Transform};
use std::path::{Path, PathBuf};

/// Adds the meshes of the model that `file:` names, placed, to `out`.
pub fn add_model(
    source: &Source<'_>,
    assets: &mut Assets,
    entries: &[Entry<'_, '_>],
    kind_node: &Node<'_>,
    placement: Placement<'_, '_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let (file, path) = model_file(source, assets, entries, kind_node, "an obj")?;
    let meshes = assets
        .obj(&path)
        .map_err(|e| at_file(source, file, &path, e))?;
    for (mesh, own_material) in meshes.iter() {
        let mut object = Object::mesh(mesh.clone());
        if let Some(own) = own_material {
            object.material = own.clone();
        }
        add_part(
            source,
            kind_node,
            object,
            own_material.is_some(),
            &placement,
            out,
        )?;
    }
    Ok(())
}

/// Adds one part of a model (in the model's own space, with the file's material when it has
/// one: `own`) to `out`, placed and moved by the item. An explicit `material:` wins; then the
/// file's own; then the enclosing group's.
fn add_part(
    source: &Source<'_>,
    kind_node: &Node<'_>,
    part: Object,
    own: bool,
    placement: &Placement<'_, '_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let mut object = moving(part, &placement.world, &placement.world_end);
    if placement.material_explicit || !own {
        object.material = placement.material.clone().unwrap_or_default();
    }
    object.casts_shadow = placement.casts_shadow;
    source.spend(kind_node, "add")?;
    out.push(object);
    Ok(())
}

/// The `file:` of a model item and the path it names.
fn model_file<'n, 's>(
    source: &Source<'_>,
    assets: &Assets,
    entries: &[Entry<'n, 's>],
    kind_node: &Node<'_>,
    what: &str,
) -> Result<(&'n Node<'s>, PathBuf), SceneError> {
    let file = entries
        .iter()
        .find(|e| e.name == "file")
        .map(|e| e.value)
        .ok_or_else(|| source.error(kind_node, "file", format!("{what} needs `file:`")))?;
    Ok((file, assets.resolve(source.string(file, "file")?)))
}

/// A model's error placed at the `file:` that names it when it has no line in the model to
/// show: about the file as a whole (it could not be read), or about a part of it named by its
/// key alone (a glTF file's JSON path, `meshes[0].primitives[0].indices`), which the message
/// then names with the model. An error with a place in the model (an OBJ line, a glTF file's
/// JSON syntax) is left there, where its line is shown.
fn at_file(source: &Source<'_>, file: &Node<'_>, path: &Path, e: SceneError) -> SceneError {
    if e.path != path || e.span.is_some() {
        return e;
    }
    match &e.key {
        None => source.error(file, "file", e.message),
        Some(key) => source.error(
            file,
            "file",
            format!(
                "in `{}`, at `{}`: {}",
                path.display(),
                crate::error::clip(key),
                e.message
            ),
        ),
    }
}

/// Adds the mesh primitives of the glTF model that `file:` names, each placed by its node and
/// then by the item (through [`GLTF_TO_BOOK`]), to `out`. An explicit `material:` replaces the
/// file's materials; the file's cameras and lights are used only when it is rendered
/// directly.
pub fn add_gltf(
    source: &Source<'_>,
    assets: &mut Assets,
    entries: &[Entry<'_, '_>],
    kind_node: &Node<'_>,
    placement: Placement<'_, '_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let (file, path) = model_file(source, assets, entries, kind_node, "a gltf")?;
    let model = assets
        .gltf(&path)
        .map_err(|e| at_file(source, file, &path, e))?;
    let mirror = Transform::new(GLTF_TO_BOOK);
    for part in &model.objects {
        let placed = part.placed_by(&mirror).map_err(|_| {
            source.error(
                kind_node,
                "file",
                "a node of the model has a singular transform",
            )
        })?;
        add_part(source, kind_node, placed, true, &placement, out)?;
    }
    Ok(())
}

/// Adds the mesh of the PLY model that `file:` names, placed, to `out`, with the item's
/// material (or the enclosing group's): a PLY file has no materials of its own.
pub fn add_ply(
    source: &Source<'_>,
    assets: &mut Assets,
    entries: &[Entry<'_, '_>],
    kind_node: &Node<'_>,
    placement: Placement<'_, '_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let (file, path) = model_file(source, assets, entries, kind_node, "a ply")?;
    let mesh = assets
        .ply(&path)
        .map_err(|e| at_file(source, file, &path, e))?;
    add_part(
        source,
        kind_node,
        Object::mesh(mesh),
        false,
        &placement,
        out,
    )
}
