//! Motion: where an item is when the shutter closes (`motion:`, `velocity:`), and where it is
//! in an animation's frame (`per-frame:`).
//!
//! Separate from placement proper because these keys are about time: each turns the item's
//! own transform into another one, which placement then composes like any other.

use crate::defines::{Defines, Trail};
use crate::error::SceneError;
use crate::material::checked;
use crate::source::{Entry, Node, Source};
use crate::transform::transform_list;
use glam::DMat4;
use rayforge::{Object, Transform};

/// The item's own transform at animation frame `frame`: `per-frame` (a transform list) applied
/// `frame` times after it, about the point where the item's own origin lands (its centre, for
/// the book's solids), as Fundamentals of Ray Tracing's `blockmovie` turns its block a little
/// before each picture.
pub fn per_frame<'n>(
    source: &Source<'_>,
    defines: &Defines<'n, '_>,
    entries: &[Entry<'n, '_>],
    own: DMat4,
    frame: u64,
) -> Result<DMat4, SceneError> {
    let Some(e) = entries.iter().find(|e| e.name == "per-frame") else {
        return Ok(own);
    };
    let step = transform_list(source, defines, e.value, &mut Trail::new())?;
    checked(source, e.value, step)?;
    let centre = own.transform_point3(glam::DVec3::ZERO);
    let about = DMat4::from_translation(centre) * step * DMat4::from_translation(-centre);
    let mut placed = own;
    for _ in 0..frame {
        placed = about * placed;
    }
    Ok(placed)
}

/// The item's own transform when the shutter closes, if it moves: `motion:` gives it as a
/// transform list (like `transform:`), `velocity: [x, y, z]` as the distance travelled while
/// the shutter is open (added after the item's own transform). Returns the key's node, for
/// errors.
pub fn motion_end<'n>(
    source: &Source<'_>,
    defines: &Defines<'n, '_>,
    entries: &[Entry<'n, '_>],
    own: DMat4,
) -> Result<Option<(&'n Node<'n>, DMat4)>, SceneError> {
    let motion = entries.iter().find(|e| e.name == "motion");
    let velocity = entries.iter().find(|e| e.name == "velocity");
    match (motion, velocity) {
        (Some(_), Some(v)) => Err(source.error(
            v.key,
            "velocity",
            "give either `motion:` (where the item ends up) or `velocity:` (how far it moves), \
             not both",
        )),
        (Some(m), None) => {
            let end = transform_list(source, defines, m.value, &mut Trail::new())?;
            checked(source, m.value, end)?;
            Ok(Some((m.value, end)))
        }
        (None, Some(v)) => {
            let [x, y, z] = source.triple(v.value, "velocity")?;
            Ok(Some((
                v.value,
                DMat4::from_translation(glam::DVec3::new(x, y, z)) * own,
            )))
        }
        (None, None) => Ok(None),
    }
}

/// An object (with the identity transform) placed at `start` when the shutter opens and `end`
/// when it closes.
pub fn moving(object: Object, start: &Transform, end: &Transform) -> Object {
    // A primitive or mesh with the identity transform: placing it multiplies by the identity,
    // which cannot make an invertible transform singular.
    object
        .placed_by_moving(start, end)
        .unwrap_or_else(|_| object.with_transform_of(*start))
}
