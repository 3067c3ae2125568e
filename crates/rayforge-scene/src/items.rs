//! The items of a scene file: `add: camera`, `add: light`, shapes, and defined object templates.

use crate::defines::{is_reference, merge, Defines, Trail};
use crate::error::SceneError;
use crate::material::{checked, color, material};
use crate::source::{check_keys, Entry, Node, Source};
use crate::transform::transform_list;
use glam::DMat4;
use rayforge::math::{point, vector, view_transform};
use rayforge::{Camera, Light, Material, Object, Shape};

/// The shapes `add:` may name, for messages.
pub const SHAPE_KINDS: &[&str] = &["sphere", "plane", "cube", "cylinder", "cone"];

/// Keys every shape accepts.
const SHAPE_KEYS: &[&str] = &["add", "material", "transform", "shadow"];
/// Keys cylinders and cones accept besides those.
const QUADRIC_KEYS: &[&str] = &[
    "add",
    "material",
    "transform",
    "shadow",
    "min",
    "max",
    "closed",
];

/// The camera from `add: camera`.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Camera, SceneError> {
    check_keys(
        source,
        entries,
        "a camera",
        &[
            "add",
            "width",
            "height",
            "field-of-view",
            "from",
            "to",
            "up",
        ],
    )?;
    let get = |k: &str| {
        entries
            .iter()
            .find(|e| e.name == k)
            .map(|e| e.value)
            .ok_or_else(|| source.error(item, k, format!("the camera needs `{k}:`")))
    };
    let width = source.integer(get("width")?, "width", 1)? as usize;
    let height = source.integer(get("height")?, "height", 1)? as usize;
    let fov_node = get("field-of-view")?;
    let fov = source.number(fov_node, "field-of-view")?;
    if !(fov > 0.0 && fov < std::f64::consts::PI) {
        return Err(source.error(
            fov_node,
            "field-of-view",
            format!("the field of view is in radians and must lie between 0 and π, found {fov}"),
        ));
    }
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
    let view = rayforge::Transform::try_new(view_transform(from, to, up))
        .map_err(|e| source.error(item, "up", format!("the view transform is singular: {e}")))?;
    Ok(Camera::new(width, height, fov).with_transform_of(view))
}

/// A point light from `add: light`.
pub fn light(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    check_keys(source, entries, "a light", &["add", "at", "intensity"])?;
    let get = |k: &str| {
        entries
            .iter()
            .find(|e| e.name == k)
            .map(|e| e.value)
            .ok_or_else(|| source.error(item, k, format!("the light needs `{k}:`")))
    };
    let [x, y, z] = source.triple(get("at")?, "at")?;
    let intensity = color(source, get("intensity")?, "intensity")?;
    Ok(Light::point(point(x, y, z), intensity))
}

/// The entries of an `add:` item after expanding a template: `add: NAME` where NAME is a
/// define whose value is itself an object. The item's keys override the template's, except
/// `transform`, which composes (the template's placement first, then the item's); the result
/// also returns the template's transform lists in order.
pub fn expand_template<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    entries: Vec<Entry<'n, 's>>,
    kind: &'n Node<'s>,
    trail: &mut Trail<'n>,
) -> Result<(Vec<Entry<'n, 's>>, Vec<&'n Node<'s>>), SceneError> {
    let name = source.string(kind, "add")?;
    let mut transforms = Vec::new();
    if SHAPE_KINDS.contains(&name) || name == "camera" || name == "light" || !is_reference(kind) {
        if let Some(t) = entries.iter().find(|e| e.name == "transform") {
            transforms.push(t.value);
        }
        return Ok((entries, transforms));
    }
    if !defines.contains(name) {
        return Err(unknown_kind(source, kind, name));
    }
    let mut template = defines.mapping_entries(source, kind, "add", trail)?;
    let inner_kind = template
        .iter()
        .find(|e| e.name == "add")
        .map(|e| e.value)
        .ok_or_else(|| {
            source.error(
                kind,
                "add",
                format!(
                    "`{name}` is not a shape; expected one of: camera, light, {} or the name of a defined object",
                    SHAPE_KINDS.join(", ")
                ),
            )
        })?;
    let template_without_transform: Vec<_> = template
        .iter()
        .copied()
        .filter(|e| e.name != "transform")
        .collect();
    let (expanded, mut inner_transforms) = expand_template(
        source,
        defines,
        template_without_transform,
        inner_kind,
        trail,
    )?;
    if let Some(t) = template.iter().find(|e| e.name == "transform") {
        inner_transforms.push(t.value);
    }
    template = expanded;
    for e in entries {
        if e.name == "add" {
            continue;
        }
        if e.name == "transform" {
            inner_transforms.push(e.value);
        } else {
            merge(&mut template, e);
        }
    }
    trail.pop();
    Ok((template, inner_transforms))
}

/// Builds a shape from its (expanded) entries and transform lists.
pub fn shape<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    entries: &[Entry<'n, 's>],
    transforms: &[&'n Node<'s>],
) -> Result<Object, SceneError> {
    let kind_node = entries
        .iter()
        .find(|e| e.name == "add")
        .expect("every item has `add`")
        .value;
    let kind = source.string(kind_node, "add")?;
    let quadric = |make: fn(f64, f64, bool) -> Shape| -> Result<Shape, SceneError> {
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
    };
    let (shape, keys) = match kind {
        "sphere" => (Shape::Sphere, SHAPE_KEYS),
        "plane" => (Shape::Plane, SHAPE_KEYS),
        "cube" => (Shape::Cube, SHAPE_KEYS),
        "cylinder" => (
            quadric(|minimum, maximum, closed| Shape::Cylinder {
                minimum,
                maximum,
                closed,
            })?,
            QUADRIC_KEYS,
        ),
        "cone" => (
            quadric(|minimum, maximum, closed| Shape::Cone {
                minimum,
                maximum,
                closed,
            })?,
            QUADRIC_KEYS,
        ),
        other => return Err(unknown_kind(source, kind_node, other)),
    };
    check_keys(source, entries, &format!("a {kind}"), keys)?;
    let mut object = Object::new(shape);
    let mut matrix = DMat4::IDENTITY;
    for t in transforms {
        matrix = transform_list(source, defines, t, &mut Trail::new())? * matrix;
    }
    if let Some(last) = transforms.last() {
        object.transform = checked(source, last, matrix)?;
    }
    for e in entries {
        match e.name {
            "material" => object.material = material(source, defines, e.value, &Material::DEFAULT)?,
            "shadow" => object.casts_shadow = source.boolean(e.value, "shadow")?,
            _ => {}
        }
    }
    Ok(object)
}

/// The error for an `add:` that names neither a shape nor a defined object.
fn unknown_kind(source: &Source<'_>, node: &Node<'_>, name: &str) -> SceneError {
    source.error(
        node,
        "add",
        format!(
            "unknown kind `{name}`; expected one of: camera, light, {} or the name of a defined object",
            SHAPE_KINDS.join(", ")
        ),
    )
}
