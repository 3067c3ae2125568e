//! PLY models (issue 45's `plymesh`, held to issue 44's rules for untrusted readers): small
//! files written here in every encoding read to the triangles they hold, every kind of damage
//! is an error at its place (line and column of text, byte offset of binary), the file is
//! opened as untrusted input, `add: ply` places one in a scene, and a PLY cube renders under
//! the path tracer exactly as the same cube written as OBJ.

mod support;

use rayforge::geometry::{Mesh, Winding};
use rayforge::{Point3, Vec3};
use rayforge_scene::ply::{parse_ply, read_ply_file};
use rayforge_scene::{load_file_with, LoadOptions, SceneError, DEFAULT_MAX_TRIANGLES};
use std::io::Write;
use std::path::{Path, PathBuf};

/// How a generated file's body is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

const ENCODINGS: [Encoding; 3] = [Encoding::Ascii, Encoding::Little, Encoding::Big];

/// A property to write: its type (and a list's count type) and name.
#[derive(Clone, Copy)]
struct Prop {
    ty: &'static str,
    count: Option<&'static str>,
    name: &'static str,
}

fn scalar(ty: &'static str, name: &'static str) -> Prop {
    Prop {
        ty,
        count: None,
        name,
    }
}

fn list(count: &'static str, ty: &'static str, name: &'static str) -> Prop {
    Prop {
        ty,
        count: Some(count),
        name,
    }
}

/// An element to write: its properties, and per row the values of each property (one for a
/// scalar, the items of a list).
struct Elem {
    name: &'static str,
    props: Vec<Prop>,
    rows: Vec<Vec<Vec<f64>>>,
}

/// `value` written as `ty` in a binary body.
fn binary(out: &mut Vec<u8>, ty: &str, value: f64, big: bool) {
    let mut bytes = match ty {
        "char" | "int8" => (value as i8).to_le_bytes().to_vec(),
        "uchar" | "uint8" => (value as u8).to_le_bytes().to_vec(),
        "short" | "int16" => (value as i16).to_le_bytes().to_vec(),
        "ushort" | "uint16" => (value as u16).to_le_bytes().to_vec(),
        "int" | "int32" => (value as i32).to_le_bytes().to_vec(),
        "uint" | "uint32" => (value as u32).to_le_bytes().to_vec(),
        "float" | "float32" => (value as f32).to_le_bytes().to_vec(),
        "double" | "float64" => value.to_le_bytes().to_vec(),
        other => panic!("no type {other}"),
    };
    if big {
        bytes.reverse();
    }
    out.extend(bytes);
}

/// `value` written as `ty` in a text body.
fn text(ty: &str, value: f64) -> String {
    match ty {
        "float" | "float32" => format!("{}", value as f32),
        "double" | "float64" => format!("{value}"),
        _ => format!("{}", value as i64),
    }
}

/// A whole PLY file of `elements` in `encoding`, with a comment and an `obj_info` line.
fn encode(elements: &[Elem], encoding: Encoding) -> Vec<u8> {
    let format = match encoding {
        Encoding::Ascii => "ascii",
        Encoding::Little => "binary_little_endian",
        Encoding::Big => "binary_big_endian",
    };
    let mut out =
        format!("ply\nformat {format} 1.0\ncomment made by tests/ply.rs\nobj_info none\n");
    for e in elements {
        out += &format!("element {} {}\n", e.name, e.rows.len());
        for p in &e.props {
            match p.count {
                Some(c) => out += &format!("property list {c} {} {}\n", p.ty, p.name),
                None => out += &format!("property {} {}\n", p.ty, p.name),
            }
        }
    }
    out += "end_header\n";
    let mut out = out.into_bytes();
    for e in elements {
        for row in &e.rows {
            let mut words = Vec::new();
            for (p, values) in e.props.iter().zip(row) {
                if let Some(c) = p.count {
                    match encoding {
                        Encoding::Ascii => words.push(text(c, values.len() as f64)),
                        _ => binary(&mut out, c, values.len() as f64, encoding == Encoding::Big),
                    }
                }
                for &v in values {
                    match encoding {
                        Encoding::Ascii => words.push(text(p.ty, v)),
                        _ => binary(&mut out, p.ty, v, encoding == Encoding::Big),
                    }
                }
            }
            if encoding == Encoding::Ascii {
                out.extend(words.join(" ").into_bytes());
                out.push(b'\n');
            }
        }
    }
    out
}

