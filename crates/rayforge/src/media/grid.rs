//! A heterogeneous medium: a dense 3D grid of densities (pbrt-v4's `uniformgrid`, Mitsuba's
//! grid volume) over a box in the medium's own space, placed in the world by a transform.
//! The coefficients at a point are the medium's σa and σs times the density there,
//! interpolated trilinearly between the grid's samples (which sit at the centres of its
//! cells, as in pbrt-v4); outside the box the density is 0. Its majorant grid
//! ([`MajorantGrid`]) bounds the density cell by cell for null-collision tracking.

use super::glow::{ColorGrid, Glow};
use super::majorant::MajorantGrid;
use super::phase::HenyeyGreenstein;
use super::MediumError;
use crate::color::Color;
use crate::math::{Aabb, Point3, Transform, Vec3};

/// The most samples a density grid may hold (512³): a grid is read whole into memory, four
/// bytes a sample.
pub const MAX_GRID_SAMPLES: usize = 512 * 512 * 512;

/// Densities sampled on a regular grid, x fastest, then y, then z.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityGrid {
    size: [usize; 3],
    values: Vec<f32>,
}

impl DensityGrid {
    /// A grid of `size` samples holding `values` (x fastest): each size at least 1, the
    /// count `size`'s product and at most [`MAX_GRID_SAMPLES`], every value finite and at
    /// least 0.
    pub fn new(size: [usize; 3], values: Vec<f32>) -> Result<Self, MediumError> {
        let count = size
            .iter()
            .try_fold(1usize, |n, &s| n.checked_mul(s))
            .filter(|&n| n <= MAX_GRID_SAMPLES && size.iter().all(|&s| s > 0))
            .ok_or(MediumError::GridSize(size))?;
        if values.len() != count {
            return Err(MediumError::GridCount {
                expected: count,
                found: values.len(),
            });
        }
        if let Some(at) = values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(MediumError::GridValue {
                at,
                value: f64::from(values[at]),
            });
        }
        Ok(Self { size, values })
    }

    /// The samples along x, y and z.
    pub fn size(&self) -> [usize; 3] {
        self.size
    }

    /// How many samples it holds.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether it holds none (never: a grid has at least one sample).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Sample `i` (x fastest).
    #[inline]
    pub fn value(&self, i: usize) -> f32 {
        self.values[i]
    }

    /// The largest sample.
    pub fn max_value(&self) -> f64 {
        self.values.iter().fold(0.0f64, |m, &v| m.max(f64::from(v)))
    }

    /// The sample at integer coordinates, held to the grid (its edges extend outwards).
    #[inline]
    fn at(&self, x: isize, y: isize, z: isize) -> f64 {
        let c = |v: isize, n: usize| v.clamp(0, n as isize - 1) as usize;
        let [nx, ny, nz] = self.size;
        f64::from(self.values[(c(z, nz) * ny + c(y, ny)) * nx + c(x, nx)])
    }

    /// The density at `p` in the unit cube (the grid's box), trilinearly interpolated
    /// between the samples at the cells' centres.
    #[inline]
    pub fn lookup(&self, p: Point3) -> f64 {
        let [nx, ny, nz] = self.size;
        let s = Vec3::new(
            p.x * nx as f64 - 0.5,
            p.y * ny as f64 - 0.5,
            p.z * nz as f64 - 0.5,
        );
        let f = s.floor();
        let d = s - f;
        let (x, y, z) = (f.x as isize, f.y as isize, f.z as isize);
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let x00 = lerp(self.at(x, y, z), self.at(x + 1, y, z), d.x);
        let x10 = lerp(self.at(x, y + 1, z), self.at(x + 1, y + 1, z), d.x);
        let x01 = lerp(self.at(x, y, z + 1), self.at(x + 1, y, z + 1), d.x);
        let x11 = lerp(self.at(x, y + 1, z + 1), self.at(x + 1, y + 1, z + 1), d.x);
        lerp(lerp(x00, x10, d.y), lerp(x01, x11, d.y), d.z)
    }

    /// The largest density the interpolation takes anywhere in the box `[lo, hi]` of the
    /// unit cube: the largest sample among those that weigh on a point of it.
    pub fn max_over(&self, lo: Point3, hi: Point3) -> f64 {
        let range = |l: f64, h: f64, n: usize| {
            let a = ((l * n as f64 - 0.5).floor() as isize).clamp(0, n as isize - 1);
            let b = ((h * n as f64 - 0.5).floor() as isize + 1).clamp(0, n as isize - 1);
            a..=b
        };
        let [nx, ny, nz] = self.size;
        let mut most = 0.0f64;
        for z in range(lo.z, hi.z, nz) {
            for y in range(lo.y, hi.y, ny) {
                for x in range(lo.x, hi.x, nx) {
                    most = most.max(self.at(x, y, z));
                }
            }
        }
        most
    }
}

