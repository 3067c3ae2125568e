//! `rayforge denoise IN -o OUT`: an image rendered earlier or elsewhere (linear OpenEXR or
//! PFM) denoised by Intel Open Image Denoise, guided by its albedo and normals (an OpenEXR
//! file's own `albedo` and `normal` layers, as `render --aovs` writes them, or files named by
//! `--albedo` and `--normal`), and written as `rayforge render` writes its images (linear PFM
//! and OpenEXR, sRGB PNG and PPM), atomically, never over an input.

use crate::args::DenoiseArgs;
use crate::atomic_write::{check_writable, not_an_input, write_atomically};
use crate::denoise::Guides;
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::sizing::DEFAULT_MAX_PIXELS;
use rayforge::canvas::Canvas;
use rayforge::color::Color;
use std::path::Path;
use std::time::Instant;

/// Denoises `args.input` into `args.output`; nothing is written on any error.
pub fn run(args: &DenoiseArgs) -> Result<(), Failure> {
    let format = ImageFormat::from_path(&args.output)?;
    let inputs = [
        Some((args.input.as_path(), "the input image")),
        args.albedo.as_deref().map(|p| (p, "the albedo image")),
        args.normal.as_deref().map(|p| (p, "the normal image")),
    ];
    not_an_input(&args.output, inputs.into_iter().flatten())?;
    check_writable(&args.output)?;
    if args.threads == Some(0) {
        return Err(Failure::usage("--threads must be at least 1, found 0"));
    }
    let denoiser = crate::denoise::load("rayforge denoise")?;
    let Inputs {
        image,
        albedo,
        normal,
    } = read_inputs(&args.input, args.albedo.as_deref(), args.normal.as_deref())?;
    let threads = args.threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let started = Instant::now();
    let guides = albedo.as_ref().map(|albedo| Guides {
        albedo,
        normal: normal.as_ref(),
    });
    let what = format!("`{}`", args.input.display());
    let mut out = crate::denoise::denoise(&denoiser.session(threads), &image, guides, &what)?;
    crate::path_output::encode_for(format, &mut out);
    write_atomically(&args.output, &format.encode(&out)?)?;
    if !args.quiet {
        let guided = match (&albedo, &normal) {
            (Some(_), Some(_)) => "guided by albedo and normals",
            (Some(_), None) => "guided by albedo",
            _ => "without guides",
        };
        eprintln!(
            "denoised `{}` ({}×{}, {guided}) with {} in {:.2}s: wrote `{}`",
            args.input.display(),
            out.width(),
            out.height(),
            denoiser.describe(),
            started.elapsed().as_secs_f64(),
            args.output.display()
        );
    }
    Ok(())
}

/// The image to denoise and its guides, read and checked.
pub struct Inputs {
    /// The image.
    pub image: Canvas,
    /// Its albedo: the `--albedo` file's, else the input's own layer.
    pub albedo: Option<Canvas>,
    /// Its normals: the `--normal` file's, else the input's own layer (only with an albedo).
    pub normal: Option<Canvas>,
}

/// Reads the image `input` and its guides (`albedo` and `normal` files, else the input's own
/// layers), each refused with the file named when it is not a linear image within the
/// limits, a guide of another size than the image, a normal without an albedo: everything
/// `rayforge denoise` checks of its inputs before OIDN is given them.
pub fn read_inputs(
    input: &Path,
    albedo: Option<&Path>,
    normal: Option<&Path>,
) -> Result<Inputs, Failure> {
    let image = read_linear(input)?;
    let guide = |file: Option<&Path>, layer: Option<Canvas>, what: &str| {
        let Some(path) = file else {
            return Ok(layer);
        };
        let guide = read_linear(path)?.color;
        let size = |c: &Canvas| format!("{}×{}", c.width(), c.height());
        if size(&guide) != size(&image.color) {
            return Err(Failure::usage(format!(
                "the {what} image `{}` is {} pixels, the image `{}` {}: they must be the same \
                 size",
                path.display(),
                size(&guide),
                input.display(),
                size(&image.color)
            )));
        }
        Ok(Some(guide))
    };
    let albedo = guide(albedo, image.albedo, "albedo")?;
    let normal = guide(normal, image.normal, "normal")?;
    if normal.is_some() && albedo.is_none() {
        return Err(Failure::usage(
            "a normal guide needs an albedo guide beside it (--albedo, or an OpenEXR input's \
             albedo layer)",
        ));
    }
    Ok(Inputs {
        image: image.color,
        albedo,
        normal,
    })
}

