//! The items of a scene file: `add: camera`, `add: light`, shapes, and defined object templates.

use crate::assets::Assets;
use crate::defines::{is_reference, merge, Defines, Trail};
use crate::error::SceneError;
use crate::material::{checked, material};
use crate::source::{as_str, check_keys, required, Entry, Node, Source};
use crate::transform::transform_list;
use glam::DMat4;
use rayforge::math::{point, vector, view_transform};
use rayforge::{
    AreaLight, Camera, CsgOperation, Group, Light, Material, Object, Shape, SpotLight, Transform,
};

/// The shapes `add:` may name, for messages.
pub const SHAPE_KINDS: &[&str] = &[
    "sphere",
    "plane",
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
    "csg",
];

/// Keys every shape, group, CSG and model accepts: what places it, moves it and colours it.
const SHAPE_KEYS: &[&str] = &[
    "add",
    "material",
    "transform",
    "shadow",
    "motion",
    "velocity",
    "per-frame",
];

/// The keys a kind of item accepts besides [`SHAPE_KEYS`].
fn own_keys(kind: &str) -> &'static [&'static str] {
    match kind {
        "group" => &["children"],
        "csg" => &["operation", "left", "right"],
        "obj" => &["file"],
        "cylinder" | "cone" => &["min", "max", "closed"],
        "torus" => &["major-radius", "minor-radius"],
        "ring" => &["inner-radius", "outer-radius"],
        "disc" => &["radius"],
        _ => &[],
    }
}

/// What `add: camera` gives: the camera and how to sample its pixels.
pub struct CameraItem {
    /// The camera.
    pub camera: Camera,
    /// Samples per pixel (`samples`, default 1).
    pub samples: u32,
    /// A zoom camera's `anti-alias` grid size.
    pub anti_alias: Option<u32>,
}

/// The camera from `add: camera`: the book's (`field-of-view`, `from`, `to`, `up`), Computer
/// Graphics from Scratch's (`viewport`) or Fundamentals of Ray Tracing's (`zoom`).
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<CameraItem, SceneError> {
    if entries.iter().any(|e| e.name == "zoom") {
        return crate::zoom_camera::camera(source, entries, item);
    }
    let (camera, samples) = if entries.iter().any(|e| e.name == "viewport") {
        let camera = crate::viewport::camera(source, entries, item)?;
        finish_camera(source, entries, camera)?
    } else {
        pinhole_camera(source, entries, item)?
    };
    Ok(CameraItem {
        camera,
        samples,
        anti_alias: None,
    })
}

/// The Ray Tracer Challenge's camera.
fn pinhole_camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<(Camera, u32), SceneError> {
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
            "samples",
            "aperture",
            "focal-distance",
            "shutter",
        ],
    )?;
    let get = |k: &str| required(source, entries, item, k, "the camera");
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
    let mut camera = Camera::new(width, height, fov).with_transform_of(view);
    if let Some(aperture_entry) = entries.iter().find(|e| e.name == "aperture") {
        let aperture = source.number(aperture_entry.value, "aperture")?;
        if aperture < 0.0 {
            return Err(source.error(
                aperture_entry.value,
                "aperture",
                "the aperture cannot be negative",
            ));
        }
        let focal_node = get("focal-distance")?;
        let focal = source.number(focal_node, "focal-distance")?;
        if focal <= 0.0 {
            return Err(source.error(
                focal_node,
                "focal-distance",
                "the focal distance must be positive",
            ));
        }
        camera = camera.with_lens(aperture, focal);
    }
    finish_camera(source, entries, camera)
}

