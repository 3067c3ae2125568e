//! An environment map: radiance arriving from every direction, stored as an equirectangular
//! (latitude–longitude) image, and sampled in proportion to its brightness so that a small sun
//! in a large sky is found by a few samples rather than by chance.
//!
//! The convention (shared with the reference scenes and Mitsuba 3): in a `W × H` map, texel
//! `(i, j)` (column `i` from the left, row `j` from the top) holds the radiance arriving from
//! the direction `(sin φ sin θ, cos θ, −cos φ sin θ)` with `φ = 2π (i + ½) / W` and
//! `θ = π j / (H − 1)`: +Y is up, row 0 the zenith and row `H − 1` the nadir. Between texel
//! centres the radiance is interpolated bilinearly, wrapping around in φ and clamped in θ.

use crate::color::Color;
use crate::math::distribution::Distribution2D;
use crate::math::Vec3;
use glam::DMat3;
use std::f64::consts::PI;

/// Why an environment map cannot be made from what was given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EnvironmentError {
    /// Too few texels to interpolate between: a column and two rows (zenith and nadir) at least.
    #[error(
        "an environment map needs at least 1 column and 2 rows (zenith and nadir); \
         this one is {width}×{height}"
    )]
    TooSmall {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
    },
    /// The texels do not fill the map.
    #[error("a {width}×{height} environment map needs {expected} texels; {got} were given")]
    WrongTexelCount {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// `width × height`.
        expected: u128,
        /// Texels given.
        got: usize,
    },
    /// The scale is negative, infinite or NaN.
    #[error("the environment map's scale is {0}: it must be a finite number, not negative")]
    BadScale(f64),
    /// A texel's radiance (after scaling) is negative, infinite or NaN.
    #[error(
        "environment map texel (column {column}, row {row}) is ({}, {}, {}) after scaling: {reason}",
        radiance.red, radiance.green, radiance.blue
    )]
    BadTexel {
        /// Column, from the left.
        column: usize,
        /// Row, from the top.
        row: usize,
        /// Its radiance after scaling.
        radiance: Color,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The transform given is not a rotation (it would stretch solid angles, and the map's
    /// densities would no longer integrate to one).
    #[error("an environment map's transform must be a rotation (orthonormal, determinant 1): {0}")]
    NotRotation(String),
}

/// Radiance arriving from every direction, read from an equirectangular image (see the module
/// documentation for the exact convention), so that scenes can be lit by a photographed or
/// simulated sky; with importance sampling by luminance, so that its bright parts are found.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvironmentMap {
    width: usize,
    height: usize,
    /// Scaled radiance, row by row from the top.
    texels: Vec<Color>,
    /// World directions into the map's own frame.
    to_local: DMat3,
    /// The map's frame into world directions (the inverse of `to_local`).
    to_world: DMat3,
    /// Over `(u', v)` with `u' = φ / 2π − ½ / W` (wrapped into `[0, 1)`) and `v = θ / π`:
    /// `W` columns and `H − 1` rows of cells, each cell the bilinear patch between four texel
    /// centres, weighted by the largest luminance of its corners and by its solid angle.
    distribution: Distribution2D,
    /// The mean radiance over the sphere.
    average: Color,
}

