//! Canvas items: `add: canvas-line` and `add: canvas-triangle`, drawings on the image itself in
//! Computer Graphics from Scratch's canvas coordinates (its 2D stages).
//!
//! ```yaml
//! - add: canvas-line
//!   from: [-200, -100]        # canvas pixels from the centre, y up
//!   to: [240, 120]
//!   color: [0, 0, 0]
//! - add: canvas-triangle
//!   points: [[-200, -250], [200, 50], [20, 250]]
//!   color: [0, 1, 0]
//!   style: shaded             # wireframe, filled (the default) or shaded
//!   intensities: [0.3, 0.1, 1]
//! ```
//!
//! A point of three numbers is a point in front of the eye, projected (see
//! [`CanvasPoint::Projected`]).

use crate::error::SceneError;
use crate::material::color;
use crate::source::{check_keys, required, Entry, Node, Source};
use glam::{DVec2, DVec3};
use rayforge::draw2d::{CanvasItem, CanvasPoint, TriangleStyle};
use rayforge::Color;

/// The item kinds this module reads.
pub const CANVAS_KINDS: &[&str] = &["canvas-line", "canvas-triangle"];

/// A canvas item of kind `kind` (one of [`CANVAS_KINDS`]).
pub fn canvas_item(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
    kind: &str,
) -> Result<CanvasItem, SceneError> {
    let what = if kind == "canvas-line" {
        "a canvas line"
    } else {
        "a canvas triangle"
    };
    let allowed: &[&str] = if kind == "canvas-line" {
        &["add", "from", "to", "color"]
    } else {
        &["add", "points", "color", "style", "intensities"]
    };
    check_keys(source, entries, what, allowed)?;
    let get = |k: &str| required(source, entries, item, k, what);
    // The book draws in black unless told otherwise.
    let color = match entries.iter().find(|e| e.name == "color") {
        Some(e) => color(source, e.value, "color")?,
        None => Color::BLACK,
    };
    if kind == "canvas-line" {
        return Ok(CanvasItem::Line {
            from: point(source, get("from")?, "from")?,
            to: point(source, get("to")?, "to")?,
            color,
        });
    }
    let points_node = get("points")?;
    let corners = source.sequence(points_node, "points")?;
    let [a, b, c] = corners else {
        return Err(source.error(
            points_node,
            "points",
            format!("a triangle has 3 corners, found {} items", corners.len()),
        ));
    };
    let points = [
        point(source, a, "points")?,
        point(source, b, "points")?,
        point(source, c, "points")?,
    ];
    let intensities = entries.iter().find(|e| e.name == "intensities");
    let style_entry = entries.iter().find(|e| e.name == "style");
    let style = match style_entry
        .map(|e| source.string(e.value, "style"))
        .transpose()?
    {
        None | Some("filled") => TriangleStyle::Filled,
        Some("wireframe") => TriangleStyle::Wireframe,
        Some("shaded") => {
            let node = get("intensities")?;
            TriangleStyle::Shaded(intensity_triple(source, node)?)
        }
        Some(other) => {
            return Err(source.error(
                style_entry.map_or(item, |e| e.value),
                "style",
                format!("unknown style `{other}`; expected wireframe, filled or shaded"),
            ))
        }
    };
    if let (Some(e), false) = (intensities, matches!(style, TriangleStyle::Shaded(_))) {
        return Err(source.error(
            e.key,
            "intensities",
            "`intensities` shade a triangle: add `style: shaded`",
        ));
    }
    Ok(CanvasItem::Triangle {
        points,
        color,
        style,
    })
}

/// `[x, y]` on the canvas, or `[x, y, z]` in front of the eye (z > 0).
fn point(source: &Source<'_>, node: &Node<'_>, key: &str) -> Result<CanvasPoint, SceneError> {
    let items = source.sequence(node, key)?;
    match items {
        [x, y] => Ok(CanvasPoint::Canvas(DVec2::new(
            source.number(x, key)?,
            source.number(y, key)?,
        ))),
        [x, y, z] => {
            let p = DVec3::new(
                source.number(x, key)?,
                source.number(y, key)?,
                source.number(z, key)?,
            );
            if p.z <= 0.0 {
                return Err(source.error(
                    z,
                    key,
                    format!(
                        "a point to project must lie in front of the eye (z > 0), found z = {}",
                        p.z
                    ),
                ));
            }
            Ok(CanvasPoint::Projected(p))
        }
        _ => Err(source.error(
            node,
            key,
            format!(
                "expected [x, y] on the canvas or [x, y, z] in front of the eye, found {} items",
                items.len()
            ),
        )),
    }
}

/// The book's `h` at each corner: three numbers, none negative.
fn intensity_triple(source: &Source<'_>, node: &Node<'_>) -> Result<[f64; 3], SceneError> {
    let h = source.triple(node, "intensities")?;
    if h.iter().any(|&v| v < 0.0) {
        return Err(source.error(
            node,
            "intensities",
            "an intensity cannot be negative (0 is black, 1 the full colour)",
        ));
    }
    Ok(h)
}
