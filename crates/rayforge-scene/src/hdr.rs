//! High-dynamic-range images (environment maps): OpenEXR, Radiance RGBE (`.hdr`) and PFM,
//! read into linear RGB colours, bounded like every file a scene names.
//!
//! The format is told by the file's first bytes, not its name. Every reader checks the size the
//! header declares against the pixel limit and costs the memory reading it takes (the file, the
//! decoder's buffers, the colours and the environment map's sampling tables) against the room
//! left for the scene's images, before it allocates anything for pixels; the large buffers are
//! taken fallibly, and the third-party decoders (EXR, RGBE) run under `catch_unwind`, so a
//! hostile or damaged file is an error naming the file, never a crash or an exhausted memory.

use crate::files::read_bounded;
use crate::images::{
    fallible_vec, guarded, to_colors, Room, ENVIRONMENT_BYTES_PER_TEXEL, MAX_IMAGE_BYTES,
    MAX_TEXTURE_PIXELS,
};
use rayforge::color::Color;
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// A decoded HDR image: `width × height` linear RGB texels, row by row from the top row of the
/// picture, each row from the left: the layout an environment map wants.
#[derive(Debug, Clone, PartialEq)]
pub struct HdrImage {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Row-major texels, row 0 the top of the image.
    pub texels: Vec<Color>,
}

/// Why an HDR image could not be read: the file, and what is wrong with it, so the message
/// alone tells a user which file to fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("cannot read the HDR image `{}`: {reason}", path.display())]
pub struct HdrError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong.
    pub reason: String,
}

/// Reads the OpenEXR (first RGB layer; half, float or integer channels; alpha ignored),
/// Radiance RGBE or PFM image at `path` for an environment map, refusing images of more than
/// [`MAX_TEXTURE_PIXELS`] pixels or whose reading would take more than `room` allows before
/// their pixels are allocated, files over [`MAX_IMAGE_BYTES`], truncated or malformed data, and
/// non-finite values, each with an error naming the file.
pub fn read_hdr_image(path: &Path, room: Room) -> Result<HdrImage, HdrError> {
    let fail = |reason: String| HdrError {
        path: path.to_path_buf(),
        reason,
    };
    let bytes = read_bounded(path, MAX_IMAGE_BYTES).map_err(&fail)?;
    decode_hdr_image(&bytes, room, ENVIRONMENT_BYTES_PER_TEXEL)
        .unwrap_or_else(|| {
            Err(
                "it is not an OpenEXR, Radiance HDR (RGBE) or PFM image (its first bytes are \
                 none of theirs)"
                    .to_string(),
            )
        })
        .map_err(fail)
}

/// Decodes the OpenEXR, Radiance HDR or PFM image in `bytes` (`None` when they are none of
/// these), refusing it before its pixels are allocated when the file held, the decoder's own
/// buffers and `bytes_per_texel` for each texel kept would not fit in `room`, and refusing
/// non-finite values. The error is the reason, for the caller to name the file.
pub fn decode_hdr_image(
    bytes: &[u8],
    room: Room,
    bytes_per_texel: u64,
) -> Option<Result<HdrImage, String>> {
    let cost = |width: u64, height: u64, buffers: u64| -> Result<(), String> {
        check_size(width, height)?;
        let cost = bytes.len() as u64 + buffers + width * height * bytes_per_texel;
        room.check(cost, &format!("a {width}×{height} HDR image"))
    };
    let image = if bytes.starts_with(&EXR_MAGIC) {
        read_exr(bytes, &cost)
    } else if bytes.starts_with(b"#?") {
        read_rgbe(bytes, &cost)
    } else if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
        read_pfm(bytes, &cost)
    } else {
        return None;
    };
    Some(image.and_then(|image| {
        match image
            .texels
            .iter()
            .position(|c| !c.to_array().iter().all(|v| v.is_finite()))
        {
            Some(index) => {
                let c = image.texels[index];
                Err(format!(
                    "pixel (column {}, row {} from the top) is ({}, {}, {}): values must be \
                     finite",
                    index % image.width,
                    index / image.width,
                    c.red,
                    c.green,
                    c.blue
                ))
            }
            None => Ok(image),
        }
    }))
}