impl EnvironmentMap {
    /// A map `width` texels across and `height` down, from `texels` listed row by row from the
    /// top (each row from the left), every one multiplied by `scale`. Refuses maps smaller than
    /// 1 × 2, a wrong number of texels, and texels that are negative, infinite or NaN after
    /// scaling (naming the first such texel), since any of them would poison every pixel that
    /// sees the sky.
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<Color>,
        scale: f64,
    ) -> Result<Self, EnvironmentError> {
        if width < 1 || height < 2 {
            return Err(EnvironmentError::TooSmall { width, height });
        }
        let expected = width as u128 * height as u128;
        if expected != texels.len() as u128 {
            return Err(EnvironmentError::WrongTexelCount {
                width,
                height,
                expected,
                got: texels.len(),
            });
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(EnvironmentError::BadScale(scale));
        }
        let mut texels = texels;
        for (index, texel) in texels.iter_mut().enumerate() {
            *texel = *texel * scale;
            let channels = texel.to_array();
            let reason = if channels.iter().any(|c| c.is_nan()) {
                Some("a channel is not a number")
            } else if channels.iter().any(|c| c.is_infinite()) {
                Some("a channel is infinite")
            } else if channels.iter().any(|&c| c < 0.0) {
                Some("a channel is negative")
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(EnvironmentError::BadTexel {
                    column: index % width,
                    row: index / width,
                    radiance: *texel,
                    reason,
                });
            }
        }
        let distribution = sampling_distribution(width, height, &texels);
        let average = average_radiance(width, height, &texels);
        Ok(Self {
            width,
            height,
            texels,
            to_local: DMat3::IDENTITY,
            to_world: DMat3::IDENTITY,
            distribution,
            average,
        })
    }

    /// The map turned in the world, so that a scene can put the sun where it wants:
    /// `world_to_local` takes a world direction into the map's own frame (the one of the module
    /// documentation). It must be a rotation (within 1e-6); anything else would stretch solid
    /// angles and break the sampling densities.
    pub fn with_transform(mut self, world_to_local: DMat3) -> Result<Self, EnvironmentError> {
        let m = world_to_local;
        if !m.is_finite() {
            return Err(EnvironmentError::NotRotation(
                "it has a non-finite entry".into(),
            ));
        }
        let error = (m.transpose() * m - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |acc, e| acc.max(e.abs()));
        if error > 1e-6 {
            return Err(EnvironmentError::NotRotation(format!(
                "its columns are not orthonormal (off by {error:e})"
            )));
        }
        if m.determinant() < 0.0 {
            return Err(EnvironmentError::NotRotation(
                "it is a reflection (determinant −1)".into(),
            ));
        }
        self.to_local = m;
        self.to_world = m.transpose();
        Ok(self)
    }

    /// Texels across (in φ).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Texels down (in θ), zenith to nadir.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The texel in column `column` and row `row` after scaling, to inspect a map as it was read.
    pub fn texel(&self, column: usize, row: usize) -> Option<Color> {
        if column >= self.width {
            return None;
        }
        self.texels.get(row * self.width + column).copied()
    }

    /// The radiance arriving from the world direction `direction` (the way a ray travels to
    /// escape to the sky; it need not be normalised), interpolated bilinearly between texel
    /// centres. A zero or non-finite direction sees black.
    pub fn radiance(&self, direction: Vec3) -> Color {
        match self.angles(direction) {
            Some((phi, theta)) => self.lookup(phi, theta),
            None => Color::BLACK,
        }
    }

    /// The radiance arriving from `direction`, as [`radiance`](Self::radiance), and the
    /// density with which [`sample`](Self::sample) draws it, as [`pdf`](Self::pdf): what a
    /// path that escapes needs, for the price of one conversion to angles.
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Color, f64) {
        match self.angles(direction) {
            Some((phi, theta)) => (self.lookup(phi, theta), self.pdf_at(phi, theta)),
            None => (Color::BLACK, 0.0),
        }
    }

    /// `(φ, θ)` of a world direction in the map's frame, φ in `[0, 2π)`, θ in `[0, π]`.
    fn angles(&self, direction: Vec3) -> Option<(f64, f64)> {
        let d = (self.to_local * direction).try_normalize()?;
        // atan2 rather than acos(y): full precision near the poles, where acos loses digits.
        // (The components are those of a unit vector: the square root cannot overflow, and
        // it is not the library's slower `hypot`.)
        let theta = (d.x * d.x + d.z * d.z).sqrt().atan2(d.y);
        let mut phi = d.x.atan2(-d.z);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        if phi >= 2.0 * PI {
            phi = 0.0;
        }
        Some((phi, theta))
    }

    /// The bilinear interpolation at `(φ, θ)` in the map's frame.
    fn lookup(&self, phi: f64, theta: f64) -> Color {
        let (w, h) = (self.width, self.height);
        // Texel centres sit at whole numbers of s and t.
        let s = phi / (2.0 * PI) * w as f64 - 0.5;
        let t = (theta / PI * (h - 1) as f64).clamp(0.0, (h - 1) as f64);
        let s0 = s.floor();
        let fs = s - s0;
        let c0 = (s0 as i64).rem_euclid(w as i64) as usize;
        let c1 = (c0 + 1) % w;
        let r0 = (t.floor() as usize).min(h - 2);
        let ft = t - r0 as f64;
        let at = |c: usize, r: usize| self.texels[r * w + c];
        let top = at(c0, r0).lerp(at(c1, r0), fs);
        let bottom = at(c0, r0 + 1).lerp(at(c1, r0 + 1), fs);
        top.lerp(bottom, ft)
    }

    /// A direction drawn in proportion (roughly) to the radiance arriving from it, from two
    /// uniform random numbers in `[0, 1)`: the world direction (unit length), the radiance
    /// arriving from it, and the density per unit solid angle, equal to [`pdf`](Self::pdf) of
    /// that direction. `None` only if the draw lands exactly on a pole, where the density per
    /// solid angle is undefined (it never does for random numbers inside `(0, 1)`).
    pub fn sample(&self, u: [f64; 2]) -> Option<(Vec3, Color, f64)> {
        let ([cell_u, v], pdf_uv) = self.distribution.sample(u);
        let mut phi = 2.0 * PI * (cell_u + 0.5 / self.width as f64);
        if phi >= 2.0 * PI {
            phi -= 2.0 * PI;
        }
        let theta = PI * v;
        let sin_theta = theta.sin();
        if sin_theta <= 0.0 || pdf_uv <= 0.0 {
            return None;
        }
        let local = Vec3::new(phi.sin() * sin_theta, theta.cos(), -phi.cos() * sin_theta);
        let direction = (self.to_world * local).normalize();
        let pdf = pdf_uv / (2.0 * PI * PI * sin_theta);
        Some((direction, self.lookup(phi, theta), pdf))
    }

    /// The density per unit solid angle with which [`sample`](Self::sample) draws the world
    /// direction `direction`, for weighing its samples against another strategy's (multiple
    /// importance sampling). 0 for a zero or non-finite direction and at the poles.
    pub fn pdf(&self, direction: Vec3) -> f64 {
        match self.angles(direction) {
            Some((phi, theta)) => self.pdf_at(phi, theta),
            None => 0.0,
        }
    }

    /// [`pdf`](Self::pdf) of the direction at `(φ, θ)` in the map's frame.
    fn pdf_at(&self, phi: f64, theta: f64) -> f64 {
        let sin_theta = theta.sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let cell_u = (phi / (2.0 * PI) - 0.5 / self.width as f64).rem_euclid(1.0);
        let v = theta / PI;
        self.distribution.pdf([cell_u, v]) / (2.0 * PI * PI * sin_theta)
    }

    /// The mean radiance over the sphere of directions, `∫ L(ω) dω / 4π`, integrated exactly
    /// for the bilinear map: how bright the sky is as a whole, for choosing between it and the
    /// other lights by power.
    pub fn average_radiance(&self) -> Color {
        self.average
    }

    /// The power the map sends into a scene bounded by a sphere of radius `scene_radius`:
    /// `π r² · 4π · average radiance` (the flux through a disc of the scene's size from every
    /// direction), the number to weigh against other lights' power when picking one.
    pub fn power(&self, scene_radius: f64) -> Color {
        self.average * (PI * scene_radius * scene_radius * 4.0 * PI)
    }
}

