//! An environment map: radiance arriving from every direction, stored as an equirectangular
//! (latitude–longitude) image, and sampled in proportion to its brightness so that a small sun
//! in a large sky is found by a few samples rather than by chance.
//!
//! The convention (shared with the reference scenes and Mitsuba 3): in a `W × H` map, texel
//! `(i, j)` (column `i` from the left, row `j` from the top) holds the radiance arriving from
//! the direction `(sin φ sin θ, cos θ, −cos φ sin θ)` with `φ = 2π (i + ½) / W` and
//! `θ = π j / (H − 1)`: +Y is up, row 0 the zenith and row `H − 1` the nadir. Between texel
//! centres the radiance is interpolated bilinearly, wrapping around in φ and clamped in θ.
//!
//! Directions are drawn with a density that is bilinear in the same way: a cell between four
//! texel centres is picked in proportion to its share, then a point inside it by the
//! interpolated luminance itself, so a small sun's samples carry almost the same weight
//! wherever in its cells they land. (A density constant over each cell, as tables of texels
//! usually give, wastes most of a one-texel sun's samples on its dim edges: the weight of a
//! sample then varies by its position under the interpolation's tent, and the noise of every
//! sunlit diffuse surface with it.)
//!
//! The density is *compensated* for multiple importance sampling (Karlík, Šik, Vévoda,
//! Skřivan and Křivánek, "MIS compensation", 2019): every texel's luminance is lowered by the
//! map's average before it becomes a weight, so light samples go to what stands out of the
//! sky (the sun, bright clouds) and the even part of the sky, which a diffuse surface's own
//! cosine-weighted directions find well, is left to them, the two weighed by the power
//! heuristic. A floor keeps every direction possible, so the estimate stays unbiased. On the
//! reference scene lit by a sky with a small sun, the two changes together leave the diffuse
//! sphere a fifth to two fifths of its squared error (away from the caustic the mirror sphere
//! throws on it, which only paths bounced off the mirror find).
//!
//! A map may also be in pbrt-v4's layout ([`EnvironmentMap::equal_area`]): a square image in
//! Clarberg's equal-area octahedral mapping of the sphere (`equal_area_square_to_sphere`),
//! +z the pole of its own frame, each pixel the same solid angle `4π / N`. As pbrt-v4 does, it
//! is read by the nearest pixel and sampled by a table over its pixels (constant over each),
//! the weights compensated as above; a direction's density is the table's over the square
//! divided by `4π`.
//!
//! And a map may be in pbrt's latitude–longitude layout ([`EnvironmentMap::lat_long`], the
//! equirectangular maps pbrt-v3 read and older exporters still write): +z the pole, texel
//! `(x, y)` of a `W × H` image the directions of `φ` in `2π [x, x + 1) / W` (from +x towards
//! +y) and `θ` in `π [y, y + 1] / H` (from +z), row 0 at the pole. It is read by the nearest
//! texel too and sampled by the same kind of table, each texel's weight times its solid angle
//! `2π / W · (cos θ_y − cos θ_(y+1))` (the `sin θ` Jacobian of the angles, integrated over the
//! texel's band), a point in the texel drawn uniformly in solid angle (uniform in `φ` and in
//! `cos θ`), so a direction's density is its texel's probability over its solid angle: constant
//! over the texel, with no `1 / sin θ` at the poles.

use crate::color::Color;
use crate::math::distribution::Distribution2D;
use crate::math::Vec3;
use crate::math::{
    atan2_turns, equal_area_sphere_to_square, equal_area_square_to_sphere, sin_cos_turns,
};
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
    /// A map without a texel (a latitude–longitude map needs one at least).
    #[error("an environment map needs at least one texel; this one is {width}×{height}")]
    Empty {
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
    /// An equal-area map that is not square.
    #[error(
        "an equal-area (octahedral) environment map is square, as pbrt-v4 requires; this one \
         is {width}×{height} (an equirectangular map is twice as wide as high: give it as one)"
    )]
    NotSquare {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
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
    layout: Layout,
    width: usize,
    height: usize,
    /// Scaled radiance, row by row from the top.
    texels: Vec<Color>,
    /// World directions into the map's own frame.
    to_local: DMat3,
    /// The map's frame into world directions (the inverse of `to_local`).
    to_world: DMat3,
    /// The sampling weight at each texel centre, row by row from the top: its luminance (the
    /// map's brightest channel scaled to 1, so no sum overflows) less the map's average
    /// luminance, not below zero (see the module documentation), plus a floor of a thousandth
    /// of the mean, so that every direction can be drawn, times the mean of sin θ over its
    /// row's band (the solid angle a texel stands for). Between centres it is interpolated
    /// bilinearly, as the radiance is; over `(u', v)` (below) it is the sampling density, up
    /// to the constant `cells.integral()`.
    weights: Vec<f64>,
    /// Over `(u', v)` with `u' = φ / 2π − ½ / W` (wrapped into `[0, 1)`) and `v = θ / π`:
    /// `W` columns and `H − 1` rows of cells, each cell the bilinear patch between four texel
    /// centres, picked in proportion to its mean weight (the integral of its patch).
    cells: Distribution2D,
    /// The mean radiance over the sphere.
    average: Color,
    /// For a latitude–longitude map, `cos θ` at the edges of its rows (`H + 1` of them, from
    /// the top); empty for the other layouts.
    bands: Vec<f64>,
}

