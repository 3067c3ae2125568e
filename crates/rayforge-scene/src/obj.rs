//! Wavefront OBJ files (chapter 15) and their MTL material libraries.
//!
//! Reads vertices (`v`), normals (`vn`), texture coordinates (`vt`), faces (`f` in every form:
//! `1 2 3`, `1/2/3`, `1//3`, `1/2`, negative indices counting back from the end), polygons
//! fan-triangulated, named groups (`g`), and `mtllib`/`usemtl`. Lines it does not understand are
//! counted, as the book's parser counts them. Errors name the file, line, column and keyword.
//!
//! A face's front is OBJ's: the side from which its corners turn counter-clockwise in the
//! file's right-handed axes ([`Winding::RightHanded`](rayforge::geometry::Winding)), the
//! reverse of the book's triangles. The corners are kept in the file's order.

use crate::error::{SceneError, Span};
use crate::files::Folder;
use crate::stop::StopFlag;
use crate::text_line::TextLine;
use rayforge::{Color, Material, Point3, Vec3};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// One triangle of a face: indices (0-based) into the file's lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjTriangle {
    /// Corners, in [`ObjFile::vertices`].
    pub vertices: [u32; 3],
    /// Corner normals, in [`ObjFile::normals`], when every corner has one.
    pub normals: Option<[u32; 3]>,
    /// Corner texture coordinates, in [`ObjFile::texcoords`], when every corner has them.
    pub texcoords: Option<[u32; 3]>,
    /// The material in force (`usemtl`), in [`ObjFile::material_names`].
    pub material: Option<u32>,
}

/// A named group of triangles (`g name`); the first group is the default, unnamed one.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObjGroup {
    /// The name after `g` (empty for the default group).
    pub name: String,
    /// Its triangles.
    pub triangles: Vec<ObjTriangle>,
}

/// A parsed OBJ file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObjFile {
    /// Vertex positions (the book's 1-based `vertices[1]` is `vertices[0]` here).
    pub vertices: Vec<Point3>,
    /// Vertex normals.
    pub normals: Vec<Vec3>,
    /// Texture coordinates (u, v).
    pub texcoords: Vec<[f64; 2]>,
    /// The default group first, then each named group in order of first appearance.
    pub groups: Vec<ObjGroup>,
    /// Lines that were not understood (the book's `parser.ignored`).
    pub ignored_lines: usize,
    /// Material names used by `usemtl`, indexed by [`ObjTriangle::material`].
    pub material_names: Vec<String>,
    /// The `mtllib` statements: which files, and where they were named.
    pub material_libraries: Vec<(String, Span)>,
    /// Materials read from the `mtllib` files, by name.
    pub materials: HashMap<String, Material>,
}

impl ObjFile {
    /// The book's `parser.default_group`.
    pub fn default_group(&self) -> &ObjGroup {
        &self.groups[0]
    }

    /// A named group.
    pub fn group(&self, name: &str) -> Option<&ObjGroup> {
        self.groups.iter().find(|g| g.name == name)
    }
}

/// Loads an image named by a material library (`map_Kd`).
pub type TextureLoader<'a> =
    dyn FnMut(&Path) -> Result<Arc<rayforge::shading::Texture>, SceneError> + 'a;

/// The most triangles a scene's models may hold together by default (and three times as many
/// vertices, normals or texture coordinates of each kind in one model). A million-triangle model loads in about two
/// seconds and takes some 200 MB; ten times that is the largest a scene may have unless the
/// caller (`--max-triangles` on the command line) says otherwise.
pub const DEFAULT_MAX_TRIANGLES: usize = 10_000_000;

/// The largest OBJ or MTL file read (1 GiB, about twenty million triangles with normals).
pub const MAX_MODEL_BYTES: u64 = 1 << 30;

