//! PLY models (the Stanford polygon format, version 1.0), as `add: ply` and pbrt-v4's
//! `Shape "plymesh"` read them: text and binary bodies in either byte order, gzip-compressed
//! or not (`.ply.gz`, told by the gzip magic, not the name).
//!
//! What is read: the `vertex` element's `x`, `y`, `z`; its normals `nx`, `ny`, `nz` (used when
//! all three are there: smooth shading); its texture coordinates from the first complete pair
//! of `u v`, `s t`, `texture_u texture_v`, `texture_s texture_t` (pbrt-v4's names, in its
//! order); the `face` element's `vertex_indices` (or `vertex_index`) list, with a count of any
//! whole-number type and indices of any whole-number type. Every other element and property
//! (colours, `face_indices`, confidence values, lists included) is read past by its declared
//! type. Triangles are kept; a quad `a b c d` becomes `(a b c)` and `(a c d)`, the two
//! triangles pbrt-v4 cuts a quad into when it needs triangles (it renders a quad that is not
//! flat as a bilinear patch, which these two triangles only approach); a polygon of more
//! corners is cut into a fan from its first corner, as OBJ faces are (pbrt-v4 skips such a
//! face with a warning). A face's front is the side from which its corners turn
//! counter-clockwise in the file's right-handed axes ([`Winding::RightHanded`], as OBJ's),
//! which is the side of pbrt-v4's geometric normal `(p1 − p0) × (p2 − p0)`.
//!
//! The file is input from outside and read as such: a regular file only
//! ([`crate::files::open_regular`]), at most [`MAX_MODEL_BYTES`] (and as much once inflated),
//! and the header's counts checked against the mesh size limit and against the bytes the body
//! has before anything is allocated for them, so that a header claiming 2^40 vertices is an
//! error, not an allocation. Coordinates, normals and texture coordinates must be finite;
//! every index must name a vertex. Errors name the file, the element (counting from 0) and
//! property, and the place: the line and column of a header or a text body, the byte offset
//! of a binary body.
//!
//! Our own reader, not a crate's: `ply-rs` has had no release since 2020, and its maintained
//! fork `ply-rs-bw` (like `ply-rs`) reads every element into a map of named properties (some
//! hundred bytes a vertex, where a mesh needs 24), sizes nothing against the file before
//! allocating, and reports errors without the element or the byte they are at. The format is
//! small enough (a header of four kinds of line, eight scalar types) that reading it here costs
//! less than working round those.

mod body;
mod header;

use crate::error::SceneError;
use crate::obj::MAX_MODEL_BYTES;
use crate::stop::StopFlag;
use body::{At, Body};
use header::{Element, Header, Kind, Scalar};
use rayforge::geometry::{Mesh, MeshError, MeshFace, Winding};
use rayforge::{Point3, Vec3};
use std::io::Read;
use std::path::Path;

pub use header::MAX_HEADER_BYTES;

/// Reads the PLY model at `path` (gzip-compressed or not) into one mesh of at most
/// `max_triangles` triangles (and three times as many vertices), its faces fronting as
/// OBJ's do ([`Winding::RightHanded`]). Whether the file may be read at all (inside a scene's
/// folder) is the caller's to check first; the file must be a regular one, of at most
/// [`MAX_MODEL_BYTES`].
pub fn read_ply_file(path: &Path, max_triangles: usize) -> Result<Mesh, SceneError> {
    read_ply_in(path, max_triangles, &StopFlag::default())
}

/// [`read_ply_file`] that stops at the first element after `stop` is set.
pub(crate) fn read_ply_in(
    path: &Path,
    max_triangles: usize,
    stop: &StopFlag,
) -> Result<Mesh, SceneError> {
    let bytes = crate::files::read_bounded(path, MAX_MODEL_BYTES)
        .map_err(|e| SceneError::new(path, format!("cannot read `{}`: {e}", path.display())))?;
    parse_ply_in(&bytes, path, max_triangles, stop)
}

/// Reads a PLY model from the bytes of its file (gzip-compressed or not); `path` names the
/// file in errors. See [`read_ply_file`].
pub fn parse_ply(bytes: &[u8], path: &Path, max_triangles: usize) -> Result<Mesh, SceneError> {
    parse_ply_in(bytes, path, max_triangles, &StopFlag::default())
}

/// [`parse_ply`] that stops at the first element after `stop` is set.
pub(crate) fn parse_ply_in(
    bytes: &[u8],
    path: &Path,
    max_triangles: usize,
    stop: &StopFlag,
) -> Result<Mesh, SceneError> {
    if bytes.starts_with(&[0x1f, 0x8b]) {
        let inflated = gunzip(bytes, path, max_triangles, stop)?;
        return parse_plain(&inflated, path, max_triangles, stop);
    }
    parse_plain(bytes, path, max_triangles, stop)
}

