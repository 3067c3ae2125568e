//! Image files decoded within a budget on memory: the budget a scene's images share, the
//! texture decoder (PNG, JPEG, PNM, TGA) and the pieces the HDR readers use too. Every image is
//! costed from its header before anything is allocated for its pixels, and the buffers that
//! can be large are taken fallibly, so an image bomb or a machine short of memory is an error
//! naming the file, never an exhausted memory or an abort.

use rayforge::shading::{Filter, Texture};
use rayforge::Color;

/// The memory a scene's images take, against its limit: each image's colours for as long as
/// the scene lives, and while one is decoded, also its file and the decoder's buffers. Every
/// image is costed from its header before anything is allocated for its pixels, so an image
/// that would go over the limit is refused before it is decoded.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ImageMemory {
    /// Bytes held by the images read so far.
    held: u64,
    /// The limit (`LoadOptions::max_image_memory`).
    max: u64,
}

impl ImageMemory {
    /// Nothing held yet, within `max` bytes.
    pub(crate) fn new(max: u64) -> Self {
        Self { held: 0, max }
    }

    /// What the next image may take, decoding included.
    pub(crate) fn room(&self) -> Room {
        Room {
            bytes: self.max.saturating_sub(self.held),
            held: self.held,
            max: self.max,
        }
    }

    /// Counts an image's colours as held from now on.
    pub(crate) fn hold(&mut self, bytes: u64) {
        self.held = self.held.saturating_add(bytes);
    }
}

/// What one image may take, with what explains it in an error.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Room {
    /// Bytes left in the scene's images' memory.
    bytes: u64,
    /// Bytes the scene's other images hold.
    held: u64,
    /// The limit.
    max: u64,
}

impl Room {
    /// Refuses an image whose decoding would take `cost` bytes (`what` says of what), more than
    /// there is room for.
    pub(crate) fn check(&self, cost: u64, what: &str) -> Result<(), String> {
        if cost <= self.bytes {
            return Ok(());
        }
        let held = if self.held > 0 {
            format!(" and the scene's other images hold {} bytes", self.held)
        } else {
            String::new()
        };
        Err(format!(
            "reading it takes {cost} bytes ({what}){held}: more than the limit of {} bytes on \
             the memory of a scene's images (`LoadOptions::max_image_memory` in the library)",
            self.max
        ))
    }

    /// The `image` crate's error in words that name the limit it hit.
    fn explain(&self, e: image::ImageError) -> String {
        use image::error::{ImageError, LimitErrorKind};
        match e {
            ImageError::Limits(limit) => match limit.kind() {
                LimitErrorKind::DimensionError => {
                    format!("it is more than {MAX_TEXTURE_SIDE} pixels on a side, the limit")
                }
                LimitErrorKind::InsufficientMemory => format!(
                    "its decoder needs more than the {} bytes left of the limit of {} bytes on \
                     the memory of a scene's images (`LoadOptions::max_image_memory` in the \
                     library)",
                    self.bytes, self.max
                ),
                _ => limit.to_string(),
            },
            other => other.to_string(),
        }
    }
}

/// Decodes an image of at most `room` bytes, decoding included; the error is the reason.
///
/// The `image` crate's limits hold the decoder to the image side and to `room`; then the header
/// is costed before a pixel is decoded: the file's bytes, the decoder's output in the image's
/// own format (16-bit channels and alpha included), a JPEG decoder's copy of the file and its
/// planes, and the 24-byte colours the texture keeps. The buffers that can be large are taken
/// fallibly, so a machine short of memory gets this error, not an abort.
pub(crate) fn decode(bytes: &[u8], room: Room) -> Result<Texture, String> {
    decode_with_alpha(bytes, room, false).map(|(texture, _)| texture)
}

/// [`decode`], and with `keep_alpha` the image's alpha channel as a second, grey texture
/// (`None` when the image has no alpha), costed within the same room.
pub(crate) fn decode_with_alpha(
    bytes: &[u8],
    room: Room,
    keep_alpha: bool,
) -> Result<(Texture, Option<Texture>), String> {
    decode_image(bytes, room, keep_alpha, None)
}

