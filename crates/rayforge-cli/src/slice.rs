//! Slices: one render cut into N pieces that separate processes (on separate machines) render
//! alone and `rayforge merge` joins into the image of the whole render.
//!
//! Two cuts:
//!
//! - **Rows** ([`Cut::Rows`]), for every renderer: slice I of N takes rows I, I + N, I + 2N, …
//!   Each pixel is a pure function of the scene, its position and its sample numbers, so a row
//!   is the same whichever process renders it, and the merged image is byte for byte the
//!   image of one process. Rows are dealt out in turn rather than in N bands because a row's
//!   cost follows what it sees (sky is cheap, glass is dear) and changes slowly down the
//!   image: with interleaving, the costs of any two slices differ by at most the total
//!   variation of the cost down the image plus one row's cost, whatever N and whatever the
//!   scene, where equal bands can put all the expensive rows in one slice (a floor in the lower
//!   half). It needs no pre-pass, which every slice would have to repeat to agree on the cut.
//! - **Samples** ([`Cut::Samples`]), for the path tracer: slice I takes the I-th of N
//!   contiguous ranges of each pixel's sample sequence (`spp · I / N .. spp · (I+1) / N`),
//!   all pixels. Every sample costs the same in expectation, so the slices are balanced; the
//!   merge adds their sums in slice order (see `docs/distributed.md` for what that keeps).
//!
//! Which slice a process renders is `--slice I/N`, or `--slice auto/N` for a scheduler's job
//! array, whose index is in [`INDEX_VARIABLES`].

use crate::args::SliceBy;
use crate::failure::Failure;
use std::ops::Range;

/// The most slices a render may be cut into: far more than any cluster's nodes, and small
/// enough that a merge's bookkeeping of which slices it has is never a burden.
pub const MAX_SLICES: u64 = 1 << 20;

/// Where schedulers put a task's index in its job array, in the order they are read: Slurm's
/// job arrays and Kubernetes' Indexed Jobs, both counting from 0 when asked to.
pub const INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// How a render is cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// Interleaved rows: slice I has rows I, I + N, …
    Rows,
    /// Ranges of each pixel's sample sequence.
    Samples,
}

impl Cut {
    /// The cut `--slice-by` asks for (rows by default).
    pub fn from_arg(arg: Option<SliceBy>) -> Self {
        match arg {
            None | Some(SliceBy::Rows) => Cut::Rows,
            Some(SliceBy::Samples) => Cut::Samples,
        }
    }

    /// Its name, as `--slice-by` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Cut::Rows => "rows",
            Cut::Samples => "samples",
        }
    }
}

/// `--slice` as given: the index (or `auto`) and the count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SliceRequest {
    /// The index, or `None` for `auto` (the scheduler's).
    index: Option<u64>,
    /// How many slices.
    count: u64,
}

/// One slice of a render: the `index`-th of `count`, cut by `cut`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slice {
    /// Which slice, from 0.
    pub index: u64,
    /// How many slices the render is cut into.
    pub count: u64,
    /// How.
    pub cut: Cut,
}

impl SliceRequest {
    /// Parses `I/N` or `auto/N` (N from 1 to [`MAX_SLICES`], I below N).
    pub fn parse(text: &str) -> Result<Self, Failure> {
        let bad = |why: &str| {
            Failure::usage(format!(
                "--slice takes I/N (slice I, from 0, of N) or auto/N, found `{text}`: {why}"
            ))
        };
        let (index, count) = text.split_once('/').ok_or_else(|| bad("there is no `/`"))?;
        let count: u64 = count
            .trim()
            .parse()
            .map_err(|_| bad("N is not a whole number"))?;
        if count == 0 || count > MAX_SLICES {
            return Err(bad(&format!("N must be from 1 to {MAX_SLICES}")));
        }
        let index = match index.trim() {
            "auto" => None,
            i => {
                let i: u64 = i
                    .parse()
                    .map_err(|_| bad("I is not a whole number nor `auto`"))?;
                if i >= count {
                    return Err(bad(&format!(
                        "slices are counted from 0, so I must be below N ({count})"
                    )));
                }
                Some(i)
            }
        };
        Ok(Self { index, count })
    }

    /// The slice, cut by `cut`, its index taken from `variable` (the environment, or a test's
    /// stand-in) for `auto`: the first of [`INDEX_VARIABLES`] that is set.
    pub fn resolve(
        self,
        cut: Cut,
        variable: impl Fn(&str) -> Option<String>,
    ) -> Result<Slice, Failure> {
        let count = self.count;
        let index = match self.index {
            Some(index) => index,
            None => {
                let (name, value) = INDEX_VARIABLES
                    .iter()
                    .find_map(|&name| variable(name).map(|value| (name, value)))
                    .ok_or_else(|| {
                        Failure::usage(format!(
                            "--slice auto/{count} takes the slice's index from {} (Slurm job \
                             arrays) or {} (Kubernetes Indexed Jobs), and neither is set; give \
                             the index instead (--slice I/{count})",
                            INDEX_VARIABLES[0], INDEX_VARIABLES[1]
                        ))
                    })?;
                let index: u64 = value.trim().parse().map_err(|_| {
                    Failure::usage(format!(
                        "--slice auto/{count}: {name} is `{value}`, not a whole number"
                    ))
                })?;
                if index >= count {
                    return Err(Failure::usage(format!(
                        "--slice auto/{count}: {name} is {index}, past the last slice, {}; \
                         slices are counted from 0 (Slurm: --array=0-{})",
                        count - 1,
                        count - 1
                    )));
                }
                index
            }
        };
        Ok(Slice { index, count, cut })
    }
}

