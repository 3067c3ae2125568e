//! Sampling in proportion to a tabulated function: [`Distribution1D`] (piecewise constant over
//! `[0, 1)`, or a choice among bins) and [`Distribution2D`] (a marginal over rows, then one
//! conditional per row).
//!
//! A renderer draws most samples where they matter: lights in proportion to their power, mesh
//! triangles in proportion to their area (discrete sampling), and directions towards an
//! environment map's bright texels (continuous sampling). Each sample comes with its density,
//! and the density of any point can be asked again later (multiple importance sampling needs
//! both), so both are computed from one table and agree exactly.

/// Why a table of weights cannot be sampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DistributionError {
    /// There is nothing to choose from.
    #[error("a distribution needs at least one weight; none were given")]
    Empty,
    /// A weight is negative, infinite or NaN: no probability follows from it.
    #[error("weight {index} is {value}: weights must be finite and not negative")]
    InvalidWeight {
        /// Where the weight is (row-major for a 2D table).
        index: usize,
        /// The weight.
        value: f64,
    },
    /// A 2D table's size does not match its weights.
    #[error("a {width}×{height} table needs {expected} weights; {got} were given")]
    WrongSize {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// `width × height` (or `None` shown as 0 when it overflows).
        expected: usize,
        /// Weights given.
        got: usize,
    },
}

/// The largest `f64` below 1, the upper end of every random number used here.
const ONE_MINUS_EPSILON: f64 = 1.0 - f64::EPSILON / 2.0;

/// A random number clamped into `[0, 1)` (NaN becomes 0), so that no caller's rounding can
/// pick a bin past the end.
#[inline]
fn unit(u: f64) -> f64 {
    if u >= 0.0 {
        u.min(ONE_MINUS_EPSILON)
    } else {
        0.0
    }
}

/// A piecewise-constant density over `[0, 1)` with `len()` equal bins, and the same table seen
/// as a discrete choice among the bins, so that one structure serves picking a light or a
/// triangle (discrete) and picking a coordinate of an environment map (continuous).
///
/// Weights must be finite and not negative. When they are all zero, sampling is uniform (so a
/// black environment or a scene of dark lights still yields valid samples) while
/// [`integral`](Self::integral) reports 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution1D {
    /// Each bin's probability (summing to 1).
    probabilities: Vec<f64>,
    /// `cdf[i]` is the probability of bins `0..i`; `cdf[0] = 0`, `cdf[len] = 1`, and bins of
    /// zero probability have exactly equal ends, so they are never chosen.
    cdf: Vec<f64>,
    /// The mean of the weights: the integral of the step function over `[0, 1)`.
    integral: f64,
}

impl Distribution1D {
    /// A distribution whose bin `i` is chosen with probability `weights[i] / Σ weights`.
    pub fn new(weights: &[f64]) -> Result<Self, DistributionError> {
        if weights.is_empty() {
            return Err(DistributionError::Empty);
        }
        if let Some((index, &value)) = weights
            .iter()
            .enumerate()
            .find(|(_, w)| !(w.is_finite() && **w >= 0.0))
        {
            return Err(DistributionError::InvalidWeight { index, value });
        }
        let n = weights.len();
        // Scaled by the largest weight first, so that a sum of huge weights cannot overflow.
        let largest = weights.iter().copied().fold(0.0, f64::max);
        let (scale, uniform) = if largest > 0.0 {
            (1.0 / largest, false)
        } else {
            (1.0, true)
        };
        let scaled = |w: f64| if uniform { 1.0 } else { w * scale };
        let total: f64 = weights.iter().map(|&w| scaled(w)).sum();
        let integral = if uniform {
            0.0
        } else {
            largest * (total / n as f64)
        };
        let probabilities: Vec<f64> = weights.iter().map(|&w| scaled(w) / total).collect();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        let mut running = 0.0;
        for &w in weights {
            running += scaled(w);
            cdf.push(running / total);
        }
        // Everything from the last bin that can be chosen onwards ends at exactly 1, so rounding
        // can neither leave a gap at the top nor give trailing empty bins a sliver.
        let last = weights.iter().rposition(|&w| scaled(w) > 0.0).unwrap_or(0);
        for c in &mut cdf[last + 1..] {
            *c = 1.0;
        }
        Ok(Self {
            probabilities,
            cdf,
            integral,
        })
    }

