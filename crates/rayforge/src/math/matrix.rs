//! The book's matrix API (chapters 3 and 4) over glam's column-major matrices.
//!
//! The book writes matrices row by row and indexes them `M[row, col]`; glam stores columns. The
//! constructors here take rows, and [`BookMatrix::at`] reads `M[row, col]`, so the book's tables
//! can be typed in as printed. Inversion itself is glam's; the submatrix/minor/cofactor steps are
//! here because the book teaches the determinant through them.

use glam::{DMat2, DMat3, DMat4, DVec3};

/// A 2×2 matrix from the book's rows.
pub fn matrix2(rows: [[f64; 2]; 2]) -> DMat2 {
    DMat2::from_cols_array_2d(&rows).transpose()
}

/// A 3×3 matrix from the book's rows.
pub fn matrix3(rows: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&rows).transpose()
}

/// A 4×4 matrix from the book's rows.
pub fn matrix4(rows: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols_array_2d(&rows).transpose()
}

/// The book's row-major view of a square matrix, with the determinant taught by cofactors.
pub trait BookMatrix: Sized {
    /// The matrix one size smaller.
    type Sub;
    /// The element at `row`, `col`.
    fn at(&self, row: usize, col: usize) -> f64;
    /// The matrix with `row` and `col` removed.
    fn submatrix(&self, row: usize, col: usize) -> Self::Sub;
    /// The determinant, expanded along the first row of cofactors.
    fn book_determinant(&self) -> f64;
    /// The determinant of the submatrix at `row`, `col`.
    fn minor(&self, row: usize, col: usize) -> f64;
    /// The minor, negated when `row + col` is odd.
    fn cofactor(&self, row: usize, col: usize) -> f64 {
        let minor = self.minor(row, col);
        if (row + col) % 2 == 1 {
            -minor
        } else {
            minor
        }
    }
}

impl BookMatrix for DMat2 {
    type Sub = f64;
    fn at(&self, row: usize, col: usize) -> f64 {
        self.col(col)[row]
    }
    fn submatrix(&self, row: usize, col: usize) -> f64 {
        self.at(1 - row, 1 - col)
    }
    fn book_determinant(&self) -> f64 {
        self.at(0, 0) * self.at(1, 1) - self.at(0, 1) * self.at(1, 0)
    }
    fn minor(&self, row: usize, col: usize) -> f64 {
        self.submatrix(row, col)
    }
}

/// Copies the rows and columns of an `N×N` matrix, skipping one of each, into a smaller one.
fn skip_row_col<const N: usize, const M: usize>(
    at: impl Fn(usize, usize) -> f64,
    row: usize,
    col: usize,
) -> [[f64; M]; M] {
    let mut out = [[0.0; M]; M];
    let keep = |skip: usize| (0..N).filter(move |&i| i != skip);
    for (r_out, r) in keep(row).enumerate() {
        for (c_out, c) in keep(col).enumerate() {
            out[r_out][c_out] = at(r, c);
        }
    }
    out
}

impl BookMatrix for DMat3 {
    type Sub = DMat2;
    fn at(&self, row: usize, col: usize) -> f64 {
        self.col(col)[row]
    }
    fn submatrix(&self, row: usize, col: usize) -> DMat2 {
        matrix2(skip_row_col::<3, 2>(|r, c| self.at(r, c), row, col))
    }
    fn book_determinant(&self) -> f64 {
        (0..3).map(|c| self.at(0, c) * self.cofactor(0, c)).sum()
    }
    fn minor(&self, row: usize, col: usize) -> f64 {
        self.submatrix(row, col).book_determinant()
    }
}

impl BookMatrix for DMat4 {
    type Sub = DMat3;
    fn at(&self, row: usize, col: usize) -> f64 {
        self.col(col)[row]
    }
    fn submatrix(&self, row: usize, col: usize) -> DMat3 {
        matrix3(skip_row_col::<4, 3>(|r, c| self.at(r, c), row, col))
    }
    fn book_determinant(&self) -> f64 {
        (0..4).map(|c| self.at(0, c) * self.cofactor(0, c)).sum()
    }
    fn minor(&self, row: usize, col: usize) -> f64 {
        self.submatrix(row, col).book_determinant()
    }
}

/// `translation(x, y, z)`: moves points, leaves vectors alone.
pub fn translation(x: f64, y: f64, z: f64) -> DMat4 {
    DMat4::from_translation(DVec3::new(x, y, z))
}

/// `scaling(x, y, z)`: scales each axis; negative factors reflect.
pub fn scaling(x: f64, y: f64, z: f64) -> DMat4 {
    DMat4::from_scale(DVec3::new(x, y, z))
}

