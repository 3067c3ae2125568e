//! Anti-aliasing: where in a pixel the camera rays go.
//!
//! Every choice here is a pure function of the pixel (its seed is its index), so images are
//! identical for any thread count and any order in which pixels are rendered.

use crate::camera::CameraSample;
use crate::color::Color;
use crate::math::random::{Jitter, SplitMix64};

/// A camera sample through image point (`x`, `y`) with the lens point drawn from `lens` and
/// the instant from `shutter` (separate streams, so adding motion blur changes no lens sample).
fn drawn(x: f64, y: f64, lens: &mut SplitMix64, shutter: &mut SplitMix64) -> CameraSample {
    CameraSample {
        x,
        y,
        lens_u: lens.next_offset(),
        lens_v: lens.next_offset(),
        time: shutter.next_offset(),
    }
}

/// How each pixel is sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampling {
    /// One ray through the pixel's centre (the book's renderer).
    Centre,
    /// An `n × n` grid of cells, one ray at a random point of each cell (stratified, jittered),
    /// averaged with equal weights.
    Stratified {
        /// Cells per side (the pixel takes `n²` samples).
        per_side: u32,
    },
    /// `n` rays for a count that is no square: Shirley's N-rooks sampling (a Latin hypercube).
    /// The pixel is cut into `n` columns and `n` rows; each ray takes its own column and its
    /// own row (the rows shuffled), at a random point of that cell, so that the rays are
    /// stratified along each axis as a grid's would be, and averaged with equal weights.
    Rooks {
        /// Rays per pixel.
        samples: u32,
    },
    /// Fundamentals of Ray Tracing's anti-aliasing: an `n × n` grid of rays from each pixel's
    /// top-left corner at steps of `1/n` (no jitter), averaged.
    Grid {
        /// Rays per side.
        per_side: u32,
    },
    /// Chapter 17's adaptive scheme: rays at the four corners and the centre; where any corner
    /// differs from the centre by more than `threshold` (in any channel), the pixel is split into
    /// quarters and each is sampled the same way, down to `depth` levels.
    Adaptive {
        /// The largest channel difference accepted without subdividing.
        threshold: f64,
        /// How many times a pixel may be split.
        depth: u32,
    },
}

impl Sampling {
    /// Exactly `spp` samples per pixel, as `--spp` means for every renderer: a stratified
    /// grid when `spp` is a square (4 → 2×2, 9 → 3×3), N-rooks otherwise (5 → 5 rays in 5
    /// columns and 5 rows); 1 or 0 means one ray through the centre.
    pub fn with_samples(spp: u32) -> Self {
        if spp <= 1 {
            return Sampling::Centre;
        }
        let per_side = spp.isqrt();
        if per_side * per_side == spp {
            Sampling::Stratified { per_side }
        } else {
            Sampling::Rooks { samples: spp }
        }
    }

    /// Camera rays per pixel: the grid's cells, or for adaptive sampling the five of an
    /// unsplit pixel (its corners and centre), the least it takes.
    pub fn camera_rays(self) -> u64 {
        match self {
            Sampling::Centre => 1,
            Sampling::Grid { per_side } | Sampling::Stratified { per_side } => {
                u64::from(per_side) * u64::from(per_side)
            }
            Sampling::Rooks { samples } => u64::from(samples),
            Sampling::Adaptive { .. } => 5,
        }
    }

    /// Passes that refine an image up to this sampling (a progressive render's): one ray
    /// through each pixel's centre, then grids of the same kind with 2, 4, 8, … rays a side
    /// (each pass about four times the rays of the one before, so the time to the next image
    /// grows with the time spent), then this sampling itself; N-rooks after stratified grids
    /// of fewer rays; adaptive sampling after the centre pass alone.
    pub fn refining_passes(self) -> Vec<Sampling> {
        let mut passes = vec![Sampling::Centre];
        let mut per_side = 2;
        match self {
            Sampling::Centre => return passes,
            Sampling::Stratified { per_side: most } | Sampling::Grid { per_side: most } => {
                while per_side < most {
                    passes.push(match self {
                        Sampling::Grid { .. } => Sampling::Grid { per_side },
                        _ => Sampling::Stratified { per_side },
                    });
                    per_side *= 2;
                }
            }
            Sampling::Rooks { samples } => {
                while per_side * per_side < samples {
                    passes.push(Sampling::Stratified { per_side });
                    per_side *= 2;
                }
            }
            Sampling::Adaptive { .. } => {}
        }
        passes.push(self);
        passes
    }