/// How much of a compressed model is inflated between two looks at the stop flag.
const INFLATE_STEP: u64 = 1 << 20;

/// Inflates a gzip-compressed model, to at most [`MAX_MODEL_BYTES`]. The header comes first and
/// its counts are checked against the limits before the body is inflated, so that a small
/// file claiming a huge mesh is refused without inflating a gigabyte. The body is inflated a
/// mebibyte at a time (a few milliseconds), the stop flag looked at before each.
fn gunzip(
    bytes: &[u8],
    path: &Path,
    max_triangles: usize,
    stop: &StopFlag,
) -> Result<Vec<u8>, SceneError> {
    let failed = |e: std::io::Error| {
        SceneError::new(
            path,
            format!("`{}` is not a readable gzip file: {e}", path.display()),
        )
    };
    let mut decoder = flate2::read::MultiGzDecoder::new(bytes);
    let mut out = Vec::new();
    (&mut decoder)
        .take(MAX_HEADER_BYTES as u64 + 1)
        .read_to_end(&mut out)
        .map_err(failed)?;
    let header = header::parse(&out, path)?;
    check_counts(&header, path, max_triangles)?;
    let mut room = MAX_MODEL_BYTES + 1 - out.len() as u64;
    while room > 0 {
        stop.check(path)?;
        let read = (&mut decoder)
            .take(room.min(INFLATE_STEP))
            .read_to_end(&mut out)
            .map_err(failed)?;
        if read == 0 {
            break;
        }
        room -= read as u64;
    }
    if out.len() as u64 > MAX_MODEL_BYTES {
        return Err(SceneError::new(
            path,
            format!(
                "`{}` inflates to more than {MAX_MODEL_BYTES} bytes, the model size limit",
                path.display()
            ),
        ));
    }
    Ok(out)
}

/// The header's counts within the mesh size limit: at most `max_triangles` faces (each is at
/// least one triangle) and three times as many vertices, as OBJ models are held to.
fn check_counts(header: &Header, path: &Path, max_triangles: usize) -> Result<(), SceneError> {
    let max_vertices = max_triangles.saturating_mul(3) as u64;
    for (name, max, what) in [
        ("vertex", max_vertices, "three per triangle of "),
        ("face", max_triangles as u64, ""),
    ] {
        if let Some(element) = header.element(name) {
            if element.count > max {
                return Err(SceneError::new(
                    path,
                    format!(
                        "the header declares {} `{name}` elements, more than {max}, {what}the mesh \
                         size limit (`--max-triangles` on the command line)",
                        element.count
                    ),
                )
                .at(element.span)
                .with_key(name));
            }
        }
    }
    Ok(())
}

/// Every element's values fit in the body: the fewest bytes the header's counts need (see
/// [`Element::min_bytes`]) are there, so that no count larger than the file is believed.
fn check_room(header: &Header, body_len: usize, path: &Path) -> Result<(), SceneError> {
    let mut needed: u64 = 0;
    for element in &header.elements {
        let own = element.count.checked_mul(element.min_bytes(header.format));
        needed = match own.and_then(|n| needed.checked_add(n)) {
            Some(n) if n <= body_len as u64 + 1 => n,
            _ => {
                return Err(SceneError::new(
                    path,
                    format!(
                        "the header declares {} `{}` elements, which need at least {} bytes, \
                         but the file has {body_len} after its header: it is cut short, or the \
                         count is wrong",
                        element.count,
                        element.name,
                        own.map_or("more than 2^64".to_string(), |n| n.to_string())
                    ),
                )
                .at(element.span)
                .with_key(element.name.as_str()))
            }
        };
    }
    Ok(())
}

/// What a vertex property is to the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    /// Coordinate `0..3` of the position, normal or texture coordinates.
    Position(usize),
    Normal(usize),
    Texcoord(usize),
    /// Read past.
    Skip,
}

