//! glTF mesh primitives as rayforge meshes: positions, normals, texture coordinates,
//! tangents and vertex colours read through the `gltf` crate's accessors (sparse ones
//! included), indices checked, triangle strips and fans unrolled, and tangents generated for
//! normal maps where the file gives none.

use super::buffers::Buffers;
use super::paths::error;
use crate::error::SceneError;
use crate::stop::StopFlag;
use glam::{DVec3, DVec4};
use rayforge::geometry::{Mesh, MeshError, MeshFace, VertexAttributes};
use rayforge::{Point3, Vec3};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The meshes of a model, read once per primitive however many nodes use them.
pub(crate) struct Meshes<'a> {
    path: &'a Path,
    buffers: &'a Buffers,
    /// Read so far, by (mesh, primitive, whether tangents were needed).
    by_primitive: HashMap<(usize, usize, bool), Option<Arc<Mesh>>>,
    /// Triangles the model may still hold.
    triangles_left: usize,
    max_triangles: usize,
    /// What was left out, for warnings.
    pub notes: Vec<String>,
    /// Looked at before each node and each primitive.
    stop: &'a StopFlag,
}

impl<'a> Meshes<'a> {
    pub fn new(
        path: &'a Path,
        buffers: &'a Buffers,
        max_triangles: usize,
        stop: &'a StopFlag,
    ) -> Self {
        Self {
            stop,
            path,
            buffers,
            by_primitive: HashMap::new(),
            triangles_left: max_triangles,
            max_triangles,
            notes: Vec::new(),
        }
    }

    /// `Err`, naming the part `at` (`nodes[3]`), once the stop flag is set.
    pub fn stopped_at(&self, at: &str) -> Result<(), SceneError> {
        self.stop.check(self.path).map_err(|e| e.with_key(at))
    }

    /// The mesh of a primitive (`None` for points and lines, which have no surface), with
    /// tangents when `tangents` (its material has a normal map) and the texture coordinate
    /// set `uv_set`.
    pub fn primitive(
        &mut self,
        mesh: &::gltf::Mesh<'_>,
        primitive: &::gltf::Primitive<'_>,
        tangents: bool,
        uv_set: u32,
    ) -> Result<Option<Arc<Mesh>>, SceneError> {
        let key = (mesh.index(), primitive.index(), tangents);
        if let Some(m) = self.by_primitive.get(&key) {
            return Ok(m.clone());
        }
        let at = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
        self.stopped_at(&at)?;
        let built = self.read(primitive, &at, tangents, uv_set)?;
        self.by_primitive.insert(key, built.clone());
        Ok(built)
    }