/// What a reader asks before it allocates for pixels: whether an image of this width and
/// height, whose decoder takes this many bytes of its own, may be read.
type Cost<'a> = &'a dyn Fn(u64, u64, u64) -> Result<(), String>;

/// The four bytes every OpenEXR file starts with.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Refuses a declared size that is empty or over the limits (of pixels, and of a side, as for
/// every image a scene reads), before anything is allocated for it.
fn check_size(width: u64, height: u64) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("the image is empty ({width}×{height} pixels)"));
    }
    if width.max(height) > u64::from(crate::images::MAX_TEXTURE_SIDE) {
        return Err(format!(
            "it is {width}×{height} pixels, more than {} pixels on a side, the limit",
            crate::images::MAX_TEXTURE_SIDE
        ));
    }
    match width.checked_mul(height) {
        Some(pixels) if pixels <= MAX_TEXTURE_PIXELS => Ok(()),
        _ => Err(format!(
            "it is {width}×{height} pixels, more than the limit of {MAX_TEXTURE_PIXELS} pixels"
        )),
    }
}

/// The first layer of an OpenEXR file that has R, G and B channels, at its full resolution.
fn read_exr(bytes: &[u8], cost: Cost<'_>) -> Result<HdrImage, String> {
    use exr::prelude::*;
    guarded(|| {
        let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
            .map_err(|e| format!("its OpenEXR header is invalid: {e}"))?;
        let has = |h: &exr::meta::header::Header, name: &str| {
            h.channels.list.iter().any(|c| c.name.eq(name))
        };
        let header = meta
            .headers
            .iter()
            .find(|h| !h.deep && has(h, "R") && has(h, "G") && has(h, "B"))
            .ok_or("it has no layer with R, G and B channels")?;
        // Every layer is held to the limits, not only the one read: the decoder reads each
        // layer's table of chunk offsets, whose length follows from the layer's size. The
        // decoder's own buffers are a block of the file at a time, counted as the file again.
        let mut largest = 0;
        for h in std::iter::once(header).chain(&meta.headers) {
            let size = h.layer_size;
            cost(
                size.width() as u64,
                size.height() as u64,
                bytes.len() as u64,
            )?;
            largest = largest.max(size.width() * size.height());
        }
        // Taken here, where failing is an error, and handed to the decoder, which would
        // otherwise allocate it infallibly; within its capacity, the resize cannot allocate.
        let texels = std::cell::Cell::new(fallible_vec(largest)?);
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .rgb_channels(
                |size, _| {
                    let mut texels = texels.take();
                    texels.resize(size.width() * size.height(), Color::BLACK);
                    HdrImage {
                        width: size.width(),
                        height: size.height(),
                        texels,
                    }
                },
                |image: &mut HdrImage, position, (r, g, b): (f32, f32, f32)| {
                    let index = position.y() * image.width + position.x();
                    if let Some(texel) = image.texels.get_mut(index) {
                        *texel = Color::new(f64::from(r), f64::from(g), f64::from(b));
                    }
                },
            )
            .first_valid_layer()
            .all_attributes()
            .non_parallel()
            .from_buffered(Cursor::new(bytes))
            .map_err(|e| format!("its OpenEXR data is invalid: {e}"))?;
        Ok(image.layer_data.channel_data.pixels)
    })
}