/// What every camera accepts: `samples` per pixel and the `shutter` interval.
pub fn finish_camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    mut camera: Camera,
) -> Result<(Camera, u32), SceneError> {
    let samples = match entries.iter().find(|e| e.name == "samples") {
        Some(e) => {
            let n = source.integer(e.value, "samples", 1)?;
            if n > MAX_SAMPLES_PER_PIXEL {
                return Err(source.error(
                    e.value,
                    "samples",
                    format!("{n} samples per pixel is more than the limit {MAX_SAMPLES_PER_PIXEL}"),
                ));
            }
            n as u32
        }
        None => 1,
    };
    if let Some(shutter) = entries.iter().find(|e| e.name == "shutter") {
        let times = source.sequence(shutter.value, "shutter")?;
        let [open, close] = times else {
            return Err(source.error(
                shutter.value,
                "shutter",
                format!(
                    "expected [open, close], two instants, found {} items",
                    times.len()
                ),
            ));
        };
        let (open, close) = (
            source.number(open, "shutter")?,
            source.number(close, "shutter")?,
        );
        if close < open {
            return Err(source.error(
                shutter.value,
                "shutter",
                "the shutter closes before it opens",
            ));
        }
        camera = camera.with_shutter(open, close);
    }
    Ok((camera, samples))
}

/// A light from `add: light`: a point light (`at`), or an area light (`corner`, `uvec`,
/// `usteps`, `vvec`, `vsteps`, optionally `jitter`), as the soft-shadows bonus chapter writes it,
/// a spotlight (`angle`), or with `type:` Computer Graphics from Scratch's `ambient` and
/// `directional` lights.
pub fn light(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    if let Some(kind) = entries.iter().find(|e| e.name == "type") {
        match source.string(kind.value, "type")? {
            "point" => {}
            "ambient" | "directional" => return crate::lights::cgfs_light(source, entries, item),
            other => {
                return Err(source.error(
                    kind.value,
                    "type",
                    format!(
                        "unknown light type `{other}`; expected point, ambient or directional \
                         (area lights and spotlights are told by `corner` and `angle`)"
                    ),
                ))
            }
        }
    }
    let area = entries.iter().any(|e| e.name == "corner");
    let spot = entries.iter().any(|e| e.name == "angle");
    let (what, allowed): (&str, &[&str]) = if area {
        (
            "an area light",
            &[
                "add",
                "intensity",
                "corner",
                "uvec",
                "usteps",
                "vvec",
                "vsteps",
                "jitter",
            ],
        )
    } else if spot {
        (
            "a spotlight",
            &["add", "at", "intensity", "direction", "angle", "fade"],
        )
    } else {
        ("a point light", &["add", "type", "at", "intensity"])
    };
    check_keys(source, entries, what, allowed)?;
    let get = |k: &str| required(source, entries, item, k, what);
    let intensity = crate::lights::intensity(source, get("intensity")?)?;
    if spot {
        let [x, y, z] = source.triple(get("at")?, "at")?;
        let direction_node = get("direction")?;
        let [dx, dy, dz] = source.triple(direction_node, "direction")?;
        let angle_node = get("angle")?;
        let angle = source.number(angle_node, "angle")?;
        if !(angle > 0.0 && angle < std::f64::consts::PI) {
            return Err(source.error(
                angle_node,
                "angle",
                format!("the cone's half-angle is in radians, between 0 and π; found {angle}"),
            ));
        }
        let fade = match entries.iter().find(|e| e.name == "fade") {
            Some(e) => source.number(e.value, "fade")?,
            None => 0.0,
        };
        let light = SpotLight::new(point(x, y, z), vector(dx, dy, dz), angle, fade, intensity)
            .ok_or_else(|| source.error(direction_node, "direction", "the direction is zero"))?;
        return Ok(Light::Spot(light));
    }
    if !area {
        let [x, y, z] = source.triple(get("at")?, "at")?;
        return Ok(Light::point(point(x, y, z), intensity));
    }
    let [cx, cy, cz] = source.triple(get("corner")?, "corner")?;
    let [ux, uy, uz] = source.triple(get("uvec")?, "uvec")?;
    let [vx, vy, vz] = source.triple(get("vvec")?, "vvec")?;
    let usteps = source.integer(get("usteps")?, "usteps", 1)?;
    let vsteps = source.integer(get("vsteps")?, "vsteps", 1)?;
    if usteps * vsteps > MAX_LIGHT_SAMPLES {
        return Err(source.error(
            get("usteps")?,
            "usteps",
            format!("{usteps}×{vsteps} samples is more than the limit {MAX_LIGHT_SAMPLES}"),
        ));
    }
    let mut light = AreaLight::new(
        point(cx, cy, cz),
        vector(ux, uy, uz),
        usteps as u32,
        vector(vx, vy, vz),
        vsteps as u32,
        intensity,
    );
    if let Some(j) = entries.iter().find(|e| e.name == "jitter") {
        light.jitter = source.boolean(j.value, "jitter")?;
    }
    Ok(Light::Area(light))
}

