//! The primitive shapes: `sphere`, `plane`, `rectangle`, `cube`, `cylinder`, `cone`, `torus`, `ring`,
//! `disc` and Fundamentals of Ray Tracing's `icosahedron` and `dodecahedron`, with their own
//! keys.
//!
//! Separate from groups, CSG and models because a shape is a leaf: one object, built from its
//! own keys alone.

use super::kinds::{unknown_kind, ITEM_KINDS};
use super::motion::moving;
use super::placement::Placement;
use crate::error::SceneError;
use crate::source::{Entry, Node, Source};
use rayforge::{Object, Shape};
use std::sync::Arc;

/// The shape an `add:` names, with its shape-specific keys.
pub fn shape(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    kind_node: &Node<'_>,
    kind: &str,
) -> Result<Shape, SceneError> {
    match kind {
        "sphere" => Ok(Shape::Sphere),
        "plane" => Ok(Shape::Plane),
        "cube" => Ok(Shape::Cube),
        "rectangle" => Ok(Shape::Rectangle),
        "cylinder" => quadric(source, entries, |minimum, maximum, closed| {
            Shape::Cylinder {
                minimum,
                maximum,
                closed,
            }
        }),
        "cone" => quadric(source, entries, |minimum, maximum, closed| Shape::Cone {
            minimum,
            maximum,
            closed,
        }),
        "torus" => torus(source, entries),
        "ring" | "disc" => ring(source, entries, kind),
        // Fundamentals of Ray Tracing's polyhedra, with its size parameter 1 (scale to taste).
        "icosahedron" => Ok(Shape::Mesh(Arc::new(rayforge::geometry::icosahedron()))),
        "dodecahedron" => Ok(Shape::Mesh(Arc::new(rayforge::geometry::dodecahedron()))),
        kind if ITEM_KINDS.contains(&kind) => Err(source.error(
            kind_node,
            "add",
            format!(
                "a {kind} cannot be a defined object, a group's child or a CSG operand: add it \
                 as an item of its own"
            ),
        )),
        other => Err(unknown_kind(source, kind_node, other)),
    }
}

/// Adds the shape's object, placed, to `out`.
pub fn add_shape(
    source: &Source<'_>,
    kind_node: &Node<'_>,
    shape: Shape,
    placement: Placement<'_, '_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let mut object = moving(Object::new(shape), &placement.world, &placement.world_end);
    object.material = placement.material.unwrap_or_default();
    object.casts_shadow = placement.casts_shadow;
    source.spend(kind_node, "add")?;
    out.push(object);
    Ok(())
}

/// A cylinder or cone (`make`), cut at `min` and `max` (default unbounded) and `closed` there
/// (default open).
fn quadric(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    make: fn(f64, f64, bool) -> Shape,
) -> Result<Shape, SceneError> {
    let mut minimum = f64::NEG_INFINITY;
    let mut maximum = f64::INFINITY;
    let mut closed = false;
    for e in entries {
        match e.name {
            "min" => minimum = source.number(e.value, "min")?,
            "max" => maximum = source.number(e.value, "max")?,
            "closed" => closed = source.boolean(e.value, "closed")?,
            _ => {}
        }
    }
    Ok(make(minimum, maximum, closed))
}

/// A thin ring (`inner-radius`, default 0.5; `outer-radius`, default 1) or disc (`radius`,
/// default 1) in the xz plane.
fn ring(source: &Source<'_>, entries: &[Entry<'_, '_>], kind: &str) -> Result<Shape, SceneError> {
    let (mut inner, mut outer) = if kind == "disc" {
        (0.0, 1.0)
    } else {
        (0.5, 1.0)
    };
    for e in entries {
        let radius = match e.name {
            "inner-radius" => &mut inner,
            "outer-radius" | "radius" => &mut outer,
            _ => continue,
        };
        *radius = source.number(e.value, e.name)?;
        if *radius < 0.0 {
            return Err(source.error(e.value, e.name, "a radius cannot be negative"));
        }
    }
    if inner >= outer {
        // Blame the key the file has: the inner radius if given, else the outer one.
        let blamed = entries
            .iter()
            .find(|e| e.name == "inner-radius")
            .or_else(|| {
                entries
                    .iter()
                    .find(|e| matches!(e.name, "outer-radius" | "radius"))
            });
        let (node, key) = blamed.map_or((entries[0].value, kind), |e| (e.value, e.name));
        return Err(source.error(
            node,
            key,
            format!("the inner radius {inner} must be smaller than the outer {outer}"),
        ));
    }
    Ok(Shape::Ring { inner, outer })
}

/// A torus: `major-radius` (its tube's centre circle, default 1) and `minor-radius` (the tube,
/// default 0.25), both positive.
fn torus(source: &Source<'_>, entries: &[Entry<'_, '_>]) -> Result<Shape, SceneError> {
    let (mut major, mut minor) = (1.0, 0.25);
    for e in entries {
        let radius = match e.name {
            "major-radius" => &mut major,
            "minor-radius" => &mut minor,
            _ => continue,
        };
        *radius = source.number(e.value, e.name)?;
        if *radius <= 0.0 {
            return Err(source.error(e.value, e.name, "a torus radius must be positive"));
        }
    }
    Ok(Shape::Torus { major, minor })
}