/// How a map's texels cover the sphere.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// Latitude and longitude, +Y up, interpolated bilinearly (the module's convention).
    Equirectangular,
    /// pbrt-v4's equal-area octahedral square, +z up, read by the nearest texel: `weights` is
    /// then one weight per texel and `cells` a table over the texels.
    EqualArea,
    /// pbrt's latitude–longitude rectangle, +z up, read by the nearest texel, with `weights`
    /// and `cells` as for `EqualArea` (each weight times its texel's solid angle) and `bands`
    /// the rows' edges.
    LatLong,
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
        check_texel_count(width, height, texels.len())?;
        let texels = scaled_texels(width, texels, scale)?;
        let weights = sampling_weights(width, height, &texels);
        let cells = cell_distribution(width, height, &weights);
        let average = average_radiance(width, height, &texels);
        Ok(Self {
            layout: Layout::Equirectangular,
            width,
            height,
            texels,
            weights,
            cells,
            to_local: DMat3::IDENTITY,
            to_world: DMat3::IDENTITY,
            average,
            bands: Vec::new(),
        })
    }

    /// A map in pbrt-v4's equal-area octahedral layout: a square `side × side` image, texels
    /// row by row from the top, each multiplied by `scale`; texel `(x, y)` holds the radiance
    /// from `equal_area_square_to_sphere((x + ½) / side, (y + ½) / side)` in the map's frame
    /// (+z its pole). Refuses what [`new`](Self::new) refuses, and maps that are not square
    /// (pbrt-v4 refuses them too: they are unlikely to be equal-area maps).
    pub fn equal_area(
        width: usize,
        height: usize,
        texels: Vec<Color>,
        scale: f64,
    ) -> Result<Self, EnvironmentError> {
        if width != height || width == 0 {
            return Err(EnvironmentError::NotSquare { width, height });
        }
        check_texel_count(width, height, texels.len())?;
        let texels = scaled_texels(width, texels, scale)?;
        // Every texel is the same solid angle.
        Ok(Self::texel_table(
            Layout::EqualArea,
            width,
            height,
            texels,
            Vec::new(),
            |_| 1.0,
        ))
    }

    /// A map in pbrt's latitude–longitude (equirectangular) layout, the one pbrt-v3 read: a
    /// `width × height` image (any size of at least one texel; pbrt's are twice as wide as
    /// high), texels row by row from the top, each multiplied by `scale`; texel `(x, y)` holds
    /// the radiance from the directions `(sin θ cos φ, sin θ sin φ, cos θ)` of the map's frame
    /// with `φ / 2π` in `[x, x + 1) / width` and `θ / π` in `[y, y + 1] / height`, read by the
    /// nearest texel (see the module documentation). Refuses an empty map, a wrong number of
    /// texels and texels that are negative, infinite or NaN after scaling.
    pub fn lat_long(
        width: usize,
        height: usize,
        texels: Vec<Color>,
        scale: f64,
    ) -> Result<Self, EnvironmentError> {
        if width == 0 || height == 0 {
            return Err(EnvironmentError::Empty { width, height });
        }
        check_texel_count(width, height, texels.len())?;
        let texels = scaled_texels(width, texels, scale)?;
        // cos θ at the rows' edges, from the turns θ / 2π (exact at the poles and the equator).
        let bands: Vec<f64> = (0..=height)
            .map(|edge| sin_cos_turns(0.5 * edge as f64 / height as f64).1)
            .collect();
        let per_column = 2.0 * PI / width as f64;
        let solid_angles: Vec<f64> = bands
            .windows(2)
            .map(|edge| per_column * (edge[0] - edge[1]))
            .collect();
        Ok(Self::texel_table(
            Layout::LatLong,
            width,
            height,
            texels,
            bands,
            |row| solid_angles[row],
        ))
    }

    /// A map read by the nearest texel (`layout` one of the table layouts) from its scaled
    /// `texels`, whose rows each cover `solid_angle(row)` per texel (in any unit: only their
    /// ratios count), sampled by a table of each texel's compensated luminance (see the module
    /// documentation) times its solid angle.
    fn texel_table(
        layout: Layout,
        width: usize,
        height: usize,
        texels: Vec<Color>,
        bands: Vec<f64>,
        solid_angle: impl Fn(usize) -> f64,
    ) -> Self {
        let lum: Vec<f64> = texels.iter().map(|c| c.luminance().max(0.0)).collect();
        let brightest = lum.iter().fold(0.0f64, |m, &l| m.max(l));
        let norm = if brightest > 0.0 {
            1.0 / brightest
        } else {
            0.0
        };
        // The luminance and the radiance averaged over the sphere.
        let (mut weighted, mut radiance, mut total) = (0.0, Color::BLACK, 0.0);
        for (row, (lum, texels)) in lum
            .chunks_exact(width)
            .zip(texels.chunks_exact(width))
            .enumerate()
        {
            let omega = solid_angle(row);
            weighted += lum.iter().sum::<f64>() * norm * omega;
            radiance += texels.iter().fold(Color::BLACK, |acc, &c| acc + c) * omega;
            total += omega * width as f64;
        }
        let mean = weighted / total;
        let average = radiance * (1.0 / total);
        let floor = if mean > 0.0 { 1e-3 * mean } else { 1.0 };
        let weights: Vec<f64> = lum
            .iter()
            .enumerate()
            .map(|(i, l)| ((l * norm - mean).max(0.0) + floor) * solid_angle(i / width))
            .collect();
        let cells = Distribution2D::new(width, height, &weights)
            .expect("texel weights are finite and positive, one per texel");
        Self {
            layout,
            width,
            height,
            texels,
            to_local: DMat3::IDENTITY,
            to_world: DMat3::IDENTITY,
            weights,
            cells,
            average,
            bands,
        }
    }

    /// The map placed in the world by any orthogonal `world_to_local` (a rotation, or a
    /// rotation and a mirror: pbrt-v4's light transforms may mirror the sky, and a mirror keeps
    /// solid angles, so the densities still integrate to one).
    pub fn with_frame(self, world_to_local: DMat3) -> Result<Self, EnvironmentError> {
        self.transformed(world_to_local, true)
    }

    /// The map turned in the world, so that a scene can put the sun where it wants:
    /// `world_to_local` takes a world direction into the map's own frame (the one of the module
    /// documentation). It must be a rotation (within 1e-6); anything else would stretch solid
    /// angles and break the sampling densities.
    pub fn with_transform(self, world_to_local: DMat3) -> Result<Self, EnvironmentError> {
        self.transformed(world_to_local, false)
    }

    /// [`with_transform`](Self::with_transform), mirrors allowed where `mirror`.
    fn transformed(
        mut self,
        world_to_local: DMat3,
        mirror: bool,
    ) -> Result<Self, EnvironmentError> {
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
        if m.determinant() < 0.0 && !mirror {
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
        if self.layout != Layout::Equirectangular {
            return self
                .texel_towards(direction)
                .map_or(Color::BLACK, |(i, _)| self.texels[i]);
        }
        match self.locate(direction) {
            Some((at, _)) => self.radiance_at(at),
            None => Color::BLACK,
        }
    }

    /// The radiance arriving from `direction`, as [`radiance`](Self::radiance), and the
    /// density with which [`sample`](Self::sample) draws it, as [`pdf`](Self::pdf): what a
    /// path that escapes needs, for the price of one conversion to angles.
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Color, f64) {
        if self.layout != Layout::Equirectangular {
            return self
                .texel_towards(direction)
                .map_or((Color::BLACK, 0.0), |(i, pdf)| (self.texels[i], pdf));
        }
        match self.locate(direction) {
            Some((at, sin_theta)) => (self.radiance_at(at), self.pdf_at(at, sin_theta)),
            None => (Color::BLACK, 0.0),
        }
    }

    /// The texel of a map read by the nearest texel (equal-area or latitude–longitude) that a
    /// world direction falls in, and the density per solid angle with which
    /// [`sample`](Self::sample) draws it; `None` for a zero or non-finite direction.
    fn texel_towards(&self, direction: Vec3) -> Option<(usize, f64)> {
        let d = (self.to_local * direction).try_normalize()?;
        let (u, v) = if self.layout == Layout::LatLong {
            // θ by an arctangent (full precision near the poles), both angles in turns.
            let theta = atan2_turns((d.x * d.x + d.y * d.y).sqrt(), d.z);
            let phi = atan2_turns(d.y, d.x);
            (if phi < 0.0 { phi + 1.0 } else { phi }, 2.0 * theta)
        } else {
            equal_area_sphere_to_square(d)
        };
        let column = ((u * self.width as f64) as usize).min(self.width - 1);
        let row = ((v * self.height as f64) as usize).min(self.height - 1);
        let index = row * self.width + column;
        Some((index, self.texel_pdf(index)))
    }

    /// The density per solid angle of directions in texel `index` of a map read by the
    /// nearest texel: the texel's probability in the table over its solid angle (`4π / N` for
    /// every texel of an equal-area map).
    fn texel_pdf(&self, index: usize) -> f64 {
        let count = (self.width * self.height) as f64;
        let probability = self.weights[index] / (self.cells.integral() * count);
        let solid_angle = if self.layout == Layout::LatLong {
            let row = index / self.width;
            2.0 * PI / self.width as f64 * (self.bands[row] - self.bands[row + 1])
        } else {
            4.0 * PI / count
        };
        probability / solid_angle
    }

    /// [`sample`](Self::sample) of a map read by the nearest texel: a texel by its weight, a
    /// point in it uniformly in solid angle (an equal-area map's mapping keeps areas; a
    /// latitude–longitude texel is uniform in φ and in cos θ).
    fn sample_texel(&self, u: [f64; 2]) -> Option<(Vec3, Color, f64)> {
        let ((column, row), _, [x, y]) = self.cells.sample_cell(u);
        let local = if self.layout == Layout::LatLong {
            let (sin_phi, cos_phi) = sin_cos_turns((column as f64 + x) / self.width as f64);
            let (top, bottom) = (self.bands[row], self.bands[row + 1]);
            let cos_theta = top + (bottom - top) * y;
            let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
            Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
        } else {
            let side = self.width as f64;
            equal_area_square_to_sphere((column as f64 + x) / side, (row as f64 + y) / side)
        };
        let index = row * self.width + column;
        let direction = (self.to_world * local).try_normalize()?;
        Some((direction, self.texels[index], self.texel_pdf(index)))
    }

    /// Where a world direction falls among the texel centres, and the sine of its θ in the
    /// map's frame; `None` for a zero or non-finite direction.
    fn locate(&self, direction: Vec3) -> Option<(CellPoint, f64)> {
        // Rays' directions come unit already (to within rounding), and a rotation keeps them
        // so: normalising again cost a square root and a division for every escaped path.
        let d = self.to_local * direction;
        let d = if (d.length_squared() - 1.0).abs() <= 1e-12 {
            d
        } else {
            d.try_normalize()?
        };
        // An arctangent rather than acos(y): full precision near the poles, where acos loses
        // digits. (The components are those of a unit vector: the square root cannot
        // overflow, and it is not the library's slower `hypot`.) Both angles in turns.
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        let theta = atan2_turns(sin_theta, d.y);
        let mut phi = atan2_turns(d.x, -d.z);
        if phi < 0.0 {
            phi += 1.0;
        }
        if phi >= 1.0 {
            phi = 0.0;
        }
        let (w, h) = (self.width, self.height);
        // Texel centres sit at whole numbers of s and t. (θ in turns is at most ½.)
        let s = phi * w as f64 - 0.5;
        let t = (2.0 * theta * (h - 1) as f64).clamp(0.0, (h - 1) as f64);
        // Whole parts by conversion (the library's `floor` is a call on the baseline target):
        // s is at least −½, t not negative.
        let whole = s as i64;
        let s0 = if (whole as f64) > s { whole - 1 } else { whole };
        // s0 lies in [−1, W − 1]: wrapping it needs no division (the `min` only guards the
        // index against rounding).
        let column = (if s0 < 0 { s0 + w as i64 } else { s0 } as usize).min(w - 1);
        let s0 = s0 as f64;
        let row = (t as usize).min(h - 2);
        let at = CellPoint {
            column,
            row,
            across: s - s0,
            down: t - row as f64,
        };
        Some((at, sin_theta))
    }

    /// The four values of `table` (one per texel) at the corners of `at`'s cell: top left,
    /// top right (wrapping around in φ), bottom left, bottom right.
    #[inline]
    fn corners<T: Copy>(&self, table: &[T], at: CellPoint) -> [T; 4] {
        let w = self.width;
        let next = if at.column + 1 == w { 0 } else { at.column + 1 };
        let (top, bottom) = (at.row * w, (at.row + 1) * w);
        [
            table[top + at.column],
            table[top + next],
            table[bottom + at.column],
            table[bottom + next],
        ]
    }

    /// The radiance at `at`, interpolated bilinearly.
    fn radiance_at(&self, at: CellPoint) -> Color {
        let [a, b, c, d] = self.corners(&self.texels, at);
        a.lerp(b, at.across).lerp(c.lerp(d, at.across), at.down)
    }

    /// The density per unit solid angle at `at`, whose θ has sine `sin_theta`: the bilinear
    /// weight over the whole map's integral of it, turned from `(u', v)` (a `2π × π` rectangle
    /// of angles) into solid angle.
    fn pdf_at(&self, at: CellPoint, sin_theta: f64) -> f64 {
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let [a, b, c, d] = self.corners(&self.weights, at);
        let weight = bilinear(a, b, c, d, at.across, at.down);
        weight / (self.cells.integral() * 2.0 * PI * PI * sin_theta)
    }

    /// A direction drawn in proportion (roughly) to the radiance arriving from it, from two
    /// uniform random numbers in `[0, 1)`: the world direction (unit length), the radiance
    /// arriving from it, and the density per unit solid angle, equal to [`pdf`](Self::pdf) of
    /// that direction. `None` only if the draw lands exactly on a pole, where the density per
    /// solid angle is undefined (it never does for random numbers inside `(0, 1)`).
    pub fn sample(&self, u: [f64; 2]) -> Option<(Vec3, Color, f64)> {
        if self.layout != Layout::Equirectangular {
            return self.sample_texel(u);
        }
        let ((column, row), _, [u_across, u_down]) = self.cells.sample_cell(u);
        let at = CellPoint {
            column,
            row,
            across: 0.0,
            down: 0.0,
        };
        // Down the cell the weight's marginal is linear between its two rows' sums; across,
        // at that height, linear between the two sides.
        let [a, b, c, d] = self.corners(&self.weights, at);
        let down = sample_linear(u_down, a + b, c + d);
        let across = sample_linear(u_across, a + (c - a) * down, b + (d - b) * down);
        let at = CellPoint { across, down, ..at };
        let (w, h) = (self.width as f64, (self.height - 1) as f64);
        // φ = 2π (column + across + ½) / W and θ = π (row + down) / (H − 1), as turns.
        let (sin_phi, cos_phi) = sin_cos_turns((column as f64 + across + 0.5) / w);
        let (sin_theta, cos_theta) = sin_cos_turns(0.5 * (row as f64 + down) / h);
        if sin_theta <= 0.0 {
            return None;
        }
        let pdf = self.pdf_at(at, sin_theta);
        if pdf <= 0.0 {
            return None;
        }
        let local = Vec3::new(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta);
        let direction = (self.to_world * local).normalize();
        Some((direction, self.radiance_at(at), pdf))
    }

    /// The density per unit solid angle with which [`sample`](Self::sample) draws the world
    /// direction `direction`, for weighing its samples against another strategy's (multiple
    /// importance sampling). 0 for a zero or non-finite direction and at the poles.
    pub fn pdf(&self, direction: Vec3) -> f64 {
        if self.layout != Layout::Equirectangular {
            return self.texel_towards(direction).map_or(0.0, |(_, pdf)| pdf);
        }
        match self.locate(direction) {
            Some((at, sin_theta)) => self.pdf_at(at, sin_theta),
            None => 0.0,
        }
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

/// A direction drawn from an environment map with given numbers, drawn at most once however
/// many estimates read it: at a path vertex, next-event estimation (where it picks the sky)
/// and the sky seen in each mirror ball take the same light point, and a draw is a cell
/// found in two tables, two square roots and two sines.
#[derive(Debug, Clone, Copy)]
pub struct SkyDraw {
    u: [f64; 2],
    drawn: Option<Option<(Vec3, Color, f64)>>,
}

impl SkyDraw {
    /// The draw for the numbers `u`, not made yet.
    #[inline]
    pub fn new(u: [f64; 2]) -> Self {
        Self { u, drawn: None }
    }

    /// The numbers the draw is made with.
    #[inline]
    pub fn numbers(&self) -> [f64; 2] {
        self.u
    }

    /// The draw `sample` makes with these numbers (a sky's: [`EnvironmentMap::sample`], or
    /// the lights' sum of maps), made on the first call. (Every call must name the same sky.)
    #[inline]
    pub fn of(
        &mut self,
        sample: impl FnOnce([f64; 2]) -> Option<(Vec3, Color, f64)>,
    ) -> Option<(Vec3, Color, f64)> {
        let u = self.u;
        *self.drawn.get_or_insert_with(|| sample(u))
    }
}

/// Refuses `got` texels for a `width × height` map unless they fill it.
fn check_texel_count(width: usize, height: usize, got: usize) -> Result<(), EnvironmentError> {
    let expected = width as u128 * height as u128;
    if expected != got as u128 {
        return Err(EnvironmentError::WrongTexelCount {
            width,
            height,
            expected,
            got,
        });
    }
    Ok(())
}

/// `texels`, each times `scale`, refused (naming the first bad texel of a map `width` across)
/// where the scale or a scaled texel is negative, infinite or NaN.
fn scaled_texels(
    width: usize,
    mut texels: Vec<Color>,
    scale: f64,
) -> Result<Vec<Color>, EnvironmentError> {
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(EnvironmentError::BadScale(scale));
    }
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
    Ok(texels)
}