/// Reads an OBJ file, and the MTL files it names (relative to it, and inside its folder),
/// loading their texture maps with `load_texture`. At most [`DEFAULT_MAX_TRIANGLES`] triangles.
/// A file that is not a model (binary, not UTF-8, or with no vertex or face statement at all)
/// is an error, not an empty model.
pub fn read_obj_file(
    path: &Path,
    load_texture: &mut TextureLoader<'_>,
) -> Result<ObjFile, SceneError> {
    read_obj_in(
        path,
        &Folder::of_file(path, false),
        load_texture,
        DEFAULT_MAX_TRIANGLES,
        &StopFlag::default(),
    )
}

/// [`read_obj_file`] for a scene: the MTL files and images the model names must be inside
/// `folder` (the scene's), and it may hold at most `max_triangles` triangles (see
/// [`parse_obj_with_limit`]), stopping at the first statement after `stop` is set.
pub(crate) fn read_obj_in(
    path: &Path,
    folder: &Folder,
    load_texture: &mut TextureLoader<'_>,
    max_triangles: usize,
    stop: &StopFlag,
) -> Result<ObjFile, SceneError> {
    let text = read_text(path)?;
    if text.contains('\0') {
        return Err(SceneError::new(
            path,
            format!("`{}` is binary, not an OBJ model", path.display()),
        ));
    }
    // A file that is not a model would otherwise read as an empty one, its lines ignored;
    // said before parsing, so that no error quotes a line of it.
    if !statements(&text, path).any(|(_, keyword)| keyword == "v" || keyword == "f") {
        return Err(SceneError::new(
            path,
            format!(
                "`{}` is not an OBJ model: it has no vertex (`v`) or face (`f`) statement",
                path.display()
            ),
        ));
    }
    let mut obj = parse_obj_in(&text, path, max_triangles, stop)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    // Names in the libraries are held to the folder too, before the loader reads them.
    let mut load_inside = |image: &Path| {
        folder.check(image).map_err(|e| SceneError::new(image, e))?;
        load_texture(image)
    };
    for (name, span) in obj.material_libraries.clone() {
        let located = |message: String| SceneError::new(path, message).at(span).with_key("mtllib");
        let mtl_path = dir.join(&name);
        folder.check(&mtl_path).map_err(located)?;
        let mtl_text = read_text(&mtl_path).map_err(|e| located(e.message))?;
        obj.materials
            .extend(parse_mtl(&mtl_text, &mtl_path, &mut load_inside)?);
    }
    Ok(obj)
}

fn read_text(path: &Path) -> Result<String, SceneError> {
    let bytes = crate::files::read_bounded(path, MAX_MODEL_BYTES)
        .map_err(|e| SceneError::new(path, format!("cannot read `{}`: {e}", path.display())))?;
    String::from_utf8(bytes).map_err(|_| {
        SceneError::new(
            path,
            format!("`{}` is not a UTF-8 text file", path.display()),
        )
    })
}

/// What an OBJ or MTL statement adds to a line's errors: its numbers.
impl TextLine<'_> {
    /// The numbers after the keyword: at least `min`, at most `max`, all finite.
    fn numbers<const N: usize>(&self, key: &str, min: usize) -> Result<[f64; N], SceneError> {
        let mut out = [0.0; N];
        let mut count = 0;
        for (col, word) in self.words().skip(1) {
            let value: f64 = word.parse().map_err(|_| {
                self.error(
                    col,
                    word.len(),
                    key,
                    format!("expected a number, found `{word}`"),
                )
            })?;
            if !value.is_finite() {
                return Err(self.error(col, word.len(), key, format!("`{word}` is not finite")));
            }
            if count == N {
                return Err(self.error(
                    col,
                    word.len(),
                    key,
                    format!("`{key}` takes at most {N} numbers"),
                ));
            }
            out[count] = value;
            count += 1;
        }
        if count < min {
            return Err(self.error(
                0,
                key.len(),
                key,
                format!("`{key}` needs {min} numbers, found {count}"),
            ));
        }
        Ok(out)
    }
}