/// The most camera rays per pixel a scene may ask for.
const MAX_SAMPLES_PER_PIXEL: u64 = 4096;

/// The most samples one area light may take: each is a shadow ray per shading point.
const MAX_LIGHT_SAMPLES: u64 = 4096;

/// An `add:` item with any object templates expanded.
pub struct Expanded<'n, 's> {
    /// Its keys: the templates' merged with the item's own (`add:` names a shape kind).
    pub entries: Vec<Entry<'n, 's>>,
    /// Its transform lists in the order they apply: the innermost template's first, the
    /// item's own last.
    pub transforms: Vec<&'n Node<'s>>,
}

/// Expands an `add:` item whose kind names a template: `add: NAME` where NAME is a define
/// whose value is itself an object. The item's keys override the template's, except
/// `transform`, which composes (the template's placement first, then the item's).
///
/// The names of the templates expanded are left on `trail`: the caller truncates it once the
/// object is built, so that a template's children (or CSG operands) that instantiate the
/// template again are reported as a cycle rather than recursing forever.
pub fn expand_template<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    entries: Vec<Entry<'n, 's>>,
    kind: &'n Node<'s>,
    trail: &mut Trail<'n>,
) -> Result<Expanded<'n, 's>, SceneError> {
    let name = source.string(kind, "add")?;
    let item_kind = ["camera", "light", "canvas-line", "canvas-triangle"].contains(&name);
    if SHAPE_KINDS.contains(&name) || item_kind || !is_reference(kind) {
        let transforms = entries
            .iter()
            .filter(|e| e.name == "transform")
            .map(|e| e.value)
            .collect();
        return Ok(Expanded {
            entries,
            transforms,
        });
    }
    if !defines.contains(name) {
        return Err(unknown_kind(source, kind, name));
    }
    let template = defines.mapping_entries(source, kind, "add", trail)?;
    // Stays on the trail while the object is built (see above).
    trail.push(name);
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
    let mut expanded = expand_template(
        source,
        defines,
        template_without_transform,
        inner_kind,
        trail,
    )?;
    if let Some(t) = template.iter().find(|e| e.name == "transform") {
        expanded.transforms.push(t.value);
    }
    for e in entries {
        if e.name == "add" {
            continue;
        }
        if e.name == "transform" {
            expanded.transforms.push(e.value);
        } else {
            merge(&mut expanded.entries, e);
        }
    }
    Ok(expanded)
}

/// What a shape inherits from the groups around it.
#[derive(Debug, Clone)]
pub struct Inherited {
    /// `world_from_parent`: every enclosing group's transform, composed.
    pub matrix: DMat4,
    /// The animation frame being built (0 for a still): `per-frame` steps apply this often.
    pub frame: u64,
    /// `world_from_parent` when the shutter closes (equal to `matrix` unless a group moves).
    pub end_matrix: DMat4,
    /// The nearest enclosing group's material, for children that set none.
    pub material: Option<Material>,
    /// False when an enclosing group has `shadow: false`.
    pub casts_shadow: bool,
    /// How many groups enclose this item.
    pub depth: usize,
}