/// A point of the map among its texel centres: the cell whose top-left texel is in `column`
/// and `row`, and how far across (towards the next column) and down (towards the next row)
/// the point lies in it, each in `[0, 1]`.
#[derive(Debug, Clone, Copy)]
struct CellPoint {
    column: usize,
    row: usize,
    across: f64,
    down: f64,
}

/// The bilinear interpolation of the corners `a` (top left), `b` (top right), `c` (bottom
/// left) and `d` (bottom right) at `x` across and `y` down.
#[inline]
fn bilinear(a: f64, b: f64, c: f64, d: f64, x: f64, y: f64) -> f64 {
    let top = a + (b - a) * x;
    let bottom = c + (d - c) * x;
    top + (bottom - top) * y
}

/// A point of `[0, 1)` drawn with density proportional to `(1 − x) a + x b` (`a`, `b` not
/// negative) from a uniform `u` in `[0, 1)`. The cumulative distribution is a quadratic; its
/// root is taken in the form `u (a + b) / (a + √((1 − u) a² + u b²))`, which does not cancel
/// when `a` and `b` are close, and is `u` itself when they are equal.
#[inline]
fn sample_linear(u: f64, a: f64, b: f64) -> f64 {
    let denominator = a + (a * a + u * (b * b - a * a)).max(0.0).sqrt();
    if denominator <= 0.0 {
        // Both ends zero (no weight to follow: uniform) or a = 0 and u = 0.
        return if a + b > 0.0 { 0.0 } else { u };
    }
    (u * (a + b) / denominator).min(1.0 - f64::EPSILON / 2.0)
}