/// The non-blank lines of a file with their first word (the statement's keyword), numbered and
/// positioned for errors. OBJ and MTL share this shape.
fn statements<'t>(text: &'t str, path: &'t Path) -> impl Iterator<Item = (TextLine<'t>, &'t str)> {
    let mut offset = 0;
    text.split_inclusive('\n')
        .enumerate()
        .filter_map(move |(index, raw)| {
            let line = TextLine {
                path,
                number: index + 1,
                offset,
                text: raw.trim_end_matches(['\n', '\r']),
            };
            offset += raw.len();
            let keyword = line.words().next()?.1;
            Some((line, keyword))
        })
}

/// Parses OBJ text; `path` names the file in errors. At most [`DEFAULT_MAX_TRIANGLES`]
/// triangles.
pub fn parse_obj(text: &str, path: &Path) -> Result<ObjFile, SceneError> {
    parse_obj_with_limit(text, path, DEFAULT_MAX_TRIANGLES)
}

/// [`parse_obj`] with a mesh size limit: more than `max_triangles` triangles, or three times
/// as many vertices, normals or texture coordinates of any one kind, is an error at the line
/// that goes over it.
pub fn parse_obj_with_limit(
    text: &str,
    path: &Path,
    max_triangles: usize,
) -> Result<ObjFile, SceneError> {
    parse_obj_in(text, path, max_triangles, &StopFlag::default())
}

/// [`parse_obj_with_limit`] that stops at the first statement after `stop` is set.
pub(crate) fn parse_obj_in(
    text: &str,
    path: &Path,
    max_triangles: usize,
    stop: &StopFlag,
) -> Result<ObjFile, SceneError> {
    let mut triangles = 0usize;
    let too_many = |line: &TextLine<'_>| {
        line.error(
            0,
            1,
            "f",
            format!(
                "the model has more than {max_triangles} triangles, the mesh size limit \
                 (`--max-triangles` on the command line)"
            ),
        )
    };
    // Vertices, normals and texture coordinates are bounded too: three per triangle, as a
    // model whose faces share no corners has.
    let max_vertices = max_triangles.saturating_mul(3);
    let room = |line: &TextLine<'_>, key: &str, count: usize| {
        if count >= max_vertices {
            Err(line.error(
                0,
                key.len(),
                key,
                format!(
                    "the model has more than {max_vertices} entries of one kind (`v`, `vn` or \
                     `vt`), three per triangle of the mesh size limit (`--max-triangles` on the \
                     command line)"
                ),
            ))
        } else {
            Ok(())
        }
    };
    let mut obj = ObjFile {
        groups: vec![ObjGroup::default()],
        ..ObjFile::default()
    };
    let mut current_group = 0;
    let mut current_material = None;
    // Names to indices: a file may name hundreds of thousands of groups or materials, and a
    // linear search for each would take quadratic time.
    let mut group_index: HashMap<String, usize> = HashMap::from([(String::new(), 0)]);
    let mut material_index: HashMap<String, u32> = HashMap::new();
    let mut corners: Vec<Corner> = Vec::with_capacity(8);
    let texcoords_named = statements(text, path).any(|(_, keyword)| keyword == "vt");
    for (line, keyword) in statements(text, path) {
        stop.check(path).map_err(|e| e.at(line.span(0, 0)))?;
        match keyword {
            "v" => {
                room(&line, "v", obj.vertices.len())?;
                let [x, y, z, _w] = line.numbers::<4>("v", 3)?;
                obj.vertices.push(Point3::new(x, y, z));
            }
            "vn" => {
                room(&line, "vn", obj.normals.len())?;
                let [x, y, z] = line.numbers::<3>("vn", 3)?;
                obj.normals.push(Vec3::new(x, y, z));
            }
            "vt" => {
                room(&line, "vt", obj.texcoords.len())?;
                let [u, v, _w] = line.numbers::<3>("vt", 1)?;
                obj.texcoords.push([u, v]);
            }
            "f" => {
                corners.clear();
                for (col, word) in line.words().skip(1) {
                    corners.push(corner(&line, &obj, texcoords_named, col, word)?);
                }
                if corners.len() < 3 {
                    return Err(line.error(
                        0,
                        1,
                        "f",
                        format!("a face needs at least 3 corners, found {}", corners.len()),
                    ));
                }
                triangles += corners.len() - 2;
                if triangles > max_triangles {
                    return Err(too_many(&line));
                }
                // Fan triangulation: (1, 2, 3), (1, 3, 4), … as the book does.
                for k in 1..corners.len() - 1 {
                    let tri = [corners[0], corners[k], corners[k + 1]];
                    let all = |f: fn(&Corner) -> Option<u32>| -> Option<[u32; 3]> {
                        Some([f(&tri[0])?, f(&tri[1])?, f(&tri[2])?])
                    };
                    obj.groups[current_group].triangles.push(ObjTriangle {
                        vertices: tri.map(|c| c.vertex),
                        normals: all(|c| c.normal),
                        texcoords: all(|c| c.texcoord),
                        material: current_material,
                    });
                }
            }
            "g" => {
                let name = line.text.trim_start()[1..].trim().to_string();
                current_group = *group_index.entry(name).or_insert_with_key(|name| {
                    obj.groups.push(ObjGroup {
                        name: name.clone(),
                        triangles: Vec::new(),
                    });
                    obj.groups.len() - 1
                });
            }
            "usemtl" => {
                let name = line.text.trim_start()["usemtl".len()..].trim().to_string();
                current_material = Some(*material_index.entry(name).or_insert_with_key(|name| {
                    obj.material_names.push(name.clone());
                    (obj.material_names.len() - 1) as u32
                }));
            }
            "mtllib" => {
                for (col, word) in line.words().skip(1) {
                    obj.material_libraries.push((
                        word.to_string(),
                        Span {
                            line: line.number,
                            column: col + 1,
                            offset: line.offset + col,
                            len: word.len(),
                        },
                    ));
                }
            }
            // Understood, and not needed for rendering: comments, object names, smoothing
            // groups, parameter-space vertices, lines and points.
            k if k.starts_with('#') => {}
            "o" | "s" | "vp" | "l" | "p" => {}
            _ => obj.ignored_lines += 1,
        }
    }
    Ok(obj)
}

