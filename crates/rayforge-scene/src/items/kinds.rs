//! The kinds of object an `add:` may name, the keys each accepts, and the error for a name
//! that is none of them.
//!
//! Separate so that the template expander and the shape reader, which both tell a kind from a
//! template's name and report unknown kinds, share one list without importing each other.

use crate::error::SceneError;
use crate::source::{Node, Source};

/// The shapes `add:` may name, for messages.
pub const SHAPE_KINDS: &[&str] = &[
    "sphere",
    "plane",
    "rectangle",
    "cube",
    "cylinder",
    "cone",
    "torus",
    "ring",
    "disc",
    "icosahedron",
    "dodecahedron",
    "group",
    "obj",
    "gltf",
    "ply",
    "csg",
    "array",
];

/// The items that are not objects: each is added as an item of its own, never from a
/// template, a group's children or a CSG operand.
pub const ITEM_KINDS: &[&str] = &["camera", "light", "canvas-line", "canvas-triangle"];

/// Keys every shape, group, CSG and model accepts: what places it, moves it and colours it.
const SHAPE_KEYS: &[&str] = &[
    "add",
    "material",
    "transform",
    "shadow",
    "motion",
    "velocity",
    "per-frame",
    "interior",
    "exterior",
];

/// The keys a kind of item accepts besides [`SHAPE_KEYS`].
fn own_keys(kind: &str) -> &'static [&'static str] {
    match kind {
        "group" => &["children"],
        "csg" => &["operation", "left", "right"],
        "obj" | "gltf" | "ply" => &["file"],
        "array" => &["of", "count", "step", "colors"],
        "cylinder" | "cone" => &["min", "max", "closed"],
        "torus" => &["major-radius", "minor-radius"],
        "ring" => &["inner-radius", "outer-radius"],
        "disc" => &["radius"],
        _ => &[],
    }
}

/// Every key an item of `kind` accepts.
pub fn keys(kind: &str) -> Vec<&'static str> {
    SHAPE_KEYS.iter().chain(own_keys(kind)).copied().collect()
}

/// The error for an `add:` that names neither a shape nor a defined object.
pub fn unknown_kind(source: &Source<'_>, node: &Node<'_>, name: &str) -> SceneError {
    source.error(
        node,
        "add",
        format!(
            "unknown kind `{name}`; expected one of: camera, light, canvas-line, canvas-triangle, {} or the name of a defined object",
            SHAPE_KINDS.join(", ")
        ),
    )
}