/// [`decode`] for a file whose format its first bytes may not tell: `fallback` is the format
/// to read it in then (a TGA file, which has no signature, told by its name).
pub(crate) fn decode_as(
    bytes: &[u8],
    room: Room,
    fallback: Option<image::ImageFormat>,
) -> Result<Texture, String> {
    decode_image(bytes, room, false, fallback).map(|(texture, _)| texture)
}

/// [`decode_with_alpha`], reading in `fallback`'s format what the first bytes do not tell.
fn decode_image(
    bytes: &[u8],
    room: Room,
    keep_alpha: bool,
    fallback: Option<image::ImageFormat>,
) -> Result<(Texture, Option<Texture>), String> {
    use image::ImageDecoder;
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    if let (None, Some(format)) = (reader.format(), fallback) {
        reader.set_format(format);
    }
    let is_jpeg = reader.format() == Some(image::ImageFormat::Jpeg);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(room.bytes);
    reader.limits(limits);
    // The decoders are third-party code fed untrusted bytes: a panic in one is a broken image,
    // reported as such, not a crash of the renderer.
    guarded(move || {
        let decoder = reader.into_decoder().map_err(|e| room.explain(e))?;
        let (w, h) = decoder.dimensions();
        let pixels = u64::from(w) * u64::from(h);
        if pixels > MAX_TEXTURE_PIXELS {
            return Err(format!(
                "it is {w}×{h} pixels; the limit is {MAX_TEXTURE_PIXELS} pixels"
            ));
        }
        let color = decoder.color_type();
        let output = decoder.total_bytes();
        let jpeg = if is_jpeg {
            bytes.len() as u64 + (u64::from(w) + 16) * (u64::from(h) + 16) * JPEG_PLANE_BYTES
        } else {
            0
        };
        let keep_alpha = keep_alpha && color.has_alpha();
        let kept = if keep_alpha { 2 } else { 1 };
        let cost = bytes.len() as u64 + output + jpeg + kept * pixels * COLOR_BYTES;
        room.check(cost, &format!("{w}×{h} pixels of {color:?}"))?;
        let mut buffer = fallible_vec(output as usize)?;
        buffer.resize(output as usize, 0);
        decoder
            .read_image(&mut buffer)
            .map_err(|e| room.explain(e))?;
        let colors = to_colors(&buffer, color, pixels as usize)?;
        let texture = |texels| {
            Texture::new(w as usize, h as usize, texels, Filter::Bilinear)
                .ok_or_else(|| "the image is empty".to_string())
        };
        let alpha = if keep_alpha {
            Some(texture(alpha_of(&buffer, color, pixels as usize)?)?)
        } else {
            None
        };
        Ok((texture(colors)?, alpha))
    })
}

/// The decoder's output in its own format as colours (alpha dropped, grey spread over red,
/// green and blue), each channel its integer over the largest value, in `f32` as the `image`
/// crate's own conversion computes it (so textures are the same as before it was replaced).
pub(crate) fn to_colors(
    buffer: &[u8],
    color: image::ColorType,
    pixels: usize,
) -> Result<Vec<Color>, String> {
    use image::ColorType as C;
    let (channels, bytes_per_channel) = match color {
        C::L8 => (1, 1),
        C::La8 => (2, 1),
        C::Rgb8 => (3, 1),
        C::Rgba8 => (4, 1),
        C::L16 => (1, 2),
        C::La16 => (2, 2),
        C::Rgb16 => (3, 2),
        C::Rgba16 => (4, 2),
        C::Rgb32F => (3, 4),
        C::Rgba32F => (4, 4),
        other => return Err(format!("its colour type ({other:?}) is not supported")),
    };
    let channel = |c: &[u8]| -> f64 {
        f64::from(match bytes_per_channel {
            1 => f32::from(c[0]) / 255.0,
            2 => f32::from(u16::from_ne_bytes([c[0], c[1]])) / 65535.0,
            _ => f32::from_ne_bytes([c[0], c[1], c[2], c[3]]),
        })
    };
    let stride = channels * bytes_per_channel;
    if buffer.len() != pixels * stride {
        return Err("the decoder's output does not match the image's size".into());
    }
    let mut colors = fallible_vec(pixels)?;
    colors.extend(buffer.chunks_exact(stride).map(|p| {
        let at = |k: usize| channel(&p[k * bytes_per_channel..]);
        if channels < 3 {
            let grey = at(0);
            Color::new(grey, grey, grey)
        } else {
            Color::new(at(0), at(1), at(2))
        }
    }));
    Ok(colors)
}

