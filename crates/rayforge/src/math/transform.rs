//! A transform with its inverse and normal matrix computed once, when it is set.
//!
//! Rays are moved into object space with the inverse on every intersection test, and normals back
//! with the inverse transpose; computing those per ray would dominate the render, so they are baked.

use glam::{DAffine3, DMat3, DMat4, DVec3};

/// A matrix that cannot be inverted (determinant zero, or not finite), so cannot place an object.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("{}", self.explain())]
pub struct SingularTransform {
    /// The offending determinant.
    pub determinant: f64,
}

impl SingularTransform {
    /// Why the matrix cannot place an object: flat (determinant 0 or tiny), or so large that
    /// its determinant overflows (a scale of 1e300), which is not the same mistake.
    fn explain(&self) -> String {
        if self.determinant.is_finite() {
            format!(
                "the transform is singular (determinant {}) and cannot be inverted",
                self.determinant
            )
        } else {
            format!(
                "the transform is too large (its determinant is {}): a scale, shear or \
                 translation past what 64-bit numbers can invert",
                self.determinant
            )
        }
    }
}

/// An invertible affine transform: `world_from_object`, its inverse and the normal matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    matrix: DMat4,
    forward: DAffine3,
    inverse: DAffine3,
    /// Inverse transpose of the linear part: maps object-space normals to world space.
    normal: DMat3,
    /// The linear part is diagonal (scaling, translation, mirrors: most of the book's
    /// placements): the inverse and the normal map then take three products instead of nine,
    /// with the same result (the skipped terms are exact zeros).
    axis_aligned: bool,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// Determinants smaller than this are treated as singular: inverting them would produce
/// coordinates so large that every later computation is noise.
const MIN_DETERMINANT: f64 = 1e-12;

impl Transform {
    /// The identity transform.
    pub const IDENTITY: Self = Self {
        matrix: DMat4::IDENTITY,
        forward: DAffine3::IDENTITY,
        inverse: DAffine3::IDENTITY,
        normal: DMat3::IDENTITY,
        axis_aligned: true,
    };

    /// A transform from a matrix, or an error when it cannot be inverted.
    ///
    /// The bottom row is assumed to be `0 0 0 1` (every transform the book builds is affine).
    pub fn try_new(matrix: DMat4) -> Result<Self, SingularTransform> {
        let determinant = matrix.determinant();
        if !determinant.is_finite() || determinant.abs() < MIN_DETERMINANT || !matrix.is_finite() {
            return Err(SingularTransform { determinant });
        }
        let forward = DAffine3::from_mat4(matrix);
        let inverse = forward.inverse();
        let normal = inverse.matrix3.transpose();
        let m = inverse.matrix3;
        let axis_aligned = [
            m.x_axis.y, m.x_axis.z, m.y_axis.x, m.y_axis.z, m.z_axis.x, m.z_axis.y,
        ]
        .iter()
        .all(|&e| e == 0.0);
        Ok(Self {
            matrix,
            forward,
            inverse,
            normal,
            axis_aligned,
        })
    }

    /// A transform from a matrix.
    ///
    /// # Panics
    /// When the matrix is singular; use [`Transform::try_new`] for user input.
    pub fn new(matrix: DMat4) -> Self {
        match Self::try_new(matrix) {
            Ok(t) => t,
            Err(e) => panic!("{e}"),
        }
    }

    /// The matrix as given.
    pub fn matrix(&self) -> DMat4 {
        self.matrix
    }

    /// The inverse matrix (`object_from_world`).
    pub fn inverse_matrix(&self) -> DMat4 {
        DMat4::from(self.inverse)
    }

    /// Transforms a point (translation applies).
    #[inline]
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.forward.transform_point3(p)
    }

    /// Transforms a vector (translation does not apply).
    #[inline]
    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.forward.transform_vector3(v)
    }

    /// Applies the inverse to a point: world space to object space.
    #[inline]
    pub fn inverse_point(&self, p: DVec3) -> DVec3 {
        if self.axis_aligned {
            diagonal(&self.inverse.matrix3) * p + self.inverse.translation
        } else {
            self.inverse.transform_point3(p)
        }
    }

    /// Applies the inverse to a vector.
    #[inline]
    pub fn inverse_vector(&self, v: DVec3) -> DVec3 {
        if self.axis_aligned {
            diagonal(&self.inverse.matrix3) * v
        } else {
            self.inverse.transform_vector3(v)
        }
    }

    /// Maps an object-space normal to world space and normalises it (the book's inverse-transpose
    /// trick, with `w` dropped by construction). A zero normal (a cone's apex) stays zero rather
    /// than becoming NaN.
    #[inline]
    pub fn normal(&self, n: DVec3) -> DVec3 {
        let world = if self.axis_aligned {
            diagonal(&self.normal) * n
        } else {
            self.normal * n
        };
        world.normalize_or_zero()
    }

    /// Whether the transform mirrors (its linear part's determinant is negative): tangent
    /// frames then change hands.
    #[inline]
    pub fn mirrors(&self) -> bool {
        self.forward.matrix3.determinant() < 0.0
    }

    /// The absolute determinant of the linear part: how much the transform scales volumes.
    #[inline]
    pub fn volume_scale(&self) -> f64 {
        self.forward.matrix3.determinant().abs()
    }

    /// An object-space normal mapped to world space by the inverse transpose, not normalised:
    /// its length times [`volume_scale`](Self::volume_scale) is how much the transform
    /// stretches a small patch of surface with that (unit) normal, which the path tracer needs
    /// to turn a density over an object's own surface into one over its surface in the world.
    #[inline]
    pub fn normal_unnormalised(&self, n: DVec3) -> DVec3 {
        self.normal * n
    }

    /// Maps a world-space normal back to object space (the inverse of [`Transform::normal`]:
    /// the transpose of the linear part), normalised.
    #[inline]
    pub fn normal_to_object(&self, n: DVec3) -> DVec3 {
        (self.forward.matrix3.transpose() * n).normalize_or_zero()
    }

    /// `self` applied after `inner`: `self * inner` in matrix terms.
    pub fn then_after(&self, inner: &Transform) -> Result<Self, SingularTransform> {
        Self::try_new(self.matrix * inner.matrix)
    }
}

/// The diagonal of a matrix, as a vector.
#[inline]
fn diagonal(m: &DMat3) -> DVec3 {
    DVec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z)
}
