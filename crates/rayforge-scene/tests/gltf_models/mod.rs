//! glTF 2.0 models written by the tests themselves: a small writer of glTF documents (their
//! buffers, accessors, meshes, materials, textures and nodes, as `.glb` or as `.gltf` with a
//! `.bin` beside it) and the models that `tests/gltf.rs` probes, each made to show one thing
//! a reader can get wrong (which corner a texture coordinate names, which way a node turns,
//! what a sparse accessor moves, how a sampler wraps, which way a normal map leans).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// glTF's component types.
const FLOAT: u32 = 5126;
const UNSIGNED_BYTE: u32 = 5121;
const UNSIGNED_SHORT: u32 = 5123;

/// A glTF document being written: one binary buffer and the JSON arrays that describe it.
#[derive(Default)]
pub struct Gltf {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
    meshes: Vec<String>,
    nodes: Vec<String>,
    roots: Vec<usize>,
    materials: Vec<String>,
    samplers: Vec<String>,
    images: Vec<String>,
    textures: Vec<String>,
    cameras: Vec<String>,
}

fn list(items: &[String]) -> String {
    format!("[{}]", items.join(","))
}

fn numbers<const N: usize>(v: [f64; N]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", parts.join(","))
}

impl Gltf {
    /// `bytes` as a buffer view (aligned to four bytes), with its stride when given.
    pub fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        let stride = stride.map_or(String::new(), |s| format!(",\"byteStride\":{s}"));
        self.views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{offset},\"byteLength\":{}{stride}}}",
            bytes.len()
        ));
        self.views.len() - 1
    }

    /// An accessor of `count` elements of `kind` (`"VEC3"`, ...) in `view` from `offset`,
    /// with `extra` JSON members (`min`, `max`, `sparse`).
    pub fn accessor(
        &mut self,
        view: Option<usize>,
        offset: usize,
        component: u32,
        count: usize,
        kind: &str,
        extra: &str,
    ) -> usize {
        let view = view.map_or(String::new(), |v| {
            format!("\"bufferView\":{v},\"byteOffset\":{offset},")
        });
        self.accessors.push(format!(
            "{{{view}\"componentType\":{component},\"count\":{count},\"type\":\"{kind}\"{extra}}}"
        ));
        self.accessors.len() - 1
    }

    /// Floats of `N` components each as an accessor (positions get their bounds, as glTF
    /// requires).
    pub fn floats<const N: usize>(&mut self, data: &[[f64; N]], bounds: bool) -> usize {
        let bytes: Vec<u8> = data
            .iter()
            .flatten()
            .flat_map(|x| (*x as f32).to_le_bytes())
            .collect();
        let view = self.view(&bytes, None);
        let kind = match N {
            2 => "VEC2",
            3 => "VEC3",
            4 => "VEC4",
            _ => unreachable!("a vector of 2, 3 or 4"),
        };
        let extra = if bounds { min_max(data) } else { String::new() };
        self.accessor(Some(view), 0, FLOAT, data.len(), kind, &extra)
    }

    /// Triangle indices as unsigned shorts.
    pub fn indices_u16(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices
            .iter()
            .flat_map(|i| (*i as u16).to_le_bytes())
            .collect();
        let view = self.view(&bytes, None);
        self.accessor(Some(view), 0, UNSIGNED_SHORT, indices.len(), "SCALAR", "")
    }

    /// Triangle indices as bytes.
    pub fn indices_u8(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices.iter().map(|i| *i as u8).collect();
        let view = self.view(&bytes, None);
        self.accessor(Some(view), 0, UNSIGNED_BYTE, indices.len(), "SCALAR", "")
    }

    /// A mesh of one triangle list: its `attributes` (name, accessor), indices and material.
    pub fn mesh(
        &mut self,
        attributes: &[(&str, usize)],
        indices: Option<usize>,
        material: Option<usize>,
    ) -> usize {
        let mut a = String::new();
        for (i, (name, accessor)) in attributes.iter().enumerate() {
            let comma = if i == 0 { "" } else { "," };
            write!(a, "{comma}\"{name}\":{accessor}").unwrap();
        }
        let mut primitive = format!("{{\"attributes\":{{{a}}}");
        if let Some(i) = indices {
            write!(primitive, ",\"indices\":{i}").unwrap();
        }
        if let Some(m) = material {
            write!(primitive, ",\"material\":{m}").unwrap();
        }
        primitive.push('}');
        self.meshes
            .push(format!("{{\"primitives\":[{primitive}]}}"));
        self.meshes.len() - 1
    }

    /// A whole shape as a mesh: positions, normals, texture coordinates where given, and
    /// unsigned short indices.
    pub fn geometry(&mut self, shape: &Geometry, material: Option<usize>) -> usize {
        let p = self.floats(&shape.positions, true);
        let n = self.floats(&shape.normals, false);
        let mut attributes = vec![("POSITION", p), ("NORMAL", n)];
        if !shape.uvs.is_empty() {
            attributes.push(("TEXCOORD_0", self.floats(&shape.uvs, false)));
        }
        let i = self.indices_u16(&shape.indices);
        self.mesh(&attributes, Some(i), material)
    }

    /// A node (its JSON members, e.g. `"mesh":0,"translation":[1,0,0]`) at the scene's root.
    pub fn root(&mut self, members: &str) -> usize {
        let node = self.node(members);
        self.roots.push(node);
        node
    }

    /// A node that is not at the root (a child named by another's `children`).
    pub fn node(&mut self, members: &str) -> usize {
        self.nodes.push(format!("{{{members}}}"));
        self.nodes.len() - 1
    }

    /// A material of glTF's metallic-roughness model (`pbr` the members of
    /// `pbrMetallicRoughness`, `rest` other members, each list empty or ending in no comma).
    pub fn material(&mut self, pbr: &str, rest: &str) -> usize {
        let rest = if rest.is_empty() {
            String::new()
        } else {
            format!(",{rest}")
        };
        self.materials
            .push(format!("{{\"pbrMetallicRoughness\":{{{pbr}}}{rest}}}"));
        self.materials.len() - 1
    }

    /// A plain material of one colour.
    pub fn colour(&mut self, rgb: [f64; 3]) -> usize {
        let [r, g, b] = rgb;
        self.material(
            &format!("\"baseColorFactor\":[{r:?},{g:?},{b:?},1.0],\"metallicFactor\":0.0,\"roughnessFactor\":1.0"),
            "",
        )
    }

    /// `image` as a PNG held in a buffer view, and a texture of it sampled by `sampler` (the
    /// sampler's JSON members).
    pub fn texture(&mut self, image: &image::RgbImage, sampler: &str) -> usize {
        let mut png = Vec::new();
        image
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let view = self.view(&png, None);
        self.images.push(format!(
            "{{\"bufferView\":{view},\"mimeType\":\"image/png\"}}"
        ));
        self.samplers.push(format!("{{{sampler}}}"));
        self.textures.push(format!(
            "{{\"sampler\":{},\"source\":{}}}",
            self.samplers.len() - 1,
            self.images.len() - 1
        ));
        self.textures.len() - 1
    }

    /// A camera (its JSON members: `type` and its projection).
    pub fn camera(&mut self, members: &str) -> usize {
        self.cameras.push(format!("{{{members}}}"));
        self.cameras.len() - 1
    }

    /// The JSON document, its buffer given by `uri` (none: the GLB's binary chunk).
    fn json(&self, uri: Option<&str>) -> String {
        let uri = uri.map_or(String::new(), |u| format!(",\"uri\":\"{u}\""));
        let mut doc = format!(
            "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"rayforge tests\"}},\
             \"scene\":0,\"scenes\":[{{\"nodes\":{:?}}}],\"nodes\":{},\"meshes\":{},\
             \"accessors\":{},\"bufferViews\":{},\
             \"buffers\":[{{\"byteLength\":{}{uri}}}]",
            self.roots,
            list(&self.nodes),
            list(&self.meshes),
            list(&self.accessors),
            list(&self.views),
            padded(&self.bin).len(),
        );
        for (name, items) in [
            ("materials", &self.materials),
            ("samplers", &self.samplers),
            ("images", &self.images),
            ("textures", &self.textures),
            ("cameras", &self.cameras),
        ] {
            if !items.is_empty() {
                write!(doc, ",\"{name}\":{}", list(items)).unwrap();
            }
        }
        doc.push('}');
        doc
    }

    /// The model as a binary glTF (`.glb`): the header, the JSON chunk and the binary chunk.
    pub fn glb(&self) -> Vec<u8> {
        let mut json = self.json(None).into_bytes();
        while json.len() % 4 != 0 {
            json.push(b' ');
        }
        let bin = padded(&self.bin);
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    /// Writes the model into `dir` as `name.glb`; its path.
    pub fn write_glb(&self, dir: &Path, name: &str) -> PathBuf {
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, self.glb()).unwrap();
        path
    }

    /// Writes the model into `dir` as `name.gltf` (JSON) with its buffer in `name.bin`; the
    /// path of the `.gltf`.
    pub fn write_gltf(&self, dir: &Path, name: &str) -> PathBuf {
        let bin = format!("{name}.bin");
        std::fs::write(dir.join(&bin), padded(&self.bin)).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, self.json(Some(&bin))).unwrap();
        path
    }
}