/// The vertices of a unit square in z = 0 and one apex above it, as rows of x y z.
fn square_vertices() -> Vec<Vec<Vec<f64>>> {
    [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
    ]
    .iter()
    .map(|p| p.iter().map(|&c| vec![c]).collect())
    .collect()
}

fn xyz(ty: &'static str) -> Vec<Prop> {
    vec![scalar(ty, "x"), scalar(ty, "y"), scalar(ty, "z")]
}

/// A face element of `faces` with corners in a `count`/`index` list called `name`.
fn faces(count: &'static str, index: &'static str, name: &'static str, faces: &[&[u32]]) -> Elem {
    Elem {
        name: "face",
        props: vec![list(count, index, name)],
        rows: faces
            .iter()
            .map(|f| vec![f.iter().map(|&i| f64::from(i)).collect()])
            .collect(),
    }
}

fn parse(bytes: &[u8]) -> Result<Mesh, SceneError> {
    parse_ply(bytes, Path::new("model.ply"), DEFAULT_MAX_TRIANGLES)
}

fn triangles(mesh: &Mesh) -> Vec<[u32; 3]> {
    mesh.faces().map(|f| f.vertices).collect()
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

#[test]
fn triangles_and_quads_read_in_every_encoding_with_every_list_type() {
    // A quad a b c d is cut into (a b c) and (a c d), as pbrt-v4 cuts it; a triangle stays.
    let expected = vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]];
    for encoding in ENCODINGS {
        for (count, index, name, coordinates) in [
            ("uchar", "int", "vertex_indices", "float"),
            ("int", "uint", "vertex_index", "double"),
            ("uint", "int32", "vertex_indices", "float32"),
            ("uint8", "ushort", "vertex_indices", "float64"),
        ] {
            let file = encode(
                &[
                    Elem {
                        name: "vertex",
                        props: xyz(coordinates),
                        rows: square_vertices(),
                    },
                    faces(count, index, name, &[&[0, 1, 2, 3], &[0, 1, 4]]),
                ],
                encoding,
            );
            let what = format!("{encoding:?} {count} {index} {name} {coordinates}");
            let mesh = parse(&file).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(triangles(&mesh), expected, "{what}");
            assert_eq!(mesh.positions()[4], Point3::new(0.5, 0.5, 1.0), "{what}");
            assert!(
                mesh.normals().is_empty() && mesh.texcoords().is_empty(),
                "{what}"
            );
            // The front is where the corners turn counter-clockwise in right-handed axes:
            // the square's corners turn so seen from +z.
            assert_eq!(mesh.winding(), Winding::RightHanded, "{what}");
            assert_eq!(mesh.face_normal(0).normalize(), Vec3::Z, "{what}");
            // The same file compressed reads the same.
            let zipped = parse(&gzip(&file)).unwrap_or_else(|e| panic!("{what}, gzip: {e}"));
            assert_eq!(triangles(&zipped), expected, "{what}, gzip");
            assert_eq!(zipped.positions(), mesh.positions(), "{what}, gzip");
        }
    }
}

#[test]
fn a_polygon_of_more_corners_is_cut_into_a_fan() {
    let file = encode(
        &[
            Elem {
                name: "vertex",
                props: xyz("float"),
                rows: square_vertices(),
            },
            faces("uchar", "int", "vertex_indices", &[&[0, 1, 2, 4, 3]]),
        ],
        Encoding::Ascii,
    );
    assert_eq!(
        triangles(&parse(&file).unwrap()),
        vec![[0, 1, 2], [0, 2, 4], [0, 4, 3]]
    );
}

