//! The PLY reader as a fuzz target: [`run`] takes the bytes of a file (text, binary or gzip)
//! and renders what the reader made of it, and [`seeds`] writes the small files it starts from.
//! Kept a plain function of the input's bytes, so that any engine can call it.

use rayforge::{Object, World};
use rayforge_scene::ply::parse_ply;
use rayforge_scene::SceneError;
use std::io::Write;
use std::path::Path;

/// Runs one input: read as a PLY model with the fuzzing mesh limit, then rendered tiny.
/// Whether the reader accepted it. An error must say something and, when it points into the
/// file, lie inside it on the line it names (the command shows that line).
pub fn run(input: &[u8]) -> bool {
    let path = Path::new("fuzz-input.ply");
    match parse_ply(input, path, super::FUZZ_MAX_TRIANGLES) {
        Ok(mesh) => {
            assert!(mesh.face_count() > 0, "an accepted model has no faces");
            let mut world = World::new();
            world.objects.push(Object::mesh(std::sync::Arc::new(mesh)));
            super::lit_model_render(world);
            true
        }
        Err(e) => {
            check_error(&e, input);
            false
        }
    }
}

/// A refusal says something; a place in a file that is not compressed (a compressed one's
/// places are in its inflated text) lies inside the bytes, on the line it names.
fn check_error(e: &SceneError, input: &[u8]) {
    let shown = e.to_string();
    assert!(!e.message.trim().is_empty(), "an empty message: {shown}");
    let Some(span) = e.span else {
        return;
    };
    assert!(span.line >= 1 && span.column >= 1, "{shown}");
    if input.starts_with(&[0x1f, 0x8b]) {
        return;
    }
    let end = span.offset.checked_add(span.len);
    assert!(
        end.is_some_and(|end| end <= input.len()),
        "the error's span {span:?} is outside the file ({} bytes): {shown}",
        input.len()
    );
    let breaks = input[..span.offset].iter().filter(|&&b| b == b'\n').count();
    assert_eq!(
        breaks + 1,
        span.line,
        "the span {span:?} is not on its line: {shown}"
    );
    let line_start = input[..span.offset]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    assert_eq!(
        span.offset - line_start + 1,
        span.column,
        "{span:?}: {shown}"
    );
}

/// Small PLY files in each encoding: a tetrahedron of triangles and a quad, with normals and
/// texture coordinates, list types of each width, extra properties and elements, a polygon of
/// five corners, and the same compressed.
pub fn seeds() -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        out.push(tetrahedron(format, false));
        out.push(tetrahedron(format, true));
    }
    let gz = |bytes: &[u8]| {
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(bytes).expect("writing to memory");
        encoder.finish().expect("writing to memory")
    };
    out.push(gz(&out[0]));
    out.push(gz(&out[3]));
    out
}

/// A tetrahedron over a square base (the base one quad), `rich` with normals, texture
/// coordinates, a colour, a confidence list, an extra element and a pentagon.
fn tetrahedron(format: &str, rich: bool) -> Vec<u8> {
    let big = format == "binary_big_endian";
    let text = format == "ascii";
    let corners = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
    ];
    let mut faces: Vec<Vec<u32>> = vec![
        vec![0, 3, 2, 1],
        vec![0, 1, 4],
        vec![1, 2, 4],
        vec![2, 3, 4],
        vec![3, 0, 4],
    ];
    if rich {
        faces.push(vec![0, 1, 2, 4, 3]);
    }
    let mut header = format!("ply\nformat {format} 1.0\ncomment fuzz seed\n");
    if rich {
        header += "element material 1\nproperty uchar red\nproperty list uint8 float32 weights\n";
    }
    header += &format!("element vertex {}\n", corners.len());
    header += "property float x\nproperty float y\nproperty float z\n";
    if rich {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
        header += "property float s\nproperty float t\nproperty uchar red\n";
        header += "property list uchar double confidence\n";
    }
    header += &format!("element face {}\n", faces.len());
    header += if rich {
        "property int face_indices\nproperty list int uint vertex_index\n"
    } else {
        "property list uchar int vertex_indices\n"
    };
    header += "end_header\n";
    let mut out = header.into_bytes();
    let mut words: Vec<String> = Vec::new();
    let put = |out: &mut Vec<u8>, value: f64, ty: &str, words: &mut Vec<String>| {
        if text {
            words.push(if ty == "f32" || ty == "f64" {
                format!("{value}")
            } else {
                format!("{}", value as i64)
            });
            return;
        }
        let mut bytes = match ty {
            "u8" => vec![value as u8],
            "i32" => (value as i32).to_le_bytes().to_vec(),
            "u32" => (value as u32).to_le_bytes().to_vec(),
            "f32" => (value as f32).to_le_bytes().to_vec(),
            _ => value.to_le_bytes().to_vec(),
        };
        if big {
            bytes.reverse();
        }
        out.extend(bytes);
    };
    let end_line = |out: &mut Vec<u8>, words: &mut Vec<String>| {
        if text {
            out.extend(words.join(" ").into_bytes());
            out.push(b'\n');
            words.clear();
        }
    };
    if rich {
        put(&mut out, 7.0, "u8", &mut words);
        put(&mut out, 2.0, "u8", &mut words);
        put(&mut out, 0.25, "f32", &mut words);
        put(&mut out, 0.75, "f32", &mut words);
        end_line(&mut out, &mut words);
    }
    for (i, c) in corners.iter().enumerate() {
        for &x in c {
            put(&mut out, f64::from(x), "f32", &mut words);
        }
        if rich {
            for x in [0.0, 0.6, 0.8, c[0].into(), c[1].into(), 200.0] {
                put(
                    &mut out,
                    x,
                    if x == 200.0 { "u8" } else { "f32" },
                    &mut words,
                );
            }
            put(&mut out, i as f64, "u8", &mut words);
            for k in 0..i {
                put(&mut out, k as f64 * 0.5, "f64", &mut words);
            }
        }
        end_line(&mut out, &mut words);
    }
    for (i, f) in faces.iter().enumerate() {
        if rich {
            put(&mut out, i as f64, "i32", &mut words);
            put(&mut out, f.len() as f64, "i32", &mut words);
            for &v in f {
                put(&mut out, f64::from(v), "u32", &mut words);
            }
        } else {
            put(&mut out, f.len() as f64, "u8", &mut words);
            for &v in f {
                put(&mut out, f64::from(v), "i32", &mut words);
            }
        }
        end_line(&mut out, &mut words);
    }
    out
}