/// A Radiance RGBE (`.hdr`) file, by the `image` crate's decoder.
fn read_rgbe(bytes: &[u8], cost: Cost<'_>) -> Result<HdrImage, String> {
    use image::ImageDecoder;
    guarded(|| {
        let decoder = image::codecs::hdr::HdrDecoder::new(Cursor::new(bytes))
            .map_err(|e| format!("its Radiance HDR header is invalid: {e}"))?;
        let (w, h) = decoder.dimensions();
        let output = decoder.total_bytes();
        cost(u64::from(w), u64::from(h), output)?;
        let mut buffer = fallible_vec(output as usize)?;
        buffer.resize(output as usize, 0);
        let color = decoder.color_type();
        decoder
            .read_image(&mut buffer)
            .map_err(|e| format!("its Radiance HDR data is invalid: {e}"))?;
        let (width, height) = (w as usize, h as usize);
        Ok(HdrImage {
            width,
            height,
            texels: to_colors(&buffer, color, width * height)?,
        })
    })
}

/// The longest token of a PFM header read (a size or a scale): anything longer is not PFM.
const MAX_PFM_TOKEN: usize = 64;

/// A portable float map: `PF` (colour) or `Pf` (grey), whitespace, width, height, and a scale
/// whose sign gives the byte order (negative: little-endian) and whose size is ignored, then
/// exactly one whitespace byte and 32-bit floats, rows from the bottom of the picture up.
fn read_pfm(bytes: &[u8], cost: Cost<'_>) -> Result<HdrImage, String> {
    let channels: usize = match &bytes[..2] {
        b"PF" => 3,
        _ => 1,
    };
    let mut at = 2;
    let mut token = |what: &str| -> Result<&str, String> {
        let start_whitespace = at;
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        if at == start_whitespace {
            return Err(format!(
                "its PFM header is malformed: expected whitespace before the {what}"
            ));
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() && at - start <= MAX_PFM_TOKEN {
            at += 1;
        }
        if at == start || at - start > MAX_PFM_TOKEN {
            return Err(format!("its PFM header is malformed: no {what}"));
        }
        std::str::from_utf8(&bytes[start..at])
            .map_err(|_| format!("its PFM header is malformed: the {what} is not text"))
    };
    let number = |text: &str, what: &str| -> Result<u64, String> {
        text.parse::<u64>().map_err(|_| {
            format!("its PFM header is malformed: the {what} `{text}` is not a whole number")
        })
    };
    let width = number(token("width")?, "width")?;
    let height = number(token("height")?, "height")?;
    let scale_text = token("scale")?;
    let scale: f64 = scale_text.parse().map_err(|_| {
        format!("its PFM header is malformed: the scale `{scale_text}` is not a number")
    })?;
    if !scale.is_finite() || scale == 0.0 {
        return Err(format!(
            "its PFM scale is {scale}: it must be a non-zero number (its sign gives the byte order)"
        ));
    }
    let little_endian = scale < 0.0;
    // Exactly one whitespace byte ends the header.
    if !bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
        return Err("its PFM header does not end in a line break before the data".into());
    }
    let data = &bytes[at + 1..];
    cost(width, height, 0)?;
    let (w, h) = (width as usize, height as usize);
    let needed = (w * h)
        .checked_mul(channels * 4)
        .ok_or("its size overflows")?;
    if data.len() < needed {
        return Err(format!(
            "it is truncated: a {w}×{h} PFM needs {needed} bytes of data; it has {}",
            data.len()
        ));
    }
    let value = |k: usize| {
        let four: [u8; 4] = data[4 * k..4 * k + 4].try_into().expect("four bytes");
        f64::from(if little_endian {
            f32::from_le_bytes(four)
        } else {
            f32::from_be_bytes(four)
        })
    };
    let mut texels = fallible_vec(w * h)?;
    texels.resize(w * h, Color::BLACK);
    for (file_row, row) in texels.chunks_exact_mut(w).rev().enumerate() {
        for (column, texel) in row.iter_mut().enumerate() {
            let k = (file_row * w + column) * channels;
            *texel = if channels == 3 {
                Color::new(value(k), value(k + 1), value(k + 2))
            } else {
                let v = value(k);
                Color::new(v, v, v)
            };
        }
    }
    Ok(HdrImage {
        width: w,
        height: h,
        texels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::images::ImageMemory;
    use std::io::Write;

    /// Room for any test image.
    fn roomy() -> Room {
        ImageMemory::new(1 << 30).room()
    }

    /// Texels that tell rows, columns and channels apart, exactly representable in f16.
    fn known(w: usize, h: usize) -> Vec<Color> {
        (0..w * h)
            .map(|k| {
                let (x, y) = ((k % w) as f64, (k / w) as f64);
                Color::new(x + 0.25, y * 2.0 + 0.5, 100.0 + x * 8.0 + y)
            })
            .collect()
    }

    fn write_file(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
        let path = dir.path().join(name);
        std::fs::File::create(&path)
            .and_then(|mut f| f.write_all(bytes))
            .expect("write a test file");
        path
    }

    /// A PFM file of `texels` (row 0 the top), in the byte order the scale's sign gives.
    fn pfm(w: usize, h: usize, texels: &[Color], grey: bool, scale: &str) -> Vec<u8> {
        let magic = if grey { "Pf" } else { "PF" };
        let mut bytes = format!("{magic}\n{w} {h}\n{scale}\n").into_bytes();
        let little = scale.starts_with('-');
        for row in (0..h).rev() {
            for c in &texels[row * w..(row + 1) * w] {
                let channels = if grey {
                    vec![c.red]
                } else {
                    c.to_array().to_vec()
                };
                for v in channels {
                    let v = v as f32;
                    bytes.extend(if little {
                        v.to_le_bytes()
                    } else {
                        v.to_be_bytes()
                    });
                }
            }
        }
        bytes
    }

    #[test]
    fn pfm_colour_in_both_byte_orders_reads_back_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let (w, h) = (3, 2);
        let texels = known(w, h);
        for scale in ["-1.0", "1.0", "-0.5"] {
            let path = write_file(&dir, "a.pfm", &pfm(w, h, &texels, false, scale));
            let image = read_hdr_image(&path, roomy()).unwrap();
            assert_eq!((image.width, image.height), (w, h));
            assert_eq!(image.texels, texels, "scale {scale}");
        }
    }

    #[test]
    fn pfm_grey_fills_all_channels() {
        let dir = tempfile::tempdir().unwrap();
        let texels: Vec<Color> = (0..4).map(|k| Color::WHITE * (k as f64 + 0.5)).collect();
        let path = write_file(&dir, "g.pfm", &pfm(2, 2, &texels, true, "-1"));
        assert_eq!(read_hdr_image(&path, roomy()).unwrap().texels, texels);
    }

    #[test]
    fn bad_pfm_files_are_refused_with_reasons() {
        let dir = tempfile::tempdir().unwrap();
        let good = pfm(3, 2, &known(3, 2), false, "-1.0");
        let cases: Vec<(&str, Vec<u8>, &str)> = vec![
            ("truncated", good[..good.len() - 1].to_vec(), "truncated"),
            ("header only", b"PF\n3 2\n-1.0\n".to_vec(), "truncated"),
            ("no size", b"PF\n".to_vec(), "no width"),
            ("words", b"PF\nthree 2\n-1\n".to_vec(), "not a whole number"),
            (
                "zero scale",
                b"PF\n1 1\n0\n............".to_vec(),
                "non-zero",
            ),
            (
                "nan scale",
                b"PF\n1 1\nnan\n............".to_vec(),
                "non-zero",
            ),
            (
                "huge",
                b"PF\n99999999999 99999999999\n-1\n".to_vec(),
                "limit",
            ),
            ("empty", b"PF\n0 5\n-1\n".to_vec(), "empty"),
            // 100,000 pixels in all, within the pixel limit, but past the side's.
            (
                "one row",
                b"PF\n100000 1\n-1\n".to_vec(),
                "more than 16384 pixels on a side",
            ),
            ("no break", b"PF\n1 1\n-1".to_vec(), "line break"),
            (
                "long token",
                [b"PF\n".as_slice(), &[b'9'; 500]].concat(),
                "no width",
            ),
            ("garbage", b"\x00\x01garbage".to_vec(), "not an OpenEXR"),
        ];
        for (name, bytes, expected) in cases {
            let path = write_file(&dir, "bad.pfm", &bytes);
            let e = read_hdr_image(&path, roomy()).unwrap_err();
            assert_eq!(e.path, path);
            assert!(e.reason.contains(expected), "{name}: {e}");
            assert!(e.to_string().contains("bad.pfm"), "{e}");
        }
        // A non-finite value is named by its place in the picture (row 0 at the top).
        let mut texels = known(3, 2);
        texels[4] = Color::new(1.0, f64::INFINITY, 0.0);
        let path = write_file(&dir, "inf.pfm", &pfm(3, 2, &texels, false, "1"));
        let e = read_hdr_image(&path, roomy()).unwrap_err();
        assert!(e.reason.contains("column 1, row 1"), "{e}");
    }

    /// Each reader costs the image before its pixels are allocated: the file, its decoder's
    /// buffers and what the map keeps, exactly; a byte less of room refuses it.
    #[test]
    fn the_memory_limit_is_enforced_before_decoding() {
        let dir = tempfile::tempdir().unwrap();
        let pfm_path = write_file(&dir, "a.pfm", &pfm(3, 2, &known(3, 2), false, "-1"));
        let exr_path = dir.path().join("a.exr");
        exr::prelude::write_rgb_file(&exr_path, 3, 2, |_, _| (1.0f32, 1.0f32, 1.0f32)).unwrap();
        let hdr_path = write_file(&dir, "a.hdr", &rgbe(3, 2, &known(3, 2)));
        let kept = 6 * ENVIRONMENT_BYTES_PER_TEXEL;
        let file = |path: &Path| std::fs::metadata(path).unwrap().len();
        // The PFM's pixels are read from the file; the EXR decoder's blocks are counted as the
        // file again; the RGBE decoder's output is three f32 a pixel.
        let cases = [
            (file(&pfm_path) + kept, pfm_path),
            (2 * file(&exr_path) + kept, exr_path),
            (file(&hdr_path) + 6 * 12 + kept, hdr_path),
        ];
        for (cost, path) in cases {
            assert!(
                read_hdr_image(&path, ImageMemory::new(cost).room()).is_ok(),
                "{}",
                path.display()
            );
            let e = read_hdr_image(&path, ImageMemory::new(cost - 1).room()).unwrap_err();
            assert!(e.reason.contains(&format!("takes {cost} bytes")), "{e}");
            assert!(e.reason.contains("max_image_memory"), "{e}");
        }
    }

    #[test]
    fn exr_of_each_sample_type_reads_back() {
        use exr::prelude::f16;
        let dir = tempfile::tempdir().unwrap();
        let (w, h) = (5, 3);
        let texels = known(w, h);
        let at = |x: usize, y: usize| texels[y * w + x];
        let path = dir.path().join("f32.exr");
        exr::prelude::write_rgb_file(&path, w, h, |x, y| {
            let c = at(x, y);
            (c.red as f32, c.green as f32, c.blue as f32)
        })
        .unwrap();
        assert_eq!(read_hdr_image(&path, roomy()).unwrap().texels, texels);

        let path = dir.path().join("f16.exr");
        exr::prelude::write_rgb_file(&path, w, h, |x, y| {
            let c = at(x, y);
            (
                f16::from_f64(c.red),
                f16::from_f64(c.green),
                f16::from_f64(c.blue),
            )
        })
        .unwrap();
        // The test texels are exact in half precision.
        assert_eq!(read_hdr_image(&path, roomy()).unwrap().texels, texels);

        let path = dir.path().join("u32.exr");
        exr::prelude::write_rgb_file(&path, w, h, |x, y| (x as u32, y as u32, 7u32)).unwrap();
        let image = read_hdr_image(&path, roomy()).unwrap();
        assert_eq!(image.texels[2 * w + 4], Color::new(4.0, 2.0, 7.0));

        // Alpha is ignored.
        let path = dir.path().join("rgba.exr");
        exr::prelude::write_rgba_file(&path, w, h, |x, y| {
            let c = at(x, y);
            (c.red as f32, c.green as f32, c.blue as f32, 0.5f32)
        })
        .unwrap();
        let image = read_hdr_image(&path, roomy()).unwrap();
        assert_eq!((image.width, image.height), (w, h));
        assert_eq!(image.texels, texels);
    }

    #[test]
    fn damaged_exr_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("good.exr");
        exr::prelude::write_rgb_file(&path, 16, 16, |x, y| (x as f32, y as f32, 1.0f32)).unwrap();
        let good = std::fs::read(&path).unwrap();
        for cut in [4, 20, good.len() / 2, good.len() - 3] {
            let path = write_file(&dir, "cut.exr", &good[..cut]);
            let e = read_hdr_image(&path, roomy()).unwrap_err();
            assert!(e.reason.contains("OpenEXR"), "cut at {cut}: {e}");
        }
        let mut garbage = EXR_MAGIC.to_vec();
        garbage.extend((0..400u32).map(|k| (k.wrapping_mul(2_654_435_761) >> 13) as u8));
        let path = write_file(&dir, "garbage.exr", &garbage);
        assert!(read_hdr_image(&path, roomy()).is_err());
        // No R, G and B: a luminance-only file.
        let path = dir.path().join("y.exr");
        {
            use exr::prelude::*;
            let channels = SpecificChannels::build()
                .with_channel("Y")
                .with_channel("A")
                .with_pixel_fn(|_| (1.0f32, 1.0f32));
            Image::from_channels((2, 2), channels)
                .write()
                .to_file(&path)
                .unwrap();
        }
        let e = read_hdr_image(&path, roomy()).unwrap_err();
        assert!(e.reason.contains("R, G and B"), "{e}");
    }

    /// A Radiance RGBE file of `texels`, by the `image` crate's encoder.
    fn rgbe(w: usize, h: usize, texels: &[Color]) -> Vec<u8> {
        let pixels: Vec<image::Rgb<f32>> = texels
            .iter()
            .map(|c| image::Rgb([c.red as f32, c.green as f32, c.blue as f32]))
            .collect();
        let mut bytes = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut bytes)
            .encode(&pixels, w, h)
            .unwrap();
        bytes
    }

    #[test]
    fn rgbe_reads_back_within_its_precision() {
        let dir = tempfile::tempdir().unwrap();
        let (w, h) = (9, 4);
        let texels = known(w, h);
        let path = write_file(&dir, "a.hdr", &rgbe(w, h, &texels));
        let image = read_hdr_image(&path, roomy()).unwrap();
        assert_eq!((image.width, image.height), (w, h));
        for (got, want) in image.texels.iter().zip(&texels) {
            // RGBE keeps 8 bits of mantissa against the largest channel.
            let tolerance = want.max_channel() / 128.0;
            for (g, e) in got.to_array().iter().zip(want.to_array()) {
                assert!((g - e).abs() <= tolerance, "{got:?} vs {want:?}");
            }
        }
        let good = rgbe(w, h, &texels);
        let path = write_file(&dir, "cut.hdr", &good[..good.len() - 10]);
        assert!(read_hdr_image(&path, roomy()).is_err());
        let path = write_file(
            &dir,
            "bad.hdr",
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y x\n",
        );
        let e = read_hdr_image(&path, roomy()).unwrap_err();
        assert!(e.reason.contains("Radiance"), "{e}");
    }

    #[test]
    fn missing_files_and_directories_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope.exr");
        let e = read_hdr_image(&missing, roomy()).unwrap_err();
        assert_eq!(e.path, missing);
        assert!(read_hdr_image(dir.path(), roomy()).is_err());
    }
}