/// `rotation_x(r)`: rotates by `r` radians about x, left-handed as the book's figures show.
pub fn rotation_x(r: f64) -> DMat4 {
    let (s, c) = r.sin_cos();
    matrix4([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, c, -s, 0.0],
        [0.0, s, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// `rotation_y(r)`: rotates by `r` radians about y.
pub fn rotation_y(r: f64) -> DMat4 {
    let (s, c) = r.sin_cos();
    matrix4([
        [c, 0.0, s, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [-s, 0.0, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// `rotation_z(r)`: rotates by `r` radians about z.
pub fn rotation_z(r: f64) -> DMat4 {
    let (s, c) = r.sin_cos();
    matrix4([
        [c, -s, 0.0, 0.0],
        [s, c, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// `shearing(xy, xz, yx, yz, zx, zy)`: each component moves in proportion to the other two.
pub fn shearing(xy: f64, xz: f64, yx: f64, yz: f64, zx: f64, zy: f64) -> DMat4 {
    matrix4([
        [1.0, xy, xz, 0.0],
        [yx, 1.0, yz, 0.0],
        [zx, zy, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// The view of right-handed renderers (pbrt, Mitsuba): an eye at `from` looking at `to`, the
/// image's right along `forward × up`, and the orientation orthonormal (lengths and angles
/// kept; a mirror, as the camera's own frame is the book's left-handed one).
///
/// The book's [`view_transform`] differs twice: its image's right is `up × forward` (a
/// left-handed world), and it does not normalise `forward × up`, so a camera whose `up` is not
/// perpendicular to its line of sight sees a field wider than its field of view says (by
/// `1 / sin` of the angle between them). Its scenes are kept as the book renders them; scenes
/// written for right-handed renderers ask for this one (the camera's `handedness: right`).
pub fn look_at(from: DVec3, to: DVec3, up: DVec3) -> DMat4 {
    let forward = (to - from).normalize_or_zero();
    let right = forward.cross(up).normalize_or_zero();
    let true_up = right.cross(forward);
    // The camera looks down its −z, and its image's right is its −x (see `Camera`).
    let orientation = matrix4([
        [-right.x, -right.y, -right.z, 0.0],
        [true_up.x, true_up.y, true_up.z, 0.0],
        [-forward.x, -forward.y, -forward.z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    orientation * translation(-from.x, -from.y, -from.z)
}

/// `view_transform(from, to, up)`: orients the world relative to an eye at `from` looking at `to`.
///
/// The result is singular when `up` is parallel to the line of sight (or `from == to`); callers
/// that take user input check that with [`crate::math::Transform::try_new`].
pub fn view_transform(from: DVec3, to: DVec3, up: DVec3) -> DMat4 {
    let forward = (to - from).normalize_or_zero();
    let left = forward.cross(up.normalize_or_zero());
    let true_up = left.cross(forward);
    let orientation = matrix4([
        [left.x, left.y, left.z, 0.0],
        [true_up.x, true_up.y, true_up.z, 0.0],
        [-forward.x, -forward.y, -forward.z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    orientation * translation(-from.x, -from.y, -from.z)
}

#[cfg(test)]
mod look_at_tests {
    use super::*;

    #[test]
    fn look_at_is_orthonormal_and_its_image_right_is_forward_cross_up() {
        // A camera looking down and ahead: the book's view would widen the field by 2 %.
        let (from, to, up) = (
            DVec3::new(0.0, 1.5, 5.0),
            DVec3::new(0.0, 0.5, 0.0),
            DVec3::Y,
        );
        let m = look_at(from, to, up);
        let linear = glam::DMat3::from_mat4(m);
        assert!((linear * linear.transpose() - glam::DMat3::IDENTITY)
            .abs_diff_eq(glam::DMat3::ZERO, 1e-12));
        // A mirror, not a rotation: the book's camera has its image's right along its own −x
        // in a left-handed frame, and this camera's right is forward × up in a right-handed one.
        assert!((linear.determinant() + 1.0).abs() < 1e-12);
        // The camera's −x (the image's right) is forward × up in the world.
        let forward = (to - from).normalize();
        let right = forward.cross(up).normalize();
        let image_right = linear.transpose() * DVec3::NEG_X;
        assert!((image_right - right).length() < 1e-12);
        // The eye goes to the origin, the target onto the camera's −z.
        assert!(m.transform_point3(from).length() < 1e-12);
        let t = m.transform_point3(to);
        assert!(t.x.abs() < 1e-12 && t.y.abs() < 1e-12 && t.z < 0.0);
    }
}
