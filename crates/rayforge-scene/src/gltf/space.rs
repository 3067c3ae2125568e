//! glTF's space and the book's.

use glam::DMat4;

/// From glTF's right-handed space to the book's left-handed one: z mirrored.
pub const GLTF_TO_BOOK: DMat4 = DMat4::from_cols_array(&[
    1.0, 0.0, 0.0, 0.0, //
    0.0, 1.0, 0.0, 0.0, //
    0.0, 0.0, -1.0, 0.0, //
    0.0, 0.0, 0.0, 1.0,
]);