#[test]
fn normals_and_texture_coordinates_are_read_under_each_of_their_names() {
    for (u, v) in [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ] {
        for encoding in ENCODINGS {
            let mut props = xyz("float");
            props.extend([
                scalar("float", "nx"),
                scalar("float", "ny"),
                scalar("float", "nz"),
                scalar("float", u),
                scalar("float", v),
            ]);
            let rows = square_vertices()
                .into_iter()
                .enumerate()
                .map(|(i, mut row)| {
                    let i = i as f64;
                    row.extend([
                        vec![0.0],
                        vec![i * 0.25],
                        vec![1.0],
                        vec![i * 0.125],
                        vec![0.5],
                    ]);
                    row
                })
                .collect();
            let file = encode(
                &[
                    Elem {
                        name: "vertex",
                        props,
                        rows,
                    },
                    faces("uchar", "int", "vertex_indices", &[&[0, 1, 4]]),
                ],
                encoding,
            );
            let mesh = parse(&file).unwrap_or_else(|e| panic!("{u} {v} {encoding:?}: {e}"));
            assert_eq!(mesh.normals()[2], Vec3::new(0.0, 0.5, 1.0));
            assert_eq!(mesh.texcoords()[3], [0.375, 0.5]);
            let face = mesh.face(0);
            assert_eq!(face.normals, Some([0, 1, 4]));
            assert_eq!(face.texcoords, Some([0, 1, 4]));
        }
    }
}

/// Properties and elements the mesh does not use, scalars and lists of every type, before,
/// between and after the ones it does, are read past.
#[test]
fn extra_properties_and_elements_are_read_past() {
    for encoding in ENCODINGS {
        let mut props = vec![scalar("uchar", "red"), list("uchar", "float", "weights")];
        props.extend(xyz("double"));
        props.extend([scalar("short", "confidence"), scalar("float", "u")]);
        let rows = square_vertices()
            .into_iter()
            .enumerate()
            .map(|(i, xyz)| {
                let mut row = vec![vec![200.0], vec![0.5; i]];
                row.extend(xyz);
                row.extend([vec![-7.0], vec![0.25]]);
                row
            })
            .collect();
        let file = encode(
            &[
                Elem {
                    name: "material",
                    props: vec![scalar("float", "shininess"), list("int", "uchar", "name")],
                    rows: vec![vec![vec![2.5], vec![65.0, 66.0]]],
                },
                Elem {
                    name: "vertex",
                    props,
                    rows,
                },
                Elem {
                    name: "edge",
                    props: vec![scalar("int", "vertex1"), scalar("int", "vertex2")],
                    rows: vec![vec![vec![0.0], vec![1.0]]; 3],
                },
                Elem {
                    name: "face",
                    props: vec![
                        scalar("int", "face_indices"),
                        list("uchar", "uint", "vertex_indices"),
                        list("uchar", "float", "texcoord"),
                    ],
                    rows: vec![
                        vec![vec![3.0], vec![0.0, 1.0, 2.0, 3.0], vec![0.0; 6]],
                        vec![vec![1.0], vec![0.0, 1.0, 4.0], vec![]],
                    ],
                },
                Elem {
                    name: "trailer",
                    props: vec![list("uint", "double", "values")],
                    rows: vec![vec![vec![1.0, 2.0, 3.0]]],
                },
            ],
            encoding,
        );
        let mesh = parse(&file).unwrap_or_else(|e| panic!("{encoding:?}: {e}"));
        assert_eq!(
            triangles(&mesh),
            vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]],
            "{encoding:?}"
        );
        assert_eq!(
            mesh.positions()[2],
            Point3::new(1.0, 1.0, 0.0),
            "{encoding:?}"
        );
        // A lone `u` is no texture coordinate pair: it is read past too.
        assert!(mesh.texcoords().is_empty(), "{encoding:?}");
    }
}

/// The message of the error, with its place: `line:column` for text, the error's key.
fn located(e: &SceneError) -> (Option<(usize, usize)>, Option<String>) {
    (e.span.map(|s| (s.line, s.column)), e.key.clone())
}

const TRIANGLE_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

