//! Files a scene refers to (OBJ meshes, images, environment maps), found inside the scene
//! file's folder and read once each, within the scene's limits on triangles and on the memory
//! its images take.

use crate::error::SceneError;
use crate::files::{read_bounded, Folder};
use crate::hdr::{read_hdr_image, HdrImage};
use crate::images::{
    decode, ImageMemory, COLOR_BYTES, ENVIRONMENT_BYTES_PER_TEXEL, MAX_IMAGE_BYTES,
};
use crate::obj::{read_obj_in, to_meshes};
use rayforge::geometry::Mesh;
use rayforge::shading::Texture;
use rayforge::Material;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The meshes of one OBJ file, each with the material its `usemtl` names (if any).
pub type ObjMeshes = Arc<Vec<(Arc<Mesh>, Option<Material>)>>;

/// Loaded assets, keyed by path: a model used by several items is read and indexed once, and
/// its instances share the mesh.
pub struct Assets {
    folder: Folder,
    meshes: HashMap<PathBuf, ObjMeshes>,
    textures: Textures,
    /// The most triangles the scene's models may hold together.
    max_triangles: usize,
    /// How many they hold so far.
    triangles: usize,
}

impl Assets {
    /// Assets for the scene file at `scene_path`: names resolve in its folder and must stay
    /// inside it unless `allow_outside`; its models together may hold at most `max_triangles`
    /// triangles and its images (textures and environment maps) take at most
    /// `max_image_memory` bytes.
    pub fn new(
        scene_path: &Path,
        allow_outside: bool,
        max_triangles: usize,
        max_image_memory: u64,
    ) -> Self {
        Self {
            folder: Folder::of_file(scene_path, allow_outside),
            meshes: HashMap::new(),
            textures: Textures {
                by_path: HashMap::new(),
                memory: ImageMemory::new(max_image_memory),
            },
            max_triangles,
            triangles: 0,
        }
    }

    /// Where a file named in the scene is (whether it may be read is checked when it is).
    pub fn resolve(&self, name: &str) -> PathBuf {
        self.folder.named().join(name)
    }

    /// The meshes of an OBJ file, read on first use.
    pub fn obj(&mut self, path: &Path) -> Result<ObjMeshes, SceneError> {
        if let Some(m) = self.meshes.get(path) {
            return Ok(m.clone());
        }
        self.folder
            .check(path)
            .map_err(|e| SceneError::new(path, e))?;
        let (folder, textures) = (&self.folder, &mut self.textures);
        // One model is held to the limit as it is read; then the scene's total is.
        let obj = read_obj_in(
            path,
            folder,
            &mut |image| cached_texture(textures, folder, image),
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
        cached_texture(&mut self.textures, &self.folder, path)
    }

    /// An environment map (OpenEXR, Radiance HDR or PFM), within what is left of the images'
    /// memory; the error is the reason, for the caller to place at the `file:` that names it.
    pub fn environment_image(&mut self, path: &Path) -> Result<HdrImage, String> {
        self.folder.check(path)?;
        let memory = &mut self.textures.memory;
        let image = read_hdr_image(path, memory.room()).map_err(|e| e.to_string())?;
        memory.hold((image.width * image.height) as u64 * ENVIRONMENT_BYTES_PER_TEXEL);
        Ok(image)
    }
}

/// The images a scene has read, and the memory they take.
struct Textures {
    by_path: HashMap<PathBuf, Arc<Texture>>,
    memory: ImageMemory,
}

/// An image texture from `cache`, read and added on first use if `folder` allows it, within
/// the cache's limit on the memory of all the scene's images.
fn cached_texture(
    cache: &mut Textures,
    folder: &Folder,
    path: &Path,
) -> Result<Arc<Texture>, SceneError> {
    if let Some(t) = cache.by_path.get(path) {
        return Ok(t.clone());
    }
    let fail = |e: String| {
        SceneError::new(
            path,
            format!("cannot read the image `{}`: {e}", path.display()),
        )
    };
    folder.check(path).map_err(|e| SceneError::new(path, e))?;
    let bytes = read_bounded(path, MAX_IMAGE_BYTES).map_err(fail)?;
    let texture = decode(&bytes, cache.memory.room()).map_err(fail)?;
    cache
        .memory
        .hold((texture.width() * texture.height()) as u64 * COLOR_BYTES);
    let texture = Arc::new(texture);
    cache.by_path.insert(path.to_path_buf(), texture.clone());
    Ok(texture)
}
