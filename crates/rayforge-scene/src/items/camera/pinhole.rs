//! The Ray Tracer Challenge's camera: `add: camera` with `field-of-view`, `from`, `to` and
//! `up`, and optionally the thin lens of depth of field (`aperture`, `focal-distance`).
//!
//! Separate from the other books' cameras: it is the one placed by a view transform, and the
//! one with a lens.

use crate::error::SceneError;
use crate::source::{check_keys, required, Entry, Node, Source};
use rayforge::math::{point, vector, view_transform};
use rayforge::{Camera, Transform};

/// The keys the book's camera accepts.
const KEYS: &[&str] = &[
    "add",
    "width",
    "height",
    "field-of-view",
    "from",
    "to",
    "up",
    "samples",
    "aperture",
    "focal-distance",
    "shutter",
];

/// The book's camera of an `add: camera` item with neither `zoom:` nor `viewport:`.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Camera, SceneError> {
    check_keys(source, entries, "a camera", KEYS)?;
    let get = |k: &str| required(source, entries, item, k, "the camera");
    let width = source.integer(get("width")?, "width", 1)? as usize;
    let height = source.integer(get("height")?, "height", 1)? as usize;
    let fov = field_of_view(source, get("field-of-view")?)?;
    let view = view(source, entries, item)?;
    let camera = Camera::new(width, height, fov).with_transform_of(view);
    lens(source, entries, item, camera)
}

/// `field-of-view`, in radians strictly between 0 and π.
fn field_of_view(source: &Source<'_>, node: &Node<'_>) -> Result<f64, SceneError> {
    let fov = source.number(node, "field-of-view")?;
    if !(fov > 0.0 && fov < std::f64::consts::PI) {
        return Err(source.error(
            node,
            "field-of-view",
            format!("the field of view is in radians and must lie between 0 and π, found {fov}"),
        ));
    }
    Ok(fov)
}

/// The view transform from `from`, `to` and `up`.
fn view(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Transform, SceneError> {
    let get = |k: &str| required(source, entries, item, k, "the camera");
    let [fx, fy, fz] = source.triple(get("from")?, "from")?;
    let to_node = get("to")?;
    let [tx, ty, tz] = source.triple(to_node, "to")?;
    let up_node = get("up")?;
    let [ux, uy, uz] = source.triple(up_node, "up")?;
    let (from, to, up) = (point(fx, fy, fz), point(tx, ty, tz), vector(ux, uy, uz));
    if from == to {
        return Err(source.error(to_node, "to", "the camera looks at its own position"));
    }
    if (to - from).cross(up).length_squared() < 1e-18 {
        return Err(source.error(
            up_node,
            "up",
            "`up` is zero or parallel to the direction of view",
        ));
    }
    Transform::try_new(view_transform(from, to, up))
        .map_err(|e| source.error(item, "up", format!("the view transform is singular: {e}")))
}

/// The camera with a thin lens, when it has `aperture` (which then needs `focal-distance`).
fn lens(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
    camera: Camera,
) -> Result<Camera, SceneError> {
    let Some(aperture_entry) = entries.iter().find(|e| e.name == "aperture") else {
        return Ok(camera);
    };
    let aperture = source.number(aperture_entry.value, "aperture")?;
    if aperture < 0.0 {
        return Err(source.error(
            aperture_entry.value,
            "aperture",
            "the aperture cannot be negative",
        ));
    }
    let focal_node = required(source, entries, item, "focal-distance", "the camera")?;
    let focal = source.number(focal_node, "focal-distance")?;
    if focal <= 0.0 {
        return Err(source.error(
            focal_node,
            "focal-distance",
            "the focal distance must be positive",
        ));
    }
    Ok(camera.with_lens(aperture, focal))
}
