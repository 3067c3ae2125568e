//! pbrt-v4's bilinear patches (`bilinearmesh`) as triangles.
//!
//! A patch is `P(u, v) = (1−u)(1−v) p00 + u(1−v) p10 + (1−u)v p01 + uv p11`. pbrt-v4
//! intersects it exactly; rayforge tessellates it, because its meshes already carry
//! everything a `bilinearmesh` needs to behave as a `trianglemesh` (the front by pbrt's rule,
//! shading normals, uv, alpha, emission and light sampling by area, `--max-triangles`), where
//! an exact patch would need all of it again in the geometry layer. The tessellation is
//! faithful to a stated bound:
//!
//! - A planar patch (its corners in one plane, to [`PLANAR`] of its size) is exactly two
//!   triangles, split along the diagonal that keeps both on the patch's side (either, for a
//!   convex quad): the same surface as pbrt-v4's.
//! - A curved patch is an `n × n` grid in `(u, v)`, each cell two triangles. The patch's only
//!   second derivative is its twist `d = p00 − p10 − p01 + p11`, and a cell's triangles are
//!   within `|d| / 4n²` of it (the bilinear `uv` is at most 1/4 from its linear interpolant on
//!   a unit cell's triangle), so `n` is the least with that within [`TOLERANCE`] of the
//!   patch's size (its bounding box's diagonal): at most 23 a side, about a thousand
//!   triangles, for any patch. Each grid point carries the patch's own normal
//!   `∂P/∂u × ∂P/∂v` (or its `N` interpolated) as its shading normal, so it shades as the
//!   smooth patch does.
//!
//! The front is pbrt-v4's: `∂P/∂u × ∂P/∂v`, `(p10 − p00) × (p01 − p00)` at `p00`, which the
//! triangles keep (they are wound `p00, p10, p11` and `p00, p11, p01` in the patch's order);
//! with `N`, the side of the interpolated `N`, as for a `trianglemesh`. Texture coordinates
//! are the patch's `(u, v)` (or its corners' `uv`) at each grid point; within a planar patch
//! that is no parallelogram, the triangles interpolate them linearly where pbrt-v4 does so
//! bilinearly (the same at the corners and along the edges).

use glam::{DVec2, DVec3};

/// A planar patch's corners are within this fraction of its size of one plane.
pub const PLANAR: f64 = 1e-9;

/// A curved patch's triangles are within this fraction of its size of the patch.
pub const TOLERANCE: f64 = 1e-3;

/// One patch's corners (pbrt-v4's order: `p00, p10, p01, p11`) with their normals and uv.
pub struct Patch {
    pub p: [DVec3; 4],
    pub n: Option<[DVec3; 4]>,
    pub uv: [DVec2; 4],
}

/// The triangles of patches, appended patch by patch.
#[derive(Default)]
pub struct Tessellation {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub texcoords: Vec<[f64; 2]>,
    pub indices: Vec<u32>,
}

impl Patch {
    /// The point at `(u, v)`.
    pub fn at(&self, u: f64, v: f64) -> DVec3 {
        lerp4(self.p, u, v)
    }

    /// `∂P/∂u × ∂P/∂v` at `(u, v)`: the patch's front.
    fn normal(&self, u: f64, v: f64) -> DVec3 {
        let [p00, p10, p01, p11] = self.p;
        let du = (1.0 - v) * (p10 - p00) + v * (p11 - p01);
        let dv = (1.0 - u) * (p01 - p00) + u * (p11 - p10);
        du.cross(dv)
    }

    /// The size the bounds are relative to: the corners' bounding box's diagonal.
    fn size(&self) -> f64 {
        let lo = self.p.iter().copied().fold(DVec3::INFINITY, DVec3::min);
        let hi = self.p.iter().copied().fold(DVec3::NEG_INFINITY, DVec3::max);
        (hi - lo).length()
    }