/// One corner of a face: `v`, `v/vt`, `v//vn` or `v/vt/vn`, resolved to 0-based indices.
#[derive(Debug, Clone, Copy)]
struct Corner {
    vertex: u32,
    normal: Option<u32>,
    texcoord: Option<u32>,
}

/// The corner `word` of a face, at column `col` of `line`. Every index must name an entry read
/// before it; texture indices too, unless the file has no `vt` at all (`texcoords_named`
/// false): then they name nothing and are ignored, as the book's parser ignores texture
/// indices altogether (its "faces with normals" file uses 0 and 102).
fn corner(
    line: &TextLine<'_>,
    obj: &ObjFile,
    texcoords_named: bool,
    col: usize,
    word: &str,
) -> Result<Corner, SceneError> {
    let mut parts = word.split('/');
    let resolve = |part: &str, count: usize, what: &str, plural: &str| {
        let err = |message: String| line.error(col, word.len(), "f", message);
        let n: i64 = part
            .parse()
            .map_err(|_| err(format!("expected a {what} index, found `{part}`")))?;
        // 1-based from the start, or negative counting back from the latest.
        let index = if n > 0 { n - 1 } else { count as i64 + n };
        if n == 0 || index < 0 || index >= count as i64 {
            return Err(err(format!(
                "{what} index {n} is out of range (there are {count} {plural} so far)"
            )));
        }
        Ok(index as u32)
    };
    let vertex = resolve(
        parts.next().unwrap_or(""),
        obj.vertices.len(),
        "vertex",
        "vertices",
    )?;
    let texcoord = match parts.next() {
        Some("") | None => None,
        Some(_) if !texcoords_named => None,
        Some(t) => Some(resolve(
            t,
            obj.texcoords.len(),
            "texture coordinate",
            "texture coordinates",
        )?),
    };
    let normal = match parts.next() {
        Some("") | None => None,
        Some(n) => Some(resolve(n, obj.normals.len(), "normal", "normals")?),
    };
    if parts.next().is_some() {
        return Err(line.error(
            col,
            word.len(),
            "f",
            format!("`{word}` has more than three parts"),
        ));
    }
    Ok(Corner {
        vertex,
        normal,
        texcoord,
    })
}