fn padded(bin: &[u8]) -> Vec<u8> {
    let mut out = bin.to_vec();
    while out.len() % 4 != 0 {
        out.push(0);
    }
    out
}

/// The `min` and `max` members of an accessor holding `data`.
fn min_max<const N: usize>(data: &[[f64; N]]) -> String {
    let mut lo = [f64::MAX; N];
    let mut hi = [f64::MIN; N];
    for v in data {
        for i in 0..N {
            // As the file holds them: in single precision.
            let x = f64::from(v[i] as f32);
            lo[i] = lo[i].min(x);
            hi[i] = hi[i].max(x);
        }
    }
    format!(",\"min\":{},\"max\":{}", numbers(lo), numbers(hi))
}

/// Triangles with their vertices' attributes, faces counter-clockwise seen from the front
/// (glTF's rule).
#[derive(Default, Clone)]
pub struct Geometry {
    pub positions: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub uvs: Vec<[f64; 2]>,
    pub indices: Vec<u32>,
}

impl Geometry {
    /// A rectangle from its centre, its half extent along `right` and along `up` (its front
    /// faces `right × up`), texture coordinates `uv` at its top-left, top-right, bottom-left
    /// and bottom-right corners.
    pub fn quad(centre: [f64; 3], right: [f64; 3], up: [f64; 3], uv: [[f64; 2]; 4]) -> Geometry {
        let at = |a: f64, b: f64| -> [f64; 3] {
            std::array::from_fn(|i| centre[i] + a * right[i] + b * up[i])
        };
        let n = normalize(cross(right, up));
        Geometry {
            positions: vec![at(-1.0, 1.0), at(1.0, 1.0), at(-1.0, -1.0), at(1.0, -1.0)],
            normals: vec![n; 4],
            uvs: uv.to_vec(),
            // Counter-clockwise seen from the front: bottom-left, bottom-right, top-right.
            indices: vec![2, 3, 1, 2, 1, 0],
        }
    }