#[test]
fn a_damaged_header_is_an_error_at_its_line_and_word() {
    let cases: &[(&str, (usize, usize), &str, &str)] = &[
        ("plx\n", (0, 0), "", "does not start with the line `ply`"),
        (
            "ply\nformat text 1.0\n",
            (2, 8),
            "format",
            "unknown encoding `text`",
        ),
        (
            "ply\nformat ascii 2.0\n",
            (2, 14),
            "format",
            "version `2.0`",
        ),
        ("ply\nformat ascii\n", (2, 13), "format", "needs a version"),
        (
            "ply\nelement vertex 3\n",
            (2, 1),
            "element",
            "before the `format` line",
        ),
        (
            "ply\nformat ascii 1.0\nproperty float x\n",
            (3, 1),
            "property",
            "before any `element`",
        ),
        (
            "ply\nformat ascii 1.0\nelement vertex -3\n",
            (3, 16),
            "element",
            "whole number",
        ),
        (
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty real x\n",
            (4, 10),
            "property",
            "unknown type `real`",
        ),
        (
            "ply\nformat ascii 1.0\nelement face 3\nproperty list float int vertex_indices\n",
            (4, 15),
            "property",
            "whole-number type",
        ),
        (
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\n",
            (5, 16),
            "property",
            "a second property `x`",
        ),
        (
            "ply\nformat ascii 1.0\nelement vertex 0\nelement vertex 0\n",
            (4, 9),
            "element",
            "a second element",
        ),
        (
            "ply\nformat ascii 1.0\nbanana\n",
            (3, 1),
            "header",
            "unknown header line `banana`",
        ),
        (
            "ply\nformat ascii 1.0\nelement vertex 3\n",
            (4, 1),
            "end_header",
            "without `end_header`",
        ),
        ("ply\nend_header\n", (2, 1), "format", "no `format` line"),
    ];
    for &(file, place, key, message) in cases {
        let e = parse(file.as_bytes()).unwrap_err();
        assert!(e.message.contains(message), "{file:?}: {e}");
        if key.is_empty() {
            assert_eq!(located(&e), (None, None), "{file:?}: {e}");
        } else {
            assert_eq!(
                located(&e),
                (Some(place), Some(key.into())),
                "{file:?}: {e}"
            );
        }
        assert_eq!(e.path, Path::new("model.ply"));
    }
    // A header without an end in a megabyte is refused there.
    let mut long = b"ply\nformat ascii 1.0\n".to_vec();
    long.extend(std::iter::repeat_n(b'c', 2 << 20));
    let e = parse(&long).unwrap_err();
    assert!(
        e.message
            .contains("the header is longer than 1048576 bytes"),
        "{e}"
    );
}

#[test]
fn a_damaged_text_body_is_an_error_at_its_line_and_column() {
    let cases: &[(&str, (usize, usize), &str, &str)] = &[
        // Cut short: a missing line, a missing value.
        (
            "0 0 0\n1 0 0\n0 1 0\n\n\n\n",
            (16, 1),
            "face",
            "the file ends before face #0",
        ),
        // (Without the blank lines the header's count alone shows it is cut.)
        (
            "0 0 0\n1 0 0\n0 1 0\n",
            (7, 14),
            "face",
            "need at least 2 bytes, but the file has 18",
        ),
        (
            "0 0 0\n1 0 0\n0 1\n3 0 1 2\n",
            (12, 4),
            "vertex.z",
            "vertex #2: its line ends before property `z`",
        ),
        (
            "0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n",
            (11, 5),
            "vertex.z",
            "expected a number for `z`, found `x`",
        ),
        (
            "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n",
            (11, 1),
            "vertex.x",
            "`x` is NaN, not a finite number",
        ),
        (
            "0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n",
            (12, 5),
            "vertex.z",
            "`z` is inf, not a finite number",
        ),
        (
            "0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n",
            (10, 7),
            "vertex",
            "more values on its line",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
            (13, 7),
            "face.vertex_indices",
            "vertex index 3 is out of range: the file has 3 vertices",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
            (13, 5),
            "face.vertex_indices",
            "vertex index -1 is out of range",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
            (13, 5),
            "face.vertex_indices",
            "at least 3 corners, found 2",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n",
            (13, 1),
            "face.vertex_indices",
            "300 is outside the range of its type (0 to 255)",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n",
            (13, 5),
            "face.vertex_indices",
            "expected a whole number",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n9 9 9\n",
            (14, 1),
            "end_header",
            "more lines than the header declares",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
            (13, 6),
            "face.vertex_indices",
            "its line ends before property `vertex_indices`",
        ),
    ];
    for &(body, place, key, message) in cases {
        let file = format!("{TRIANGLE_HEADER}{body}");
        let e = parse(file.as_bytes()).unwrap_err();
        assert!(e.message.contains(message), "{body:?}: {e}");
        assert_eq!(
            located(&e),
            (Some(place), Some(key.into())),
            "{body:?}: {e}"
        );
        // The span lies inside the file, on the line it names.
        let span = e.span.unwrap();
        assert!(span.offset + span.len <= file.len(), "{body:?}: {span:?}");
        assert_eq!(
            file[..span.offset].matches('\n').count() + 1,
            span.line,
            "{body:?}"
        );
    }
    // Blank lines between elements and at the end, and CRLF line ends, are fine.
    let file = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n0 0 0\r\n\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n\r\n";
    assert_eq!(triangles(&parse(file.as_bytes()).unwrap()), vec![[0, 1, 2]]);
}