/// The θ of row `row` of a map `height` rows high.
fn row_theta(row: usize, height: usize) -> f64 {
    PI * row as f64 / (height - 1) as f64
}

/// The sampling weight of each texel (see the comment on `EnvironmentMap`'s `weights`): its
/// luminance with the map's brightest channel scaled to 1, less the map's average luminance
/// (not below zero), plus a floor of a thousandth of the mean (all 1 for a black map, which
/// then samples by solid angle alone), times the mean of sin θ over the band of θ within half
/// a row of its own (clamped at the poles, so a pole's texels keep a weight and the density
/// stays continuous).
fn sampling_weights(width: usize, height: usize, texels: &[Color]) -> Vec<f64> {
    let brightest = texels.iter().fold(0.0, |m: f64, c| m.max(c.max_channel()));
    let scale = if brightest > 0.0 {
        1.0 / brightest
    } else {
        0.0
    };
    let lum: Vec<f64> = texels
        .iter()
        .map(|&c| Color::luminance(c * scale).max(0.0))
        .collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    let floor = if mean > 0.0 { 1e-3 * mean } else { 1.0 };
    let half_row = 0.5 * PI / (height - 1) as f64;
    let band_sine = |row: usize| {
        let theta = row_theta(row, height);
        let (a, b) = ((theta - half_row).max(0.0), (theta + half_row).min(PI));
        (a.cos() - b.cos()) / (b - a)
    };
    let (mut sum, mut area) = (0.0, 0.0);
    for (row, texels) in lum.chunks_exact(width).enumerate() {
        let sine = band_sine(row);
        sum += texels.iter().sum::<f64>() * sine;
        area += width as f64 * sine;
    }
    // The luminance averaged over the sphere, which every texel gives up.
    let average = if area > 0.0 { sum / area } else { 0.0 };
    lum.chunks_exact(width)
        .enumerate()
        .flat_map(|(row, texels)| {
            let sine = band_sine(row);
            texels
                .iter()
                .map(move |l| ((l - average).max(0.0) + floor) * sine)
        })
        .collect()
}