    /// The colour of pixel (`x`, `y`), given `trace` for one camera sample.
    ///
    /// One ray goes through the pixel's centre, from the lens's centre, half way through the
    /// shutter. Several rays also spread over the lens (focal blur) and the shutter interval
    /// (motion blur), each drawn independently of the pixel's stratum so that the blurs and
    /// edge smoothing do not correlate.
    pub fn pixel(
        &self,
        x: usize,
        y: usize,
        seed: u64,
        mut trace: impl FnMut(CameraSample) -> Color,
    ) -> Color {
        let (x, y) = (x as f64, y as f64);
        // A different stream from the one that jitters area lights.
        let mut rng = SplitMix64::new(seed ^ 0xA5A5_5A5A_C3C3_3C3C);
        let mut shutter = SplitMix64::new(seed ^ 0x0B5E_55ED_0F71_3501);
        match *self {
            Sampling::Centre => trace(CameraSample::centred(x + 0.5, y + 0.5)),
            Sampling::Stratified { per_side } => {
                let n = per_side.max(1);
                let cell = 1.0 / n as f64;
                let mut sum = Color::BLACK;
                for j in 0..n {
                    for i in 0..n {
                        let dx = (i as f64 + rng.next_offset()) * cell;
                        let dy = (j as f64 + rng.next_offset()) * cell;
                        let sample = drawn(x + dx, y + dy, &mut rng, &mut shutter);
                        sum += trace(sample);
                    }
                }
                sum / (n * n) as f64
            }
            Sampling::Rooks { samples } => {
                let n = samples.max(1);
                let cell = 1.0 / n as f64;
                // The rows in a random order (Fisher–Yates), drawn before any ray.
                let mut rows: Vec<u32> = (0..n).collect();
                for i in (1..rows.len()).rev() {
                    let j = (rng.next_offset() * (i + 1) as f64) as usize;
                    rows.swap(i, j.min(i));
                }
                let mut sum = Color::BLACK;
                for (column, &row) in rows.iter().enumerate() {
                    let dx = (column as f64 + rng.next_offset()) * cell;
                    let dy = (f64::from(row) + rng.next_offset()) * cell;
                    sum += trace(drawn(x + dx, y + dy, &mut rng, &mut shutter));
                }
                sum / f64::from(n)
            }
            Sampling::Grid { per_side } => {
                let n = per_side.max(1);
                let step = 1.0 / n as f64;
                let mut sum = Color::BLACK;
                for i in 0..n {
                    for j in 0..n {
                        let (px, py) = (x + i as f64 * step, y + j as f64 * step);
                        sum += trace(CameraSample::centred(px, py));
                    }
                }
                sum / (n * n) as f64
            }
            Sampling::Adaptive { threshold, depth } => {
                let mut at = |px, py| trace(drawn(px, py, &mut rng, &mut shutter));
                adaptive(x, y, 1.0, threshold, depth, &mut at)
            }
        }
    }
}

/// The adaptive estimate of the square at (`x`, `y`) with side `size`.
fn adaptive(
    x: f64,
    y: f64,
    size: f64,
    threshold: f64,
    depth: u32,
    trace: &mut impl FnMut(f64, f64) -> Color,
) -> Color {
    let centre = trace(x + size / 2.0, y + size / 2.0);
    let corners = [
        trace(x, y),
        trace(x + size, y),
        trace(x, y + size),
        trace(x + size, y + size),
    ];
    let differs = corners.iter().any(|c| {
        let d = *c - centre;
        d.red.abs().max(d.green.abs()).max(d.blue.abs()) > threshold
    });
    if !differs || depth == 0 {
        return (corners.iter().copied().sum::<Color>() + centre) / 5.0;
    }
    let half = size / 2.0;
    let quarters = [(x, y), (x + half, y), (x, y + half), (x + half, y + half)];
    quarters
        .iter()
        .map(|&(qx, qy)| adaptive(qx, qy, half, threshold, depth - 1, trace))
        .sum::<Color>()
        / 4.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refining_passes_grow_by_the_same_kind_up_to_the_sampling() {
        assert_eq!(Sampling::Centre.refining_passes(), [Sampling::Centre]);
        let stratified = |per_side| Sampling::Stratified { per_side };
        assert_eq!(
            stratified(6).refining_passes(),
            [
                Sampling::Centre,
                stratified(2),
                stratified(4),
                stratified(6)
            ]
        );
        assert_eq!(
            stratified(4).refining_passes(),
            [Sampling::Centre, stratified(2), stratified(4)]
        );
        let grid = Sampling::Grid { per_side: 3 };
        assert_eq!(
            grid.refining_passes(),
            [Sampling::Centre, Sampling::Grid { per_side: 2 }, grid]
        );
        let adaptive = Sampling::Adaptive {
            threshold: 0.1,
            depth: 2,
        };
        assert_eq!(adaptive.refining_passes(), [Sampling::Centre, adaptive]);
        let rooks = Sampling::Rooks { samples: 20 };
        assert_eq!(
            rooks.refining_passes(),
            [Sampling::Centre, stratified(2), stratified(4), rooks]
        );
        assert_eq!(rooks.camera_rays(), 20);
        assert_eq!(stratified(6).camera_rays(), 36);
        assert_eq!(adaptive.camera_rays(), 5);
    }
}