impl Inherited {
    /// What a top-level item inherits: nothing.
    pub const TOP: Self = Self {
        matrix: DMat4::IDENTITY,
        frame: 0,
        end_matrix: DMat4::IDENTITY,
        material: None,
        casts_shadow: true,
        depth: 0,
    };
}

/// Groups (and CSGs) may nest this deep, inline or through defined objects; deeper nesting is
/// certainly a generated or hostile file, and refusing it keeps the reader's recursion bounded
/// (an unoptimised build takes about 50 KiB of stack a level).
const MAX_GROUP_DEPTH: usize = 100;

/// Builds the objects of one (expanded) `add:` item, a shape or a group, into `out`, with
/// every enclosing group's transform baked in (the parent first: `parent * child`). `trail`
/// holds the object templates being built (see [`expand_template`]).
pub fn add_objects<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    item: &Expanded<'n, 's>,
    inherited: &Inherited,
    trail: &mut Trail<'n>,
    out: &mut Vec<rayforge::Object>,
) -> Result<(), SceneError> {
    let Expanded {
        entries,
        transforms,
    } = item;
    let kind_node = entries
        .iter()
        .find(|e| e.name == "add")
        .expect("every item has `add`")
        .value;
    let kind = source.string(kind_node, "add")?;
    let keys: Vec<&str> = SHAPE_KEYS.iter().chain(own_keys(kind)).copied().collect();
    let shape = match kind {
        "group" | "obj" | "csg" => None,
        _ => Some(shape(source, entries, kind_node, kind)?),
    };
    check_keys(source, entries, &format!("a {kind}"), &keys)?;
    let mut own = DMat4::IDENTITY;
    for t in transforms.iter().copied() {
        own = transform_list(source, defines, t, &mut Trail::new())? * own;
    }
    let placed_at = transforms.last().copied().unwrap_or(kind_node);
    checked(source, placed_at, own)?;
    let own = per_frame(source, defines, entries, own, inherited.frame)?;
    let world = checked(source, placed_at, inherited.matrix * own)?;
    let own_end = motion_end(source, defines, entries, own)?;
    let world_end = match own_end {
        Some((node, end)) => checked(source, node, inherited.end_matrix * end)?,
        None => checked(source, placed_at, inherited.end_matrix * own)?,
    };
    let mut material_here = None;
    let mut casts_shadow = inherited.casts_shadow;
    for e in entries {
        match e.name {
            "material" => {
                material_here = Some(material(
                    source,
                    defines,
                    assets,
                    e.value,
                    &Material::DEFAULT,
                )?)
            }
            "shadow" => casts_shadow &= source.boolean(e.value, "shadow")?,
            _ => {}
        }
    }
    let material_explicit = material_here.is_some();
    let material = material_here.or_else(|| inherited.material.clone());
    if kind == "csg" {
        let operation_node = required(source, entries, kind_node, "operation", "a csg")?;
        let operation = match source.string(operation_node, "operation")? {
            "union" => CsgOperation::Union,
            // SEED-NOTES.md erratum 7: the book's tests say "intersection", one listing says
            // "intersect"; both mean the same.
            "intersection" | "intersect" => CsgOperation::Intersection,
            "difference" => CsgOperation::Difference,
            "complement" => CsgOperation::Complement,
            other => {
                return Err(source.error(
                    operation_node,
                    "operation",
                    format!(
                    "unknown operation `{other}`; expected one of: union, intersection, difference, complement"
                ),
                ))
            }
        };
        let inside = Inherited {
            matrix: DMat4::IDENTITY,
            frame: inherited.frame,
            end_matrix: DMat4::IDENTITY,
            material,
            casts_shadow,
            depth: inherited.depth + 1,
        };
        if inside.depth >= MAX_GROUP_DEPTH {
            return Err(source.error(
                kind_node,
                "add",
                format!("groups and CSG nest deeper than {MAX_GROUP_DEPTH} levels"),
            ));
        }
        let mut build_operand = |key: &str| -> Result<Group, SceneError> {
            let node = required(source, entries, kind_node, key, "a csg")?;
            let mark = trail.len();
            let item = operand(source, defines, node, key, trail)?;
            let mut objects = Vec::new();
            add_objects(source, defines, assets, &item, &inside, trail, &mut objects)?;
            trail.truncate(mark);
            let mut group = Group::new();
            for o in objects {
                group.add_child(o);
            }
            Ok(group)
        };
        let left = build_operand("left")?;
        let solid = if operation == CsgOperation::Complement {
            if let Some(right) = entries.iter().find(|e| e.name == "right") {
                return Err(source.error(
                    right.key,
                    "right",
                    "a complement has one operand, `left`: everything outside it",
                ));
            }
            Object::complement(left)
        } else {
            let right = build_operand("right")?;
            Object::csg(operation, left, right)
        };
        let csg = solid
            .and_then(|c| c.placed_by_moving(&world, &world_end))
            .map_err(|e| source.error(placed_at, "transform", e.to_string()))?;
        let mut csg = csg;
        csg.casts_shadow = casts_shadow;
        source.spend(kind_node, "add")?;
        out.push(csg);
        return Ok(());
    }
    if kind == "obj" {
        let file = entries
            .iter()
            .find(|e| e.name == "file")
            .map(|e| e.value)
            .ok_or_else(|| source.error(kind_node, "file", "an obj needs `file:`"))?;
        let path = assets.resolve(source.string(file, "file")?);
        let meshes = assets.obj(&path).map_err(|e| {
            if e.path == path && e.span.is_none() {
                // The file itself could not be read: point at the `file:` that names it.
                source.error(file, "file", e.message)
            } else {
                e
            }
        })?;
        for (mesh, own_material) in meshes.iter() {
            let mut object = moving(Object::mesh(mesh.clone()), &world, &world_end);
            // An explicit `material:` wins; then the file's own; then the group's.
            object.material = match (material_explicit, own_material) {
                (false, Some(m)) => m.clone(),
                _ => material.clone().unwrap_or_default(),
            };
            object.casts_shadow = casts_shadow;
            source.spend(kind_node, "add")?;
            out.push(object);
        }
        return Ok(());
    }
    let Some(shape) = shape else {
        let children_node = entries
            .iter()
            .find(|e| e.name == "children")
            .map(|e| e.value)
            .ok_or_else(|| source.error(kind_node, "children", "a group needs `children:`"))?;
        if inherited.depth >= MAX_GROUP_DEPTH {
            return Err(source.error(
                kind_node,
                "add",
                format!("groups nest deeper than {MAX_GROUP_DEPTH} levels"),
            ));
        }
        let inside = Inherited {
            matrix: world.matrix(),
            frame: inherited.frame,
            end_matrix: world_end.matrix(),
            material,
            casts_shadow,
            depth: inherited.depth + 1,
        };
        for child in source.sequence(children_node, "children")? {
            let child_entries = source.entries(child, "children")?;
            let child_kind = child_entries
                .iter()
                .find(|e| e.name == "add")
                .map(|e| e.value)
                .ok_or_else(|| source.error(child, "children", "each child needs `add:`"))?;
            let mark = trail.len();
            let child = expand_template(source, defines, child_entries, child_kind, trail)?;
            add_objects(source, defines, assets, &child, &inside, trail, out)?;
            trail.truncate(mark);
        }
        return Ok(());
    };
    let mut object = moving(Object::new(shape), &world, &world_end);
    object.material = material.unwrap_or_default();
    object.casts_shadow = casts_shadow;
    source.spend(kind_node, "add")?;
    out.push(object);
    Ok(())
}

