//! Files a scene refers to (OBJ, glTF and PLY models, images, environment maps), found inside the scene
//! file's folder and read once each, within the scene's limits on triangles and on the memory
//! its images take.

use crate::error::SceneError;
use crate::files::{read_bounded, Folder};
use crate::gltf::model::{read_gltf, GltfModel, Limits};
use crate::hdr::{decode_hdr_image, read_hdr_image, HdrImage};
use crate::images::{
    decode, ImageMemory, Room, COLOR_BYTES, DEFAULT_MAX_IMAGE_MEMORY, ENVIRONMENT_BYTES_PER_TEXEL,
    MAX_IMAGE_BYTES,
};
use crate::obj::{read_obj_in, to_meshes_until};
use crate::ply::read_ply_in;
use crate::stop::StopFlag;
use rayforge::geometry::Mesh;
use rayforge::shading::{Filter, Texture};
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
    models: HashMap<PathBuf, Arc<GltfModel>>,
    ply_meshes: HashMap<PathBuf, Arc<Mesh>>,
    textures: Textures,
    /// The most triangles the scene's models may hold together.
    max_triangles: usize,
    /// How many they hold so far.
    triangles: usize,
    /// The flag that stops the models' reading part-way.
    stop: StopFlag,
}

impl Assets {
    /// Assets for the scene file at `scene_path`: names resolve in its folder and must stay
    /// inside it unless `allow_outside`; its models together may hold at most `max_triangles`
    /// triangles and its images (textures and environment maps) take at most
    /// `max_image_memory` bytes; the models' reading stops once `stop` is set.
    pub fn new(
        scene_path: &Path,
        allow_outside: bool,
        max_triangles: usize,
        max_image_memory: u64,
        stop: StopFlag,
    ) -> Self {
        Self {
            folder: Folder::of_file(scene_path, allow_outside),
            meshes: HashMap::new(),
            models: HashMap::new(),
            ply_meshes: HashMap::new(),
            textures: Textures {
                by_path: HashMap::new(),
                memory: ImageMemory::new(max_image_memory),
            },
            max_triangles,
            triangles: 0,
            stop,
        }
    }

    /// Every file read for the scene (models, material libraries, images, environment maps,
    /// glTF buffers), each once, in the order first read; `scene` itself left out.
    pub fn files(&self, scene: &Path) -> Vec<PathBuf> {
        let mut files = self.folder.asked();
        files.retain(|f| f != scene);
        files
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
            &self.stop,
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
        let meshes: ObjMeshes = Arc::new(
            to_meshes_until(&obj, &self.stop).ok_or_else(|| SceneError::interrupted(path))?,
        );
        self.meshes.insert(path.to_path_buf(), meshes.clone());
        Ok(meshes)
    }

    /// A glTF model, read on first use, within what is left of the scene's triangles and
    /// image memory.
    pub fn gltf(&mut self, path: &Path) -> Result<Arc<GltfModel>, SceneError> {
        if let Some(m) = self.models.get(path) {
            return Ok(m.clone());
        }
        self.folder
            .check(path)
            .map_err(|e| SceneError::new(path, e))?;
        let model = read_gltf(
            path,
            Limits {
                folder: &self.folder,
                memory: &mut self.textures.memory,
                max_triangles: self.max_triangles.saturating_sub(self.triangles),
                stop: &self.stop,
            },
        )?;
        let triangles: usize = model
            .objects
            .iter()
            .filter_map(|o| match &o.shape {
                rayforge::Shape::Mesh(m) => Some(m.face_count()),
                _ => None,
            })
            .sum();
        self.triangles = self.triangles.saturating_add(triangles);
        let model = Arc::new(model);
        self.models.insert(path.to_path_buf(), model.clone());
        Ok(model)
    }

    /// The mesh of a PLY model, read on first use, within what is left of the scene's
    /// triangles.
    pub fn ply(&mut self, path: &Path) -> Result<Arc<Mesh>, SceneError> {
        if let Some(m) = self.ply_meshes.get(path) {
            return Ok(m.clone());
        }
        self.folder
            .check(path)
            .map_err(|e| SceneError::new(path, e))?;
        let left = self.max_triangles.saturating_sub(self.triangles);
        let mesh = read_ply_in(path, left, &self.stop).map_err(|mut e| {
            if left < self.max_triangles {
                e.message = format!(
                    "{} (what the scene's models before it leave of the limit of {})",
                    e.message, self.max_triangles
                );
            }
            e
        })?;
        self.triangles = self.triangles.saturating_add(mesh.face_count());
        let mesh = Arc::new(mesh);
        self.ply_meshes.insert(path.to_path_buf(), mesh.clone());
        Ok(mesh)
    }

    /// An image texture, read on first use: PNG, JPEG, PPM/PGM/PBM, whose bytes become colours
    /// as they are (byte / 255), as the book's canvas-backed image patterns read them; or
    /// OpenEXR, Radiance HDR or PFM, whose linear values are kept as they are (HDR skyboxes and
    /// image patterns brighter than 1), within the same memory limit.
    pub fn texture(&mut self, path: &Path) -> Result<Arc<Texture>, SceneError> {
        cached_texture(&mut self.textures, &self.folder, path)
    }

    /// The bytes of a medium's grid file (`.vol`), at most `limit` of them; the error is the
    /// reason, for the caller to place at the `file:` that names it.
    pub fn volume_bytes(&mut self, path: &Path, limit: u64) -> Result<Vec<u8>, String> {
        self.folder.check(path)?;
        crate::files::read_bounded(path, limit)
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

/// Decodes an image file's bytes into a texture, within `room`: OpenEXR, Radiance HDR and PFM
/// keep their linear values (image patterns and skyboxes brighter than 1), PNG, JPEG and
/// PPM/PGM/PBM become byte / 255. The error is the reason, for the caller to name the file.
fn decode_texture(bytes: &[u8], room: Room) -> Result<Texture, String> {
    match decode_hdr_image(bytes, room, COLOR_BYTES) {
        Some(image) => {
            let image = image?;
            Texture::new(image.width, image.height, image.texels, Filter::Bilinear)
                .ok_or_else(|| "it has no pixels".to_string())
        }
        None => decode(bytes, room),
    }
}

/// Decodes an image file's bytes (OpenEXR, Radiance HDR, PFM, PNG, JPEG or PPM/PGM/PBM, told
/// apart by their contents) into a texture, as scene files' `image` patterns and MTL `map_Kd`
/// read them; `path` names the file in errors. Images over
/// [`MAX_TEXTURE_SIDE`](crate::MAX_TEXTURE_SIDE) on a side or
/// [`MAX_TEXTURE_PIXELS`](crate::MAX_TEXTURE_PIXELS) in all, or whose decoding would take more than
/// [`DEFAULT_MAX_IMAGE_MEMORY`], are refused before they are decoded.
pub fn texture_from_bytes(bytes: &[u8], path: &Path) -> Result<Texture, SceneError> {
    decode_texture(bytes, ImageMemory::new(DEFAULT_MAX_IMAGE_MEMORY).room()).map_err(|e| {
        SceneError::new(
            path,
            format!("cannot read the image `{}`: {e}", path.display()),
        )
    })
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
    let texture = decode_texture(&bytes, cache.memory.room()).map_err(fail)?;
    cache
        .memory
        .hold((texture.width() * texture.height()) as u64 * COLOR_BYTES);
    let texture = Arc::new(texture);
    cache.by_path.insert(path.to_path_buf(), texture.clone());
    Ok(texture)
}
