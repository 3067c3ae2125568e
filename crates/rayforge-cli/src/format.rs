//! Image formats: which one the output's extension names, and encoding a canvas in it.

use crate::failure::Failure;
use rayforge::Canvas;
use std::path::Path;

/// The image formats rayforge writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit PNG.
    Png,
    /// The book's plain-text P3 PPM.
    Ppm,
    /// Portable Float Map: linear 32-bit float RGB, unclamped.
    Pfm,
    /// OpenEXR: linear 32-bit float RGB, unclamped (what compositors, viewers and denoisers
    /// read).
    Exr,
    /// OpenEXR with 16-bit half floats (`--exr-half`): half the size, about three decimal
    /// digits, values past 65504 saturated.
    ExrHalf,
}

impl ImageFormat {
    /// The format named by the file's extension (any case).
    pub fn from_path(path: &Path) -> Result<Self, Failure> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Self::Png),
            Some("ppm") => Ok(Self::Ppm),
            Some("pfm") => Ok(Self::Pfm),
            Some("exr") => Ok(Self::Exr),
            _ => Err(Failure::usage(format!(
                "cannot tell the image format of `{}`: use a .png, .ppm, .pfm or .exr extension",
                path.display()
            ))),
        }
    }

    /// Whether the format keeps linear radiance (the float formats) rather than display values.
    pub fn is_linear(self) -> bool {
        matches!(self, Self::Pfm | Self::Exr | Self::ExrHalf)
    }

    /// Whether the format is OpenEXR, which holds extra layers beside the image.
    pub fn is_exr(self) -> bool {
        matches!(self, Self::Exr | Self::ExrHalf)
    }

    /// The encoded file.
    pub fn encode(self, canvas: &Canvas) -> Result<Vec<u8>, Failure> {
        match self {
            Self::Ppm => Ok(canvas.to_ppm().into_bytes()),
            Self::Pfm => to_pfm(canvas),
            Self::Exr | Self::ExrHalf => self.encode_with_layers(canvas, &[]),
            Self::Png => to_png(canvas),
        }
    }
}

impl ImageFormat {
    /// The encoded file with `layers` beside the image, each a named canvas of the same size
    /// (OpenEXR only: its channels are named `NAME.R`, `NAME.G`, `NAME.B`, the grouping that
    /// compositors, tev and denoising tools read as layers). Other formats take the image only.
    pub fn encode_with_layers(
        self,
        canvas: &Canvas,
        layers: &[Layer<'_>],
    ) -> Result<Vec<u8>, Failure> {
        match self {
            Self::Exr => to_exr(canvas, layers, false),
            Self::ExrHalf => to_exr(canvas, layers, true),
            other => other.encode(canvas),
        }
    }
}

/// 8-bit PNG of the canvas's colours (scaled by 255, rounded and clamped, as the book's PPM).
fn to_png(canvas: &Canvas) -> Result<Vec<u8>, Failure> {
    let side = |n: usize| {
        u32::try_from(n).map_err(|_| Failure::internal(format!("{n} pixels is too wide for PNG")))
    };
    let (width, height) = (side(canvas.width())?, side(canvas.height())?);
    let mut bytes = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut bytes);
    image::ImageEncoder::write_image(
        encoder,
        &canvas.to_rgb8(),
        width,
        height,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| Failure::internal(format!("PNG encoding failed: {e}")))?;
    Ok(bytes)
}

/// An image written beside the main one in an OpenEXR file (an AOV).
#[derive(Debug, Clone, Copy)]
pub struct Layer<'a> {
    /// The layer's name, or the channel's when it is one.
    pub name: &'a str,
    /// Its pixels.
    pub image: &'a Canvas,
    /// Whether it is one channel (the red of `image`) named `name`, rather than three named
    /// `NAME.R`, `NAME.G`, `NAME.B`.
    pub single: bool,
}

