//! glTF 2.0 models (`.gltf` with its buffers and images, embedded `data:` URIs, or `.glb`):
//! meshes, the node hierarchy, metallic-roughness materials, cameras and punctual lights.
//!
//! The `gltf` crate parses and validates the JSON and reads accessors (sparse ones included);
//! buffers and images are read here, through the scene's folder rules and memory limits, so a
//! hostile file meets the same bounds as a hostile scene. Errors name the file and the JSON
//! path of what is wrong (`meshes[3].primitives[0].attributes.NORMAL`).
//!
//! glTF's space is right-handed (+Y up, cameras look down −Z); the book's is left-handed. A
//! model is placed in the book's world through [`GLTF_TO_BOOK`], a mirror of z, so it looks
//! the same through the book's camera as through a glTF viewer's: every face's winding is
//! reversed to match (the book's face normal is `e2 × e1`), texture coordinates are stored
//! with v up (`1 − v`), and the tangent frames change hands with the transform.

mod buffers;
mod materials;
mod meshes;
pub(crate) mod model;
mod nodes;
mod paths;
mod scene;
mod space;

pub use crate::scene::CameraChoice;
pub use model::{GltfModel, APPROXIMATED_EXTENSIONS, SUPPORTED_EXTENSIONS};
pub use nodes::{GltfCamera, GltfLight, LightKind, Projection, MAX_NODE_DEPTH, MAX_NODE_VISITS};
pub use scene::{
    book_camera, book_lights, default_camera, default_light, default_size, is_model_file,
    model_scene, pick, DEFAULT_SKY,
};
pub use space::GLTF_TO_BOOK;