/// The item's own transform at animation frame `frame`: `per-frame` (a transform list) applied
/// `frame` times after it, about the point where the item's own origin lands (its centre, for
/// the book's solids), as Fundamentals of Ray Tracing's `blockmovie` turns its block a little
/// before each picture.
fn per_frame<'n>(
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

/// An object (with the identity transform) placed at `start` when the shutter opens and `end`
/// when it closes.
fn moving(object: Object, start: &Transform, end: &Transform) -> Object {
    // A primitive or mesh with the identity transform: placing it multiplies by the identity,
    // which cannot make an invertible transform singular.
    object
        .placed_by_moving(start, end)
        .unwrap_or_else(|_| object.with_transform_of(*start))
}

/// The item's own transform when the shutter closes, if it moves: `motion:` gives it as a
/// transform list (like `transform:`), `velocity: [x, y, z]` as the distance travelled while
/// the shutter is open (added after the item's own transform). Returns the key's node, for
/// errors.
fn motion_end<'n>(
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

/// A CSG operand (`left:` or `right:`): a shape, group, CSG or defined object, written with
/// `add:` or, as the community's files do, `type:`; or the name of a defined object. Names
/// expanded are left on `trail`, as [`expand_template`] leaves them.
fn operand<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    node: &'n Node<'s>,
    key: &str,
    trail: &mut Trail<'n>,
) -> Result<Expanded<'n, 's>, SceneError> {
    let mut entries = if let Some(name) = as_str(node) {
        let entries = defines.mapping_entries(source, node, key, trail)?;
        // On the trail while the operand is built, as for templates.
        trail.push(name);
        entries
    } else {
        source.entries(node, key)?
    };
    if !entries.iter().any(|e| e.name == "add") {
        if let Some(e) = entries.iter_mut().find(|e| e.name == "type") {
            e.name = "add";
        }
    }
    let kind = entries
        .iter()
        .find(|e| e.name == "add")
        .map(|e| e.value)
        .ok_or_else(|| source.error(node, key, "an operand needs `add:` or `type:`"))?;
    expand_template(source, defines, entries, kind, trail)
}