/// Parses an MTL material library into rayforge materials.
///
/// `Kd` becomes the colour, `Ks` (averaged) the specular weight, `Ns` the shininess, `d` (or
/// `1 - Tr`) the opacity, `Ni` the refractive index; `illum` 3 and above (ray-traced
/// reflection) makes the surface reflective by its specular weight. `map_Kd` names an image
/// (relative to the MTL file) that multiplies `Kd` where the model has texture coordinates.
pub fn parse_mtl(
    text: &str,
    path: &Path,
    load_texture: &mut TextureLoader<'_>,
) -> Result<HashMap<String, Material>, SceneError> {
    let mut out = HashMap::new();
    // The material being read, and whether `illum` asked for ray-traced reflection (applied
    // when the material ends, so it sees `Ks` wherever it was written).
    let mut current: Option<(String, Material, bool)> = None;
    let finish = |out: &mut HashMap<String, Material>,
                  (name, mut m, reflect): (String, Material, bool)| {
        if reflect {
            m.reflective = m.specular;
        }
        out.insert(name, m);
    };
    for (line, keyword) in statements(text, path) {
        if keyword == "newmtl" {
            if let Some(done) = current.take() {
                finish(&mut out, done);
            }
            let name = line.text.trim_start()["newmtl".len()..].trim().to_string();
            current = Some((name, Material::default(), false));
            continue;
        }
        let Some((_, m, reflect)) = current.as_mut() else {
            continue;
        };
        let mean = |[a, b, c]: [f64; 3]| (a + b + c) / 3.0;
        match keyword {
            "Kd" => {
                let [r, g, b] = line.numbers::<3>("Kd", 3)?;
                m.color = Color::new(r, g, b);
            }
            "Ks" => m.specular = mean(line.numbers::<3>("Ks", 3)?),
            "Ns" => m.shininess = line.numbers::<1>("Ns", 1)?[0],
            "d" => m.transparency = 1.0 - line.numbers::<1>("d", 1)?[0],
            "Tr" => m.transparency = line.numbers::<1>("Tr", 1)?[0],
            "Ni" => m.refractive_index = line.numbers::<1>("Ni", 1)?[0],
            "illum" => {
                let model = line.numbers::<1>("illum", 1)?[0];
                *reflect = model >= 3.0;
                if model == 0.0 {
                    // Illumination model 0, "colour on, ambient off": the colour as it is,
                    // unlit (each light's ambient share shows it; one white light, exactly).
                    m.ambient = 1.0;
                    m.diffuse = 0.0;
                    m.specular = 0.0;
                }
            }
            "map_Kd" => {
                // The file name is the last word (options such as `-bm 1` may precede it).
                let Some((col, name)) = line.words().last().filter(|(_, w)| *w != "map_Kd") else {
                    return Err(line.error(0, 6, "map_Kd", "`map_Kd` needs a file name".into()));
                };
                let image = path.parent().unwrap_or(Path::new(".")).join(name);
                let texture = load_texture(&image)
                    .map_err(|e| line.error(col, name.len(), "map_Kd", e.message))?;
                m.texture = Some(Box::new(rayforge::shading::UvPattern::Image(texture)));
            }
            _ => {}
        }
    }
    if let Some(done) = current {
        finish(&mut out, done);
    }
    Ok(out)
}