    fn read(
        &mut self,
        primitive: &::gltf::Primitive<'_>,
        at: &str,
        tangents: bool,
        uv_set: u32,
    ) -> Result<Option<Arc<Mesh>>, SceneError> {
        use ::gltf::mesh::Mode;
        let path = self.path;
        let mode = primitive.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.notes.push(format!(
                "{at} draws {mode:?}, which has no surface: left out"
            ));
            return Ok(None);
        }
        let buffers = self.buffers;
        check_accessors(path, at, primitive, self.max_triangles, buffers)?;
        let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let attribute = |name: &str| format!("{at}.attributes.{name}");
        // The accessor readers index into the buffers as the file says; every view was checked
        // against its buffer, and the readers return `None` past a view's end, but a panic
        // in third-party code on a damaged file is reported, not passed on.
        // Each list collected with a look at the stop flag every `STOP_EVERY` elements (a
        // primitive may hold tens of millions); a list cut short by it is dropped below.
        let stop = self.stop;
        let read = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let positions: Option<Vec<[f32; 3]>> =
                reader.read_positions().map(|i| collect_until(i, stop));
            let normals: Option<Vec<[f32; 3]>> =
                reader.read_normals().map(|i| collect_until(i, stop));
            let uvs: Option<Vec<[f32; 2]>> = reader
                .read_tex_coords(uv_set)
                .map(|t| collect_until(t.into_f32(), stop));
            let given_tangents: Option<Vec<[f32; 4]>> =
                reader.read_tangents().map(|i| collect_until(i, stop));
            let colors: Option<Vec<[f32; 4]>> = reader
                .read_colors(0)
                .map(|c| collect_until(c.into_rgba_f32(), stop));
            let indices: Option<Vec<u32>> = reader
                .read_indices()
                .map(|i| collect_until(i.into_u32(), stop));
            (positions, normals, uvs, given_tangents, colors, indices)
        }))
        .map_err(|_| {
            error(
                path,
                at,
                "the primitive's data is damaged (its reader failed)",
            )
        })?;
        self.stopped_at(at)?;
        let (positions, normals, uvs, given_tangents, colors, indices) = read;
        let positions = positions.ok_or_else(|| {
            error(
                path,
                attribute("POSITION"),
                "the primitive has no positions (or they lie outside their buffer)",
            )
        })?;
        let count = positions.len();
        if count > self.max_triangles.saturating_mul(3) {
            return Err(error(
                path,
                attribute("POSITION"),
                format!("{count} vertices are more than the limit of three per triangle of the mesh size limit ({})", self.max_triangles),
            ));
        }
        let same_count = |list: Option<usize>, name: &str| -> Result<(), SceneError> {
            match list {
                Some(n) if n != count => Err(error(
                    path,
                    attribute(name),
                    format!("it has {n} entries, but POSITION has {count}"),
                )),
                _ => Ok(()),
            }
        };
        same_count(normals.as_ref().map(Vec::len), "NORMAL")?;
        same_count(uvs.as_ref().map(Vec::len), &format!("TEXCOORD_{uv_set}"))?;
        same_count(given_tangents.as_ref().map(Vec::len), "TANGENT")?;
        same_count(colors.as_ref().map(Vec::len), "COLOR_0")?;
        // A NaN normal would shade its faces black, a NaN position or coordinate worse.
        all_finite(path, attribute("POSITION"), &positions)?;
        all_finite(
            path,
            attribute("NORMAL"),
            normals.as_deref().unwrap_or_default(),
        )?;
        let uv_name = attribute(&format!("TEXCOORD_{uv_set}"));
        all_finite(path, uv_name, uvs.as_deref().unwrap_or_default())?;
        let tangent_name = attribute("TANGENT");
        all_finite(
            path,
            tangent_name,
            given_tangents.as_deref().unwrap_or_default(),
        )?;
        all_finite(
            path,
            attribute("COLOR_0"),
            colors.as_deref().unwrap_or_default(),
        )?;
        if primitive.get(&::gltf::Semantic::Positions).is_some()
            && indices.is_none()
            && primitive.indices().is_some()
        {
            return Err(error(
                path,
                format!("{at}.indices"),
                "the indices lie outside their buffer",
            ));
        }
        let indices: Vec<u32> = indices.unwrap_or_else(|| (0..count as u32).collect());
        if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
            return Err(error(
                path,
                format!("{at}.indices"),
                format!("index {bad} is past the primitive's {count} vertices"),
            ));
        }
        let triangles = unroll(mode, &indices);
        if triangles.len() > self.triangles_left {
            return Err(error(
                path,
                at,
                format!(
                    "with this primitive's {} triangles the model holds more than the mesh size limit of {} (`--max-triangles` on the command line)",
                    triangles.len(),
                    self.max_triangles
                ),
            ));
        }
        self.triangles_left -= triangles.len();

        let points: Vec<Point3> = positions.iter().map(|p| vec3(*p)).collect();
        let normals: Vec<Vec3> = normals
            .map(|n| n.iter().map(|n| vec3(*n).normalize_or_zero()).collect())
            .unwrap_or_default();
        // Stored with v up, as every renderer here reads texture coordinates.
        let texcoords: Vec<[f64; 2]> = uvs
            .map(|t| {
                t.iter()
                    .map(|t| [f64::from(t[0]), 1.0 - f64::from(t[1])])
                    .collect()
            })
            .unwrap_or_default();
        let tangents = match (tangents, given_tangents) {
            (false, _) => Vec::new(),
            (true, Some(given)) => given
                .iter()
                .map(|t| DVec4::new(t[0].into(), t[1].into(), t[2].into(), t[3].into()))
                .collect(),
            (true, None) if !texcoords.is_empty() => {
                self.stopped_at(at)?;
                generate_tangents(&points, &normals, &texcoords, &triangles)
            }
            (true, None) => Vec::new(),
        };
        let attributes = VertexAttributes {
            tangents,
            colors: colors.unwrap_or_default(),
        };
        let has_normals = !normals.is_empty();
        let has_uvs = !texcoords.is_empty();
        // The winding reversed: see the module's parent on glTF's space and the book's.
        let faces: Vec<MeshFace> = triangles
            .iter()
            .map(|&[a, b, c]| {
                let corners = [a, c, b];
                MeshFace {
                    vertices: corners,
                    normals: has_normals.then_some(corners),
                    texcoords: has_uvs.then_some(corners),
                }
            })
            .collect();
        let mesh = Mesh::with_texcoords_until(points, normals, texcoords, faces, self.stop.flag())
            .map_err(|e| match e {
                MeshError::Stopped => SceneError::interrupted(path).with_key(at),
                e => error(path, at, e.to_string()),
            })?
            .with_attributes(attributes)
            .ok_or_else(|| error(path, at, "its vertex attributes disagree in length"))?;
        Ok(Some(Arc::new(mesh)))
    }
}

