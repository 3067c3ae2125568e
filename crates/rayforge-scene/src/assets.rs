//! Files a scene refers to (OBJ meshes), found relative to the scene file and read once each.

use crate::error::SceneError;
use crate::obj::{read_obj_file, to_meshes};
use rayforge::geometry::Mesh;
use rayforge::Material;
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
        let obj = read_obj_file(path)?;
        let meshes: ObjMeshes = Arc::new(to_meshes(&obj));
        self.meshes.insert(path.to_path_buf(), meshes.clone());
        Ok(meshes)
    }
}