/// The roles of the vertex element's properties: each scalar named `x`, `y`, `z`, the normal's
/// three when all are there, and the first complete pair of texture coordinates.
fn vertex_roles(element: &Element, path: &Path) -> Result<(Vec<Role>, bool, bool), SceneError> {
    let find = |name: &str| element.properties.iter().position(|p| p.name == name);
    let mut roles = vec![Role::Skip; element.properties.len()];
    let mut assign = |names: &[&str], role: fn(usize) -> Role| -> bool {
        let found: Vec<Option<usize>> = names.iter().map(|n| find(n)).collect();
        if found.iter().any(Option::is_none) {
            return false;
        }
        for (k, i) in found.into_iter().flatten().enumerate() {
            roles[i] = role(k);
        }
        true
    };
    if !assign(&["x", "y", "z"], Role::Position) {
        let missing = ["x", "y", "z"]
            .into_iter()
            .find(|n| find(n).is_none())
            .expect("one is missing");
        return Err(SceneError::new(
            path,
            format!("the `vertex` element has no property `{missing}`: a vertex needs x, y and z"),
        )
        .at(element.span)
        .with_key("vertex"));
    }
    let normals = assign(&["nx", "ny", "nz"], Role::Normal);
    let texcoords = [
        ["u", "v"],
        ["s", "t"],
        ["texture_u", "texture_v"],
        ["texture_s", "texture_t"],
    ]
    .iter()
    .any(|pair| assign(pair, Role::Texcoord));
    for (property, role) in element.properties.iter().zip(&roles) {
        if *role != Role::Skip && matches!(property.kind, Kind::List { .. }) {
            return Err(SceneError::new(
                path,
                format!(
                    "the vertex property `{}` is a list; it must be one number",
                    property.name
                ),
            )
            .at(element.span)
            .with_key(format!("vertex.{}", property.name)));
        }
    }
    Ok((roles, normals, texcoords))
}

/// The index of the face element's corner list (`vertex_indices`, or `vertex_index`), whose
/// count and items must be whole numbers.
fn corner_list(element: &Element, path: &Path) -> Result<usize, SceneError> {
    let index = ["vertex_indices", "vertex_index"]
        .iter()
        .find_map(|name| element.properties.iter().position(|p| p.name == *name))
        .ok_or_else(|| {
            SceneError::new(
                path,
                "the `face` element has no `vertex_indices` (or `vertex_index`) list",
            )
            .at(element.span)
            .with_key("face")
        })?;
    let property = &element.properties[index];
    match property.kind {
        Kind::List { item, .. } if item.is_integer() => Ok(index),
        _ => Err(SceneError::new(
            path,
            format!(
                "the face property `{}` must be a list of whole numbers (`property list uchar int {}`)",
                property.name, property.name
            ),
        )
        .at(element.span)
        .with_key(format!("face.{}", property.name))),
    }
}

/// Room for `count` entries in a new list, taken fallibly: the counts were checked against
/// the limits and the file, and memory may still be short.
fn list_for<T>(count: u64, path: &Path, what: &str) -> Result<Vec<T>, SceneError> {
    let mut list = Vec::new();
    list.try_reserve_exact(count as usize)
        .map_err(|_| SceneError::new(path, format!("cannot allocate room for {count} {what}")))?;
    Ok(list)
}