/// The file's triangles as meshes, one per group and material (faces that share a material
/// render as one object), each with only the vertices it uses. The material is the one named
/// by `usemtl` and found in the libraries, or `None`. Each mesh's faces have OBJ's
/// counter-clockwise fronts.
pub fn to_meshes(obj: &ObjFile) -> Vec<(Arc<rayforge::geometry::Mesh>, Option<Material>)> {
    to_meshes_until(obj, &StopFlag::default())
        .expect("meshes without a stop flag are never stopped")
}

/// [`to_meshes`], `None` once `stop` is set (looked at inside each mesh's build).
pub(crate) fn to_meshes_until(
    obj: &ObjFile,
    stop: &StopFlag,
) -> Option<Vec<(Arc<rayforge::geometry::Mesh>, Option<Material>)>> {
    use rayforge::geometry::{Mesh, MeshError, MeshFace, Winding};
    /// Old index → new index, `UNUSED` until the entry is first used in the mesh being built:
    /// a dense table is several times faster than hashing on million-face files. The table is
    /// shared by all meshes and only the entries a mesh used are reset, so a file of many
    /// small groups costs what it holds, not groups × vertices.
    struct Remap {
        map: Vec<u32>,
        used: Vec<u32>,
    }
    const UNUSED: u32 = u32::MAX;
    impl Remap {
        fn new(len: usize) -> Self {
            Self {
                map: vec![UNUSED; len],
                used: Vec::new(),
            }
        }
        fn get<T: Copy>(&mut self, list: &mut Vec<T>, source: &[T], i: u32) -> u32 {
            let slot = &mut self.map[i as usize];
            if *slot == UNUSED {
                list.push(source[i as usize]);
                *slot = (list.len() - 1) as u32;
                self.used.push(i);
            }
            *slot
        }
        fn reset(&mut self) {
            for i in self.used.drain(..) {
                self.map[i as usize] = UNUSED;
            }
        }
    }
    let mut vertex_map = Remap::new(obj.vertices.len());
    let mut normal_map = Remap::new(obj.normals.len());
    let mut texcoord_map = Remap::new(obj.texcoords.len());
    let mut out = Vec::new();
    for group in &obj.groups {
        // The group's triangles by material (a stable sort keeps each material's in file
        // order), one mesh per run.
        let mut by_material: Vec<&ObjTriangle> = group.triangles.iter().collect();
        by_material.sort_by_key(|t| t.material);
        for run in by_material.chunk_by(|a, b| a.material == b.material) {
            let material = run[0].material;
            let (mut positions, mut normals, mut texcoords) = (Vec::new(), Vec::new(), Vec::new());
            let faces: Vec<MeshFace> = run
                .iter()
                .map(|t| MeshFace {
                    vertices: t
                        .vertices
                        .map(|i| vertex_map.get(&mut positions, &obj.vertices, i)),
                    normals: t
                        .normals
                        .map(|n| n.map(|i| normal_map.get(&mut normals, &obj.normals, i))),
                    texcoords: t
                        .texcoords
                        .map(|n| n.map(|i| texcoord_map.get(&mut texcoords, &obj.texcoords, i))),
                })
                .collect();
            vertex_map.reset();
            normal_map.reset();
            texcoord_map.reset();
            if faces.is_empty() {
                continue;
            }
            // Indices were checked while parsing and remapped into range, so this fails only
            // when stopped.
            let mesh =
                match Mesh::with_texcoords_until(positions, normals, texcoords, faces, stop.flag())
                {
                    Ok(mesh) => mesh,
                    Err(MeshError::Stopped) => return None,
                    Err(_) => continue,
                };
            let mesh = mesh.with_winding(Winding::RightHanded);
            let material = material
                .and_then(|m| obj.material_names.get(m as usize))
                .and_then(|name| obj.materials.get(name))
                .cloned();
            out.push((Arc::new(mesh), material));
        }
    }
    Some(out)
}
