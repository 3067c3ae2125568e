//! Transform lists: `[translate, x, y, z]`, `[scale, …]`, `[rotate-x, r]` (radians),
//! `[rotate-x-degrees, d]`, `[shear, …]` and references to defined lists, applied in the order
//! written (the first entry acts first).

use crate::defines::{Defines, Trail};
use crate::error::SceneError;
use crate::source::{as_str, describe, Node, Source};
use glam::DMat4;
use rayforge::math::{rotation_x, rotation_y, rotation_z, scaling, shearing, translation};

/// The operations a transform entry may name, with their argument counts.
const OPERATIONS: &[(&str, usize)] = &[
    ("translate", 3),
    ("scale", 3),
    ("rotate-x", 1),
    ("rotate-y", 1),
    ("rotate-z", 1),
    ("rotate-x-degrees", 1),
    ("rotate-y-degrees", 1),
    ("rotate-z-degrees", 1),
    ("shear", 6),
];

/// The matrix of a transform list (or of a single reference to one).
pub fn transform_list<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    node: &'n Node<'s>,
    trail: &mut Trail<'n>,
) -> Result<DMat4, SceneError> {
    let mut matrix = DMat4::IDENTITY;
    if as_str(node).is_some() {
        let value = defines.lookup(source, node, "transform", trail)?;
        matrix = transform_list(source, defines, value, trail)?;
        trail.pop();
        return Ok(matrix);
    }
    for entry in source.sequence(node, "transform")? {
        let step = if as_str(entry).is_some() {
            let value = defines.lookup(source, entry, "transform", trail)?;
            let m = transform_list(source, defines, value, trail)?;
            trail.pop();
            m
        } else {
            // Each entry costs a matrix product every time the list is used, so each is a
            // part of the scene's budget: a defined list of thousands of entries used
            // thousands of times would otherwise load for minutes.
            source.spend(entry, "transform")?;
            operation(source, entry)?
        };
        // Later entries act after earlier ones: they multiply on the left.
        matrix = step * matrix;
    }
    Ok(matrix)
}

/// One `[operation, arguments…]` entry.
fn operation(source: &Source<'_>, node: &Node<'_>) -> Result<DMat4, SceneError> {
    let items = source.sequence(node, "transform")?;
    let Some((head, args)) = items.split_first() else {
        return Err(source.error(node, "transform", "empty transform entry"));
    };
    let name = as_str(head).ok_or_else(|| {
        source.error(
            head,
            "transform",
            format!(
                "expected an operation name ({}), found {}",
                names(),
                describe(head)
            ),
        )
    })?;
    let Some(&(_, arity)) = OPERATIONS.iter().find(|(n, _)| *n == name) else {
        return Err(source.error(
            head,
            "transform",
            format!("unknown transform `{name}`; expected one of: {}", names()),
        ));
    };
    // Extra numbers are ignored with a warning (one of the community's files writes
    // `[rotate-y, 0,7853981634]` with a decimal comma); too few are an error.
    let args = if args.len() > arity && args.iter().all(|a| source.number(a, name).is_ok()) {
        source.warn(
            node,
            name,
            format!(
                "`{name}` takes {arity} number{}, found {}; the extra ones are ignored",
                if arity == 1 { "" } else { "s" },
                args.len()
            ),
        );
        &args[..arity]
    } else {
        args
    };
    if args.len() != arity {
        return Err(source.error(
            node,
            name,
            format!(
                "`{name}` takes {arity} number{}, found {}",
                if arity == 1 { "" } else { "s" },
                args.len()
            ),
        ));
    }
    let a = args
        .iter()
        .map(|n| source.number(n, name))
        .collect::<Result<Vec<f64>, _>>()?;
    Ok(match name {
        "translate" => translation(a[0], a[1], a[2]),
        "scale" => scaling(a[0], a[1], a[2]),
        "rotate-x" => rotation_x(a[0]),
        "rotate-y" => rotation_y(a[0]),
        "rotate-z" => rotation_z(a[0]),
        "rotate-x-degrees" => rotation_x(a[0].to_radians()),
        "rotate-y-degrees" => rotation_y(a[0].to_radians()),
        "rotate-z-degrees" => rotation_z(a[0].to_radians()),
        _ => shearing(a[0], a[1], a[2], a[3], a[4], a[5]),
    })
}

fn names() -> String {
    OPERATIONS
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}