/// Reads an uncompressed PLY file's bytes into a mesh (see [`read_ply_file`]).
fn parse_plain(
    bytes: &[u8],
    path: &Path,
    max_triangles: usize,
    stop: &StopFlag,
) -> Result<Mesh, SceneError> {
    let header = header::parse(bytes, path)?;
    check_counts(&header, path, max_triangles)?;
    check_room(&header, bytes.len() - header.body_start, path)?;
    let Some(face) = header.element("face").filter(|f| f.count > 0) else {
        return Err(SceneError::new(
            path,
            format!(
                "`{}` has no faces (no `face` element, or none of it): a point cloud is not a mesh",
                path.display()
            ),
        ));
    };
    let Some(vertex) = header.element("vertex") else {
        return Err(SceneError::new(
            path,
            format!("`{}` has faces but no `vertex` element", path.display()),
        ));
    };
    let (roles, has_normals, has_texcoords) = vertex_roles(vertex, path)?;
    let corners_at = corner_list(face, path)?;
    let vertex_count = vertex.count;
    let mut positions: Vec<Point3> = list_for(vertex_count, path, "vertices")?;
    let mut normals: Vec<Vec3> = if has_normals {
        list_for(vertex_count, path, "normals")?
    } else {
        Vec::new()
    };
    let mut texcoords: Vec<[f64; 2]> = if has_texcoords {
        list_for(vertex_count, path, "texture coordinates")?
    } else {
        Vec::new()
    };
    let mut triangles: Vec<[u32; 3]> = list_for(face.count, path, "faces")?;
    let mut body = Body::new(
        bytes,
        header.body_start,
        header.lines,
        header.format,
        path,
        stop,
    );
    let mut corners: Vec<u32> = Vec::new();
    for element in &header.elements {
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        if element.properties.is_empty() {
            continue;
        }
        for index in 0..element.count {
            body.begin(&element.name, index, element.count)?;
            let (mut p, mut n, mut t) = ([0.0; 3], [0.0; 3], [0.0; 2]);
            for (k, property) in element.properties.iter().enumerate() {
                let at = At {
                    element: &element.name,
                    index,
                    property: &property.name,
                };
                match property.kind {
                    Kind::Scalar(scalar) => {
                        let value = body.value(scalar, &at)?;
                        let role = if is_vertex { roles[k] } else { Role::Skip };
                        let slot = match role {
                            Role::Position(i) => &mut p[i],
                            Role::Normal(i) => &mut n[i],
                            Role::Texcoord(i) => &mut t[i],
                            Role::Skip => continue,
                        };
                        if !value.is_finite() {
                            return Err(body.error_here(
                                &at,
                                format!("`{}` is {value}, not a finite number", property.name),
                            ));
                        }
                        *slot = value;
                    }
                    Kind::List { count, item } => {
                        let len = list_len(&mut body, count, item, &at)?;
                        let read_corners = is_face && k == corners_at;
                        if read_corners {
                            corners.clear();
                        }
                        for _ in 0..len {
                            let value = body.value(item, &at)?;
                            if read_corners {
                                corners.push(corner(&body, value, vertex_count, &at)?);
                            }
                        }
                    }
                }
            }
            body.end(&element.name, index)?;
            if is_vertex {
                positions.push(Point3::new(p[0], p[1], p[2]));
                if has_normals {
                    normals.push(Vec3::new(n[0], n[1], n[2]));
                }
                if has_texcoords {
                    texcoords.push(t);
                }
            } else if is_face {
                let at = At {
                    element: "face",
                    index,
                    property: &face.properties[corners_at].name,
                };
                add_face(&corners, &mut triangles, max_triangles, &body, &at)?;
            }
        }
    }
    body.finish()?;
    let faces: Vec<MeshFace> = triangles
        .into_iter()
        .map(|vertices| MeshFace {
            vertices,
            normals: has_normals.then_some(vertices),
            texcoords: has_texcoords.then_some(vertices),
        })
        .collect();
    let mesh = Mesh::with_texcoords_until(positions, normals, texcoords, faces, stop.flag())
        .map_err(|e| match e {
            MeshError::Stopped => SceneError::interrupted(path),
            e => SceneError::new(path, format!("`{}`: {e}", path.display())),
        })?;
    Ok(mesh.with_winding(Winding::RightHanded))
}

/// A list's length, read as its count type: at least 0, and no more values than the body can
/// still hold.
fn list_len(
    body: &mut Body<'_>,
    count: Scalar,
    item: Scalar,
    at: &At<'_>,
) -> Result<u64, SceneError> {
    let len = body.value(count, at)?;
    if len < 0.0 {
        return Err(body.error_here(at, format!("a list of {len} values")));
    }
    let len = len as u64;
    if !body.has_room(len, item) {
        return Err(body.error_here(
            at,
            format!(
                "a list of {len} values, more than the rest of the file holds: it is cut short, \
                 or the count is wrong"
            ),
        ));
    }
    Ok(len)
}

/// A face corner's vertex index, which must name a vertex.
fn corner(body: &Body<'_>, value: f64, vertices: u64, at: &At<'_>) -> Result<u32, SceneError> {
    if value < 0.0 || value >= vertices as f64 {
        return Err(body.error_here(
            at,
            format!(
                "vertex index {value} is out of range: the file has {vertices} vertices (counting \
                 from 0)"
            ),
        ));
    }
    Ok(value as u32)
}

/// The triangles of a face of `corners`: itself, a quad's two (as pbrt-v4 cuts it), or a
/// polygon's fan; at most `max_triangles` in all.
fn add_face(
    corners: &[u32],
    triangles: &mut Vec<[u32; 3]>,
    max_triangles: usize,
    body: &Body<'_>,
    at: &At<'_>,
) -> Result<(), SceneError> {
    if corners.len() < 3 {
        return Err(body.error_here(
            at,
            format!("a face needs at least 3 corners, found {}", corners.len()),
        ));
    }
    if triangles.len() + corners.len() - 2 > max_triangles {
        return Err(body.error_here(
            at,
            format!(
                "the model has more than {max_triangles} triangles, the mesh size limit \
                 (`--max-triangles` on the command line)"
            ),
        ));
    }
    let first = corners[0];
    triangles.extend(corners[1..].windows(2).map(|w| [first, w[0], w[1]]));
    Ok(())
}
