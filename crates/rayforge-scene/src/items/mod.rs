//! The items of a scene file, each read by the module of its kind: `add: camera` ([`camera`]),
//! `add: light` ([`lights`]), the canvas items, and objects ([`objects`]: shapes, groups, CSG,
//! OBJ models and defined object templates, placed and moving).
//!
//! This module only dispatches each `add:` item to its kind's reader and collects what they
//! read; `define:` items go to [`Defines`](crate::defines) and the `world:` item is the crate
//! root's.

mod arrays;
pub mod camera;
mod csg;
mod groups;
mod kinds;
mod lights;
mod models;
mod motion;
mod nesting;
mod objects;
mod placement;
mod shapes;
mod templates;

use crate::assets::Assets;
use crate::canvas_items::{canvas_item, CANVAS_KINDS};
use crate::defines::Defines;
use crate::error::SceneError;
use crate::media::NamedLater;
use crate::source::{as_str, Node, Source};
use camera::CameraItem;

/// What the file's items add up to, as they are read.
#[derive(Default)]
pub struct Contents {
    /// Objects and lights (and, from `world:`, the settings that go into the world).
    pub world: rayforge::World,
    /// The camera, once read.
    pub camera: Option<CameraItem>,
    /// `canvas-line` and `canvas-triangle` items, in order.
    pub canvas_items: Vec<rayforge::draw2d::CanvasItem>,
    /// The camera's `medium:`, named.
    pub camera_medium: Option<NamedLater>,
}

/// Whether a top-level item is a `define:` (which the reader keeps for later items).
pub fn is_define(item: &Node<'_>) -> bool {
    match &item.data {
        saphyr::YamlData::Mapping(map) => map.keys().any(|k| as_str(k) == Some("define")),
        _ => false,
    }
}

/// One top-level item other than a `define:` or `world:`.
pub fn add_item<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    item: &'n Node<'s>,
    read: &mut Contents,
    frame: u64,
) -> Result<(), SceneError> {
    let entries = source.entries(item, "")?;
    let Some(kind) = entries.iter().find(|e| e.name == "add").map(|e| e.value) else {
        return Err(source.error(item, "", "each item needs `add:`, `define:` or `world:`"));
    };
    match source.string(kind, "add")? {
        "camera" if read.camera.is_some() => {
            return Err(source.error(kind, "add", "a second camera: a scene has exactly one"))
        }
        "camera" => {
            // The medium the camera sits in is the renderer's business, not the lens's.
            let (medium, lens): (Vec<_>, Vec<_>) =
                entries.into_iter().partition(|e| e.name == "medium");
            if let Some(m) = medium.first() {
                read.camera_medium = Some(NamedLater::new(source, m.value, "medium")?);
            }
            read.camera = Some(camera::camera(source, &lens, item)?)
        }
        "light" => read
            .world
            .lights
            .push(lights::light(source, &entries, item)?),
        kind if CANVAS_KINDS.contains(&kind) => {
            source.spend(item, "add")?;
            let canvas_item = canvas_item(source, &entries, item, kind)?;
            read.canvas_items.push(canvas_item);
        }
        _ => objects::add_objects(
            source,
            defines,
            assets,
            entries,
            kind,
            frame,
            &mut read.world.objects,
        )?,
    }
    Ok(())
}
