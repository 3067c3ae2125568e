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
            _ => Err(Failure::usage(format!(
                "cannot tell the image format of `{}`: use a .png, .ppm or .pfm extension",
                path.display()
            ))),
        }
    }

    /// The encoded file.
    pub fn encode(self, canvas: &Canvas) -> Result<Vec<u8>, Failure> {
        match self {
            Self::Ppm => Ok(canvas.to_ppm().into_bytes()),
            Self::Pfm => Ok(to_pfm(canvas)),
            Self::Png => to_png(canvas),
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

/// PFM: a text header (`PF` for colour, the size, `-1.0` for little-endian), then the linear
/// colours as 32-bit floats, rows from the bottom of the image to the top.
fn to_pfm(canvas: &Canvas) -> Vec<u8> {
    let (w, h) = (canvas.width(), canvas.height());
    let mut out = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    out.reserve(w * h * 12);
    for row in canvas.pixels().chunks(w.max(1)).rev() {
        for c in row {
            for v in c.to_array() {
                out.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
    }
    out
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
        assert!(ImageFormat::from_path(Path::new("x.jpg")).is_err());
        assert!(ImageFormat::from_path(Path::new("png")).is_err());
    }

    #[test]
    fn pfm_rows_run_bottom_to_top_in_little_endian_floats() {
        let mut canvas = Canvas::new(1, 2);
        canvas.write_pixel(0, 0, Color::new(0.25, 0.5, 2.0));
        let bytes = to_pfm(&canvas);
        let header = b"PF\n1 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let floats: Vec<f32> = bytes[header.len()..]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(floats, [0.0, 0.0, 0.0, 0.25, 0.5, 2.0]);
    }
}