/// The triangle as a binary file (x y z floats; a uchar/int list), little-endian.
fn binary_triangle(corners: &[f64]) -> Vec<u8> {
    encode(
        &[
            Elem {
                name: "vertex",
                props: xyz("float"),
                rows: square_vertices()[..3].to_vec(),
            },
            Elem {
                name: "face",
                props: vec![list("uchar", "int", "vertex_indices")],
                rows: vec![vec![corners.to_vec()]],
            },
        ],
        Encoding::Little,
    )
}

#[test]
fn a_damaged_binary_body_is_an_error_at_its_byte() {
    let good = binary_triangle(&[0.0, 1.0, 2.0]);
    // Where the body starts: before three vertices of three floats, and a face of three.
    let body = good.len() - (3 * 12 + 1 + 3 * 4);
    parse(&good).unwrap();
    // An index past the vertices, and a negative one: at the index's byte.
    for (corners, bad, message) in [
        (&[0.0, 1.0, 3.0][..], 2, "vertex index 3 is out of range"),
        (&[0.0, -2.0, 1.0][..], 1, "vertex index -2 is out of range"),
    ] {
        let e = parse(&binary_triangle(corners)).unwrap_err();
        let byte = body + 36 + 1 + 4 * bad;
        assert!(
            e.message
                .contains(&format!("at byte {byte}, face #0: {message}")),
            "{e}"
        );
        assert_eq!(
            located(&e),
            (None, Some("face.vertex_indices".into())),
            "{e}"
        );
    }
    // A NaN coordinate: vertex 1's y.
    let mut nan = good.clone();
    let y1 = body + 12 + 4;
    nan[y1..y1 + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = parse(&nan).unwrap_err();
    assert!(
        e.message
            .contains(&format!("at byte {y1}, vertex #1: `y` is NaN")),
        "{e}"
    );
    assert_eq!(e.key.as_deref(), Some("vertex.y"), "{e}");
    // Cut inside the vertices: refused from the header, at the element's line.
    let e = parse(&good[..body + 20]).unwrap_err();
    assert!(e.message.contains("the header declares 3 `vertex` elements, which need at least 36 bytes, but the file has 20 after its header"), "{e}");
    assert_eq!(located(&e), (Some((5, 16)), Some("vertex".into())), "{e}");
    // Cut inside the face's list: at the end of the file, naming the property.
    let e = parse(&good[..good.len() - 2]).unwrap_err();
    assert!(
        e.message
            .contains("a list of 3 values, more than the rest of the file holds"),
        "{e}"
    );
    assert_eq!(e.key.as_deref(), Some("face.vertex_indices"), "{e}");
    // A list count of 2^32 - 1 is refused before it is read.
    let mut huge = String::from_utf8_lossy(&good[..body])
        .replace("list uchar int", "list uint int")
        .into_bytes();
    huge.extend(&good[body..body + 36]);
    huge.extend(u32::MAX.to_le_bytes());
    huge.extend([0; 12]);
    let e = parse(&huge).unwrap_err();
    assert!(
        e.message
            .contains("a list of 4294967295 values, more than the rest of the file holds"),
        "{e}"
    );
    // Gzip data that is not gzip is an error, not a panic.
    let mut zipped = gzip(&good);
    let n = zipped.len();
    zipped[n / 2..].fill(0xAA);
    let e = parse(&zipped).unwrap_err();
    assert!(
        e.message.contains("not a readable gzip file") || e.message.contains("cut short"),
        "{e}"
    );
}

/// Issue 44's rule: a header's counts are checked against the limits and the file before
/// anything is allocated for them.
#[test]
fn huge_counts_in_a_header_are_refused_before_anything_is_allocated_for_them() {
    let header = |vertices: u64, faces: u64| {
        format!("ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\nelement face {faces}\nproperty list uchar int vertex_indices\nend_header\n")
            .into_bytes()
    };
    let e = parse(&header(1 << 40, 1)).unwrap_err();
    assert!(e.message.contains("the header declares 1099511627776 `vertex` elements, more than 30000000, three per triangle of the mesh size limit"), "{e}");
    assert_eq!(located(&e), (Some((3, 16)), Some("vertex".into())), "{e}");
    let e = parse(&header(3, 1 << 40)).unwrap_err();
    assert!(
        e.message.contains("`face` elements, more than 10000000"),
        "{e}"
    );
    // With no limit on triangles, the file's size still holds: 2^40 vertices need 12 TiB.
    let e = parse_ply(&header(1 << 40, 1), Path::new("model.ply"), usize::MAX).unwrap_err();
    assert!(
        e.message
            .contains("which need at least 13194139533312 bytes, but the file has 0"),
        "{e}"
    );
    let e = parse_ply(&header(u64::MAX, 1), Path::new("model.ply"), usize::MAX).unwrap_err();
    assert!(
        e.message.contains("need at least more than 2^64 bytes"),
        "{e}"
    );
    // Compressed, the header is read and refused before the body is inflated.
    let e = parse(&gzip(&header(1 << 40, 1))).unwrap_err();
    assert!(e.message.contains("1099511627776 `vertex` elements"), "{e}");
    // Quads count twice against the limit.
    let quads = encode(
        &[
            Elem {
                name: "vertex",
                props: xyz("float"),
                rows: square_vertices(),
            },
            faces(
                "uchar",
                "int",
                "vertex_indices",
                &[&[0, 1, 2, 3], &[0, 1, 2, 3]],
            ),
        ],
        Encoding::Ascii,
    );
    parse_ply(&quads, Path::new("model.ply"), 4).unwrap();
    let e = parse_ply(&quads, Path::new("model.ply"), 3).unwrap_err();
    assert!(e.message.contains("more than 3 triangles"), "{e}");
    assert_eq!(e.span.map(|s| s.line), Some(18), "{e}");
}

#[test]
fn a_file_that_is_not_a_mesh_is_an_error() {
    let no_faces = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
    let e = parse(no_faces.as_bytes()).unwrap_err();
    assert!(e.message.contains("no faces"), "{e}");
    let no_z = TRIANGLE_HEADER.replace("property float z\n", "");
    let e = parse(format!("{no_z}0 0\n1 0\n0 1\n3 0 1 2\n").as_bytes()).unwrap_err();
    assert!(e.message.contains("no property `z`"), "{e}");
    assert_eq!(located(&e), (Some((3, 16)), Some("vertex".into())), "{e}");
    let no_list = TRIANGLE_HEADER.replace("vertex_indices", "corners");
    let e = parse(format!("{no_list}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").as_bytes()).unwrap_err();
    assert!(e.message.contains("no `vertex_indices`"), "{e}");
    let float_list = TRIANGLE_HEADER.replace("uchar int", "uchar float");
    let e = parse(format!("{float_list}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").as_bytes()).unwrap_err();
    assert!(e.message.contains("must be a list of whole numbers"), "{e}");
    let no_vertices = "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n";
    let e = parse(no_vertices.as_bytes()).unwrap_err();
    assert!(e.message.contains("no `vertex` element"), "{e}");
    let e = parse(b"").unwrap_err();
    assert!(e.message.contains("not a PLY model"), "{e}");
}

fn write(path: &Path, bytes: &[u8]) -> PathBuf {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, bytes).unwrap();
    path.to_path_buf()
}

