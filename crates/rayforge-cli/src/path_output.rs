//! The path tracer's files, from its resolved images to the disk: the image (linear in PFM and
//! OpenEXR, sRGB-encoded in PNG and PPM, which are for looking at), with `--aovs` the albedo,
//! normal, depth and sample-count images (beside it, or as layers of an OpenEXR file), with
//! `--denoise` the image denoised by Intel Open Image Denoise guided by the albedo and normal
//! (see [`crate::denoise`]), and with both the raw image kept too. `rayforge render` writes a
//! path-traced render through here and `rayforge merge` its merged slices, so the two write
//! the same files for the same flags. Pixels that are not finite are written black in every
//! file and counted (see [`crate::finite`]).

use crate::atomic_write::{check_writable, write_atomically};
use crate::denoise::Guides;
use crate::failure::Failure;
use crate::finite::blacken_non_finite;
use crate::format::{ImageFormat, Layer};
use rayforge::camera::Camera;
use rayforge::canvas::Canvas;
use rayforge::color::Color;
use rayforge::draw2d::Overlay;
use rayforge_denoise::Session;
use std::path::{Path, PathBuf};

/// The AOVs `--aovs` writes, in the order of `rayforge::render::path::Aovs::films`.
pub const AOV_NAMES: [&str; 4] = ["albedo", "normal", "depth", "samples"];

/// How a path-traced image is written: where, in which format, with which companions.
pub struct PathOutputs<'a> {
    /// The image's file.
    pub output: &'a Path,
    /// Its format.
    pub format: ImageFormat,
    /// `--aovs`: the AOVs are written (and, denoised, the raw image).
    pub aovs: bool,
    /// `--denoise`: the denoiser's session (the render's, whose passes it may have
    /// denoised already: its device and filters are reused).
    pub denoiser: Option<&'a Session>,
    /// The scene's canvas items and the camera they are drawn for, drawn over the image last.
    pub overlay: Option<(&'a Overlay, &'a Camera)>,
}

/// Each file written and how many of its pixels were not finite (written black), to warn
/// about after the summary.
pub type NonFinite = Vec<(usize, PathBuf)>;

impl PathOutputs<'_> {
    /// The AOVs' files beside the image (`None` when they are written as layers of an OpenEXR
    /// image, or not at all).
    fn aov_paths(&self) -> Option<[PathBuf; 4]> {
        (self.aovs && !self.format.is_exr()).then(|| aov_paths(self.output))
    }

    /// The raw image's file beside the denoised one (`None` when it is an OpenEXR layer, or
    /// not kept).
    fn noisy_path(&self) -> Option<PathBuf> {
        (self.aovs && self.denoiser.is_some() && !self.format.is_exr())
            .then(|| noisy_path(self.output))
    }

    /// Refuses, before the work is done, a file beside the image that could not be written.
    pub fn check_writable(&self) -> Result<(), Failure> {
        for path in self.aov_paths().iter().flatten().chain(&self.noisy_path()) {
            check_writable(path)?;
        }
        Ok(())
    }

    /// Writes `image` (the resolved film, linear radiance) and, resolved too, the `aovs` in
    /// the order of [`AOV_NAMES`] (needed with `--aovs` or `--denoise`), atomically; `show`
    /// is handed the image as a viewer sees it (linear, denoised when asked, before the canvas
    /// items). Returns each file's count of pixels that were not finite.
    pub fn write(
        &self,
        mut image: Canvas,
        aovs: Option<[Canvas; 4]>,
        show: impl FnOnce(&Canvas),
    ) -> Result<NonFinite, Failure> {
        let mut non_finite = vec![(blacken_non_finite(&mut image), self.output.to_path_buf())];
        let aovs = aovs.map(|mut aovs| {
            let counts = aovs.each_mut().map(blacken_non_finite);
            (aovs, counts)
        });
        // Denoised in linear radiance, before the image is encoded for its format; the raw
        // image kept, finished as it would be without --denoise, when --aovs writes it.
        let mut noisy = None;
        if let Some(denoiser) = self.denoiser {
            let guides = aovs.as_ref().map(|([albedo, normal, ..], _)| Guides {
                albedo,
                normal: Some(normal),
            });
            let denoised = crate::denoise::denoise(denoiser, &image, guides, "the image")?;
            let mut raw = std::mem::replace(&mut image, denoised);
            if self.aovs {
                self.finish(&mut raw);
                noisy = Some(raw);
            }
        }
        show(&image);
        self.finish(&mut image);
        // The AOVs, resolved; the albedo encoded as the image is, the normal in a display
        // format as normal maps store it; depth and sample count as they are (linear files
        // only).
        let aov_images = aovs.filter(|_| self.aovs).map(|aovs| {
            let ([mut albedo, mut normal, depth, samples], counts) = aovs;
            encode_for(self.format, &mut albedo);
            if !self.format.is_linear() {
                // [-1, 1] into [0, 1].
                for c in normal.pixels_mut() {
                    *c = (*c + Color::WHITE) * 0.5;
                }
            }
            ([albedo, normal, depth, samples], counts)
        });
        let (output, format) = (self.output, self.format);
        match (&aov_images, self.aov_paths()) {
            // OpenEXR holds them as layers of the one file, as compositors and denoisers read
            // them: albedo and normal as `NAME.R/G/B`, the depth as OpenEXR's standard `Z`
            // channel and the sample count as one channel `samples`.
            (Some(([albedo, normal, depth, samples], counts)), None) => {
                non_finite.push((counts.iter().sum(), output.to_path_buf()));
                let mut layers = vec![
                    Layer::rgb("albedo", albedo),
                    Layer::rgb("normal", normal),
                    Layer::single("Z", depth),
                    Layer::single("samples", samples),
                ];
                layers.extend(noisy.as_ref().map(|noisy| Layer::rgb("noisy", noisy)));
                write_atomically(output, &format.encode_with_layers(&image, &layers)?)?;
            }
            (Some((images, counts)), Some(paths)) => {
                write_atomically(output, &format.encode(&image)?)?;
                for (i, (aov, path)) in images.iter().zip(&paths).enumerate() {
                    non_finite.push((counts[i], path.clone()));
                    // Depth and sample count are no colours: always linear PFM.
                    let format = if i < 2 { format } else { ImageFormat::Pfm };
                    write_atomically(path, &format.encode(aov)?)?;
                }
                if let (Some(noisy), Some(path)) = (&noisy, self.noisy_path()) {
                    write_atomically(&path, &format.encode(noisy)?)?;
                }
            }
            _ => write_atomically(output, &format.encode(&image)?)?,
        }
        Ok(non_finite)
    }

    /// The last steps of a path-traced image, after it is resolved (and shown to a viewer, in
    /// linear values): encoded for the format, the canvas items drawn over it.
    fn finish(&self, canvas: &mut Canvas) {
        encode_for(self.format, canvas);
        if let Some((overlay, camera)) = self.overlay {
            overlay.draw(canvas, camera);
        }
    }
}