/// The θ of row `row` of a map `height` rows high.
fn row_theta(row: usize, height: usize) -> f64 {
    PI * row as f64 / (height - 1) as f64
}

/// The table the map samples from (see the comment on `EnvironmentMap`'s `distribution`): the
/// cell between columns `k`, `k + 1` and rows `j`, `j + 1` weighs the largest luminance of its
/// four corners (an upper bound of the bilinear radiance inside it, so a cell with any light is
/// never left out), plus a floor of a thousandth of the mean so the density is positive
/// everywhere, times `cos θⱼ − cos θⱼ₊₁` (its share of solid angle).
fn sampling_distribution(width: usize, height: usize, texels: &[Color]) -> Distribution2D {
    let lum: Vec<f64> = texels.iter().map(|&c| Color::luminance(c)).collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    let floor = if mean.is_finite() { 1e-3 * mean } else { 0.0 };
    let mut weights = Vec::with_capacity(width * (height - 1));
    for row in 0..height - 1 {
        let solid = row_theta(row, height).cos() - row_theta(row + 1, height).cos();
        for column in 0..width {
            let next = (column + 1) % width;
            let corners = [
                lum[row * width + column],
                lum[row * width + next],
                lum[(row + 1) * width + column],
                lum[(row + 1) * width + next],
            ];
            let brightest = corners.into_iter().fold(0.0, f64::max);
            weights.push((brightest + floor) * solid.max(0.0));
        }
    }
    // Every weight is finite and non-negative (texels were checked; a sum of huge luminances
    // is guarded by the floor's finiteness and the distribution's own scaling), so this cannot
    // fail; if it ever did, uniform sampling would still be correct.
    Distribution2D::new(width, height - 1, &weights)
        .unwrap_or_else(|_| Distribution2D::new(1, 1, &[1.0]).expect("a one-cell table is valid"))
}

