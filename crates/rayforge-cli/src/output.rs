//! Image files: encoding a canvas by format, and writing it atomically.

use crate::failure::Failure;
use rayforge::Canvas;
use std::io::Write;
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
    /// The format named by the file's extension.
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
            Self::Png => {
                let mut bytes = Vec::new();
                let encoder = image::codecs::png::PngEncoder::new(&mut bytes);
                image::ImageEncoder::write_image(
                    encoder,
                    &canvas.to_rgb8(),
                    canvas.width() as u32,
                    canvas.height() as u32,
                    image::ExtendedColorType::Rgb8,
                )
                .map_err(|e| Failure::Internal(miette::miette!("PNG encoding failed: {e}")))?;
                Ok(bytes)
            }
        }
    }
}

/// PFM: a text header (`PF`, size, `-1.0` for little-endian), then rows bottom to top.
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

/// Writes `bytes` to a temporary file beside `path`, then renames it into place: readers see
/// the old file or the complete new one, never a partial image, and a failure leaves nothing.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    let fail = |e: &dyn std::fmt::Display| {
        Failure::usage(format!("cannot write `{}`: {e}", path.display()))
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".rayforge-").suffix(".tmp");
    // Temporary files are private (0600) by default; an image should get the usual
    // permissions, which the umask then trims.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let mut file = builder.tempfile_in(dir).map_err(|e| fail(&e))?;
    file.write_all(bytes).map_err(|e| fail(&e))?;
    file.as_file().sync_all().map_err(|e| fail(&e))?;
    file.persist(path).map_err(|e| fail(&e.error))?;
    Ok(())
}