/// How many elements of an accessor are read between two looks at the stop flag.
const STOP_EVERY: usize = 1 << 16;

/// The items of `items`, or the first of them once `stop` is set (looked at every
/// [`STOP_EVERY`]): the caller drops a list cut short, seeing the flag set.
fn collect_until<T>(items: impl Iterator<Item = T>, stop: &StopFlag) -> Vec<T> {
    let mut out = Vec::with_capacity(items.size_hint().0);
    for (i, item) in items.enumerate() {
        if i % STOP_EVERY == 0 && stop.is_set() {
            break;
        }
        out.push(item);
    }
    out
}

/// Checks, before anything is read, that each accessor the primitive's readers use has a type
/// the specification allows for its attribute (the `gltf` crate's readers assume it), no more
/// elements than the mesh size limit allows (`max_triangles`: three vertices a triangle; a
/// sparse accessor with no `bufferView` has no data to bound its `count`, and its reader
/// would allocate them all at once), and, if sparse, indices that name its elements.
fn check_accessors(
    path: &Path,
    at: &str,
    primitive: &::gltf::Primitive<'_>,
    max_triangles: usize,
    buffers: &Buffers,
) -> Result<(), SceneError> {
    use ::gltf::accessor::{DataType as T, Dimensions as D};
    use ::gltf::Semantic;
    let most = max_triangles.saturating_mul(3);
    let check = |accessor: ::gltf::Accessor<'_>, name: &str, ok: bool| {
        // Strips and fans have two indices more than three a triangle.
        let most = if name == "indices" {
            most.saturating_add(2)
        } else {
            most
        };
        if accessor.count() > most {
            return Err(error(
                path,
                format!("{at}.{name}"),
                format!(
                    "accessor {} has {} elements, more than the {most} that the mesh size limit \
                     of {max_triangles} triangles allows (`--max-triangles` on the command line)",
                    accessor.index(),
                    accessor.count()
                ),
            ));
        }
        if let Some(sparse) = accessor.sparse() {
            check_sparse(path, &format!("{at}.{name}"), &accessor, &sparse, buffers)?;
        }
        // The readers also assume each element fits its stride, and at least one element.
        let element = accessor.size();
        let strides = [
            accessor.view().and_then(|v| v.stride()),
            accessor.sparse().and_then(|s| s.values().view().stride()),
        ];
        if let Some(stride) = strides.into_iter().flatten().find(|&s| s < element) {
            return Err(error(
                path,
                format!("{at}.{name}"),
                format!(
                    "accessor {}'s elements take {element} bytes, more than its view's byteStride \
                     of {stride}",
                    accessor.index()
                ),
            ));
        }
        let sparse_indices = accessor.sparse().map(|s| s.indices());
        if let Some(indices) = sparse_indices.filter(|i| {
            i.view()
                .stride()
                .is_some_and(|stride| stride < i.index_type().size())
        }) {
            return Err(error(
                path,
                format!("{at}.{name}"),
                format!(
                    "accessor {}'s sparse indices take {} bytes each, more than their view's \
                     byteStride",
                    accessor.index(),
                    indices.index_type().size()
                ),
            ));
        }
        if accessor.count() == 0 {
            return Err(error(
                path,
                format!("{at}.{name}"),
                format!("accessor {} has no elements", accessor.index()),
            ));
        }
        if ok {
            Ok(())
        } else {
            Err(error(
                path,
                format!("{at}.{name}"),
                format!(
                    "accessor {} holds {:?} {:?}, which glTF does not allow here",
                    accessor.index(),
                    accessor.dimensions(),
                    accessor.data_type()
                ),
            ))
        }
    };
    if let Some(a) = primitive.indices() {
        let ok = matches!(a.data_type(), T::U8 | T::U16 | T::U32) && a.dimensions() == D::Scalar;
        check(a, "indices", ok)?;
    }
    for (semantic, a) in primitive.attributes() {
        let (t, d) = (a.data_type(), a.dimensions());
        let (name, ok) = match &semantic {
            Semantic::Positions => ("POSITION".to_string(), t == T::F32 && d == D::Vec3),
            Semantic::Normals => ("NORMAL".to_string(), t == T::F32 && d == D::Vec3),
            Semantic::Tangents => ("TANGENT".to_string(), t == T::F32 && d == D::Vec4),
            Semantic::TexCoords(n) => (
                format!("TEXCOORD_{n}"),
                matches!(t, T::F32 | T::U8 | T::U16) && d == D::Vec2,
            ),
            Semantic::Colors(n) => (
                format!("COLOR_{n}"),
                matches!(t, T::F32 | T::U8 | T::U16) && matches!(d, D::Vec3 | D::Vec4),
            ),
            _ => continue,
        };
        check(a, &format!("attributes.{name}"), ok)?;
    }
    Ok(())
}

