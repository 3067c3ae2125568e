//! Objects: an `add:` item that names a shape, group, CSG, model (OBJ, glTF, PLY) or defined object,
//! expanded, checked for its kind's keys and placed, then built by its kind's reader.
//!
//! Separate from the readers of each kind because it is the part they share; it is also the
//! builder that groups and CSGs are handed (see [`Builder`]) to build what they hold.

use super::arrays::add_array;
use super::csg::add_csg;
use super::groups::add_group;
use super::kinds::keys;
use super::models::{add_gltf, add_model, add_ply};
use super::nesting::{Builder, Inherited};
use super::placement::place;
use super::shapes::{add_shape, shape};
use super::templates::{expand_template, Expanded};
use crate::assets::Assets;
use crate::defines::Defines;
use crate::error::SceneError;
use crate::source::{check_keys, Entry, Node, Source};
use rayforge::Object;

/// Adds the objects of the top-level item with keys `entries`, whose `add:` is `kind`, to
/// `out`, as they are at animation frame `frame`.
pub fn add_objects<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    entries: Vec<Entry<'n, 's>>,
    kind: &'n Node<'s>,
    frame: u64,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let mut trail = Vec::new();
    let item = expand_template(source, defines, entries, kind, &mut trail)?;
    let mut builder = Builder {
        source,
        defines,
        assets,
        trail,
        build: build_objects,
    };
    let top = Inherited {
        frame,
        ..Inherited::TOP
    };
    build_objects(&mut builder, &item, &top, out)
}

/// Builds the objects of one (expanded) `add:` item, a shape or a group, into `out`, with
/// every enclosing group's transform baked in (the parent first: `parent * child`). The
/// builder's trail holds the object templates being built (see [`expand_template`]).
fn build_objects<'n, 's>(
    builder: &mut Builder<'_, 'n, 's>,
    item: &Expanded<'n, 's>,
    inherited: &Inherited,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let source = builder.source;
    let entries = &item.entries;
    let kind_node = entries
        .iter()
        .find(|e| e.name == "add")
        .expect("every item has `add`")
        .value;
    let kind = source.string(kind_node, "add")?;
    let shape = match kind {
        "group" | "obj" | "gltf" | "ply" | "csg" | "array" => None,
        _ => Some(shape(source, entries, kind_node, kind)?),
    };
    check_keys(source, entries, &format!("a {kind}"), &keys(kind))?;
    let placement = place(builder, item, kind_node, inherited)?;
    let interface = placement.media.interface();
    let start = out.len();
    match (shape, kind) {
        (Some(shape), _) => add_shape(source, kind_node, shape, placement, out),
        (None, "csg") => add_csg(builder, entries, kind_node, placement, inherited, out),
        (None, "obj") => add_model(source, builder.assets, entries, kind_node, placement, out),
        (None, "gltf") => add_gltf(source, builder.assets, entries, kind_node, placement, out),
        (None, "ply") => add_ply(source, builder.assets, entries, kind_node, placement, out),
        (None, "array") => add_array(builder, entries, kind_node, placement, inherited, out),
        (None, _) => add_group(builder, entries, kind_node, placement, inherited, out),
    }?;
    // What the item says of media reaches every object it built that says nothing itself.
    for object in &mut out[start..] {
        if object.media.is_none() {
            object.media = interface;
        }
    }
    Ok(())
}