/// The table the map picks cells from (see the comment on `EnvironmentMap`'s `cells`): the
/// cell between columns `k`, `k + 1` and rows `j`, `j + 1` weighs the mean of its four
/// corners' weights, the integral of their bilinear patch.
fn cell_distribution(width: usize, height: usize, weights: &[f64]) -> Distribution2D {
    let mut table = Vec::with_capacity(width * (height - 1));
    for row in 0..height - 1 {
        for column in 0..width {
            let next = (column + 1) % width;
            let corners = weights[row * width + column]
                + weights[row * width + next]
                + weights[(row + 1) * width + column]
                + weights[(row + 1) * width + next];
            table.push(0.25 * corners);
        }
    }
    // Every weight is finite and positive (at most 2 before the sine, which is positive at
    // every row), so the table is always valid.
    Distribution2D::new(width, height - 1, &table)
        .expect("cell weights are finite and positive, one per cell")
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

    /// The sampling cells of `map` in its own frame: `(θ₀, θ₁, φ₀, φ₁)`. The density per solid
    /// angle times sin θ is bilinear in (θ, φ) on each cell, so the midpoint rule integrates it
    /// exactly cell by cell.
    fn cells(map: &EnvironmentMap) -> Vec<(f64, f64, f64, f64)> {
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
                out.push((t0, t1, p0, p1));
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
                .map(|&(t0, t1, p0, p1)| {
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
            let u = [rng.next_offset(), rng.next_offset()];
            let (d, radiance, pdf) = map.sample(u).expect("a sample");
            // A draw shared between estimates is the map's own, however often it is read.
            let mut shared = SkyDraw::new(u);
            assert_eq!(shared.of(|u| map.sample(u)), Some((d, radiance, pdf)));
            assert_eq!(shared.of(|u| map.sample(u)), Some((d, radiance, pdf)));
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
        // expected share is the pdf's integral over it, by the midpoint rule on a grid fine
        // enough (24 × 24 points a bin) that its error is far below the test's resolution.
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
        let fine = 24;
        let mut expected = vec![0.0; nc * np];
        for c in 0..nc {
            // In θ, where pdf × sin θ stays bounded even at the poles.
            let t0 = (1.0 - 2.0 * c as f64 / nc as f64).acos();
            let t1 = (1.0 - 2.0 * (c + 1) as f64 / nc as f64).acos();
            let dt = (t1 - t0) / fine as f64;
            let dp = 2.0 * PI / (np * fine) as f64;
            for p in 0..np {
                let mut sum = 0.0;
                for a in 0..fine {
                    let theta = t0 + (a as f64 + 0.5) * dt;
                    for b in 0..fine {
                        let phi = (p * fine + b) as f64 * dp + 0.5 * dp;
                        let d = map.to_world * local_direction(phi, theta);
                        sum += map.pdf(d) * theta.sin() * dt * dp;
                    }
                }
                expected[c * np + p] = sum;
            }
        }
        // The quadrature's own error (the density has kinks along the cells' edges) is a few
        // parts in 10⁴, far below the ±3 % noise of a bin's thousand samples.
        let total: f64 = expected.iter().sum();
        assert!((total - 1.0).abs() < 1e-3, "{total}");
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
        // As a renderer uses it: a light sample and a direction drawn another way (here
        // uniformly over the sphere, standing in for a BSDF), weighed by the power heuristic.
        // The compensated density leaves the sky below its average to the other strategy.
        let uniform_pdf = 1.0 / (4.0 * PI);
        let power = |a: f64, b: f64| a * a / (a * a + b * b);
        for _ in 0..n {
            let (_, radiance, pdf) = map.sample([rng.next_offset(), rng.next_offset()]).unwrap();
            let light = radiance * (power(pdf, uniform_pdf) / pdf);
            let z = 1.0 - 2.0 * rng.next_offset();
            let phi = 2.0 * PI * rng.next_offset();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let d = Vec3::new(r * phi.cos(), z, r * phi.sin());
            let (radiance, pdf) = map.radiance_and_pdf(d);
            let other = radiance * (power(uniform_pdf, pdf) / uniform_pdf);
            let estimate = (light + other).to_array().map(|c| c / (4.0 * PI));
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
                "channel {k}: {standard_error} of {truth}"
            );
        }
    }

    #[test]
    fn linear_densities_are_inverted_exactly() {
        // The drawn x is where the cumulative distribution of (1 − x) a + x b reaches u.
        let cdf = |x: f64, a: f64, b: f64| (a * x + 0.5 * (b - a) * x * x) / (0.5 * (a + b));
        for (a, b) in [
            (1.0, 1.0),
            (0.0, 3.0),
            (3.0, 0.0),
            (0.2, 0.7),
            (1.0, 1.0 + 1e-12),
        ] {
            for k in 0..=20 {
                let u = k as f64 / 20.0 * (1.0 - f64::EPSILON / 2.0);
                let x = sample_linear(u, a, b);
                assert!((0.0..1.0).contains(&x), "{a} {b} {u}: {x}");
                assert!((cdf(x, a, b) - u).abs() < 1e-12, "{a} {b} {u}: {x}");
            }
        }
        // No weight at either end: uniform.
        assert_eq!(sample_linear(0.3, 0.0, 0.0), 0.3);
        assert_eq!(sample_linear(0.0, 0.0, 2.0), 0.0);
    }

    #[test]
    fn a_small_sun_is_sampled_in_proportion_to_its_interpolated_light() {
        // One bright texel at the equator of a black sky: inside the four cells it lights,
        // the radiance is a bilinear tent, and the density follows it, so the weight of a
        // sample (luminance over density) hardly varies: only through sin θ across a cell
        // against its row's mean, and the floor. (A density constant over each cell would
        // make it vary from its mean to nothing.)
        let (w, h) = (32, 17);
        let mut texels = vec![Color::BLACK; w * h];
        texels[8 * w + 20] = Color::new(50.0, 40.0, 30.0);
        let map = EnvironmentMap::new(w, h, texels, 1.0).unwrap();
        let mut rng = SplitMix64::new(17);
        let (mut lo, mut hi, mut lit) = (f64::INFINITY, 0.0f64, 0);
        for _ in 0..20_000 {
            let (_, radiance, pdf) = map.sample([rng.next_offset(), rng.next_offset()]).unwrap();
            let weight = Color::luminance(radiance) / pdf;
            // Samples that landed where the tent is above a twentieth of its peak.
            if Color::luminance(radiance) > 0.05 * Color::luminance(Color::new(50.0, 40.0, 30.0)) {
                lit += 1;
                lo = lo.min(weight);
                hi = hi.max(weight);
            }
        }
        assert!(lit > 15_000, "{lit}");
        assert!(hi / lo < 1.05, "weights from {lo} to {hi}");
    }

    #[test]
    fn the_sky_below_its_average_is_left_to_other_strategies() {
        // Upper half twice as bright as the lower: the average lies between, so the lower half
        // keeps only the floor's weight, and the upper half the excess over the average.
        let (w, h) = (8, 9);
        let texels: Vec<Color> = (0..w * h)
            .map(|i| Color::WHITE * if i / w < 4 { 2.0 } else { 1.0 })
            .collect();
        let map = EnvironmentMap::new(w, h, texels, 1.0).unwrap();
        let up = map.pdf(local_direction(1.0, 0.3 * PI));
        let down = map.pdf(local_direction(1.0, 0.8 * PI));
        assert!(down > 0.0, "every direction stays possible");
        assert!(down < 0.01 * up, "{down} vs {up}");
        // An even sky has nothing above its average: it is sampled by solid angle.
        let even = EnvironmentMap::new(w, h, vec![Color::WHITE; w * h], 1.0).unwrap();
        for theta in [0.2, 0.5, 0.7] {
            let pdf = even.pdf(local_direction(2.0, theta * PI));
            assert!((pdf - 0.25 / PI).abs() < 0.02 / PI, "{pdf} at {theta}");
        }
    }

    /// A square map of smooth variation and one bright texel (a sun), in pbrt-v4's layout.
    fn equal_area_map(side: usize, seed: u64) -> EnvironmentMap {
        let mut rng = SplitMix64::new(seed);
        let mut texels: Vec<Color> = (0..side * side)
            .map(|_| Color::new(rng.next_offset(), rng.next_offset(), rng.next_offset()))
            .collect();
        texels[side * side / 3 + 2] = Color::new(4.0, 3.0, 2.0);
        EnvironmentMap::equal_area(side, side, texels, 1.5).unwrap()
    }

    #[test]
    fn the_equal_area_mapping_round_trips_and_keeps_areas() {
        let mut rng = SplitMix64::new(3);
        for _ in 0..20_000 {
            let (u, v) = (rng.next_offset(), rng.next_offset());
            let d = equal_area_square_to_sphere(u, v);
            assert!((d.length() - 1.0).abs() < 1e-12, "{d}");
            let (u2, v2) = equal_area_sphere_to_square(d);
            assert!(
                (u - u2).abs() < 1e-9 && (v - v2).abs() < 1e-9,
                "{u} {v} -> {u2} {v2}"
            );
        }
        // The centre is the pole; the corners the other pole.
        assert!((equal_area_square_to_sphere(0.5, 0.5) - Vec3::Z).length() < 1e-12);
        assert!((equal_area_square_to_sphere(0.0, 1.0) + Vec3::Z).length() < 1e-12);
        // Equal areas are equal solid angles: a uniform point of the square is a uniform
        // direction, so z is uniform in [-1, 1] (its mean 0, its mean square 1/3).
        let n = 200_000;
        let (mut sum, mut sum_sq) = (0.0, 0.0);
        for _ in 0..n {
            let z = equal_area_square_to_sphere(rng.next_offset(), rng.next_offset()).z;
            sum += z;
            sum_sq += z * z;
        }
        let (mean, mean_sq) = (sum / n as f64, sum_sq / n as f64);
        // Standard errors: 1/sqrt(3n) and sqrt(4/45 / n).
        assert!(mean.abs() < 4.0 / (3.0 * n as f64).sqrt(), "{mean}");
        assert!(
            (mean_sq - 1.0 / 3.0).abs() < 4.0 * (4.0 / 45.0 / n as f64).sqrt(),
            "{mean_sq}"
        );
    }

    #[test]
    fn an_equal_area_map_reads_its_texels_and_its_pdf_integrates_to_one() {
        let side = 16;
        let mirror = DMat3::from_diagonal(Vec3::new(1.0, -1.0, 1.0)) * DMat3::from_rotation_z(0.3);
        for frame in [DMat3::IDENTITY, mirror] {
            let map = equal_area_map(side, 5).with_frame(frame).unwrap();
            // Each texel's centre, in the world, sees that texel.
            for (row, column) in [(0, 0), (3, 7), (15, 15), (8, 1)] {
                let local = equal_area_square_to_sphere(
                    (column as f64 + 0.5) / side as f64,
                    (row as f64 + 0.5) / side as f64,
                );
                let world = frame.transpose() * local;
                assert_eq!(map.radiance(world), map.texel(column, row).unwrap());
            }
            // Every texel is 4π/N of solid angle: the sum of pdf × 4π/N over the texel centres.
            let total: f64 = (0..side * side)
                .map(|i| {
                    let (c, r) = (i % side, i / side);
                    let local = equal_area_square_to_sphere(
                        (c as f64 + 0.5) / side as f64,
                        (r as f64 + 0.5) / side as f64,
                    );
                    map.pdf(frame.transpose() * local) * 4.0 * PI / (side * side) as f64
                })
                .sum();
            assert!((total - 1.0).abs() < 1e-9, "{total}");
            // And by brute force over the sphere.
            let brute = integrate(400, |d| map.pdf(d));
            assert!((brute - 1.0).abs() < 2e-2, "{brute}");
            // The average is the texels' mean: each texel is the same solid angle.
            let mean = (0..side * side)
                .map(|i| map.texel(i % side, i / side).unwrap())
                .fold(Color::BLACK, |a, c| a + c)
                * (1.0 / (side * side) as f64);
            assert!(close(map.average_radiance(), mean, 1e-12));
        }
        assert!(matches!(
            EnvironmentMap::equal_area(8, 4, vec![Color::WHITE; 32], 1.0),
            Err(EnvironmentError::NotSquare { .. })
        ));
    }

    #[test]
    fn equal_area_samples_follow_their_pdf() {
        let side = 8;
        let frame = DMat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        let map = equal_area_map(side, 7).with_frame(frame).unwrap();
        let n = 200_000;
        let mut counts = vec![0u64; side * side];
        let mut rng = SplitMix64::new(11);
        for _ in 0..n {
            let u = [rng.next_offset(), rng.next_offset()];
            let (d, radiance, pdf) = map.sample(u).unwrap();
            assert!((map.pdf(d) - pdf).abs() <= 1e-9 * pdf);
            assert_eq!(map.radiance(d), radiance);
            let (s, t) = equal_area_sphere_to_square(frame * d);
            let (c, r) = (
                ((s * side as f64) as usize).min(side - 1),
                ((t * side as f64) as usize).min(side - 1),
            );
            counts[r * side + c] += 1;
        }
        // Each texel's chance: its pdf times its solid angle.
        let expected: Vec<f64> = (0..side * side)
            .map(|i| {
                let local = equal_area_square_to_sphere(
                    ((i % side) as f64 + 0.5) / side as f64,
                    ((i / side) as f64 + 0.5) / side as f64,
                );
                map.pdf(frame.transpose() * local) * 4.0 * PI / (side * side) as f64
            })
            .collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}");
        // The sun is found in proportion to its excess over the average.
        let sun = side * side / 3 + 2;
        assert!(expected[sun] > 0.1, "{}", expected[sun]);
    }

    /// A 2:1 latitude–longitude map of smooth variation and a bright texel (a sun) near the
    /// pole, where the rows' solid angles differ most.
    fn lat_long_map(width: usize, height: usize, seed: u64) -> EnvironmentMap {
        let mut rng = SplitMix64::new(seed);
        let mut texels: Vec<Color> = (0..width * height)
            .map(|_| Color::new(rng.next_offset(), rng.next_offset(), rng.next_offset()))
            .collect();
        texels[width + 3] = Color::new(40.0, 30.0, 20.0);
        EnvironmentMap::lat_long(width, height, texels, 1.5).unwrap()
    }

    /// The direction (pbrt's: +z the pole, φ from +x towards +y) of the point `(x, y)` of a
    /// latitude–longitude map `w × h`, in texels.
    fn lat_long_direction(x: f64, y: f64, w: usize, h: usize) -> Vec3 {
        let (phi, theta) = (2.0 * PI * x / w as f64, PI * y / h as f64);
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// The solid angle of a texel of row `row` of a `w × h` latitude–longitude map.
    fn lat_long_solid_angle(row: usize, w: usize, h: usize) -> f64 {
        let (a, b) = (PI * row as f64 / h as f64, PI * (row + 1) as f64 / h as f64);
        2.0 * PI / w as f64 * (a.cos() - b.cos())
    }

    #[test]
    fn a_lat_long_map_reads_its_texels_and_its_pdf_integrates_to_one() {
        let (w, h) = (16, 8);
        let mirror = DMat3::from_diagonal(Vec3::new(1.0, -1.0, 1.0)) * DMat3::from_rotation_x(0.4);
        for frame in [DMat3::IDENTITY, mirror] {
            let map = lat_long_map(w, h, 5).with_frame(frame).unwrap();
            // Each texel's centre and a point near its corner, in the world, see that texel.
            for (column, row) in [(0, 0), (3, 1), (15, 7), (8, 4), (5, 3)] {
                for (dx, dy) in [(0.5, 0.5), (0.01, 0.01), (0.99, 0.98)] {
                    let local = lat_long_direction(column as f64 + dx, row as f64 + dy, w, h);
                    let world = frame.transpose() * local;
                    assert_eq!(
                        map.radiance(world),
                        map.texel(column, row).unwrap(),
                        "({column}, {row}) + ({dx}, {dy})"
                    );
                }
            }
            // The pole and the seam: +z is row 0, φ = 0 column 0, just below it the last.
            let world = |d: Vec3| frame.transpose() * d;
            assert_eq!(map.radiance(world(Vec3::Z)), map.texel(0, 0).unwrap());
            assert_eq!(map.radiance(world(-Vec3::Z)), map.texel(0, h - 1).unwrap());
            let below_seam = lat_long_direction(w as f64 - 1e-6, 4.5, w, h);
            assert_eq!(
                map.radiance(world(below_seam)),
                map.texel(w - 1, 4).unwrap()
            );
            // Each texel's pdf (constant over it) times its solid angle sums to 1.
            let total: f64 = (0..w * h)
                .map(|i| {
                    let (c, r) = (i % w, i / w);
                    let d = lat_long_direction(c as f64 + 0.5, r as f64 + 0.5, w, h);
                    map.pdf(world(d)) * lat_long_solid_angle(r, w, h)
                })
                .sum();
            assert!((total - 1.0).abs() < 1e-9, "{total}");
            // And by brute force over the sphere.
            let brute = integrate(400, |d| map.pdf(d));
            assert!((brute - 1.0).abs() < 2e-2, "{brute}");
            // The average weighs each texel by its solid angle.
            let mean = (0..w * h)
                .map(|i| map.texel(i % w, i / w).unwrap() * lat_long_solid_angle(i / w, w, h))
                .fold(Color::BLACK, |a, c| a + c)
                * (0.25 / PI);
            assert!(close(map.average_radiance(), mean, 1e-12));
            let brute = integrate(400, |d| map.radiance(d).green) / (4.0 * PI);
            assert!((brute - mean.green).abs() < 1e-2 * mean.green, "{brute}");
        }
        assert!(matches!(
            EnvironmentMap::lat_long(0, 4, Vec::new(), 1.0),
            Err(EnvironmentError::Empty { .. })
        ));
        assert!(matches!(
            EnvironmentMap::lat_long(4, 2, vec![Color::WHITE; 7], 1.0),
            Err(EnvironmentError::WrongTexelCount { .. })
        ));
    }

    #[test]
    fn lat_long_samples_follow_their_pdf() {
        let (w, h) = (12, 6);
        let frame = DMat3::from_rotation_y(0.9);
        let map = lat_long_map(w, h, 7).with_frame(frame).unwrap();
        let n = 300_000;
        let mut counts = vec![0u64; w * h];
        let mut rng = SplitMix64::new(11);
        // The sky's light over the sphere by importance: ∫ L dω = 4π × the average.
        let mut sum = 0.0;
        let mut sum_sq = 0.0;
        for _ in 0..n {
            let u = [rng.next_offset(), rng.next_offset()];
            let (d, radiance, pdf) = map.sample(u).unwrap();
            assert!((d.length() - 1.0).abs() < 1e-12);
            assert!(
                (map.pdf(d) - pdf).abs() <= 1e-9 * pdf,
                "{} vs {pdf}",
                map.pdf(d)
            );
            assert_eq!(map.radiance(d), radiance);
            let local = frame * d;
            let theta = local.z.clamp(-1.0, 1.0).acos();
            let phi = local.y.atan2(local.x).rem_euclid(2.0 * PI);
            let c = ((phi / (2.0 * PI) * w as f64) as usize).min(w - 1);
            let r = ((theta / PI * h as f64) as usize).min(h - 1);
            counts[r * w + c] += 1;
            let value = radiance.green / pdf;
            sum += value;
            sum_sq += value * value;
        }
        // Each texel's chance: its pdf times its solid angle.
        let expected: Vec<f64> = (0..w * h)
            .map(|i| {
                let (c, r) = (i % w, i / w);
                let d = lat_long_direction(c as f64 + 0.5, r as f64 + 0.5, w, h);
                map.pdf(frame.transpose() * d) * lat_long_solid_angle(r, w, h)
            })
            .collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}");
        // The sun is found in proportion to its excess over the average.
        let sun = w + 3;
        assert!(expected[sun] > 0.1, "{}", expected[sun]);
        let (mean, se) = {
            let mean = sum / n as f64;
            (mean, ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt())
        };
        let want = 4.0 * PI * map.average_radiance().green;
        assert!((mean - want).abs() < 4.0 * se, "{mean} ± {se} vs {want}");
    }

    #[test]
    fn a_lat_long_texel_is_drawn_uniformly_in_solid_angle() {
        // One bright texel by the pole, the rest black: its samples' cos θ is uniform over the
        // texel's band (a draw uniform in θ would crowd the pole).
        let (w, h) = (4, 2);
        let mut texels = vec![Color::BLACK; w * h];
        texels[1] = Color::WHITE;
        let map = EnvironmentMap::lat_long(w, h, texels, 1.0).unwrap();
        let mut rng = SplitMix64::new(2);
        let bins = 10;
        let mut counts = vec![0u64; bins];
        for _ in 0..100_000 {
            let (d, radiance, _) = map.sample([rng.next_offset(), rng.next_offset()]).unwrap();
            if radiance == Color::WHITE {
                // The band is cos θ in [0, 1].
                counts[((d.z * bins as f64) as usize).min(bins - 1)] += 1;
            }
        }
        let p = chi_square_p_value(&counts, &vec![1.0 / bins as f64; bins]);
        assert!(p > 1e-3, "chi-square p-value {p}: {counts:?}");
    }
}