    /// A box of half extent `half` around `centre`, four vertices a face (each with its
    /// face's normal).
    pub fn cube(centre: [f64; 3], half: f64) -> Geometry {
        let mut shape = Geometry::default();
        let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for (i, axis) in axes.iter().enumerate() {
            for sign in [1.0, -1.0] {
                let n = axis.map(|x| x * sign);
                // Two axes across the face with right × up = n.
                let right = axes[(i + 1) % 3].map(|x| x * sign);
                let up = axes[(i + 2) % 3];
                let face_centre = std::array::from_fn(|k| centre[k] + half * n[k]);
                let scaled = |v: [f64; 3]| v.map(|x| x * half);
                let face = Geometry::quad(face_centre, scaled(right), scaled(up), [[0.0; 2]; 4]);
                debug_assert!(dot(normalize(cross(right, up)), n) > 0.99);
                shape.append(&Geometry {
                    uvs: Vec::new(),
                    ..face
                });
            }
        }
        shape
    }

    /// A sphere of `radius` around `centre` in `rings` × `2 rings` quads.
    pub fn sphere(centre: [f64; 3], radius: f64, rings: u32) -> Geometry {
        let mut shape = Geometry::default();
        let segments = 2 * rings;
        for i in 0..=rings {
            let theta = std::f64::consts::PI * f64::from(i) / f64::from(rings);
            for j in 0..=segments {
                let phi = std::f64::consts::TAU * f64::from(j) / f64::from(segments);
                let n = [
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    -theta.sin() * phi.sin(),
                ];
                shape
                    .positions
                    .push(std::array::from_fn(|k| centre[k] + radius * n[k]));
                shape.normals.push(n);
            }
        }
        let row = segments + 1;
        for i in 0..rings {
            for j in 0..segments {
                let (a, b) = (i * row + j, (i + 1) * row + j);
                // Outward fronts: counter-clockwise seen from outside.
                shape.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        shape
    }

    /// `other`'s triangles added to these.
    pub fn append(&mut self, other: &Geometry) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.uvs.extend_from_slice(&other.uvs);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|x| x / l)
}
