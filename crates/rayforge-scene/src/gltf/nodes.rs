//! The node hierarchy of a glTF scene: each node's world matrix (parents first), its mesh's
//! primitives as objects sharing their meshes, its camera and its light.

use super::materials::default_material;
use super::materials::Materials;
use super::meshes::Meshes;
use super::paths::error;
use crate::error::SceneError;
use glam::{DMat4, DVec3};
use rayforge::{Color, Object, Transform};
use std::path::Path;

/// The most nodes a model's hierarchy may visit (a file whose nodes are shared between
/// parents, against the specification, could otherwise multiply its instances exponentially).
pub const MAX_NODE_VISITS: usize = 1_000_000;

/// How far a node's rotation quaternion may be from unit length (exporters round them).
const ROTATION_TOLERANCE: f64 = 1e-2;

/// The deepest a model's node hierarchy may nest.
pub const MAX_NODE_DEPTH: usize = 256;

/// A camera of the model, placed by its node (in glTF's space).
#[derive(Debug, Clone, PartialEq)]
pub struct GltfCamera {
    /// Its name, or `camera N` after its index in the file's cameras.
    pub name: String,
    /// How it projects.
    pub projection: Projection,
    /// World from camera (the camera looks down its −Z, +Y up), scale removed.
    pub world: DMat4,
}

/// A glTF camera's projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Perspective: vertical field of view (radians) and the aspect ratio, if the file gives one.
    Perspective {
        /// `yfov`.
        yfov: f64,
        /// `aspectRatio` (width over height).
        aspect: Option<f64>,
    },
    /// Orthographic: half the view's width and height in world units.
    Orthographic {
        /// `xmag`.
        xmag: f64,
        /// `ymag`.
        ymag: f64,
    },
}

/// A light of the model (`KHR_lights_punctual`), placed by its node (in glTF's space).
#[derive(Debug, Clone, PartialEq)]
pub struct GltfLight {
    /// Linear colour times intensity (candela for point and spot lights, lux for directional).
    pub intensity: Color,
    /// Where it is.
    pub position: DVec3,
    /// Where it shines (the node's −Z).
    pub direction: DVec3,
    /// Its kind, with a spot's cone half-angles (radians).
    pub kind: LightKind,
}

/// The kind of a punctual light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// Light in every direction from a point.
    Point,
    /// A cone: full inside `inner`, none outside `outer`.
    Spot {
        /// `innerConeAngle`.
        inner: f64,
        /// `outerConeAngle`.
        outer: f64,
    },
    /// Parallel light.
    Directional,
}

/// What the walk found.
pub(crate) struct Walk {
    pub objects: Vec<Object>,
    pub cameras: Vec<GltfCamera>,
    pub lights: Vec<GltfLight>,
}