/// The shape an `add:` names, with its shape-specific keys.
fn shape(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    kind_node: &Node<'_>,
    kind: &str,
) -> Result<Shape, SceneError> {
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
    match kind {
        "sphere" => Ok(Shape::Sphere),
        "plane" => Ok(Shape::Plane),
        "cube" => Ok(Shape::Cube),
        "cylinder" => quadric(|minimum, maximum, closed| Shape::Cylinder {
            minimum,
            maximum,
            closed,
        }),
        "cone" => quadric(|minimum, maximum, closed| Shape::Cone {
            minimum,
            maximum,
            closed,
        }),
        "torus" => torus(source, entries),
        "ring" | "disc" => ring(source, entries, kind),
        // Fundamentals of Ray Tracing's polyhedra, with its size parameter 1 (scale to taste).
        "icosahedron" => Ok(Shape::Mesh(std::sync::Arc::new(
            rayforge::geometry::icosahedron(),
        ))),
        "dodecahedron" => Ok(Shape::Mesh(std::sync::Arc::new(
            rayforge::geometry::dodecahedron(),
        ))),
        "camera" | "light" | "canvas-line" | "canvas-triangle" => Err(source.error(
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
        let node = entries
            .iter()
            .find(|e| e.name == "inner-radius")
            .map_or(entries[0].value, |e| e.value);
        return Err(source.error(
            node,
            "inner-radius",
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

/// The error for an `add:` that names neither a shape nor a defined object.
fn unknown_kind(source: &Source<'_>, node: &Node<'_>, name: &str) -> SceneError {
    source.error(
        node,
        "add",
        format!(
            "unknown kind `{name}`; expected one of: camera, light, canvas-line, canvas-triangle, {} or the name of a defined object",
            SHAPE_KINDS.join(", ")
        ),
    )
}
