//! The majorant grid of a heterogeneous medium: a coarse grid (16³ cells over the density
//! grid's box, as pbrt-v4's) holding the most density in each cell, walked by a 3D DDA
//! (Amanatides and Woo) along a ray. Null-collision tracking samples distances against these
//! local bounds rather than one bound for the whole medium, so a thin wisp beside a dense
//! core does not make every ray through the wisp take the core's many null collisions.

use super::grid::DensityGrid;
use crate::color::Color;
use crate::math::{point, Point3, Vec3};

/// Cells along each axis.
pub const MAJORANT_CELLS: usize = 16;

/// The most density in each of [`MAJORANT_CELLS`]³ cells of the unit cube.
#[derive(Debug, Clone, PartialEq)]
pub struct MajorantGrid {
    max: Vec<f64>,
}

impl MajorantGrid {
    /// The majorants of `density`.
    pub fn of(density: &DensityGrid) -> Self {
        let n = MAJORANT_CELLS;
        let mut max = Vec::with_capacity(n * n * n);
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let lo = point(x as f64, y as f64, z as f64) / n as f64;
                    let hi = point((x + 1) as f64, (y + 1) as f64, (z + 1) as f64) / n as f64;
                    max.push(density.max_over(lo, hi));
                }
            }
        }
        Self { max }
    }

    /// The majorant of cell `(x, y, z)`.
    #[inline]
    fn at(&self, [x, y, z]: [isize; 3]) -> f64 {
        let n = MAJORANT_CELLS;
        self.max[(z as usize * n + y as usize) * n + x as usize]
    }
}

/// A stretch of a ray over which one majorant holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MajorantSegment {
    /// Where it starts along the ray.
    pub t_min: f64,
    /// Where it ends.
    pub t_max: f64,
    /// The majorant extinction over it.
    pub sigma_maj: Color,
}

/// The cells of a majorant grid a ray crosses, in order, each as a [`MajorantSegment`].
#[derive(Debug, Clone)]
pub struct Dda<'g> {
    grid: &'g MajorantGrid,
    sigma_t: Color,
    t_min: f64,
    t_max: f64,
    next_crossing: [f64; 3],
    delta: [f64; 3],
    step: [isize; 3],
    limit: [isize; 3],
    cell: [isize; 3],
}

impl<'g> Dda<'g> {
    /// The walk of the ray `origin + t·direction` (in the unit cube of the grid) over
    /// `[t_min, t_max]`, which lies inside the cube; each cell's majorant density is scaled
    /// by `sigma_t`.
    pub fn new(
        grid: &'g MajorantGrid,
        sigma_t: Color,
        origin: Point3,
        direction: Vec3,
        t_min: f64,
        t_max: f64,
    ) -> Self {
        let n = MAJORANT_CELLS as f64;
        let entry = origin + direction * t_min;
        let (e, d) = (entry.to_array(), direction.to_array());
        let mut dda = Self {
            grid,
            sigma_t,
            t_min,
            t_max,
            next_crossing: [f64::INFINITY; 3],
            delta: [f64::INFINITY; 3],
            step: [1; 3],
            limit: [MAJORANT_CELLS as isize; 3],
            cell: [0; 3],
        };
        for axis in 0..3 {
            let cell = ((e[axis] * n) as isize).clamp(0, MAJORANT_CELLS as isize - 1);
            dda.cell[axis] = cell;
            if d[axis] == 0.0 {
                continue;
            }
            dda.delta[axis] = 1.0 / (d[axis].abs() * n);
            if d[axis] > 0.0 {
                let next = (cell + 1) as f64 / n;
                dda.next_crossing[axis] = t_min + (next - e[axis]) / d[axis];
            } else {
                let next = cell as f64 / n;
                dda.next_crossing[axis] = t_min + (next - e[axis]) / d[axis];
                dda.step[axis] = -1;
                dda.limit[axis] = -1;
            }
        }
        dda
    }
}

impl Iterator for Dda<'_> {
    type Item = MajorantSegment;

    fn next(&mut self) -> Option<MajorantSegment> {
        if self.t_min >= self.t_max {
            return None;
        }
        let c = self.next_crossing;
        let axis = if c[0] < c[1] && c[0] < c[2] {
            0
        } else if c[1] < c[2] {
            1
        } else {
            2
        };
        let exit = self.t_max.min(c[axis]);
        let segment = MajorantSegment {
            t_min: self.t_min,
            t_max: exit,
            sigma_maj: self.sigma_t * self.grid.at(self.cell),
        };
        self.t_min = exit;
        self.cell[axis] += self.step[axis];
        if c[axis] > self.t_max || self.cell[axis] == self.limit[axis] {
            self.t_min = self.t_max;
        }
        self.next_crossing[axis] += self.delta[axis];
        Some(segment)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    /// Segments tile the ray's range without gap or overlap, and each majorant bounds the
    /// density at every point of its segment.
    #[test]
    fn segments_tile_the_ray_and_bound_the_density() {
        let values: Vec<f32> = (0..(10 * 7 * 5)).map(|i| ((i * 53) % 17) as f32).collect();
        let density = DensityGrid::new([10, 7, 5], values).expect("grid");
        let grid = MajorantGrid::of(&density);
        let mut rng = SplitMix64::new(4);
        for _ in 0..200 {
            let mut r = || rng.next_offset();
            let origin = point(r(), r(), r());
            let d = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5);
            // Through the cube from t = 0 (inside) to where it leaves.
            let exit = (0..3)
                .map(|a| {
                    let (o, d) = (origin[a], d[a]);
                    if d > 0.0 {
                        (1.0 - o) / d
                    } else if d < 0.0 {
                        -o / d
                    } else {
                        f64::INFINITY
                    }
                })
                .fold(f64::INFINITY, f64::min);
            let mut at = 0.0;
            for s in Dda::new(&grid, Color::WHITE, origin, d, 0.0, exit) {
                assert!((s.t_min - at).abs() < 1e-9, "gap at {at}: {s:?}");
                assert!(s.t_max >= s.t_min);
                for k in 0..8 {
                    let t = s.t_min + (s.t_max - s.t_min) * (k as f64 + 0.5) / 8.0;
                    let p = origin + d * t;
                    assert!(density.lookup(p) <= s.sigma_maj.red + 1e-9, "{p} in {s:?}");
                }
                at = s.t_max;
            }
            assert!((at - exit).abs() < 1e-9, "ends at {at}, not {exit}");
        }
    }
}
