//! Files a scene refers to (OBJ meshes, images), found relative to the scene file and read
//! once each.

use crate::error::SceneError;
use crate::files::read_bounded;
use crate::obj::{read_obj_file_with_limit, to_meshes};
use rayforge::geometry::Mesh;
use rayforge::shading::{Filter, Texture};
use rayforge::{Color, Material};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The meshes of one OBJ file, each with the material its `usemtl` names (if any).
pub type ObjMeshes = Arc<Vec<(Arc<Mesh>, Option<Material>)>>;

/// Loaded assets, keyed by path: a model used by several items is read and indexed once, and
/// its instances share the mesh.
pub struct Assets {
    base: PathBuf,
    meshes: HashMap<PathBuf, ObjMeshes>,
    textures: Textures,
    /// The most triangles the scene's models may hold together.
    max_triangles: usize,
    /// How many they hold so far.
    triangles: usize,
}

impl Assets {
    /// Assets for the scene file at `scene_path` (relative names resolve beside it), whose
    /// models together may hold at most `max_triangles` triangles and whose images at most
    /// `max_texture_pixels` pixels.
    pub fn new(scene_path: &Path, max_triangles: usize, max_texture_pixels: u64) -> Self {
        Self {
            base: scene_path
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
            meshes: HashMap::new(),
            textures: Textures {
                by_path: HashMap::new(),
                pixels: 0,
                max_pixels: max_texture_pixels,
            },
            max_triangles,
            triangles: 0,
        }
    }

    /// The most pixels the scene's images may hold (an environment map is held to it too).
    pub fn max_texture_pixels(&self) -> u64 {
        self.textures.max_pixels
    }

    /// Where a file named in the scene is.
    pub fn resolve(&self, name: &str) -> PathBuf {
        self.base.join(name)
    }

    /// The meshes of an OBJ file, read on first use.
    pub fn obj(&mut self, path: &Path) -> Result<ObjMeshes, SceneError> {
        if let Some(m) = self.meshes.get(path) {
            return Ok(m.clone());
        }
        let textures = &mut self.textures;
        // One model is held to the limit as it is read; then the scene's total is.
        let obj = read_obj_file_with_limit(
            path,
            &mut |image| cached_texture(textures, image),
            self.max_triangles,
        )?;
        let triangles: usize = obj.groups.iter().map(|g| g.triangles.len()).sum();
        self.triangles = self.triangles.saturating_add(triangles);
        if self.triangles > self.max_triangles {
            return Err(SceneError::new(
                path,
                format!(
                    "with this model's {triangles} triangles the scene's models hold {} together, \
                     more than the mesh size limit of {} (`--max-triangles` on the command line)",
                    self.triangles, self.max_triangles
                ),
            ));
        }
        let meshes: ObjMeshes = Arc::new(to_meshes(&obj));
        self.meshes.insert(path.to_path_buf(), meshes.clone());
        Ok(meshes)
    }

    /// An image texture (PNG, JPEG, PPM/PGM/PBM), read on first use. Bytes become colours as
    /// they are (byte / 255), as the book's canvas-backed image patterns read them.
    pub fn texture(&mut self, path: &Path) -> Result<Arc<Texture>, SceneError> {
        cached_texture(&mut self.textures, path)
    }
}

/// The images a scene has read, and how many pixels they hold together.
struct Textures {
    by_path: HashMap<PathBuf, Arc<Texture>>,
    pixels: u64,
    max_pixels: u64,
}

/// An image texture from `cache`, read and added on first use, within the cache's limit on
/// the pixels of all the scene's images.
fn cached_texture(cache: &mut Textures, path: &Path) -> Result<Arc<Texture>, SceneError> {
    if let Some(t) = cache.by_path.get(path) {
        return Ok(t.clone());
    }
    let bytes = read_bounded(path, MAX_IMAGE_BYTES).map_err(|e| {
        SceneError::new(
            path,
            format!("cannot read the image `{}`: {e}", path.display()),
        )
    })?;
    let (texture, pixels) = decode(&bytes, path)?;
    cache.pixels += pixels;
    if cache.pixels > cache.max_pixels {
        return Err(SceneError::new(
            path,
            format!(
                "with this image the scene's images hold {} pixels together, more than the \
                 limit of {}",
                cache.pixels, cache.max_pixels
            ),
        ));
    }
    let texture = Arc::new(texture);
    cache.by_path.insert(path.to_path_buf(), texture.clone());
    Ok(texture)
}

/// Decodes an image file's bytes (PNG, JPEG or PPM/PGM/PBM, told apart by their contents) into
/// a texture, as scene files' `image` patterns and MTL `map_Kd` read them; `path` names the file
/// in errors. Images over [`MAX_TEXTURE_SIDE`] on a side or [`MAX_TEXTURE_PIXELS`] in all are
/// refused before they are decoded.
pub fn texture_from_bytes(bytes: &[u8], path: &Path) -> Result<Texture, SceneError> {
    decode(bytes, path).map(|(texture, _)| texture)
}

/// [`texture_from_bytes`], with the number of pixels.
fn decode(bytes: &[u8], path: &Path) -> Result<(Texture, u64), SceneError> {
    let fail = |e: &dyn std::fmt::Display| {
        SceneError::new(
            path,
            format!("cannot read the image `{}`: {e}", path.display()),
        )
    };
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| fail(&e))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    reader.limits(limits);
    // The decoders are third-party code fed untrusted bytes: a panic in one is a broken image,
    // reported as such, not a crash of the renderer.
    let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(
        move || -> Result<_, String> {
            use image::ImageDecoder;
            let decoder = reader.into_decoder().map_err(|e| e.to_string())?;
            let (w, h) = decoder.dimensions();
            if u64::from(w) * u64::from(h) > MAX_TEXTURE_PIXELS {
                return Err(format!(
                    "it is {w}×{h} pixels; the limit is {MAX_TEXTURE_PIXELS} pixels"
                ));
            }
            let image = image::DynamicImage::from_decoder(decoder).map_err(|e| e.to_string())?;
            Ok(image.to_rgb32f())
        },
    ))
    .map_err(|_| fail(&"the image decoder failed on it (the file is damaged)"))?;
    let rgb = decoded.map_err(|e| fail(&e))?;
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    let pixels = rgb
        .pixels()
        .map(|p| Color::new(p[0] as f64, p[1] as f64, p[2] as f64))
        .collect();
    Texture::new(w, h, pixels, Filter::Bilinear)
        .map(|t| (t, (w * h) as u64))
        .ok_or_else(|| fail(&"the image is empty"))
}

/// The largest image side accepted.
pub const MAX_TEXTURE_SIDE: u32 = 16_384;

/// The most pixels an image texture may have: 2²⁶ (8192 × 8192), 1.5 GiB as colours.
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 26;

/// The most pixels all of a scene's images may hold together by default: 2²⁷, 3 GiB as
/// colours.
pub const MAX_SCENE_TEXTURE_PIXELS: u64 = 1 << 27;

/// The largest image file read.
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;