/// The alpha channel of the decoder's output (8 or 16 bits, or float) as grey colours.
fn alpha_of(buffer: &[u8], color: image::ColorType, pixels: usize) -> Result<Vec<Color>, String> {
    use image::ColorType as C;
    let (channels, bytes_per_channel) = match color {
        C::La8 => (2, 1),
        C::Rgba8 => (4, 1),
        C::La16 => (2, 2),
        C::Rgba16 => (4, 2),
        C::Rgba32F => (4, 4),
        other => return Err(format!("its colour type ({other:?}) has no alpha")),
    };
    let stride = channels * bytes_per_channel;
    if buffer.len() != pixels * stride {
        return Err("the decoder's output does not match the image's size".into());
    }
    let mut alpha = fallible_vec(pixels)?;
    alpha.extend(buffer.chunks_exact(stride).map(|p| {
        let c = &p[(channels - 1) * bytes_per_channel..];
        let a = f64::from(match bytes_per_channel {
            1 => f32::from(c[0]) / 255.0,
            2 => f32::from(u16::from_ne_bytes([c[0], c[1]])) / 65535.0,
            _ => f32::from_ne_bytes([c[0], c[1], c[2], c[3]]),
        });
        Color::new(a, a, a)
    }));
    Ok(alpha)
}

/// An empty vector with room for `len` items, or an error saying that memory is short
/// (instead of the abort an infallible allocation ends in).
pub(crate) fn fallible_vec<T>(len: usize) -> Result<Vec<T>, String> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| {
        format!(
            "cannot allocate {} bytes for its pixels: the machine is short of memory",
            len.saturating_mul(std::mem::size_of::<T>())
        )
    })?;
    Ok(v)
}

/// Runs a third-party decoder on untrusted bytes: its panic is a damaged file, not a crash.
pub(crate) fn guarded<T>(decode: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(decode))
        .unwrap_or_else(|_| Err("the image decoder failed on it (the file is damaged)".into()))
}

/// The bytes a texture keeps per pixel: a colour of three `f64`.
pub(crate) const COLOR_BYTES: u64 = std::mem::size_of::<Color>() as u64;

/// The bytes an environment map keeps per texel: its colour, and the tables it is sampled by
/// (a luminance and a weight while they are built, then a probability and a cumulative sum).
pub(crate) const ENVIRONMENT_BYTES_PER_TEXEL: u64 = COLOR_BYTES + 4 * 8;

/// What a JPEG decoder takes per pixel beside its output, at most: a 16-bit coefficient for
/// each of up to four components (a progressive JPEG keeps them all until the last scan).
const JPEG_PLANE_BYTES: u64 = 4 * 2;

/// The largest image side accepted.
pub const MAX_TEXTURE_SIDE: u32 = 16_384;

/// The most pixels an image texture or environment map may have: 2²⁶ (8192 × 8192), 1.5 GiB
/// as colours.
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 26;

/// The most memory a scene's images may take by default, decoding included: 3 GiB, the colours
/// of 2²⁷ pixels.
pub const DEFAULT_MAX_IMAGE_MEMORY: u64 = 3 << 30;

/// The largest image file read.
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;