const CAMERA: &str = "- add: camera
  width: 4
  height: 4
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

fn load_in(
    dir: &Path,
    body: &str,
    options: &LoadOptions,
) -> Result<rayforge_scene::Scene, SceneError> {
    let path = dir.join("scene.yml");
    std::fs::write(&path, format!("{CAMERA}{body}")).unwrap();
    load_file_with(&path, options)
}

fn triangle_file() -> Vec<u8> {
    format!("{TRIANGLE_HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes()
}

#[test]
fn add_ply_places_the_model_with_the_items_material() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("models/tri.ply"), &triangle_file());
    write(
        &dir.path().join("models/tri.ply.gz"),
        &gzip(&triangle_file()),
    );
    let scene = load_in(
        dir.path(),
        "- add: ply\n  file: models/tri.ply\n  material: {color: [1, 0, 0]}\n  transform: [[translate, 0, 0, 2]]\n- add: ply\n  file: models/tri.ply.gz\n",
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(scene.world.objects.len(), 2);
    assert_eq!(
        scene.world.objects[0].material.color,
        rayforge::Color::new(1.0, 0.0, 0.0)
    );
    let rayforge::Shape::Mesh(mesh) = &scene.world.objects[1].shape else {
        panic!("not a mesh");
    };
    assert_eq!(mesh.face_count(), 1);
    assert!(scene.files.contains(&dir.path().join("models/tri.ply")));
    // Its keys are checked as a model's.
    let e = load_in(
        dir.path(),
        "- add: ply\n  file: models/tri.ply\n  colour: red\n",
        &LoadOptions::default(),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("colour"), "{e}");
    let e = load_in(dir.path(), "- add: ply\n", &LoadOptions::default()).unwrap_err();
    assert!(e.message.contains("a ply needs `file:`"), "{e}");
    // The scene's triangles together are held to the limit.
    let two = LoadOptions {
        max_triangles: 1,
        ..LoadOptions::default()
    };
    let e = load_in(
        dir.path(),
        "- add: ply\n  file: models/tri.ply\n- add: ply\n  file: models/tri.ply.gz\n",
        &two,
    )
    .unwrap_err();
    assert!(e.message.contains("more than 0"), "{e}");
}

