//! Errors about a glTF file, located by the JSON path of what is wrong
//! (`meshes[3].primitives[0].attributes.NORMAL`) in the error's key.

use crate::error::SceneError;
use std::path::Path;

/// An error about the model file `path` at the JSON path `at`.
pub(crate) fn error(path: &Path, at: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::new(path, message).with_key(at)
}
