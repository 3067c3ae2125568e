//! Seed inputs: the repository's own scenes and models, the inputs written for the fuzzer in
//! `corpus/`, the community scenes and models and the Khronos glTF samples where they lie
//! beside the repository (`../shared`, read there, never copied in; a clone without it fuzzes
//! from the rest), and small images made here in every format and colour type the decoder
//! reads.

use crate::targets::repo_root;
use std::path::Path;

/// The longest input fuzzed, and the longest seed handed to the engine: past the live page's
/// limit on a message (64 KiB), so that the limit is met. Longer seeds (the 122 KB benchmark
/// scene) are replayed by `cargo test` but not handed to the engine, which would spend its
/// first pass on them (an AFL++ run stayed on that scene, 10 inputs/s, for all its 8 minutes).
pub const MAX_LEN: usize = 72 << 10;

/// The seeds of the target called `name`, in a fixed order: the files under `corpus/NAME/`
/// (sorted by path), and for the targets that have them, the repository's own files of the
/// kind, those of the project's shared folder (`../shared`, read there, never copied in; a
/// clone without it fuzzes from the rest) and inputs generated here. Never empty: a target
/// with no seed at all starts from the empty input.
pub fn seeds(name: &str) -> Vec<Vec<u8>> {
    let root = repo_root();
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    let shared = root.join("../shared");
    let mut seeds = Vec::new();
    files_under(&corpus.join(name), &[], &mut seeds);
    match name {
        "scene" => {
            files_under(&root.join("scenes"), &["yml", "yaml"], &mut seeds);
            files_under(&shared.join("community-scenes"), &["yml"], &mut seeds);
            file(&shared.join("models/bounding-boxes.yml"), &mut seeds);
        }
        "obj" => {
            files_under(&root.join("scenes"), &["obj", "mtl"], &mut seeds);
            file(&shared.join("models/suzanne-low.obj"), &mut seeds);
        }
        "image" => seeds.extend(generated_images()),
        "ply" => seeds.extend(crate::targets::ply::seeds()),
        "pbrt" => seeds.extend(crate::targets::pbrt::seeds()),
        "denoise" => seeds.extend(crate::targets::denoise::seeds()),
        "gltf" => files_under(&shared.join("models/gltf"), &["gltf", "glb"], &mut seeds),
        "page" => seeds.extend(page_messages()),
        _ => {}
    }
    if seeds.is_empty() {
        seeds.push(Vec::new());
    }
    seeds
}

/// Writes the seeds of the target `name` that are no longer than [`MAX_LEN`] into `dir` (made
/// if missing) as `seed-<nnn>`, the starting corpus of a `cargo bolero test` run; how many
/// were written. Files already there (what the engine kept from earlier runs) stay.
pub fn write_seeds(name: &str, dir: &Path) -> std::io::Result<usize> {
    std::fs::create_dir_all(dir)?;
    let seeds: Vec<_> = seeds(name)
        .into_iter()
        .filter(|s| s.len() <= MAX_LEN)
        .collect();
    for (i, seed) in seeds.iter().enumerate() {
        std::fs::write(dir.join(format!("seed-{i:03}")), seed)?;
    }
    Ok(seeds.len())
}

/// The file at `path`, where there is one.
fn file(path: &Path, out: &mut Vec<Vec<u8>>) {
    out.extend(std::fs::read(path).ok());
}

/// The files under `dir` (recursively) with one of `extensions` (any, if none), sorted by path.
fn files_under(dir: &Path, extensions: &[&str], out: &mut Vec<Vec<u8>>) {
    let mut paths = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if extensions.is_empty() && !path.ends_with("README.md")
                || path
                    .extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| extensions.contains(&e))
            {
                paths.push(path);
            }
        }
    }
    paths.sort();
    out.extend(paths.iter().filter_map(|p| std::fs::read(p).ok()));
}

