//! Computer Graphics from Scratch's camera in a scene file: `add: camera` with `viewport:`.
//!
//! ```yaml
//! - add: camera
//!   width: 600                 # the canvas, Cw × Ch pixels
//!   height: 600
//!   viewport: [1, 1]           # Vw × Vh, in scene units
//!   distance: 1                # d, eye to viewport (default 1)
//!   position: [3, 0, 1]        # the eye (default the origin)
//!   rotation:                  # rows of the matrix turning the ray directions (default none)
//!     - [0.7071, 0, -0.7071]
//!     - [0, 1, 0]
//!     - [0.7071, 0, 0.7071]
//! ```
//!
//! Instead of `position` and `rotation`, `from`, `to` and `up` place it the usual way.
//!
//! Separate from the other books' cameras: it projects onto a viewport of a given size at a
//! given distance, and may be turned by a matrix written row by row.

use crate::error::SceneError;
use crate::source::{check_keys, required, Entry, Node, Source};
use rayforge::camera::Viewport;
use rayforge::{point, vector, Camera};

/// The keys a viewport camera accepts.
const KEYS: &[&str] = &[
    "add",
    "width",
    "height",
    "viewport",
    "distance",
    "position",
    "rotation",
    "from",
    "to",
    "up",
    "samples",
    "shutter",
    "iso",
    "exposure-time",
    "white-balance",
    "max-component",
];

/// The viewport camera of an `add: camera` item that has `viewport:`.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Camera, SceneError> {
    check_keys(source, entries, "a viewport camera", KEYS)?;
    let required = |k: &str| required(source, entries, item, k, "the camera");
    let width = source.integer(required("width")?, "width", 1)? as usize;
    let height = source.integer(required("height")?, "height", 1)? as usize;
    let [width_units, height_units] = size(source, required("viewport")?)?;
    let mut viewport = Viewport {
        width: width_units,
        height: height_units,
        distance: distance(source, value(entries, "distance"))?,
        ..Viewport::BOOK
    };
    place(source, entries, item, &mut viewport)?;
    Camera::viewport(width, height, viewport).ok_or_else(|| {
        source.error(
            value(entries, "rotation").unwrap_or(item),
            "rotation",
            "the rotation matrix cannot be inverted",
        )
    })
}

/// The value of `key`, if the item has it.
fn value<'n, 's>(entries: &[Entry<'n, 's>], key: &str) -> Option<&'n Node<'s>> {
    entries.iter().find(|e| e.name == key).map(|e| e.value)
}

/// `viewport: [Vw, Vh]`, both positive.
fn size(source: &Source<'_>, node: &Node<'_>) -> Result<[f64; 2], SceneError> {
    let sizes = source.sequence(node, "viewport")?;
    let [vw, vh] = sizes else {
        return Err(source.error(
            node,
            "viewport",
            format!("expected [width, height], found {} items", sizes.len()),
        ));
    };
    let (vw, vh) = (
        source.number(vw, "viewport")?,
        source.number(vh, "viewport")?,
    );
    if vw <= 0.0 || vh <= 0.0 {
        return Err(source.error(node, "viewport", "the viewport's sides must be positive"));
    }
    Ok([vw, vh])
}

/// `distance`, eye to viewport: positive, default 1.
fn distance(source: &Source<'_>, node: Option<&Node<'_>>) -> Result<f64, SceneError> {
    let Some(node) = node else {
        return Ok(1.0);
    };
    let d = source.number(node, "distance")?;
    if d <= 0.0 {
        return Err(source.error(node, "distance", "the distance must be positive"));
    }
    Ok(d)
}

/// Places the eye and turns the view: by `from`, `to` and `up`, or by `position` and
/// `rotation` (never both ways).
fn place(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
    viewport: &mut Viewport,
) -> Result<(), SceneError> {
    let look_at = ["from", "to", "up"]
        .iter()
        .find_map(|k| value(entries, k).map(|n| (*k, n)));
    let Some((key, node)) = look_at else {
        return position_and_rotation(source, entries, viewport);
    };
    if let Some(other) = ["position", "rotation"]
        .iter()
        .find(|k| value(entries, k).is_some())
    {
        return Err(source.error(
            node,
            key,
            format!("place the camera with `from`, `to`, `up` or with `position`, `rotation`, not both (`{other}` is given too)"),
        ));
    }
    let required = |k: &str| required(source, entries, item, k, "the camera");
    let [fx, fy, fz] = source.triple(required("from")?, "from")?;
    let [tx, ty, tz] = source.triple(required("to")?, "to")?;
    let up_node = required("up")?;
    let [ux, uy, uz] = source.triple(up_node, "up")?;
    let from = point(fx, fy, fz);
    viewport.position = from;
    viewport.rotation =
        Viewport::look_at(from, point(tx, ty, tz), vector(ux, uy, uz)).ok_or_else(|| {
            source.error(
                up_node,
                "up",
                "`up` is zero or parallel to the line of sight, or the camera looks at itself",
            )
        })?;
    Ok(())
}

/// `position` (the eye, default the origin) and `rotation` (three rows of three numbers,
/// default none).
fn position_and_rotation(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    viewport: &mut Viewport,
) -> Result<(), SceneError> {
    if let Some(p) = value(entries, "position") {
        let [x, y, z] = source.triple(p, "position")?;
        viewport.position = point(x, y, z);
    }
    if let Some(r) = value(entries, "rotation") {
        let rows = source.sequence(r, "rotation")?;
        if rows.len() != 3 {
            return Err(source.error(
                r,
                "rotation",
                format!("expected 3 rows of 3 numbers, found {} rows", rows.len()),
            ));
        }
        for (i, row) in rows.iter().enumerate() {
            viewport.rotation[i] = source.triple(row, "rotation")?;
        }
    }
    Ok(())
}