/// `∫ L(ω) dω / 4π` for the bilinear map, exactly: across φ the interpolation is periodic and
/// piecewise linear, so its integral is the mean of the row times 2π; down θ, on the band
/// between rows `j` and `j + 1` with `θ` from `a` to `b` and `f = (θ − a)/(b − a)`,
/// `∫ f sin θ dθ = (sin b − sin a)/(b − a) − cos b` and `∫ (1 − f) sin θ dθ` is the rest of
/// `cos a − cos b`.
fn average_radiance(width: usize, height: usize, texels: &[Color]) -> Color {
    let row_mean = |row: usize| {
        texels[row * width..(row + 1) * width]
            .iter()
            .fold(Color::BLACK, |acc, &c| acc + c)
            / width as f64
    };
    let mut total = Color::BLACK;
    for row in 0..height - 1 {
        let (a, b) = (row_theta(row, height), row_theta(row + 1, height));
        let whole = a.cos() - b.cos();
        let lower = (b.sin() - a.sin()) / (b - a) - b.cos();
        let upper = whole - lower;
        total = total + row_mean(row) * upper + row_mean(row + 1) * lower;
    }
    // ∫ dφ = 2π; the sphere is 4π.
    total * (2.0 * PI / (4.0 * PI))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::stats::chi_square_p_value;

    /// The direction of the texel centre `(i, j)` of a `w × h` map, per the convention.
    fn texel_direction(i: usize, j: usize, w: usize, h: usize) -> Vec3 {
        let phi = 2.0 * PI * (i as f64 + 0.5) / w as f64;
        let theta = PI * j as f64 / (h - 1) as f64;
        Vec3::new(
            phi.sin() * theta.sin(),
            theta.cos(),
            -phi.cos() * theta.sin(),
        )
    }

    fn close(a: Color, b: Color, tolerance: f64) -> bool {
        (a - b).to_array().iter().all(|d| d.abs() <= tolerance)
    }

    /// A varied map: random texels with a bright "sun" of a few texels.
    fn test_map(w: usize, h: usize, seed: u64) -> EnvironmentMap {
        let mut rng = SplitMix64::new(seed);
        let mut texels: Vec<Color> = (0..w * h)
            .map(|_| {
                Color::new(
                    rng.next_offset(),
                    rng.next_offset() * 0.5,
                    rng.next_offset() * 2.0,
                )
            })
            .collect();
        texels[w + 2] = Color::new(40.0, 30.0, 20.0);
        texels[w + 3] = Color::new(20.0, 20.0, 20.0);
        texels[(h - 1) * w] = Color::BLACK;
        EnvironmentMap::new(w, h, texels, 1.5).unwrap()
    }

    #[test]
    fn a_bright_texel_is_seen_from_its_direction() {
        let (w, h) = (8, 5);
        // (Not rows 0 and H − 1: every column's texel there claims the same direction, the pole.)
        for (i, j) in [(2, 1), (0, 1), (7, 3), (5, 2)] {
            let mut texels = vec![Color::BLACK; w * h];
            texels[j * w + i] = Color::new(10.0, 5.0, 2.0);
            let map = EnvironmentMap::new(w, h, texels, 1.0).unwrap();
            let seen = map.radiance(texel_direction(i, j, w, h));
            assert!(
                close(seen, Color::new(10.0, 5.0, 2.0), 1e-9),
                "{i},{j}: {seen:?}"
            );
            // A neighbouring texel's centre sees none of it.
            let other = map.radiance(texel_direction((i + 2) % w, j, w, h));
            assert!(close(other, Color::BLACK, 1e-9));
        }
    }

    #[test]
    fn row_zero_is_up_and_the_last_row_down() {
        let (w, h) = (4, 3);
        let mut texels = vec![Color::new(0.0, 1.0, 0.0); w * h];
        texels[..w].fill(Color::new(1.0, 0.0, 0.0));
        texels[(h - 1) * w..].fill(Color::new(0.0, 0.0, 1.0));
        let map = EnvironmentMap::new(w, h, texels, 2.0).unwrap();
        assert!(close(
            map.radiance(Vec3::Y),
            Color::new(2.0, 0.0, 0.0),
            1e-12
        ));
        assert!(close(
            map.radiance(-Vec3::Y * 3.0),
            Color::new(0.0, 0.0, 2.0),
            1e-12
        ));
        assert!(close(
            map.radiance(Vec3::X),
            Color::new(0.0, 2.0, 0.0),
            1e-12
        ));
        assert_eq!(map.radiance(Vec3::ZERO), Color::BLACK);
        assert_eq!(map.radiance(Vec3::splat(f64::NAN)), Color::BLACK);
    }

    #[test]
    fn bilinear_between_centres_and_wrapping_in_phi() {
        let (w, h) = (8, 3);
        let texels: Vec<Color> = (0..w * h)
            .map(|k| Color::new(k as f64, (k % w) as f64, (k / w) as f64))
            .collect();
        let map = EnvironmentMap::new(w, h, texels.clone(), 1.0).unwrap();
        let at = |i: usize, j: usize| texels[j * w + i];
        // +X is φ = π/2, halfway between the centres of columns 1 and 2; θ = π/2 is row 1.
        let mid = (at(1, 1) + at(2, 1)) * 0.5;
        assert!(close(map.radiance(Vec3::X), mid, 1e-12));
        // θ = π/4 is halfway between rows 0 and 1 (at column 1's centre).
        let phi = 2.0 * PI * 1.5 / w as f64;
        let theta = PI / 4.0;
        let d = Vec3::new(
            phi.sin() * theta.sin(),
            theta.cos(),
            -phi.cos() * theta.sin(),
        );
        assert!(close(map.radiance(d), (at(1, 0) + at(1, 1)) * 0.5, 1e-12));
        // −Z is φ = 0, halfway between the last column and the first: the map wraps around.
        let wrap = (at(w - 1, 1) + at(0, 1)) * 0.5;
        assert!(close(map.radiance(-Vec3::Z), wrap, 1e-12));
        // A quarter of a texel either side of φ = 0.
        let quarter = 0.25 * 2.0 * PI / w as f64;
        let d = Vec3::new(-quarter.sin(), 0.0, -quarter.cos());
        let expected = at(w - 1, 1).lerp(at(0, 1), 0.25);
        assert!(close(map.radiance(d), expected, 1e-12));
        let d = Vec3::new(quarter.sin(), 0.0, -quarter.cos());
        let expected = at(w - 1, 1).lerp(at(0, 1), 0.75);
        assert!(close(map.radiance(d), expected, 1e-12));
    }

    #[test]
    fn one_column_is_a_function_of_height_only() {
        let map = EnvironmentMap::new(
            1,
            3,
            vec![Color::WHITE, Color::BLACK, Color::new(0.0, 0.0, 4.0)],
            1.0,
        )
        .unwrap();
        let d = Vec3::new(1.0, 1.0, 0.0);
        assert!(close(map.radiance(d), Color::WHITE * 0.5, 1e-12));
        let (dir, radiance, pdf) = map.sample([0.3, 0.9]).unwrap();
        assert!((pdf - map.pdf(dir)).abs() <= 1e-9 * pdf);
        assert!(close(radiance, map.radiance(dir), 1e-9));
    }

    #[test]
    fn refuses_bad_maps_naming_the_texel() {
        assert_eq!(
            EnvironmentMap::new(4, 1, vec![Color::WHITE; 4], 1.0),
            Err(EnvironmentError::TooSmall {
                width: 4,
                height: 1
            })
        );
        assert!(matches!(
            EnvironmentMap::new(0, 2, vec![], 1.0),
            Err(EnvironmentError::TooSmall { .. })
        ));
        assert!(matches!(
            EnvironmentMap::new(2, 2, vec![Color::WHITE; 3], 1.0),
            Err(EnvironmentError::WrongTexelCount { got: 3, .. })
        ));
        assert!(matches!(
            EnvironmentMap::new(2, 2, vec![Color::WHITE; 4], -1.0),
            Err(EnvironmentError::BadScale(_))
        ));
        let mut texels = vec![Color::WHITE; 6];
        texels[5] = Color::new(1.0, f64::NAN, 0.0);
        let e = EnvironmentMap::new(3, 2, texels, 1.0).unwrap_err();
        assert!(matches!(
            e,
            EnvironmentError::BadTexel {
                column: 2,
                row: 1,
                ..
            }
        ));
        assert!(e.to_string().contains("column 2, row 1"), "{e}");
        let mut texels = vec![Color::WHITE; 6];
        texels[1] = Color::new(1e300, 0.0, 0.0);
        let e = EnvironmentMap::new(3, 2, texels, 1e10).unwrap_err();
        assert!(e.to_string().contains("infinite"), "{e}");
        let mut texels = vec![Color::WHITE; 6];
        texels[0] = Color::new(-0.5, 0.0, 0.0);
        let e = EnvironmentMap::new(3, 2, texels, 1.0).unwrap_err();
        assert!(e.to_string().contains("negative"), "{e}");
    }

    #[test]
    fn a_transform_turns_the_sky() {
        let (w, h) = (8, 5);
        let mut texels = vec![Color::BLACK; w * h];
        texels[w + 2] = Color::new(10.0, 5.0, 2.0);
        let rotation = DMat3::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
        let map = EnvironmentMap::new(w, h, texels, 1.0)
            .unwrap()
            .with_transform(rotation)
            .unwrap();
        // The texel's own direction in the map's frame is, in the world, the rotation's inverse
        // applied to it.
        let world = rotation.transpose() * texel_direction(2, 1, w, h);
        assert!(close(map.radiance(world), Color::new(10.0, 5.0, 2.0), 1e-9));
        let scaled = DMat3::from_diagonal(Vec3::new(2.0, 1.0, 1.0));
        let map = EnvironmentMap::new(1, 2, vec![Color::WHITE; 2], 1.0).unwrap();
        assert!(map.clone().with_transform(scaled).is_err());
        let mirror = DMat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        assert!(map.with_transform(mirror).is_err());
    }

    #[test]
    fn the_average_of_a_constant_map_is_the_constant() {
        let c = Color::new(0.25, 1.0, 3.0);
        for (w, h) in [(1, 2), (7, 3), (64, 32)] {
            let map = EnvironmentMap::new(w, h, vec![c; w * h], 1.0).unwrap();
            assert!(close(map.average_radiance(), c, 1e-12), "{w}×{h}");
            let power = map.power(2.0);
            assert!(close(power, c * (16.0 * PI * PI), 1e-9));
        }
    }

    /// `∫ f(ω) dω` over the sphere by the midpoint rule in (θ, φ), `n` × `2n` points.
    fn integrate(n: usize, f: impl Fn(Vec3) -> f64) -> f64 {
        let (dt, dp) = (PI / n as f64, PI / n as f64);
        let mut sum = 0.0;
        for a in 0..n {
            let theta = (a as f64 + 0.5) * dt;
            for b in 0..2 * n {
                let phi = (b as f64 + 0.5) * dp;
                sum += f(local_direction(phi, theta)) * theta.sin();
            }
        }
        sum * dt * dp
    }

    /// The direction of `(φ, θ)` per the convention.
    fn local_direction(phi: f64, theta: f64) -> Vec3 {
        Vec3::new(
            phi.sin() * theta.sin(),
            theta.cos(),
            -phi.cos() * theta.sin(),
        )
    }

    /// The sampling cells of `map` in its own frame: `(θ₀, θ₁, φ₀, φ₁, density in (θ, φ))`.
    /// The density per solid angle times sin θ is constant on each cell, so integrals over
    /// cells are exact sums.
    fn cells(map: &EnvironmentMap) -> Vec<(f64, f64, f64, f64, f64)> {
        let (w, rows) = (map.width, map.height - 1);
        let mut out = Vec::new();
        for j in 0..rows {
            for k in 0..w {
                let (t0, t1) = (
                    PI * j as f64 / rows as f64,
                    PI * (j + 1) as f64 / rows as f64,
                );
                let (p0, p1) = (
                    2.0 * PI * (k as f64 + 0.5) / w as f64,
                    2.0 * PI * (k as f64 + 1.5) / w as f64,
                );
                let centre = [(k as f64 + 0.5) / w as f64, (j as f64 + 0.5) / rows as f64];
                let density = map.distribution.pdf(centre) / (2.0 * PI * PI);
                out.push((t0, t1, p0, p1, density));
            }
        }
        out
    }

    #[test]
    fn the_pdf_integrates_to_one_over_the_sphere() {
        let turned = test_map(16, 9, 1)
            .with_transform(DMat3::from_rotation_x(0.4) * DMat3::from_rotation_y(2.0))
            .unwrap();
        for map in [test_map(16, 9, 1), test_map(5, 2, 2), turned] {
            // One point per cell, at its centre, given to `pdf` as a world direction: exact.
            let total: f64 = cells(&map)
                .iter()
                .map(|&(t0, t1, p0, p1, _)| {
                    let theta = 0.5 * (t0 + t1);
                    let d = map.to_world * local_direction(0.5 * (p0 + p1), theta);
                    map.pdf(d) * theta.sin() * (t1 - t0) * (p1 - p0)
                })
                .sum();
            assert!((total - 1.0).abs() < 1e-9, "{total}");
            // And by brute force, not aligned with the cells.
            let brute = integrate(400, |d| map.pdf(d));
            assert!((brute - 1.0).abs() < 1e-2, "{brute}");
        }
    }

    #[test]
    fn quadrature_agrees_with_the_exact_average() {
        let map = test_map(16, 9, 4);
        let luminance_average = integrate(800, |d| Color::luminance(map.radiance(d))) / (4.0 * PI);
        let exact = Color::luminance(map.average_radiance());
        assert!(
            (luminance_average - exact).abs() < 1e-3 * exact,
            "{luminance_average} {exact}"
        );
    }

    #[test]
    fn samples_report_their_pdf_and_radiance() {
        let map = test_map(16, 9, 5)
            .with_transform(DMat3::from_rotation_y(1.1) * DMat3::from_rotation_x(-0.3))
            .unwrap();
        let mut rng = SplitMix64::new(9);
        for _ in 0..20_000 {
            let (d, radiance, pdf) = map
                .sample([rng.next_offset(), rng.next_offset()])
                .expect("a sample");
            assert!((d.length() - 1.0).abs() < 1e-12);
            assert!(pdf > 0.0);
            let again = map.pdf(d);
            assert!((pdf - again).abs() <= 1e-9 * pdf, "{pdf} vs {again} at {d}");
            assert!(close(radiance, map.radiance(d), 1e-9));
            // What an escaping path asks for at once is the same pair, for any length.
            assert_eq!(
                map.radiance_and_pdf(d * 3.5),
                (map.radiance(d * 3.5), map.pdf(d * 3.5))
            );
        }
        assert_eq!(map.radiance_and_pdf(Vec3::ZERO), (Color::BLACK, 0.0));
    }

    #[test]
    fn where_there_is_light_there_is_density() {
        // A single lit texel among black ones: every direction that sees any of it can be drawn.
        let (w, h) = (6, 4);
        let mut texels = vec![Color::BLACK; w * h];
        texels[2 * w + 4] = Color::WHITE;
        let map = EnvironmentMap::new(w, h, texels, 1.0).unwrap();
        let mut rng = SplitMix64::new(13);
        for _ in 0..20_000 {
            let z = 2.0 * rng.next_offset() - 1.0;
            let phi = 2.0 * PI * rng.next_offset();
            let r = (1.0 - z * z).sqrt();
            let d = Vec3::new(r * phi.cos(), z, r * phi.sin());
            if Color::luminance(map.radiance(d)) > 0.0 {
                assert!(map.pdf(d) > 0.0, "{d}");
            }
        }
        // An all-black map still samples (uniformly in its cells) and sees black.
        let black = EnvironmentMap::new(3, 3, vec![Color::BLACK; 9], 1.0).unwrap();
        let (d, radiance, pdf) = black.sample([0.2, 0.7]).unwrap();
        assert_eq!(radiance, Color::BLACK);
        assert!((pdf - black.pdf(d)).abs() < 1e-12 * pdf);
        assert_eq!(black.average_radiance(), Color::BLACK);
    }

    #[test]
    fn sampled_directions_follow_the_pdf() {
        let map = test_map(16, 9, 6)
            .with_transform(DMat3::from_rotation_z(0.3))
            .unwrap();
        // Bins equal in cos θ and φ of the map's frame (equal solid angles); each bin's
        // expected share is the pdf's exact integral over it, from the cells it overlaps.
        let (nc, np) = (10, 20);
        let mut rng = SplitMix64::new(21);
        let n = 200_000;
        let mut counts = vec![0u64; nc * np];
        for _ in 0..n {
            let (d, _, _) = map.sample([rng.next_offset(), rng.next_offset()]).unwrap();
            let local = map.to_local * d;
            let c = (((1.0 - local.y) / 2.0 * nc as f64) as usize).min(nc - 1);
            let phi = local.x.atan2(-local.z).rem_euclid(2.0 * PI);
            let p = ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1);
            counts[c * np + p] += 1;
        }
        let overlap = |lo: f64, hi: f64, a: f64, b: f64| (hi.min(b) - lo.max(a)).max(0.0);
        let cells = cells(&map);
        let mut expected = vec![0.0; nc * np];
        for c in 0..nc {
            let t0 = (1.0 - 2.0 * c as f64 / nc as f64).acos();
            let t1 = (1.0 - 2.0 * (c + 1) as f64 / nc as f64).acos();
            for p in 0..np {
                let a = 2.0 * PI * p as f64 / np as f64;
                let b = 2.0 * PI * (p + 1) as f64 / np as f64;
                expected[c * np + p] = cells
                    .iter()
                    .map(|&(ct0, ct1, cp0, cp1, density)| {
                        // The last column of cells runs past 2π and wraps around.
                        let phi =
                            overlap(cp0, cp1, a, b) + overlap(cp0 - 2.0 * PI, cp1 - 2.0 * PI, a, b);
                        density * overlap(ct0, ct1, t0, t1) * phi
                    })
                    .sum();
            }
        }
        let total: f64 = expected.iter().sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}");
    }

    #[test]
    fn monte_carlo_by_importance_agrees_with_the_average() {
        let map = test_map(32, 17, 8);
        let exact = map.average_radiance();
        let mut rng = SplitMix64::new(99);
        let n = 50_000;
        let (mut sum, mut sum_sq) = ([0.0; 3], [0.0; 3]);
        for _ in 0..n {
            let (_, radiance, pdf) = map.sample([rng.next_offset(), rng.next_offset()]).unwrap();
            let estimate = radiance.to_array().map(|c| c / pdf / (4.0 * PI));
            for k in 0..3 {
                sum[k] += estimate[k];
                sum_sq[k] += estimate[k] * estimate[k];
            }
        }
        for k in 0..3 {
            let mean = sum[k] / n as f64;
            let variance = (sum_sq[k] / n as f64 - mean * mean).max(0.0);
            let standard_error = (variance / n as f64).sqrt();
            let truth = exact.to_array()[k];
            assert!(
                (mean - truth).abs() < 4.0 * standard_error + 1e-12,
                "channel {k}: {mean} ± {standard_error} vs {truth}"
            );
            // Importance sampling keeps the error small: well under a percent here.
            assert!(
                standard_error < 0.01 * truth,
                "channel {k}: {standard_error}"
            );
        }
    }
}