/// Checks a sparse accessor's indices: at most as many as the accessor has elements, inside
/// their view, strictly increasing and each naming an element (the `gltf` crate's reader
/// silently drops an index past the end or out of order, and with it the value it replaces).
fn check_sparse(
    path: &Path,
    at: &str,
    accessor: &::gltf::Accessor<'_>,
    sparse: &::gltf::accessor::sparse::Sparse<'_>,
    buffers: &Buffers,
) -> Result<(), SceneError> {
    let fail = |why: String| error(path, format!("{at}.sparse"), why);
    let (count, elements) = (sparse.count(), accessor.count());
    if count > elements {
        return Err(fail(format!(
            "accessor {} replaces {count} of its elements, but it has {elements}",
            accessor.index()
        )));
    }
    let indices = sparse.indices();
    let view = indices.view();
    let size = indices.index_type().size();
    let stride = view.stride().unwrap_or(size);
    // Every view was checked against its buffer when the buffers were read.
    let data = buffers
        .get(view.buffer().index())
        .and_then(|b| b.get(view.offset()..view.offset() + view.length()))
        .unwrap_or_default();
    let mut previous = None;
    for k in 0..count {
        let start = indices.offset().saturating_add(k.saturating_mul(stride));
        let Some(bytes) = data.get(start..start.saturating_add(size)) else {
            return Err(fail(format!(
                "its indices run past the end of their view (bufferViews[{}], {} bytes): index \
                 {k} of {count} is not in it",
                view.index(),
                view.length()
            )));
        };
        let index = bytes
            .iter()
            .rev()
            .fold(0u64, |n, &b| (n << 8) | u64::from(b));
        if index >= elements as u64 {
            return Err(fail(format!(
                "its index {k} is {index}, past the accessor's {elements} elements"
            )));
        }
        if let Some(before) = previous.filter(|&before| index <= before) {
            return Err(fail(format!(
                "its indices are not strictly increasing: index {k} is {index}, after {before}"
            )));
        }
        previous = Some(index);
    }
    Ok(())
}

/// Refuses an attribute with a value that is not a finite number, naming the element.
fn all_finite<const N: usize>(
    path: &Path,
    at: String,
    values: &[[f32; N]],
) -> Result<(), SceneError> {
    match values.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
        None => Ok(()),
        Some(i) => Err(error(
            path,
            at,
            format!("its element {i} is {:?}, not finite numbers", values[i]),
        )),
    }
}