    /// How many bins there are.
    pub fn len(&self) -> usize {
        self.probabilities.len()
    }

    /// Always `false`: a distribution has at least one bin (kept for the usual pairing with
    /// [`len`](Self::len)).
    pub fn is_empty(&self) -> bool {
        self.probabilities.is_empty()
    }

    /// The integral over `[0, 1)` of the step function the weights describe (their mean): a
    /// 2D table's rows are weighted by it, and it tells how bright an all-round light is.
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// The probability of choosing bin `index` (0 outside the table), the discrete
    /// counterpart of [`pdf`](Self::pdf).
    pub fn probability(&self, index: usize) -> f64 {
        self.probabilities.get(index).copied().unwrap_or(0.0)
    }

    /// The bin holding the random number `u` of the cumulative distribution: never one of
    /// probability zero, never past the end.
    fn bin_of(&self, u: f64) -> usize {
        // One bin (a scene's only light) needs no search.
        if self.len() == 1 {
            return 0;
        }
        // The last bin whose start is at or below u; its end is above u since u < 1 = cdf[len].
        let after = self.cdf.partition_point(|&c| c <= u);
        after.saturating_sub(1).min(self.len() - 1)
    }

    /// A bin chosen with its probability from a uniform random number `u` in `[0, 1)`, and
    /// that probability: to pick one light by power or one triangle by area.
    pub fn sample_discrete(&self, u: f64) -> (usize, f64) {
        let index = self.bin_of(unit(u));
        (index, self.probabilities[index])
    }

    /// [`sample_discrete`](Self::sample_discrete), and also `u` rescaled to `[0, 1)` within the
    /// chosen bin's share of the unit interval: a fresh random number for the choices that
    /// follow (a light's point after the light), uniform and independent of the bin.
    pub fn sample_discrete_reused(&self, u: f64) -> (usize, f64, f64) {
        let u = unit(u);
        let index = self.bin_of(u);
        let (start, end) = (self.cdf[index], self.cdf[index + 1]);
        let rest = if end > start {
            ((u - start) / (end - start)).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        (index, self.probabilities[index], rest)
    }

    /// The bin `x` in `[0, 1)` falls in (ends clamped), as [`pdf`](Self::pdf) finds it.
    fn bin_at(&self, x: f64) -> usize {
        let n = self.len();
        if x >= 0.0 {
            ((x * n as f64) as usize).min(n - 1)
        } else {
            0
        }
    }

    /// A point of `[0, 1)` drawn with density [`pdf`](Self::pdf) from a uniform random number
    /// `u` in `[0, 1)` (by inverting the cumulative distribution), its density, and its bin.
    /// The point always lies in the returned bin as [`pdf`](Self::pdf) computes it, so the
    /// density returned equals `pdf(x)` exactly.
    pub fn sample_continuous(&self, u: f64) -> (f64, f64, usize) {
        let u = unit(u);
        let index = self.bin_of(u);
        let (start, end) = (self.cdf[index], self.cdf[index + 1]);
        let within = if end > start {
            ((u - start) / (end - start)).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        let n = self.len() as f64;
        let mut x = ((index as f64 + within) / n).min(ONE_MINUS_EPSILON);
        // Rounding may carry x over a bin's edge; step it back by ulps (a step or two at most).
        while self.bin_at(x) > index {
            x = next_down(x);
        }
        while self.bin_at(x) < index {
            x = next_up(x);
        }
        (x, self.probabilities[index] * n, index)
    }

    /// The density at `x` of the points [`sample_continuous`](Self::sample_continuous) draws:
    /// the bin's probability times the number of bins (0 outside `[0, 1)`).
    pub fn pdf(&self, x: f64) -> f64 {
        if !(0.0..1.0).contains(&x) {
            return 0.0;
        }
        self.probabilities[self.bin_at(x)] * self.len() as f64
    }
}

/// The next `f64` below a positive `x`.
fn next_down(x: f64) -> f64 {
    if x > 0.0 {
        f64::from_bits(x.to_bits() - 1)
    } else {
        x
    }
}

/// The next `f64` above a non-negative finite `x`.
fn next_up(x: f64) -> f64 {
    if x >= 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        0.0
    }
}

/// A piecewise-constant density over the unit square, from a `width × height` table: a row is
/// drawn from the marginal distribution of the rows' integrals, then a column from that row's
/// own distribution. This is how an environment map's bright texels are found in two binary
/// searches rather than one search over every texel.
///
/// Points are `[u, v]` with `u` across the columns and `v` down the rows, each in `[0, 1)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution2D {
    /// One distribution across each row's columns.
    conditional: Vec<Distribution1D>,
    /// The distribution of the rows, weighted by each row's integral.
    marginal: Distribution1D,
}