/// A linear image and the guides its file holds.
struct LinearImage {
    color: Canvas,
    albedo: Option<Canvas>,
    normal: Option<Canvas>,
}

/// The four bytes every OpenEXR file starts with.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// The most bytes an input file may hold: an uncompressed OpenEXR of [`DEFAULT_MAX_PIXELS`]
/// pixels holding the image and both guides (nine 32-bit channels), and a MiB of headers.
/// (The pixel limit, read from the header before any pixel is decoded, bounds the memory;
/// this bounds what is read to get there.)
const MAX_INPUT_BYTES: u64 = DEFAULT_MAX_PIXELS * 9 * 4 + (1 << 20);

/// Reads an OpenEXR (its first layer's `R`, `G`, `B` and, if there, `albedo.*` and
/// `normal.*`) or PFM file, told by its first bytes; refuses what is not a regular file (a
/// FIFO, a device: before reading, without waiting on it), files past [`MAX_INPUT_BYTES`],
/// other formats, images of more than [`DEFAULT_MAX_PIXELS`] and values that are not finite,
/// naming the file.
fn read_linear(path: &Path) -> Result<LinearImage, Failure> {
    let fail = |why: String| Failure::usage(format!("cannot read `{}`: {why}", path.display()));
    let bytes = rayforge_scene::files::read_bounded(path, MAX_INPUT_BYTES).map_err(fail)?;
    let image = if bytes.starts_with(&EXR_MAGIC) {
        read_exr(&bytes)
    } else if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
        read_pfm(&bytes).map(|color| LinearImage {
            color,
            albedo: None,
            normal: None,
        })
    } else {
        Err(
            "it is neither OpenEXR nor PFM (linear images are denoised; its first bytes are \
             neither's)"
                .to_string(),
        )
    }
    .map_err(fail)?;
    let layers = [
        ("", Some(&image.color)),
        ("albedo layer's ", image.albedo.as_ref()),
        ("normal layer's ", image.normal.as_ref()),
    ];
    for (layer, canvas) in layers {
        let Some(canvas) = canvas else { continue };
        if let Some(at) = canvas
            .pixels()
            .iter()
            .position(|c| !c.to_array().iter().all(|v| v.is_finite()))
        {
            let c = canvas.pixels()[at];
            return Err(fail(format!(
                "its {layer}pixel (column {}, row {} from the top) is ({}, {}, {}): values \
                 must be finite",
                at % canvas.width(),
                at / canvas.width(),
                c.red,
                c.green,
                c.blue
            )));
        }
    }
    Ok(image)
}

/// Refuses an empty image or one over the pixel limit, before its pixels are read.
fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("the image is empty ({width}×{height} pixels)"));
    }
    match (width as u64).checked_mul(height as u64) {
        Some(n) if n <= DEFAULT_MAX_PIXELS => Ok(()),
        _ => Err(format!(
            "it is {width}×{height} pixels, more than the limit of {DEFAULT_MAX_PIXELS}"
        )),
    }
}

/// The first layer of an OpenEXR file, its `R`, `G`, `B` channels and the guides' layers.
fn read_exr(bytes: &[u8]) -> Result<LinearImage, String> {
    use exr::prelude::{read, ReadChannels, ReadLayers};
    use std::io::Cursor;
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| format!("its OpenEXR header is invalid: {e}"))?;
    for header in &meta.headers {
        check_size(header.layer_size.width(), header.layer_size.height())?;
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| format!("its OpenEXR data is invalid: {e}"))?;
    let layer = image.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    // A channel of a sample a pixel: the pixels are indexed by it below. (The `exr` crate
    // refuses subsampled channels, which would hold fewer, when it reads the header.)
    let channel = |name: &str| -> Result<Option<Vec<f32>>, String> {
        let Some(c) = layer.channel_data.list.iter().find(|c| c.name.eq(name)) else {
            return Ok(None);
        };
        if c.sample_data.len() != width * height {
            return Err(format!(
                "its channel `{name}` holds {} samples for {width}×{height} pixels",
                c.sample_data.len()
            ));
        }
        Ok(Some(c.sample_data.values_as_f32().collect()))
    };
    let rgb = |prefix: &str| -> Result<Option<Canvas>, String> {
        let [r, g, b] = ["R", "G", "B"].map(|c| channel(&format!("{prefix}{c}")));
        let (Some(r), Some(g), Some(b)) = (r?, g?, b?) else {
            return Ok(None);
        };
        let pixels = (0..width * height)
            .map(|i| Color::new(f64::from(r[i]), f64::from(g[i]), f64::from(b[i])))
            .collect();
        Ok(Some(Canvas::from_pixels(width, height, pixels)))
    };
    Ok(LinearImage {
        color: rgb("")?.ok_or("its first layer has no R, G and B channels")?,
        albedo: rgb("albedo.")?,
        normal: rgb("normal.")?,
    })
}