impl Slice {
    /// Whether row `y` of the image is rendered by this slice.
    pub fn has_row(&self, y: usize) -> bool {
        match self.cut {
            Cut::Rows => y as u64 % self.count == self.index,
            Cut::Samples => true,
        }
    }

    /// The rows of a `height`-row image this slice renders, top to bottom.
    pub fn rows(&self, height: usize) -> impl Iterator<Item = usize> + '_ {
        (0..height).filter(|&y| self.has_row(y))
    }

    /// How many rows of a `height`-row image this slice renders.
    pub fn row_count(&self, height: usize) -> usize {
        match self.cut {
            Cut::Rows => {
                let (height, index, count) = (height as u64, self.index, self.count);
                // Rows index, index + count, … below height.
                (height.saturating_sub(index)).div_ceil(count) as usize
            }
            Cut::Samples => height,
        }
    }

    /// The range of each pixel's sample indices this slice takes of `spp`: all of them when
    /// cut by rows, else the `index`-th of `count` near-equal contiguous ranges.
    pub fn samples(&self, spp: u64) -> Range<u64> {
        match self.cut {
            Cut::Rows => 0..spp,
            Cut::Samples => {
                // In u128: spp · count may not fit in 64 bits.
                let at = |i: u64| (u128::from(spp) * u128::from(i) / u128::from(self.count)) as u64;
                at(self.index)..at(self.index + 1)
            }
        }
    }
}

impl std::fmt::Display for Slice {
    /// `I/N`, as `--slice` takes it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn none(_: &str) -> Option<String> {
        None
    }

    fn message(failure: Failure) -> String {
        match failure {
            Failure::Input(m) => m,
            other => panic!("not a usage error: {other:?}"),
        }
    }

    #[test]
    fn indices_and_counts_are_checked() {
        let s = SliceRequest::parse("2/7").unwrap().resolve(Cut::Rows, none);
        assert_eq!(
            s.unwrap(),
            Slice {
                index: 2,
                count: 7,
                cut: Cut::Rows
            }
        );
        for bad in ["7/7", "0/0", "1", "a/3", "-1/3", "1/x", "0/2000000"] {
            assert!(SliceRequest::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn rows_are_dealt_out_in_turn_and_cover_the_image_once() {
        for height in [0, 1, 5, 12, 13] {
            for count in [1, 2, 3, 7, 20] {
                let mut seen = vec![0; height];
                for index in 0..count {
                    let s = Slice {
                        index,
                        count,
                        cut: Cut::Rows,
                    };
                    let rows: Vec<usize> = s.rows(height).collect();
                    assert_eq!(rows.len(), s.row_count(height), "{height} {count} {index}");
                    rows.iter().for_each(|&y| seen[y] += 1);
                }
                assert!(seen.iter().all(|&n| n == 1), "{height} {count}");
            }
        }
    }

    #[test]
    fn sample_ranges_tile_the_sequence() {
        for spp in [1, 7, 64, u64::MAX] {
            for count in [1, 2, 3, 7] {
                let ranges: Vec<Range<u64>> = (0..count)
                    .map(|index| {
                        Slice {
                            index,
                            count,
                            cut: Cut::Samples,
                        }
                        .samples(spp)
                    })
                    .collect();
                assert_eq!(ranges[0].start, 0);
                assert_eq!(ranges[ranges.len() - 1].end, spp);
                for pair in ranges.windows(2) {
                    assert_eq!(pair[0].end, pair[1].start);
                }
            }
        }
    }

    #[test]
    fn auto_reads_slurm_then_kubernetes() {
        let auto = SliceRequest::parse("auto/4").unwrap();
        let slurm = |n: &str| (n == "SLURM_ARRAY_TASK_ID").then(|| "3".to_string());
        assert_eq!(auto.resolve(Cut::Rows, slurm).unwrap().index, 3);
        let k8s = |n: &str| (n == "JOB_COMPLETION_INDEX").then(|| "1".to_string());
        assert_eq!(auto.resolve(Cut::Rows, k8s).unwrap().index, 1);
        let both = |n: &str| Some(if n == "SLURM_ARRAY_TASK_ID" { "0" } else { "2" }.into());
        assert_eq!(auto.resolve(Cut::Rows, both).unwrap().index, 0);
    }

    #[test]
    fn auto_without_an_index_or_out_of_range_is_refused() {
        let auto = SliceRequest::parse("auto/4").unwrap();
        let m = message(auto.resolve(Cut::Rows, none).unwrap_err());
        assert!(
            m.contains("SLURM_ARRAY_TASK_ID") && m.contains("JOB_COMPLETION_INDEX"),
            "{m}"
        );
        let four = |_: &str| Some("4".to_string());
        let m = message(auto.resolve(Cut::Rows, four).unwrap_err());
        assert!(m.contains("past the last slice, 3"), "{m}");
        let word = |_: &str| Some("x".to_string());
        let m = message(auto.resolve(Cut::Rows, word).unwrap_err());
        assert!(m.contains("not a whole number"), "{m}");
    }
}