/// Small images in each format and colour type the texture reader takes: PNG (grey, grey with
/// alpha, RGB, RGBA, 16-bit, palette), JPEG (colour and grey, baseline), and the PNM family in
/// text and binary forms.
pub fn generated_images() -> Vec<Vec<u8>> {
    use image::{ExtendedColorType, ImageEncoder};
    let (w, h) = (5u32, 3u32);
    let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i * 37 % 256) as u8).collect();
    let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * 53 % 256) as u8).collect();
    let grey: Vec<u8> = (0..w * h).map(|i| (i * 17 % 256) as u8).collect();
    let grey_alpha: Vec<u8> = (0..w * h * 2).map(|i| (i * 29 % 256) as u8).collect();
    let rgb16: Vec<u8> = (0..w * h * 6).map(|i| (i * 11 % 256) as u8).collect();
    let mut out = Vec::new();
    let png = |data: &[u8], colour| {
        let mut bytes = Vec::new();
        image::codecs::png::PngEncoder::new(&mut bytes)
            .write_image(data, w, h, colour)
            .map(|()| bytes)
            .ok()
    };
    out.extend(png(&rgb, ExtendedColorType::Rgb8));
    out.extend(png(&rgba, ExtendedColorType::Rgba8));
    out.extend(png(&grey, ExtendedColorType::L8));
    out.extend(png(&grey_alpha, ExtendedColorType::La8));
    out.extend(png(&rgb16, ExtendedColorType::Rgb16));
    out.push(palette_png());
    let jpeg = |data: &[u8], colour| {
        let mut bytes = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 80)
            .write_image(data, w, h, colour)
            .map(|()| bytes)
            .ok()
    };
    out.extend(jpeg(&rgb, ExtendedColorType::Rgb8));
    out.extend(jpeg(&grey, ExtendedColorType::L8));
    out.push(b"P3\n# a comment\n2 2\n255\n255 0 0  0 255 0\n0 0 255  255 255 255\n".to_vec());
    out.push(b"P2\n3 1\n65535\n0 32768 65535\n".to_vec());
    out.push(b"P1\n4 2\n1 0 1 0\n0 1 0 1\n".to_vec());
    let mut p6 = format!("P6\n{w} {h}\n255\n").into_bytes();
    p6.extend_from_slice(&rgb);
    out.push(p6);
    let mut p5 = format!("P5\n{w} {h}\n255\n").into_bytes();
    p5.extend_from_slice(&grey);
    out.push(p5);
    out.push(b"P4\n8 2\n\xa5\x5a".to_vec());
    let mut pam =
        format!("P7\nWIDTH {w}\nHEIGHT {h}\nDEPTH 4\nMAXVAL 255\nTUPLTYPE RGB_ALPHA\nENDHDR\n")
            .into_bytes();
    pam.extend_from_slice(&rgba);
    out.push(pam);
    out.extend(hdr_images());
    out
}

/// Requests as the live page sends them (see the page target): the headers a browser on this
/// machine sends, then a message.
fn page_messages() -> Vec<Vec<u8>> {
    let port = crate::targets::PAGE_PORT;
    let heads = [
        format!("127.0.0.1:{port}\nhttp://127.0.0.1:{port}"),
        format!("localhost:{port}\n-"),
        format!("[::1]:{port}\nhttp://[::1]:{port}"),
        format!("evil.example:{port}\nhttp://evil.example"),
    ];
    let messages = [
        r#"{"type": "render"}"#,
        r#"{"type": "render", "renderer": "ray", "lighting": "phong", "samples": 4, "width": 320, "height": 180, "yaw": 30, "pitch": -10, "preview": false}"#,
        r#"{"type": "render", "renderer": "path", "samples": null, "width": 64, "height": 64, "yaw": -720.5, "pitch": 95, "preview": true}"#,
        r#"{"type": "render", "renderer": "raster", "lighting": "cgfs", "yaw": 1e308, "pitch": -0.0}"#,
        r#"{"type": "render", "lighting": "optics", "samples": 18446744073709551615}"#,
        r#"{"type": "stop"}"#,
        r#"[1, 2, {"type": "render"}]"#,
    ];
    let mut out = Vec::new();
    for (i, head) in heads.iter().enumerate() {
        for message in messages.iter().skip(i % 2) {
            out.push(format!("{head}\n{message}").into_bytes());
        }
    }
    out
}

/// Seeds in the three HDR formats an image may also be (see `rayforge_scene::hdr`): OpenEXR
/// in half and float and in each compression the `exr` crate writes, Radiance RGBE flat and
/// run-length encoded, and PFM in colour and grey and both byte orders.
fn hdr_images() -> Vec<Vec<u8>> {
    use exr::prelude::{
        f16, Compression, Encoding, Image, Layer, LayerAttributes, LineOrder, SpecificChannels,
        Vec2, WritableImage,
    };
    let mut out = Vec::new();
    let value = |x: usize, y: usize, c: usize| ((x * 3 + y * 7 + c) % 11) as f32 * 0.75 - 1.5;
    for compression in [
        Compression::Uncompressed,
        Compression::RLE,
        Compression::ZIP1,
        Compression::ZIP16,
        Compression::PIZ,
        Compression::PXR24,
    ] {
        let encoding = Encoding {
            compression,
            blocks: exr::prelude::Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        };
        let mut bytes = std::io::Cursor::new(Vec::new());
        let written = if compression == Compression::ZIP1 {
            let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
                let h = |c| f16::from_f32(value(x, y, c));
                (h(0), h(1), h(2), h(3))
            });
            Image::from_layer(Layer::new(
                (5, 3),
                LayerAttributes::default(),
                encoding,
                channels,
            ))
            .write()
            .to_buffered(&mut bytes)
        } else {
            let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                (value(x, y, 0), value(x, y, 1), value(x, y, 2))
            });
            Image::from_layer(Layer::new(
                (5, 3),
                LayerAttributes::default(),
                encoding,
                channels,
            ))
            .write()
            .to_buffered(&mut bytes)
        };
        if written.is_ok() {
            out.push(bytes.into_inner());
        }
    }
    let pixels: Vec<image::Rgb<f32>> = (0..15)
        .map(|i| image::Rgb([0, 1, 2].map(|c| value(i % 5, i / 5, c).abs() * 40.0)))
        .collect();
    for width in [5, 16] {
        // The encoder run-length encodes rows of 8 to 32 767 pixels and writes others flat.
        let rows: Vec<image::Rgb<f32>> = pixels.iter().cycle().take(width * 3).copied().collect();
        let mut bytes = Vec::new();
        if image::codecs::hdr::HdrEncoder::new(&mut bytes)
            .encode(&rows, width, 3)
            .is_ok()
        {
            out.push(bytes);
        }
    }
    for (magic, channels, scale) in [("PF", 3, "-1.0"), ("PF", 3, "1.0"), ("Pf", 1, "-2.5")] {
        let mut bytes = format!("{magic}\n5 3\n{scale}\n").into_bytes();
        for i in 0..15 * channels {
            let v = value(i % 5, i / 15, i % 3);
            if scale.starts_with('-') {
                bytes.extend_from_slice(&v.to_le_bytes());
            } else {
                bytes.extend_from_slice(&v.to_be_bytes());
            }
        }
        out.push(bytes);
    }
    out
}