impl Distribution2D {
    /// A distribution over a `width × height` table of weights stored row by row
    /// (`weights[row * width + column]`), with the same rules for weights as
    /// [`Distribution1D::new`].
    pub fn new(width: usize, height: usize, weights: &[f64]) -> Result<Self, DistributionError> {
        let expected = width.checked_mul(height);
        if expected != Some(weights.len()) {
            return Err(DistributionError::WrongSize {
                width,
                height,
                expected: expected.unwrap_or(0),
                got: weights.len(),
            });
        }
        if width == 0 || height == 0 {
            return Err(DistributionError::Empty);
        }
        let conditional = weights
            .chunks_exact(width)
            .enumerate()
            .map(|(row, w)| {
                Distribution1D::new(w).map_err(|e| match e {
                    DistributionError::InvalidWeight { index, value } => {
                        DistributionError::InvalidWeight {
                            index: row * width + index,
                            value,
                        }
                    }
                    other => other,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let rows: Vec<f64> = conditional.iter().map(Distribution1D::integral).collect();
        let marginal = Distribution1D::new(&rows)?;
        Ok(Self {
            conditional,
            marginal,
        })
    }

    /// The integral of the table's step function over the unit square (the mean weight).
    pub fn integral(&self) -> f64 {
        self.marginal.integral()
    }

    /// A point `[u, v]` of the unit square drawn with density [`pdf`](Self::pdf) from two
    /// uniform random numbers in `[0, 1)` (the first chooses the column, the second the row),
    /// and its density, equal to `pdf` of the point.
    pub fn sample(&self, u: [f64; 2]) -> ([f64; 2], f64) {
        let (v, pdf_row, row) = self.marginal.sample_continuous(u[1]);
        let (x, pdf_column, _) = self.conditional[row].sample_continuous(u[0]);
        ([x, v], pdf_row * pdf_column)
    }

    /// The density at `[u, v]` of the points [`sample`](Self::sample) draws (0 outside the
    /// unit square).
    pub fn pdf(&self, point: [f64; 2]) -> f64 {
        let [x, v] = point;
        if !(0.0..1.0).contains(&x) || !(0.0..1.0).contains(&v) {
            return 0.0;
        }
        let row = self.marginal.bin_at(v);
        self.marginal.pdf(v) * self.conditional[row].pdf(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::stats::chi_square_p_value;

    #[test]
    fn refuses_empty_and_invalid_weights() {
        assert_eq!(Distribution1D::new(&[]), Err(DistributionError::Empty));
        for bad in [f64::NAN, f64::INFINITY, -1.0] {
            let e = Distribution1D::new(&[1.0, bad]).unwrap_err();
            assert!(matches!(
                e,
                DistributionError::InvalidWeight { index: 1, .. }
            ));
        }
        let e = Distribution2D::new(2, 2, &[1.0, 1.0, 1.0, -2.0]).unwrap_err();
        assert!(matches!(
            e,
            DistributionError::InvalidWeight { index: 3, .. }
        ));
        assert!(matches!(
            Distribution2D::new(2, 3, &[1.0; 5]),
            Err(DistributionError::WrongSize { .. })
        ));
        assert!(Distribution2D::new(0, 0, &[]).is_err());
    }

    #[test]
    fn probabilities_integral_and_pdf_follow_the_weights() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]).unwrap();
        assert_eq!(d.len(), 3);
        assert!(!d.is_empty());
        assert!((d.integral() - 4.0 / 3.0).abs() < 1e-15);
        assert_eq!(d.probability(0), 0.25);
        assert_eq!(d.probability(1), 0.0);
        assert_eq!(d.probability(2), 0.75);
        assert_eq!(d.probability(3), 0.0);
        assert!((d.pdf(0.1) - 0.75).abs() < 1e-15);
        assert_eq!(d.pdf(0.5), 0.0);
        assert!((d.pdf(0.9) - 2.25).abs() < 1e-15);
        assert_eq!(d.pdf(-0.1), 0.0);
        assert_eq!(d.pdf(1.0), 0.0);
    }

    #[test]
    fn pdf_integrates_to_one() {
        let weights = [0.5, 2.0, 0.0, 7.0, 1.0, 0.25, 3.0];
        let d = Distribution1D::new(&weights).unwrap();
        let n = 7000;
        let sum: f64 = (0..n).map(|k| d.pdf((k as f64 + 0.5) / n as f64)).sum();
        assert!((sum / n as f64 - 1.0).abs() < 1e-12);

        let d2 = Distribution2D::new(3, 2, &[1.0, 0.0, 2.0, 5.0, 0.5, 0.5]).unwrap();
        let m = 300;
        let mut sum = 0.0;
        for i in 0..m {
            for j in 0..m {
                sum += d2.pdf([(i as f64 + 0.5) / m as f64, (j as f64 + 0.5) / m as f64]);
            }
        }
        assert!((sum / (m * m) as f64 - 1.0).abs() < 1e-9);
        assert!((d2.integral() - 9.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn discrete_samples_follow_the_probabilities() {
        let weights = [1.0, 0.0, 4.0, 2.5, 0.1, 8.0, 3.0, 0.0];
        let d = Distribution1D::new(&weights).unwrap();
        let mut rng = SplitMix64::new(7);
        let n = 200_000;
        let mut counts = vec![0u64; weights.len()];
        for _ in 0..n {
            let (i, p) = d.sample_discrete(rng.next_offset());
            assert_eq!(p, d.probability(i));
            assert!(p > 0.0, "bin {i} has zero probability but was chosen");
            counts[i] += 1;
        }
        let expected: Vec<f64> = (0..weights.len()).map(|i| d.probability(i)).collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}, counts {counts:?}");
    }

    #[test]
    fn continuous_samples_follow_the_pdf_and_report_it() {
        let weights = [3.0, 1.0, 0.0, 0.5, 6.0];
        let d = Distribution1D::new(&weights).unwrap();
        let mut rng = SplitMix64::new(11);
        // 20 bins of [0, 1): four per weight.
        let mut counts = vec![0u64; 20];
        let n = 100_000;
        for _ in 0..n {
            let (x, pdf, index) = d.sample_continuous(rng.next_offset());
            assert!((0.0..1.0).contains(&x));
            assert_eq!(pdf, d.pdf(x), "at {x}");
            assert_eq!(index, (x * 5.0) as usize);
            counts[(x * 20.0) as usize] += 1;
        }
        let expected: Vec<f64> = (0..20).map(|k| d.probability(k / 4) / 4.0).collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}, counts {counts:?}");
    }

    #[test]
    fn samples_2d_follow_the_pdf_and_report_it() {
        let (w, h) = (4, 3);
        let weights = [
            1.0, 2.0, 0.0, 0.5, //
            0.0, 0.0, 0.0, 0.0, //
            3.0, 0.2, 1.0, 6.0,
        ];
        let d = Distribution2D::new(w, h, &weights).unwrap();
        let total: f64 = weights.iter().sum();
        let mut rng = SplitMix64::new(3);
        let mut counts = vec![0u64; w * h];
        for _ in 0..100_000 {
            let ([x, v], pdf) = d.sample([rng.next_offset(), rng.next_offset()]);
            assert_eq!(pdf, d.pdf([x, v]));
            assert!(pdf > 0.0);
            let cell = (v * h as f64) as usize * w + (x * w as f64) as usize;
            assert!(weights[cell] > 0.0, "sampled the empty cell {cell}");
            counts[cell] += 1;
        }
        let expected: Vec<f64> = weights.iter().map(|&x| x / total).collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}, counts {counts:?}");
    }

    #[test]
    fn edge_random_numbers_stay_in_range() {
        let tables: [&[f64]; 4] = [&[1.0], &[0.0, 0.0, 5.0, 0.0], &[2.0, 0.0, 0.0], &[1.0; 3]];
        let just_below_one = 1.0 - f64::EPSILON / 2.0;
        for weights in tables {
            let d = Distribution1D::new(weights).unwrap();
            for u in [0.0, just_below_one, 1.0, 1.5, -0.5, f64::NAN, 1e-300] {
                let (i, p) = d.sample_discrete(u);
                assert!(i < d.len() && p > 0.0, "{weights:?} at {u}: {i}, {p}");
                let (x, pdf, index) = d.sample_continuous(u);
                assert!((0.0..1.0).contains(&x), "{weights:?} at {u}: {x}");
                assert!(pdf > 0.0 && index < d.len());
                assert_eq!(pdf, d.pdf(x));
            }
        }
        // Bins of many sizes: no u just below a cdf step leaves its bin.
        let d = Distribution1D::new(&[1.0, 1e-12, 3.0, 1e-300, 0.0, 2.0]).unwrap();
        let mut rng = SplitMix64::new(5);
        for _ in 0..10_000 {
            let (x, pdf, index) = d.sample_continuous(rng.next_offset());
            assert_eq!(pdf, d.pdf(x));
            assert_eq!(d.bin_at(x), index);
        }
    }

    #[test]
    fn one_bin_is_uniform() {
        let d = Distribution1D::new(&[2.5]).unwrap();
        assert_eq!(d.integral(), 2.5);
        assert_eq!(d.sample_discrete(0.7), (0, 1.0));
        let (x, pdf, index) = d.sample_continuous(0.3);
        assert!((x - 0.3).abs() < 1e-15);
        assert_eq!((pdf, index), (1.0, 0));
    }

    #[test]
    fn all_zero_weights_sample_uniformly() {
        let d = Distribution1D::new(&[0.0; 4]).unwrap();
        assert_eq!(d.integral(), 0.0);
        assert_eq!(d.probability(2), 0.25);
        assert_eq!(d.pdf(0.6), 1.0);
        assert_eq!(d.sample_discrete(0.6), (2, 0.25));
        let d2 = Distribution2D::new(2, 2, &[0.0; 4]).unwrap();
        assert_eq!(d2.integral(), 0.0);
        let (p, pdf) = d2.sample([0.3, 0.8]);
        assert!((p[0] - 0.3).abs() < 1e-15 && (p[1] - 0.8).abs() < 1e-15);
        assert_eq!(pdf, 1.0);
    }

    #[test]
    fn huge_weights_do_not_overflow() {
        let d = Distribution1D::new(&[f64::MAX, f64::MAX, 0.0]).unwrap();
        assert_eq!(d.probability(0), 0.5);
        assert_eq!(d.sample_discrete(0.75).0, 1);
    }
}
