//! Denoising for the command (`render --denoise`, `rayforge denoise`): Intel Open Image
//! Denoise loaded through `rayforge-denoise` (which explains why at run time), its absence a
//! usage error that says how to install it, and canvases handed to it as 32-bit floats.

use crate::failure::Failure;
use rayforge::canvas::Canvas;
use rayforge::color::Color;
use rayforge_denoise::{Denoiser, Images, Session};

/// OIDN, loaded before any work so that a render is not spent first; its absence refused with
/// how to install it (exit 2).
pub fn load(flag: &str) -> Result<Denoiser, Failure> {
    Denoiser::load().map_err(|e| Failure::usage(format!("{flag}: {e}")))
}

/// The guides of an image: the first surfaces' albedo and normals.
#[derive(Debug, Clone, Copy)]
pub struct Guides<'a> {
    /// The albedo, in [0, 1].
    pub albedo: &'a Canvas,
    /// The normals, in [-1, 1] (if known).
    pub normal: Option<&'a Canvas>,
}

/// `image`, linear radiance, denoised by `session` (on its device and filters, kept from one
/// image to the next; the result is the same for any thread count), guided by `guides` when
/// given; `what` names the image in messages.
pub fn denoise(
    session: &Session,
    image: &Canvas,
    guides: Option<Guides<'_>>,
    what: &str,
) -> Result<Canvas, Failure> {
    let (width, height) = (image.width(), image.height());
    let floats = Floats::of(image, guides);
    let out = session
        .denoise(&floats.images(width, height), true)
        .map_err(|e| Failure::usage(format!("cannot denoise {what}: {e}")))?;
    let pixels = out
        .chunks_exact(3)
        .map(|c| Color::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])))
        .collect();
    Ok(Canvas::from_pixels(width, height, pixels))
}

/// Whether OIDN would be given `image` and `guides` as they are: the checks
/// [`Session::denoise`] makes before OIDN runs, made without loading it (what the fuzzer
/// reaches of the denoiser's inputs, `crate::untrusted::denoise_inputs`).
pub fn check(image: &Canvas, guides: Option<Guides<'_>>, what: &str) -> Result<(), Failure> {
    Floats::of(image, guides)
        .images(image.width(), image.height())
        .check()
        .map_err(|e| Failure::usage(format!("cannot denoise {what}: {e}")))
}

/// An image and its guides as OIDN reads them ([`floats`]).
struct Floats {
    color: Vec<f32>,
    albedo: Option<Vec<f32>>,
    normal: Option<Vec<f32>>,
}

impl Floats {
    fn of(image: &Canvas, guides: Option<Guides<'_>>) -> Self {
        Self {
            color: floats(image),
            albedo: guides.map(|g| floats(g.albedo)),
            normal: guides.and_then(|g| g.normal).map(floats),
        }
    }

    fn images(&self, width: usize, height: usize) -> Images<'_> {
        Images {
            width,
            height,
            color: &self.color,
            albedo: self.albedo.as_deref(),
            normal: self.normal.as_deref(),
        }
    }
}

/// The canvas as OIDN reads it: three 32-bit floats a pixel, rows from the top, saturating
/// at the largest float (as the float files are written) rather than becoming infinite.
fn floats(canvas: &Canvas) -> Vec<f32> {
    let most = f64::from(f32::MAX);
    canvas
        .pixels()
        .iter()
        .flat_map(|c| c.to_array())
        .map(|v| v.clamp(-most, most) as f32)
        .collect()
}