/// A 4×2 PNG with a four-colour palette and transparency, written chunk by chunk.
fn palette_png() -> Vec<u8> {
    palette_png_with(&[255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255])
}

/// A 4×2 palette PNG (pixels 0 1 2 3 / 3 2 1 0) with these bytes as its `PLTE` chunk,
/// checksums correct whatever they are.
pub fn palette_png_with(palette: &[u8]) -> Vec<u8> {
    // 4×2, bit depth 8, colour type 3 (palette).
    let header = [0, 0, 0, 4, 0, 0, 0, 2, 8, 3, 0, 0, 0];
    // Two rows, filter 0, stored in a zlib stream without compression.
    let raw = [0u8, 0, 1, 2, 3, 0, 3, 2, 1, 0];
    let mut zlib = vec![0x78, 0x01, 1, raw.len() as u8, 0, !(raw.len() as u8), 0xff];
    zlib.extend_from_slice(&raw);
    zlib.extend_from_slice(&adler32(&raw).to_be_bytes());
    png(&[
        (b"IHDR", &header),
        (b"PLTE", palette),
        (b"tRNS", &[255, 128, 0]),
        (b"IDAT", &zlib),
        (b"IEND", &[]),
    ])
}

/// A PNG file of these chunks, each with its length and CRC.
pub fn png(chunks: &[(&[u8; 4], &[u8])]) -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for (kind, data) in chunks {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        png.extend_from_slice(&body);
        png.extend_from_slice(&crc32fast::hash(&body).to_be_bytes());
    }
    png
}

fn adler32(bytes: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for &x in bytes {
        a = (a + u32::from(x)) % 65521;
        b = (b + a) % 65521;
    }
    (b << 16) | a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_carries_its_crc32() {
        let iend = png(&[(b"IEND", &[])]);
        assert_eq!(iend[8..], *b"\0\0\0\0IEND\xAE\x42\x60\x82");
    }

    #[test]
    fn every_generated_image_decodes() {
        let images = generated_images();
        // 15 8-bit images; 6 OpenEXR, 2 Radiance and 3 PFM.
        assert_eq!(images.len(), 26);
        for (i, bytes) in images.iter().enumerate() {
            let t = rayforge_scene::texture_from_bytes(bytes, Path::new("seed"));
            assert!(t.is_ok(), "seed image {i}: {:?}", t.err());
        }
    }

    #[test]
    fn written_seeds_are_the_seeds() {
        let dir = tempfile::tempdir().unwrap();
        let n = write_seeds("obj", dir.path()).unwrap();
        assert_eq!(n, seeds("obj").len());
        let first = std::fs::read(dir.path().join("seed-000")).unwrap();
        assert_eq!(first, seeds("obj")[0]);
    }

    #[test]
    fn seeds_past_the_longest_input_are_not_written() {
        let dir = tempfile::tempdir().unwrap();
        let all = seeds("scene");
        let short = all.iter().filter(|s| s.len() <= MAX_LEN);
        assert!(
            short.clone().count() < all.len(),
            "the benchmark scene is a long seed"
        );
        let n = write_seeds("scene", dir.path()).unwrap();
        assert_eq!(n, short.count());
    }

    #[test]
    fn the_repositorys_files_are_seeds() {
        assert!(seeds("scene").len() >= 14);
        assert!(seeds("obj").len() >= 4);
        // The corpus folder's own files, its README left out.
        assert_eq!(seeds("part").len(), 6);
        assert_eq!(seeds("no such target"), [Vec::<u8>::new()]);
    }
}