/// A medium whose density varies over a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct GridMedium {
    /// σa where the density is 1.
    pub sigma_a: Color,
    /// σs where the density is 1.
    pub sigma_s: Color,
    /// Radiance emitted per unit of absorption where the density is 1 (the glow follows
    /// the density, as in a flame).
    pub emission: Color,
    /// How it scatters.
    pub phase: HenyeyGreenstein,
    /// The density.
    pub density: DensityGrid,
    /// The grid's box in the medium's space.
    pub bounds: Aabb,
    /// World from the medium's space.
    pub transform: Transform,
    /// Per coarse cell, the most density there.
    pub majorant: MajorantGrid,
    /// Where the light it gives off varies over the grid (else it is `emission`).
    pub glow: Option<Box<Glow>>,
    /// Where σa and σs are grids of colours of their own (pbrt-v4's `rgbgrid`), they (the
    /// density then their largest channels' sum, which the majorants bound).
    pub colored: Option<Box<[ColorGrid; 2]>>,
}

impl GridMedium {
    /// A grid medium, its majorant grid built; `bounds` must have a positive extent.
    pub fn new(
        sigma_a: Color,
        sigma_s: Color,
        emission: Color,
        phase: HenyeyGreenstein,
        density: DensityGrid,
        bounds: Aabb,
        transform: Transform,
    ) -> Result<Self, MediumError> {
        let e = bounds.extent();
        if !(e.min_element() > 0.0 && e.is_finite()) {
            return Err(MediumError::Bounds);
        }
        let majorant = MajorantGrid::of(&density);
        Ok(Self {
            sigma_a,
            sigma_s,
            emission,
            phase,
            density,
            bounds,
            transform,
            majorant,
            glow: None,
            colored: None,
        })
    }

    /// The medium giving off `glow` (times σa, point by point) in place of `emission`.
    pub fn with_glow(mut self, glow: Glow) -> Self {
        self.glow = Some(Box::new(glow));
        self
    }

    /// A medium whose σa and σs are grids of colours (each times `scale`) over `bounds`,
    /// placed by `transform`: its density (for the majorants) is, sample by sample, the
    /// largest channel of σa plus the largest of σs; the grids must be of one size.
    pub fn of_colors(
        sigma_a: ColorGrid,
        sigma_s: ColorGrid,
        scale: f64,
        phase: HenyeyGreenstein,
        bounds: Aabb,
        transform: Transform,
    ) -> Result<Self, MediumError> {
        if sigma_a.size() != sigma_s.size() {
            return Err(MediumError::GridCount {
                expected: sigma_a.max_channels().len(),
                found: sigma_s.max_channels().len(),
            });
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(MediumError::Coefficient {
                name: "scale",
                value: Color::new(scale, scale, scale),
            });
        }
        let (a, s) = (sigma_a.max_channels(), sigma_s.max_channels());
        let values = (0..a.len()).map(|i| a.value(i) + s.value(i)).collect();
        let density = DensityGrid::new(a.size(), values)?;
        let mut medium = Self::new(
            Color::BLACK,
            Color::new(scale, scale, scale),
            Color::BLACK,
            phase,
            density,
            bounds,
            transform,
        )?;
        medium.colored = Some(Box::new([sigma_a, sigma_s]));
        Ok(medium)
    }