    /// Whether the corners lie in one plane (to [`PLANAR`]).
    fn planar(&self) -> bool {
        let [p00, p10, p01, p11] = self.p;
        let size = self.size();
        let n = (p10 - p00).cross(p01 - p00) + (p11 - p10).cross(p11 - p01);
        // A degenerate patch (a line or a point) has no area to bend.
        if n.length() <= PLANAR * size * size {
            return true;
        }
        let n = n.normalize();
        [p10, p01, p11]
            .iter()
            .all(|&q| (q - p00).dot(n).abs() <= PLANAR * size)
    }

    /// The grid's cells a side: 1 for a planar patch, else the least `n` within
    /// [`TOLERANCE`] (see the [module](self)).
    pub fn cells(&self) -> usize {
        if self.planar() {
            return 1;
        }
        let [p00, p10, p01, p11] = self.p;
        let twist = (p00 - p10 - p01 + p11).length();
        let n = (twist / (4.0 * TOLERANCE * self.size())).sqrt().ceil();
        // The twist is at most twice the size, so n is at most 23.
        if n.is_nan() {
            23
        } else {
            n.clamp(1.0, 23.0) as usize
        }
    }

    /// Appends the patch's triangles to `out`, its grid `cells` a side.
    pub fn tessellate(&self, cells: usize, out: &mut Tessellation) {
        let first = out.positions.len() as u32;
        if cells == 1 {
            // Two triangles, on the diagonal that keeps both facing the patch's front.
            let [p00, p10, p01, p11] = self.p;
            let front = self.normal(0.5, 0.5);
            let keeps = (p10 - p00).cross(p11 - p00).dot(front) >= 0.0
                && (p11 - p00).cross(p01 - p00).dot(front) >= 0.0;
            for (k, uv) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .into_iter()
                .enumerate()
            {
                out.positions.push(self.p[k]);
                out.texcoords.push(self.texcoord(uv.0, uv.1));
                out.normals.push(self.shading(uv.0, uv.1, front));
            }
            let [a, b, c, d] = [0, 1, 2, 3].map(|i| first + i);
            if keeps {
                out.indices.extend([a, b, d, a, d, c]);
            } else {
                out.indices.extend([a, b, c, b, d, c]);
            }
            return;
        }
        let step = 1.0 / cells as f64;
        for j in 0..=cells {
            for i in 0..=cells {
                let (u, v) = (i as f64 * step, j as f64 * step);
                out.positions.push(self.at(u, v));
                out.texcoords.push(self.texcoord(u, v));
                out.normals.push(self.shading(u, v, self.normal(u, v)));
            }
        }
        let row = cells as u32 + 1;
        for j in 0..cells as u32 {
            for i in 0..cells as u32 {
                let a = first + j * row + i;
                let [b, c, d] = [a + 1, a + row, a + row + 1];
                out.indices.extend([a, b, d, a, d, c]);
            }
        }
    }

    /// The shading normal at `(u, v)`: the corners' `N` interpolated, or the patch's own
    /// `normal` there.
    fn shading(&self, u: f64, v: f64, normal: DVec3) -> DVec3 {
        match self.n {
            Some(n) => lerp4(n, u, v),
            None => normal,
        }
    }

    /// The texture coordinates at `(u, v)`.
    fn texcoord(&self, u: f64, v: f64) -> [f64; 2] {
        let [a, b, c, d] = self.uv;
        let t = (1.0 - u) * (1.0 - v) * a + u * (1.0 - v) * b + (1.0 - u) * v * c + u * v * d;
        [t.x, t.y]
    }
}

/// The bilinear blend of `q` (`q00, q10, q01, q11`) at `(u, v)`.
fn lerp4(q: [DVec3; 4], u: f64, v: f64) -> DVec3 {
    (1.0 - u) * (1.0 - v) * q[0] + u * (1.0 - v) * q[1] + (1.0 - u) * v * q[2] + u * v * q[3]
}