/// A portable float map: `PF` (colour) or `Pf` (grey), the width, the height and a scale whose
/// sign is the byte order (negative: little-endian), each after whitespace, then one
/// whitespace byte and 32-bit floats, rows from the bottom of the picture up.
fn read_pfm(bytes: &[u8]) -> Result<Canvas, String> {
    let channels = if bytes.starts_with(b"PF") { 3 } else { 1 };
    let mut at = 2;
    let mut token = || -> Result<&str, String> {
        while bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
            at += 1;
        }
        let start = at;
        while bytes.get(at).is_some_and(|b| !b.is_ascii_whitespace()) && at - start < 64 {
            at += 1;
        }
        std::str::from_utf8(&bytes[start..at])
            .ok()
            .filter(|t| !t.is_empty())
            .ok_or_else(|| "its PFM header is malformed".to_string())
    };
    let number = |t: &str, what: &str| {
        t.parse::<usize>()
            .map_err(|_| format!("its PFM header's {what} is not a whole number: `{t}`"))
    };
    let width = number(token()?, "width")?;
    let height = number(token()?, "height")?;
    let scale: f64 = token()?
        .parse()
        .map_err(|_| "its PFM header's scale is not a number".to_string())?;
    check_size(width, height)?;
    // One whitespace byte ends the header.
    let data = &bytes[(at + 1).min(bytes.len())..];
    let expected = width * height * channels * 4;
    if data.len() != expected {
        return Err(format!(
            "its {width}×{height} pixels take {expected} bytes of floats, the file holds {}",
            data.len()
        ));
    }
    let value = |i: usize| {
        let b: [u8; 4] = data[i * 4..i * 4 + 4].try_into().expect("four bytes");
        f64::from(if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        })
    };
    let mut canvas = Canvas::new(width, height);
    for y in 0..height {
        // Rows from the bottom up.
        let row = height - 1 - y;
        for x in 0..width {
            let i = (row * width + x) * channels;
            let c = if channels == 3 {
                Color::new(value(i), value(i + 1), value(i + 2))
            } else {
                Color::new(value(i), value(i), value(i))
            };
            canvas.write_pixel(x, y, c);
        }
    }
    Ok(canvas)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pfm_written_by_the_command_reads_back_the_right_way_up() {
        let mut canvas = Canvas::new(3, 2);
        canvas.write_pixel(0, 0, Color::new(0.25, 0.5, 2.0));
        canvas.write_pixel(2, 1, Color::new(17.5, 0.0, 1e-3));
        let bytes = ImageFormat::Pfm.encode(&canvas).unwrap();
        let back = read_pfm(&bytes).unwrap();
        assert_eq!(back.pixel_at(0, 0), Color::new(0.25, 0.5, 2.0));
        assert_eq!(
            back.pixel_at(2, 1),
            Color::new(17.5, 0.0, f64::from(1e-3f32))
        );
        assert_eq!(back.pixel_at(1, 0), Color::BLACK);
    }

    #[test]
    fn a_short_or_malformed_pfm_is_refused() {
        let bytes = ImageFormat::Pfm.encode(&Canvas::new(2, 2)).unwrap();
        let e = read_pfm(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(e.contains("take 48 bytes"), "{e}");
        assert!(read_pfm(b"PF\nx 2\n-1\n").unwrap_err().contains("width"));
        assert!(read_pfm(b"PF\n0 2\n-1\n").unwrap_err().contains("empty"));
    }
}