/// Where `--aovs` writes the AOVs when the image is not OpenEXR: beside the image,
/// `out.albedo.png` and `out.normal.png` for `out.png` (in the image's format), and
/// `out.depth.pfm` and `out.samples.pfm` (always linear PFM).
pub fn aov_paths(output: &Path) -> [PathBuf; 4] {
    let ext = output
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    [
        beside(output, "albedo", &ext),
        beside(output, "normal", &ext),
        beside(output, "depth", "pfm"),
        beside(output, "samples", "pfm"),
    ]
}

/// `out.NAME.EXT` beside `out.png`.
fn beside(output: &Path, name: &str, ext: &str) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    output.with_file_name(format!("{stem}.{name}.{ext}"))
}

/// Where `--denoise --aovs` writes the raw image when the image is not OpenEXR: beside it,
/// `out.noisy.png` for `out.png`, in the image's format.
pub fn noisy_path(output: &Path) -> PathBuf {
    let ext = output
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    beside(output, "noisy", &ext)
}

/// Radiance as the format wants it: linear for PFM and OpenEXR; for the 8-bit formats,
/// encoded with the sRGB transfer curve (a display shows code values, not radiance).
pub(crate) fn encode_for(format: ImageFormat, canvas: &mut Canvas) {
    if format.is_linear() {
        return;
    }
    for c in canvas.pixels_mut() {
        *c = Color::new(srgb(c.red), srgb(c.green), srgb(c.blue));
    }
}

/// The sRGB transfer curve (IEC 61966-2-1) of a linear value, clamped to [0, 1] first.
fn srgb(linear: f64) -> f64 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_aovs_go_beside_the_image() {
        let [a, n, d, s] = aov_paths(Path::new("out/cornell.png"));
        assert_eq!(d, Path::new("out/cornell.depth.pfm"));
        assert_eq!(s, Path::new("out/cornell.samples.pfm"));
        assert_eq!(a, Path::new("out/cornell.albedo.png"));
        assert_eq!(n, Path::new("out/cornell.normal.png"));
        assert_eq!(
            noisy_path(Path::new("out/cornell.png")),
            Path::new("out/cornell.noisy.png")
        );
    }

    #[test]
    fn the_srgb_curve_meets_its_fixed_points() {
        assert_eq!(srgb(0.0), 0.0);
        assert!((srgb(1.0) - 1.0).abs() < 1e-12);
        assert!((srgb(0.18) - 0.4614).abs() < 1e-3);
        assert_eq!(srgb(5.0), srgb(1.0));
        assert_eq!(srgb(f64::NAN), 0.0);
    }
}