fn vec3(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0].into(), p[1].into(), p[2].into())
}

/// The triangles of a list, strip or fan of indices, in glTF's winding.
fn unroll(mode: ::gltf::mesh::Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    use ::gltf::mesh::Mode;
    match mode {
        Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
            .map(|i| {
                let (a, b, c) = (indices[i], indices[i + 1], indices[i + 2]);
                // Every other triangle of a strip turns the other way.
                if i % 2 == 0 {
                    [a, b, c]
                } else {
                    [b, a, c]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..indices.len().saturating_sub(1))
            .map(|i| [indices[i], indices[i + 1], indices[0]])
            .collect(),
        _ => indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
    }
}

/// Per-vertex tangents from the texture coordinates (v up): each face's direction of growing
/// u, summed over the faces that share a vertex, made perpendicular to its normal, with the
/// sign that makes `normal × tangent` point along growing v. This is the frame MikkTSpace
/// builds for a smooth mapping (it differs where the mapping folds or is mirrored within a
/// vertex's faces).
fn generate_tangents(
    points: &[Point3],
    normals: &[Vec3],
    uvs: &[[f64; 2]],
    triangles: &[[u32; 3]],
) -> Vec<DVec4> {
    let mut sum_t = vec![DVec3::ZERO; points.len()];
    let mut sum_b = vec![DVec3::ZERO; points.len()];
    let mut sum_n = vec![DVec3::ZERO; points.len()];
    for &[a, b, c] in triangles {
        let (a, b, c) = (a as usize, b as usize, c as usize);
        let (e1, e2) = (points[b] - points[a], points[c] - points[a]);
        let (du1, dv1) = (uvs[b][0] - uvs[a][0], uvs[b][1] - uvs[a][1]);
        let (du2, dv2) = (uvs[c][0] - uvs[a][0], uvs[c][1] - uvs[a][1]);
        let det = du1 * dv2 - du2 * dv1;
        let n = e1.cross(e2);
        for v in [a, b, c] {
            sum_n[v] += n;
        }
        if det.abs() < 1e-20 || !det.is_finite() {
            continue;
        }
        let t = (e1 * dv2 - e2 * dv1) / det;
        let bt = (e2 * du1 - e1 * du2) / det;
        for v in [a, b, c] {
            sum_t[v] += t;
            sum_b[v] += bt;
        }
    }
    (0..points.len())
        .map(|v| {
            let n = normals
                .get(v)
                .copied()
                .unwrap_or(sum_n[v])
                .normalize_or_zero();
            let t = (sum_t[v] - n * n.dot(sum_t[v])).normalize_or_zero();
            let w = if n.cross(t).dot(sum_b[v]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            t.extend(w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_unroll_into_triangles_of_one_winding() {
        use ::gltf::mesh::Mode;
        assert_eq!(
            unroll(Mode::TriangleStrip, &[0, 1, 2, 3]),
            [[0, 1, 2], [2, 1, 3]]
        );
        assert_eq!(
            unroll(Mode::TriangleFan, &[0, 1, 2, 3]),
            [[1, 2, 0], [2, 3, 0]]
        );
        assert_eq!(unroll(Mode::Triangles, &[0, 1, 2, 3]), [[0, 1, 2]]);
    }

    #[test]
    fn generated_tangents_follow_growing_u_with_the_sign_of_growing_v() {
        // A quad in the xy plane facing +z, u along +x and v (up) along +y.
        let points = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let normals = [DVec3::Z; 4];
        let uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let t = generate_tangents(&points, &normals, &uvs, &[[0, 1, 2], [0, 2, 3]]);
        for tangent in &t {
            assert!(
                (tangent.truncate() - DVec3::X).length() < 1e-12,
                "{tangent:?}"
            );
            assert_eq!(tangent.w, 1.0);
        }
        // v mirrored: the bitangent runs along −y, so the sign flips.
        let mirrored = uvs.map(|[u, v]| [u, 1.0 - v]);
        let t = generate_tangents(&points, &normals, &mirrored, &[[0, 1, 2], [0, 2, 3]]);
        assert!(t.iter().all(|t| t.w == -1.0));
    }
}