#[test]
fn errors_inside_a_model_name_the_model_and_errors_about_it_name_the_scenes_file_key() {
    let dir = tempfile::tempdir().unwrap();
    let bad = format!("{TRIANGLE_HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    write(&dir.path().join("text.ply"), bad.as_bytes());
    write(
        &dir.path().join("binary.ply"),
        &binary_triangle(&[0.0, 1.0, 7.0]),
    );
    let item = |file: &str| format!("- add: ply\n  file: {file}\n");
    // Text: at its line and column in the model.
    let e = load_in(dir.path(), &item("text.ply"), &LoadOptions::default()).unwrap_err();
    assert_eq!(e.path, dir.path().join("text.ply"));
    assert_eq!(
        located(&e),
        (Some((13, 7)), Some("face.vertex_indices".into())),
        "{e}"
    );
    // Binary: at the scene's `file:`, naming the model, the property and the byte.
    let e = load_in(dir.path(), &item("binary.ply"), &LoadOptions::default()).unwrap_err();
    assert_eq!(e.path, dir.path().join("scene.yml"), "{e}");
    assert_eq!(e.span.map(|s| s.line), Some(9), "{e}");
    assert!(e.message.contains("binary.ply"), "{e}");
    assert!(e.message.contains("`face.vertex_indices`"), "{e}");
    assert!(e.message.contains("at byte"), "{e}");
    // A missing file: at the scene's `file:`.
    let e = load_in(dir.path(), &item("missing.ply"), &LoadOptions::default()).unwrap_err();
    assert_eq!(e.path, dir.path().join("scene.yml"), "{e}");
    assert!(e.message.contains("No such file"), "{e}");
}

#[cfg(unix)]
#[test]
fn a_model_is_opened_as_untrusted_input() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("scene");
    let secret = write(&root.path().join("secret.ply"), &triangle_file());
    write(&dir.join("inside.ply"), &triangle_file());
    std::os::unix::fs::symlink(&secret, dir.join("link.ply")).unwrap();
    std::os::unix::fs::symlink(dir.join("inside.ply"), dir.join("near.ply")).unwrap();
    std::fs::create_dir(dir.join("folder.ply")).unwrap();
    let fifo = dir.join("pipe.ply");
    let status = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(status.success());
    let item = |file: &str| format!("- add: ply\n  file: {file}\n");
    // Out of the scene's folder, by name or by link: refused, unless allowed.
    for file in ["../secret.ply", "link.ply"] {
        let e = load_in(&dir, &item(file), &LoadOptions::default()).unwrap_err();
        assert!(
            e.message.contains("outside the scene's folder"),
            "{file}: {e}"
        );
        assert_eq!(located(&e), (Some((9, 9)), Some("file".into())), "{e}");
        let allowed = LoadOptions {
            allow_outside: true,
            ..LoadOptions::default()
        };
        load_in(&dir, &item(file), &allowed).unwrap();
    }
    // A link that stays inside is followed.
    load_in(&dir, &item("near.ply"), &LoadOptions::default()).unwrap();
    // A named pipe and a directory: refused at once, without waiting for a writer.
    let started = std::time::Instant::now();
    for (file, what) in [("pipe.ply", "a named pipe"), ("folder.ply", "a directory")] {
        let e = load_in(&dir, &item(file), &LoadOptions::default()).unwrap_err();
        assert!(
            e.message
                .contains(&format!("it is not a regular file (it is {what})")),
            "{e}"
        );
        let e = read_ply_file(&dir.join(file), DEFAULT_MAX_TRIANGLES).unwrap_err();
        assert!(e.message.contains(what), "{e}");
    }
    assert!(started.elapsed().as_secs() < 30);
}

