//! Sampling in proportion to a table of weights: [`Distribution1D`] (a choice among bins) and
//! [`Distribution2D`] (a cell of a grid: a marginal over rows, then one conditional per row).
//!
//! A renderer draws most samples where they matter: lights in proportion to their power, mesh
//! triangles in proportion to their area, an environment map's cells in proportion to their
//! light. Each choice comes with its probability, and the probability of any bin can be asked
//! again later (multiple importance sampling needs both), so both come from one table and
//! agree exactly. A choice also hands back its random number rescaled within the chosen bin,
//! a fresh uniform number for what is drawn next (a point inside the cell).

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

/// A discrete choice among `len()` bins in proportion to their weights: picking a light by
/// power, a triangle by area, a row of an environment map's cells by their light.
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
    /// A guide to the search (the cutpoint method): `guide[g]` is the bin holding `g / G`, for
    /// `G = len()` equal slices of `[0, 1)` and `guide[G]` the last bin. A number in slice `g`
    /// lies in a bin from `guide[g]` to `guide[g + 1]`, so a draw searches a bin or two where
    /// a binary search over a sky map's row took ten steps of unpredictable branches. Empty
    /// when there are more bins than a `u32` counts (then every draw searches the whole table).
    guide: Vec<u32>,
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
        let mut distribution = Self {
            probabilities,
            cdf,
            guide: Vec::new(),
            integral,
        };
        if let Ok(slices) = u32::try_from(n) {
            distribution.guide = (0..slices)
                .map(|g| distribution.search(f64::from(g) / f64::from(slices)) as u32)
                .chain([slices - 1])
                .collect();
        }
        Ok(distribution)
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

    /// The mean of the weights (the integral over `[0, 1)` of the step function they describe):
    /// a 2D table's rows are weighted by it.
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// The probability of choosing bin `index` (0 outside the table).
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
        // The guide's slice of u bounds the search; where rounding of `u × G` put u in the
        // slice beside its own, the bounds do not hold and the whole table is searched.
        if let Some(&[first, last]) = self
            .guide
            .get((u * self.guide.len().saturating_sub(1) as f64) as usize..)
            .and_then(|g| g.first_chunk::<2>())
        {
            let (first, last) = (first as usize, last as usize);
            if self.cdf[first] <= u && u < self.cdf[last + 1] {
                let after = self.cdf[first..=last].partition_point(|&c| c <= u);
                return first + after - 1;
            }
        }
        self.search(u)
    }

    /// The last bin whose start is at or below `u` (in `[0, 1)`), found among all the bins; its
    /// end is above u since u < 1 = `cdf[len]`.
    fn search(&self, u: f64) -> usize {
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
    #[inline]
    pub fn sample_discrete_reused(&self, u: f64) -> (usize, f64, f64) {
        let u = unit(u);
        // One bin (a scene's only light) keeps the whole interval: `u` itself.
        if self.len() == 1 {
            return (0, self.probabilities[0], u);
        }
        let index = self.bin_of(u);
        let (start, end) = (self.cdf[index], self.cdf[index + 1]);
        let rest = if end > start {
            ((u - start) / (end - start)).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        (index, self.probabilities[index], rest)
    }
}

/// A choice among the cells of a `width × height` table in proportion to their weights: a row
/// is drawn from the marginal distribution of the rows' sums, then a column from that row's
/// own distribution. This is how an environment map's bright cells are found in two binary
/// searches rather than one search over every cell.
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

    /// The mean weight of the table (the integral of its step function over the unit square).
    pub fn integral(&self) -> f64 {
        self.marginal.integral()
    }

    /// A cell drawn with its probability from two uniform random numbers in `[0, 1)` (the
    /// first chooses the column, the second the row): `(column, row)`, that probability, and
    /// the two numbers rescaled to `[0, 1)` within their choices, fresh uniform numbers for
    /// placing a point inside the cell by a density of its own (an environment map's bilinear
    /// patch) without losing the stratification of the numbers given.
    pub fn sample_cell(&self, u: [f64; 2]) -> ((usize, usize), f64, [f64; 2]) {
        let (row, p_row, v) = self.marginal.sample_discrete_reused(u[1]);
        let (column, p_column, x) = self.conditional[row].sample_discrete_reused(u[0]);
        ((column, row), p_row * p_column, [x, v])
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
    fn probabilities_and_integral_follow_the_weights() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]).unwrap();
        assert_eq!(d.len(), 3);
        assert!(!d.is_empty());
        assert!((d.integral() - 4.0 / 3.0).abs() < 1e-15);
        assert_eq!(d.probability(0), 0.25);
        assert_eq!(d.probability(1), 0.0);
        assert_eq!(d.probability(2), 0.75);
        assert_eq!(d.probability(3), 0.0);
        let d2 = Distribution2D::new(3, 2, &[1.0, 0.0, 2.0, 5.0, 0.5, 0.5]).unwrap();
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
    fn a_choice_hands_back_a_fresh_uniform_number() {
        // Within each bin chosen, the rescaled number is uniform on [0, 1): four sub-bins each.
        let weights = [3.0, 1.0, 0.0, 0.5, 6.0];
        let d = Distribution1D::new(&weights).unwrap();
        let mut rng = SplitMix64::new(11);
        let mut counts = vec![0u64; weights.len() * 4];
        for _ in 0..100_000 {
            let (index, p, rest) = d.sample_discrete_reused(rng.next_offset());
            assert_eq!(p, d.probability(index));
            assert!((0.0..1.0).contains(&rest), "{rest}");
            counts[index * 4 + (rest * 4.0) as usize] += 1;
        }
        let expected: Vec<f64> = (0..counts.len())
            .map(|k| d.probability(k / 4) / 4.0)
            .collect();
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-3, "chi-square p-value {p}, counts {counts:?}");
    }

    #[test]
    fn cells_follow_their_weights() {
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
            let ((column, row), p, [x, v]) = d.sample_cell([rng.next_offset(), rng.next_offset()]);
            let cell = row * w + column;
            assert!((p - weights[cell] / total).abs() < 1e-15);
            assert!(weights[cell] > 0.0, "sampled the empty cell {cell}");
            assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&v));
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
                let (index, p, rest) = d.sample_discrete_reused(u);
                assert!(index == i && p > 0.0, "{weights:?} at {u}");
                assert!((0.0..1.0).contains(&rest), "{weights:?} at {u}: {rest}");
            }
        }
    }

    #[test]
    fn one_bin_is_uniform() {
        let d = Distribution1D::new(&[2.5]).unwrap();
        assert_eq!(d.integral(), 2.5);
        assert_eq!(d.sample_discrete(0.7), (0, 1.0));
        let (index, p, rest) = d.sample_discrete_reused(0.3);
        assert!((rest - 0.3).abs() < 1e-15);
        assert_eq!((index, p), (0, 1.0));
    }

    #[test]
    fn all_zero_weights_sample_uniformly() {
        let d = Distribution1D::new(&[0.0; 4]).unwrap();
        assert_eq!(d.integral(), 0.0);
        assert_eq!(d.probability(2), 0.25);
        assert_eq!(d.sample_discrete(0.6), (2, 0.25));
        let d2 = Distribution2D::new(2, 2, &[0.0; 4]).unwrap();
        assert_eq!(d2.integral(), 0.0);
        let (cell, p, _) = d2.sample_cell([0.3, 0.8]);
        assert_eq!((cell, p), ((0, 1), 0.25));
    }

    mod guided {
        use super::super::*;
        use proptest::prelude::*;

        proptest! {
            /// The guide only narrows the search: every number, the slices' own ends and the
            /// numbers either side of each bin's start included, lands in the bin the whole
            /// table's search gives.
            #[test]
            fn the_guided_search_finds_the_bin_the_whole_search_finds(
                weights in prop::collection::vec(prop_oneof![Just(0.0), 0.0..10.0, 1e-12..1e-9], 1..60),
                numbers in prop::collection::vec(0.0..1.0f64, 64),
            ) {
                let d = Distribution1D::new(&weights).unwrap();
                let slices = d.len() as f64;
                let edges = d.cdf.iter().flat_map(|&c| [c, c.next_down(), c.next_up()]);
                let ends = (0..d.len()).flat_map(|g| {
                    let end = g as f64 / slices;
                    [end, end.next_down(), end.next_up()]
                });
                for u in numbers.into_iter().chain(edges).chain(ends).map(unit) {
                    prop_assert_eq!(d.bin_of(u), d.search(u), "u = {}", u);
                    prop_assert!(d.probability(d.bin_of(u)) > 0.0 || d.integral() == 0.0);
                }
            }
        }
    }

    #[test]
    fn huge_weights_do_not_overflow() {
        let d = Distribution1D::new(&[f64::MAX, f64::MAX, 0.0]).unwrap();
        assert_eq!(d.probability(0), 0.5);
        assert_eq!(d.sample_discrete(0.75).0, 1);
    }
}