/// Walks the file's scene (`scene`, else the first; with none, every node without a parent).
pub(crate) fn walk(
    path: &Path,
    gltf: &::gltf::Gltf,
    meshes: &mut Meshes<'_>,
    materials: &mut Materials<'_>,
) -> Result<Walk, SceneError> {
    let roots: Vec<::gltf::Node<'_>> = match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; gltf.nodes().len()];
            for node in gltf.nodes() {
                for child in node.children() {
                    is_child[child.index()] = true;
                }
            }
            gltf.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    // The hierarchy's size is checked before anything is built: a million nodes of one
    // triangle each are a million objects (about 1.7 GB), which a refusal at the
    // millionth-and-first would have built first.
    check_hierarchy(path, &roots)?;
    let mut out = Walk {
        objects: Vec::new(),
        cameras: Vec::new(),
        lights: Vec::new(),
    };
    let mut stack: Vec<(::gltf::Node<'_>, DMat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        let at = format!("nodes[{}]", node.index());
        meshes.stopped_at(&at)?;
        if let ::gltf::scene::Transform::Decomposed { rotation, .. } = node.transform() {
            let length = rotation
                .iter()
                .map(|&q| f64::from(q).powi(2))
                .sum::<f64>()
                .sqrt();
            // glTF asks for a unit quaternion; a zero one (or far from unit) scales what the
            // node holds to nothing or skews its camera, which would render without a word.
            let unit = (length - 1.0).abs() < ROTATION_TOLERANCE;
            if !unit {
                return Err(error(
                    path,
                    format!("{at}.rotation"),
                    format!("the rotation {rotation:?} is not a unit quaternion (its length is {length})"),
                ));
            }
        }
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        if !world.is_finite() {
            return Err(error(path, at, "the node's transform is not finite"));
        }
        if let Some(mesh) = node.mesh() {
            add_mesh(&mesh, world, meshes, materials, &mut out.objects)?;
        }
        if let Some(camera) = node.camera() {
            out.cameras.push(camera_of(path, &camera, world)?);
        }
        if let Some(light) = node.light() {
            out.lights.push(light_of(&light, world));
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
    }
    Ok(out)
}

/// Walks the hierarchy from `roots` in the order [`walk`] does, building nothing: refuses it
/// at the node where the walk would pass [`MAX_NODE_VISITS`] or [`MAX_NODE_DEPTH`].
fn check_hierarchy(path: &Path, roots: &[::gltf::Node<'_>]) -> Result<(), SceneError> {
    let mut stack: Vec<(::gltf::Node<'_>, usize)> =
        roots.iter().rev().map(|n| (n.clone(), 0)).collect();
    let mut visits = 0;
    while let Some((node, depth)) = stack.pop() {
        visits += 1;
        let at = || format!("nodes[{}]", node.index());
        if visits > MAX_NODE_VISITS {
            return Err(error(path, at(), format!("the node hierarchy visits more than {MAX_NODE_VISITS} nodes (are nodes shared between parents?)")));
        }
        if depth >= MAX_NODE_DEPTH {
            return Err(error(path, at(), format!("the node hierarchy nests deeper than {MAX_NODE_DEPTH} levels (does a node contain itself?)")));
        }
        let children = stack.len();
        stack.extend(node.children().map(|child| (child, depth + 1)));
        stack[children..].reverse();
    }
    Ok(())
}

/// Refuses a file with more nodes than [`MAX_NODE_VISITS`] before its JSON is parsed: the
/// `gltf` crate's document holds some 300 bytes a node, so a million-node file of 11 MB
/// would take 300 MB to be refused. Counts the elements of the top-level `nodes` array of the
/// JSON (a `.gltf` file, or a `.glb`'s JSON chunk) in one pass over its bytes, holding
/// nothing; JSON that does not scan is left to the parser, which says where it goes wrong.
pub(crate) fn check_node_count(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    let json = match bytes.get(..20) {
        Some(header) if header.starts_with(b"glTF") && &header[16..20] == b"JSON" => {
            let length = u32::from_le_bytes([header[12], header[13], header[14], header[15]]);
            let end = 20usize.saturating_add(length as usize).min(bytes.len());
            &bytes[20..end]
        }
        _ => bytes,
    };
    if json_array_longer_than(json, b"nodes", MAX_NODE_VISITS) {
        return Err(error(
            path,
            "nodes",
            format!(
                "the file has more than {MAX_NODE_VISITS} nodes, the most a model's hierarchy \
                 may visit"
            ),
        ));
    }
    Ok(())
}

/// Whether the array under `key` in the top-level object of `json` has more than `most`
/// elements (the scan stops there).
fn json_array_longer_than(json: &[u8], key: &[u8], most: usize) -> bool {
    let (mut depth, mut in_string, mut escaped) = (0usize, false, false);
    // Where the last string at the top level began (a key), and whether the array being
    // walked is the one under `key`, with its elements so far and whether one has begun.
    let mut string_start = 0;
    let mut last_top_string: &[u8] = &[];
    let (mut counting, mut elements, mut in_element) = (false, 0usize, false);
    for (i, &b) in json.iter().enumerate() {
        if in_string {
            if escaped {
                escaped = false;
            } else if b == b'\\' {
                escaped = true;
            } else if b == b'"' {
                in_string = false;
                if depth == 1 {
                    last_top_string = &json[string_start..i];
                }
            }
            continue;
        }
        if counting && depth == 2 && !in_element && !b.is_ascii_whitespace() && b != b']' {
            in_element = true;
            elements += 1;
            if elements > most {
                return true;
            }
        }
        match b {
            b'"' => {
                in_string = true;
                string_start = i + 1;
            }
            b'{' | b'[' => {
                if b == b'[' && depth == 1 && last_top_string == key {
                    counting = true;
                }
                depth += 1;
            }
            b'}' | b']' => {
                depth = depth.saturating_sub(1);
                if depth == 1 && counting {
                    return false;
                }
            }
            b',' if counting && depth == 2 => in_element = false,
            _ => {}
        }
    }
    false
}

/// The primitives of a node's mesh as objects placed by `world` (left out when `world` is
/// singular: a node scaled to nothing is hidden).
fn add_mesh(
    mesh: &::gltf::Mesh<'_>,
    world: DMat4,
    meshes: &mut Meshes<'_>,
    materials: &mut Materials<'_>,
    out: &mut Vec<Object>,
) -> Result<(), SceneError> {
    let Ok(transform) = Transform::try_new(world) else {
        return Ok(());
    };
    for primitive in mesh.primitives() {
        let material = primitive.material();
        let built = match material.index() {
            Some(_) => materials.get(&material)?,
            None => super::materials::Built {
                material: default_material(),
                normal_mapped: false,
                uv_set: 0,
            },
        };
        let Some(shape) = meshes.primitive(mesh, &primitive, built.normal_mapped, built.uv_set)?
        else {
            continue;
        };
        let mut object = Object::mesh(shape);
        object.transform = transform;
        object.material = built.material;
        out.push(object);
    }
    Ok(())
}

/// A node's camera: the projection and the node's placement without scale. A projection the
/// specification does not allow (a field of view outside (0, π), a magnification or aspect
/// ratio that is not above 0) or a placement that has no orientation (a node scaled to
/// nothing) is refused, naming the key: it would render a wrong image without a word.
fn camera_of(
    path: &Path,
    camera: &::gltf::Camera<'_>,
    world: DMat4,
) -> Result<GltfCamera, SceneError> {
    let at = format!("cameras[{}]", camera.index());
    let positive = |key: &str, value: f32| {
        if value > 0.0 && value.is_finite() {
            Ok(f64::from(value))
        } else {
            Err(error(
                path,
                format!("{at}.{key}"),
                format!("it is {value}; it must be above 0"),
            ))
        }
    };
    let projection = match camera.projection() {
        ::gltf::camera::Projection::Perspective(p) => {
            let yfov = positive("perspective.yfov", p.yfov())?;
            if yfov >= std::f64::consts::PI {
                return Err(error(
                    path,
                    format!("{at}.perspective.yfov"),
                    format!("it is {yfov} radians; a field of view must be below π"),
                ));
            }
            let aspect = match p.aspect_ratio() {
                Some(a) => Some(positive("perspective.aspectRatio", a)?),
                None => None,
            };
            Projection::Perspective { yfov, aspect }
        }
        ::gltf::camera::Projection::Orthographic(o) => Projection::Orthographic {
            xmag: positive("orthographic.xmag", o.xmag())?,
            ymag: positive("orthographic.ymag", o.ymag())?,
        },
    };
    let (_, rotation, translation) = world.to_scale_rotation_translation();
    let rotation = rotation.normalize();
    if !rotation.is_finite() || world.determinant().abs() < f64::MIN_POSITIVE {
        return Err(error(
            path,
            at,
            "the camera's node places it with no orientation (its transform is singular)",
        ));
    }
    Ok(GltfCamera {
        name: camera
            .name()
            .map_or_else(|| format!("camera {}", camera.index()), str::to_string),
        projection,
        world: DMat4::from_rotation_translation(rotation, translation),
    })
}

/// A node's light.
fn light_of(light: &::gltf::khr_lights_punctual::Light<'_>, world: DMat4) -> GltfLight {
    use ::gltf::khr_lights_punctual::Kind;
    let [r, g, b] = light.color();
    let kind = match light.kind() {
        Kind::Point => LightKind::Point,
        Kind::Directional => LightKind::Directional,
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => LightKind::Spot {
            inner: inner_cone_angle.into(),
            outer: outer_cone_angle.into(),
        },
    };
    GltfLight {
        intensity: Color::new(r.into(), g.into(), b.into()) * f64::from(light.intensity()),
        position: world.transform_point3(DVec3::ZERO),
        direction: world.transform_vector3(-DVec3::Z).normalize_or_zero(),
        kind,
    }
}

#[cfg(test)]
mod tests {
    use super::json_array_longer_than;

    #[test]
    fn the_top_level_array_is_counted_and_nothing_else() {
        let json = br#"{"scenes": [{"nodes": [0, 1, 2, 3]}], "nodes": [{"name": "a,]\"b"}, {"children": [2, 3]}, {}], "x": [1, 2, 3, 4, 5]}"#;
        assert!(json_array_longer_than(json, b"nodes", 2));
        assert!(!json_array_longer_than(json, b"nodes", 3));
        assert!(!json_array_longer_than(br#"{"nodes": []}"#, b"nodes", 0));
        assert!(json_array_longer_than(br#"{"nodes": [ {} ]}"#, b"nodes", 0));
        // Damaged JSON is left to the parser.
        assert!(!json_array_longer_than(b"{\"nodes\": [1, 2", b"nodes", 5));
    }
}