/// A cube of six quads, as PLY (binary and text) and as OBJ with the same corners in the same
/// order: the OBJ reader fans each quad as (1 2 3), (1 3 4), the cut pbrt-v4 makes, so the
/// meshes are the same and so are the path tracer's images, byte for byte.
#[test]
fn a_ply_cube_renders_as_the_same_cube_written_as_obj() {
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                (i & 1) as f64 - 0.5,
                ((i >> 1) & 1) as f64 - 0.5,
                ((i >> 2) & 1) as f64 - 0.5,
            ]
        })
        .collect();
    // Each face counter-clockwise seen from outside, in right-handed axes.
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    // The corners in the order the faces first use them, as the OBJ reader keeps them.
    let mut order: Vec<u32> = Vec::new();
    for &i in quads.iter().flatten() {
        if !order.contains(&i) {
            order.push(i);
        }
    }
    let corners: Vec<[f64; 3]> = order.iter().map(|&i| corners[i as usize]).collect();
    let quads = quads.map(|q| q.map(|i| order.iter().position(|&o| o == i).unwrap() as u32));
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::new();
    for c in &corners {
        obj += &format!("v {} {} {}\n", c[0], c[1], c[2]);
    }
    for q in &quads {
        obj += &format!("f {} {} {} {}\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
    }
    write(&dir.path().join("cube.obj"), obj.as_bytes());
    let rows: Vec<Vec<Vec<f64>>> = corners
        .iter()
        .map(|c| c.iter().map(|&x| vec![x]).collect())
        .collect();
    let quad_refs: Vec<&[u32]> = quads.iter().map(|q| &q[..]).collect();
    for (name, encoding) in [
        ("cube.ply", Encoding::Little),
        ("cube-text.ply", Encoding::Ascii),
    ] {
        let file = encode(
            &[
                Elem {
                    name: "vertex",
                    props: xyz("float"),
                    rows: rows.clone(),
                },
                faces("uchar", "int", "vertex_indices", &quad_refs),
            ],
            encoding,
        );
        write(&dir.path().join(name), &file);
    }
    let scene = |kind: &str, file: &str| {
        load_in(
            dir.path(),
            &format!(
                "- world:\n    renderer: path\n    background: [0.6, 0.7, 0.8]\n- add: {kind}\n  file: {file}\n  transform: [[rotate-y, 0.6], [rotate-x, 0.4]]\n  material: {{type: diffuse, color: [0.8, 0.3, 0.2]}}\n"
            ),
            &LoadOptions::default(),
        )
        .unwrap()
    };
    let obj_scene = scene("obj", "cube.obj");
    let reference = support::render(&obj_scene, 24, 24, 4).resolve();
    let mesh_of = |s: &rayforge_scene::Scene| match &s.world.objects[0].shape {
        rayforge::Shape::Mesh(m) => m.clone(),
        _ => panic!("not a mesh"),
    };
    for file in ["cube.ply", "cube-text.ply"] {
        let ply_scene = scene("ply", file);
        let (ply, obj) = (mesh_of(&ply_scene), mesh_of(&obj_scene));
        assert_eq!(ply.positions(), obj.positions(), "{file}");
        assert_eq!(triangles(&ply), triangles(&obj), "{file}");
        assert_eq!(ply.winding(), obj.winding(), "{file}");
        let image = support::render(&ply_scene, 24, 24, 4).resolve();
        assert_eq!(image, reference, "{file}");
    }
    // Not a blank image: the cube is there, lit.
    assert!(
        reference
            .pixels()
            .iter()
            .any(|c| (c.red - c.blue).abs() > 0.1),
        "the cube is not seen"
    );
}
