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

use crate::source::{check_keys, Entry, Node, Source};
use crate::SceneError;
use rayforge::camera::Viewport;
use rayforge::{point, vector, Camera};

/// The keys a viewport camera accepts.
const KEYS: &[&str] = &[
    "add", "width", "height", "viewport", "distance", "position", "rotation", "from", "to", "up",
    "samples", "shutter",
];

/// The viewport camera of an `add: camera` item that has `viewport:`.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Camera, SceneError> {
    check_keys(source, entries, "a viewport camera", KEYS)?;
    let get = |k: &str| entries.iter().find(|e| e.name == k).map(|e| e.value);
    let required =
        |k: &str| get(k).ok_or_else(|| source.error(item, k, format!("the camera needs `{k}:`")));
    let width = source.integer(required("width")?, "width", 1)? as usize;
    let height = source.integer(required("height")?, "height", 1)? as usize;
    let viewport_node = required("viewport")?;
    let sizes = source.sequence(viewport_node, "viewport")?;
    let [vw, vh] = sizes else {
        return Err(source.error(
            viewport_node,
            "viewport",
            format!("expected [width, height], found {} items", sizes.len()),
        ));
    };
    let (vw, vh) = (
        source.number(vw, "viewport")?,
        source.number(vh, "viewport")?,
    );
    if vw <= 0.0 || vh <= 0.0 {
        return Err(source.error(
            viewport_node,
            "viewport",
            "the viewport's sides must be positive",
        ));
    }
    let distance = match get("distance") {
        Some(n) => {
            let d = source.number(n, "distance")?;
            if d <= 0.0 {
                return Err(source.error(n, "distance", "the distance must be positive"));
            }
            d
        }
        None => 1.0,
    };
    let mut viewport = Viewport {
        width: vw,
        height: vh,
        distance,
        ..Viewport::BOOK
    };
    let look_at = ["from", "to", "up"]
        .iter()
        .find_map(|k| get(k).map(|n| (*k, n)));
    if let Some((key, node)) = look_at {
        if let Some(other) = ["position", "rotation"].iter().find(|k| get(k).is_some()) {
            return Err(source.error(
                node,
                key,
                format!("place the camera with `from`, `to`, `up` or with `position`, `rotation`, not both (`{other}` is given too)"),
            ));
        }
        let [fx, fy, fz] = source.triple(required("from")?, "from")?;
        let [tx, ty, tz] = source.triple(required("to")?, "to")?;
        let up_node = required("up")?;
        let [ux, uy, uz] = source.triple(up_node, "up")?;
        let from = point(fx, fy, fz);
        viewport.position = from;
        viewport.rotation = Viewport::look_at(from, point(tx, ty, tz), vector(ux, uy, uz))
            .ok_or_else(|| {
                source.error(
                    up_node,
                    "up",
                    "`up` is zero or parallel to the line of sight, or the camera looks at itself",
                )
            })?;
    } else {
        if let Some(p) = get("position") {
            let [x, y, z] = source.triple(p, "position")?;
            viewport.position = point(x, y, z);
        }
        if let Some(r) = get("rotation") {
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
    }
    Camera::viewport(width, height, viewport).ok_or_else(|| {
        source.error(
            get("rotation").unwrap_or(item),
            "rotation",
            "the rotation matrix cannot be inverted",
        )
    })
}