impl<'a> Layer<'a> {
    /// Three channels `NAME.R`, `NAME.G`, `NAME.B`.
    pub fn rgb(name: &'a str, image: &'a Canvas) -> Self {
        Self {
            name,
            image,
            single: false,
        }
    }

    /// One channel `name`: the image's red (a grey quantity in every channel).
    pub fn single(name: &'a str, image: &'a Canvas) -> Self {
        Self {
            name,
            image,
            single: true,
        }
    }
}

/// OpenEXR of the canvas's linear colours and of `layers`: one part, its channels R, G, B and
/// each layer's (`NAME.R`, `NAME.G`, `NAME.B`, or one channel `NAME`), in 32-bit floats or,
/// with `half`, 16-bit ones, written by the `exr` crate into memory (the caller writes the
/// file atomically).
fn to_exr(canvas: &Canvas, layers: &[Layer<'_>], half: bool) -> Result<Vec<u8>, Failure> {
    use exr::prelude::{
        AnyChannel, AnyChannels, Encoding, FlatSamples, Image, LayerAttributes, SmallVec,
        WritableImage,
    };
    let (width, height) = (canvas.width(), canvas.height());
    if let Some(layer) = layers
        .iter()
        .find(|l| (l.image.width(), l.image.height()) != (width, height))
    {
        return Err(Failure::internal(format!(
            "the `{}` layer is not the image's size",
            layer.name
        )));
    }
    let channel = |name: String, image: &Canvas, pick: fn(&rayforge::Color) -> f64| {
        let values = image.pixels().iter().map(pick);
        let samples = if half {
            FlatSamples::F16(values.map(to_f16).collect())
        } else {
            FlatSamples::F32(values.map(to_f32).collect())
        };
        AnyChannel {
            // Colours and albedo are perceived logarithmically; normals are directions.
            quantize_linearly: name.starts_with("normal."),
            ..AnyChannel::new(name.as_str(), samples)
        }
    };
    let mut channels = Vec::new();
    let named = std::iter::once(self::Layer::rgb("", canvas)).chain(layers.iter().copied());
    for self::Layer {
        name: layer,
        image,
        single,
    } in named
    {
        if single {
            channels.push(channel(layer.to_string(), image, |c| c.red));
            continue;
        }
        let prefix = if layer.is_empty() {
            String::new()
        } else {
            format!("{layer}.")
        };
        channels.push(channel(format!("{prefix}R"), image, |c| c.red));
        channels.push(channel(format!("{prefix}G"), image, |c| c.green));
        channels.push(channel(format!("{prefix}B"), image, |c| c.blue));
    }
    let layer = exr::prelude::Layer::new(
        (width, height),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| Failure::internal(format!("OpenEXR encoding failed: {e}")))?;
    Ok(bytes.into_inner())
}

/// PFM: a text header (`PF` for colour, the size, `-1.0` for little-endian), then the linear
/// colours as 32-bit floats, rows from the bottom of the image to the top. Its buffer, 12 bytes
/// a pixel, is reserved fallibly: a failure is an error, not an abort.
fn to_pfm(canvas: &Canvas) -> Result<Vec<u8>, Failure> {
    let (w, h) = (canvas.width(), canvas.height());
    let mut out = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    out.try_reserve(w * h * 12).map_err(|_| {
        Failure::usage(format!(
            "not enough memory to encode the {w}×{h} PFM image ({} bytes)",
            w * h * 12
        ))
    })?;
    for row in canvas.pixels().chunks(w.max(1)).rev() {
        for c in row {
            for v in c.to_array() {
                out.extend_from_slice(&to_f32(v).to_le_bytes());
            }
        }
    }
    Ok(out)
}

/// A channel as a 32-bit float, saturating: a finite value beyond its range is written as the
/// largest 32-bit float of its sign rather than the infinity `as f32` would make of it, so the
/// float formats hold only finite numbers (non-finite pixels are blackened before encoding,
/// see [`crate::finite`]).
fn to_f32(v: f64) -> f32 {
    v.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32
}

/// A channel as a 16-bit half float, saturating as [`to_f32`] does: past ±65504, the largest
/// half, a finite value would otherwise round to an infinity.
fn to_f16(v: f64) -> exr::prelude::f16 {
    use exr::prelude::f16;
    f16::from_f64(v.clamp(-f16::MAX.to_f64(), f16::MAX.to_f64()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayforge::Color;

    #[test]
    fn the_extension_picks_the_format_in_any_case() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a/b.PNG")).ok(),
            Some(ImageFormat::Png)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("x.pfm")).ok(),
            Some(ImageFormat::Pfm)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("x.EXR")).ok(),
            Some(ImageFormat::Exr)
        );
        assert!(ImageFormat::from_path(Path::new("x.jpg")).is_err());
        assert!(ImageFormat::from_path(Path::new("png")).is_err());
    }

    #[test]
    fn pfm_rows_run_bottom_to_top_in_little_endian_floats() {
        let mut canvas = Canvas::new(1, 2);
        canvas.write_pixel(0, 0, Color::new(0.25, 0.5, 2.0));
        let bytes = to_pfm(&canvas).unwrap();
        let header = b"PF\n1 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let floats: Vec<f32> = bytes[header.len()..]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(floats, [0.0, 0.0, 0.0, 0.25, 0.5, 2.0]);
    }

    #[test]
    fn values_past_the_32_bit_range_saturate_instead_of_becoming_infinite() {
        assert_eq!(to_f32(1e308), f32::MAX);
        assert_eq!(to_f32(-1e308), -f32::MAX);
        assert_eq!(to_f32(0.25), 0.25);
        let mut canvas = Canvas::new(1, 1);
        canvas.write_pixel(0, 0, Color::new(1e300, -1e300, 1.0));
        let bytes = to_pfm(&canvas).unwrap();
        assert!(bytes[bytes.len() - 12..]
            .chunks(4)
            .all(|b| f32::from_le_bytes(b.try_into().unwrap()).is_finite()));
    }

    #[test]
    fn half_floats_saturate_at_65504_instead_of_becoming_infinite() {
        use exr::prelude::f16;
        for (v, half) in [
            (65504.0, 65504.0),
            (65520.0, 65504.0),
            (1e6, 65504.0),
            (1e300, 65504.0),
            (-1e9, -65504.0),
            (0.5, 0.5),
            (-0.0, -0.0),
        ] {
            let got = to_f16(v);
            assert!(got.is_finite(), "{v} became {got}");
            assert_eq!(got.to_f64(), half, "{v}");
        }
        assert_eq!(to_f16(1e300), f16::MAX);
    }

    #[test]
    fn exr_round_trips_linear_floats_top_row_first() {
        use exr::prelude::{read_first_rgba_layer_from_file, Vec2};
        let mut canvas = Canvas::new(3, 2);
        canvas.write_pixel(0, 0, Color::new(0.25, 0.5, 2.0));
        canvas.write_pixel(2, 1, Color::new(17.5, 0.0, 1e-3));
        let bytes = to_exr(&canvas, &[], false).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.exr");
        std::fs::write(&path, bytes).unwrap();
        let image = read_first_rgba_layer_from_file(
            &path,
            |size, _| vec![[0.0f32; 3]; size.width() * size.height()],
            |pixels: &mut Vec<[f32; 3]>, Vec2(x, y), (r, g, b, _): (f32, f32, f32, f32)| {
                pixels[y * 3 + x] = [r, g, b]
            },
        )
        .unwrap();
        let pixels = image.layer_data.channel_data.pixels;
        assert_eq!(pixels[0], [0.25, 0.5, 2.0]);
        assert_eq!(pixels[5], [17.5, 0.0, 1e-3]);
        assert_eq!(pixels[1], [0.0, 0.0, 0.0]);
    }
}
