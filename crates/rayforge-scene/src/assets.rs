//! Files a scene refers to (OBJ meshes), found relative to the scene file and read once each.

use crate::error::SceneError;
use crate::obj::{read_obj_file, to_meshes};
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
    textures: HashMap<PathBuf, Arc<Texture>>,
}

impl Assets {
    /// Assets for the scene file at `scene_path` (relative names resolve beside it).
    pub fn new(scene_path: &Path) -> Self {
        Self {
            base: scene_path
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
            meshes: HashMap::new(),
            textures: HashMap::new(),
        }
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
        let obj = read_obj_file(path, &mut |image| cached_texture(textures, image))?;
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

/// An image texture from `cache`, read and added on first use.
fn cached_texture(
    cache: &mut HashMap<PathBuf, Arc<Texture>>,
    path: &Path,
) -> Result<Arc<Texture>, SceneError> {
    {
        if let Some(t) = cache.get(path) {
            return Ok(t.clone());
        }
        let fail = |e: &dyn std::fmt::Display| {
            SceneError::new(
                path,
                format!("cannot read the image `{}`: {e}", path.display()),
            )
        };
        let reader = image::ImageReader::open(path)
            .map_err(|e| fail(&e))?
            .with_guessed_format()
            .map_err(|e| fail(&e))?;
        let mut reader = reader;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE);
        reader.limits(limits);
        let rgb = reader.decode().map_err(|e| fail(&e))?.to_rgb32f();
        let (w, h) = (rgb.width() as usize, rgb.height() as usize);
        let pixels = rgb
            .pixels()
            .map(|p| Color::new(p[0] as f64, p[1] as f64, p[2] as f64))
            .collect();
        let texture = Texture::new(w, h, pixels, Filter::Bilinear)
            .ok_or_else(|| fail(&"the image is empty"))?;
        let texture = Arc::new(texture);
        cache.insert(path.to_path_buf(), texture.clone());
        Ok(texture)
    }
}

/// The largest image side accepted (16384 pixels: 256 Mpixel, 6 GiB as colours, is the limit).
const MAX_TEXTURE_SIDE: u32 = 16_384;