    /// Whether it gives off light anywhere.
    pub fn emits(&self) -> bool {
        self.glow.is_some() || self.emission.max_channel() > 0.0
    }

    /// σa, σs and the radiance given off per unit of absorption at `p` in the unit cube
    /// (nothing outside it).
    #[inline]
    pub fn coefficients_at(&self, p: Point3) -> (Color, Color, Color) {
        if !(p.cmpge(Point3::ZERO).all() && p.cmple(Point3::ONE).all()) {
            return (Color::BLACK, Color::BLACK, Color::BLACK);
        }
        let (sigma_a, sigma_s) = match &self.colored {
            Some(grids) => {
                let scale = self.sigma_s.red;
                (grids[0].lookup(p) * scale, grids[1].lookup(p) * scale)
            }
            None => {
                let d = self.density.lookup(p);
                (self.sigma_a * d, self.sigma_s * d)
            }
        };
        let emission = match &self.glow {
            Some(glow) => glow.at(p),
            None => self.emission,
        };
        (sigma_a, sigma_s, emission)
    }

    /// A world point in the grid's unit cube.
    #[inline]
    pub fn to_unit(&self, p: Point3) -> Point3 {
        (self.transform.inverse_point(p) - self.bounds.min) / self.bounds.extent()
    }

    /// A world direction in the grid's unit cube (not normalised: a ray's `t` stays the
    /// world's).
    #[inline]
    pub fn to_unit_vector(&self, d: Vec3) -> Vec3 {
        self.transform.inverse_vector(d) / self.bounds.extent()
    }

    /// The density at a point of the unit cube, 0 outside it.
    #[inline]
    pub fn density_at(&self, p: Point3) -> f64 {
        if p.cmpge(Point3::ZERO).all() && p.cmple(Point3::ONE).all() {
            self.density.lookup(p)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::point;

    #[test]
    fn lookup_meets_the_samples_at_the_cell_centres_and_interpolates_between() {
        let g = DensityGrid::new([2, 1, 1], vec![1.0, 3.0]).expect("grid");
        assert_eq!(g.lookup(point(0.25, 0.5, 0.5)), 1.0);
        assert_eq!(g.lookup(point(0.75, 0.5, 0.5)), 3.0);
        assert!((g.lookup(point(0.5, 0.5, 0.5)) - 2.0).abs() < 1e-12);
        // The edges extend outwards.
        assert_eq!(g.lookup(point(0.0, 0.1, 0.9)), 1.0);
        assert_eq!(g.lookup(point(1.0, 0.0, 0.0)), 3.0);
    }

    #[test]
    fn the_maximum_over_a_box_bounds_every_lookup_in_it() {
        let values: Vec<f32> = (0..64).map(|i| ((i * 37) % 11) as f32).collect();
        let g = DensityGrid::new([4, 4, 4], values).expect("grid");
        let (lo, hi) = (point(0.3, 0.1, 0.55), point(0.6, 0.4, 0.9));
        let most = g.max_over(lo, hi);
        let mut seen = 0.0f64;
        for i in 0..20 {
            for j in 0..20 {
                for k in 0..20 {
                    let t = Vec3::new(i as f64, j as f64, k as f64) / 19.0;
                    let p = lo + (hi - lo) * t;
                    seen = seen.max(g.lookup(p));
                }
            }
        }
        assert!(seen <= most + 1e-12 && seen > 0.5 * most, "{seen} {most}");
    }

    #[test]
    fn bad_grids_are_refused() {
        assert!(DensityGrid::new([0, 1, 1], vec![]).is_err());
        assert!(DensityGrid::new([2, 2, 2], vec![1.0; 7]).is_err());
        assert!(DensityGrid::new([1, 1, 1], vec![-1.0]).is_err());
        assert!(DensityGrid::new([1, 1, 1], vec![f32::NAN]).is_err());
        assert!(DensityGrid::new([1 << 20, 1 << 20, 1 << 20], vec![]).is_err());
    }
}
