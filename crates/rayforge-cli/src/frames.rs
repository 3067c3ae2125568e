//! Animations: `--frames FIRST..LAST` and the numbered output names of its frames.

use crate::failure::Failure;
use std::path::{Path, PathBuf};

/// The most frames one command renders (a guard against `0..4000000000` typos).
pub const MAX_FRAMES: u64 = 1_000_000;

/// `FIRST..LAST` (inclusive, FIRST ≤ LAST), as `--frames` takes it.
pub fn parse_range(text: &str) -> Result<(u64, u64), Failure> {
    let bad = || {
        Failure::usage(format!(
            "--frames takes FIRST..LAST, two whole numbers with FIRST ≤ LAST, found `{text}`"
        ))
    };
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (u64, u64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a > b {
        return Err(bad());
    }
    if b - a >= MAX_FRAMES {
        return Err(Failure::usage(format!(
            "--frames {text} is more than {MAX_FRAMES} frames"
        )));
    }
    Ok((a, b))
}

/// Whether an output name has a place for the frame number: `%d`, or `%0Nd` for N digits.
pub fn has_frame_pattern(path: &Path) -> bool {
    pattern(&path.to_string_lossy()).is_some()
}

/// Where `%d` or `%0Nd` is in `name`: its byte range and its width (0 for `%d`).
fn pattern(name: &str) -> Option<(usize, usize, usize)> {
    let start = name.find('%')?;
    let rest = &name[start + 1..];
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    if rest.as_bytes().get(digits) != Some(&b'd') {
        return None;
    }
    let width = rest[..digits].parse().unwrap_or(0);
    Some((start, start + 1 + digits + 1, width.min(20)))
}

/// The output name of frame `frame`: the pattern replaced by the number, zero-padded to its
/// width (`out/frame-%04d.png` → `out/frame-0042.png`).
pub fn frame_path(path: &Path, frame: u64) -> PathBuf {
    let name = path.to_string_lossy();
    match pattern(&name) {
        Some((start, end, width)) => {
            PathBuf::from(format!("{}{frame:0width$}{}", &name[..start], &name[end..]))
        }
        None => path.to_path_buf(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_numbers_fill_the_pattern() {
        assert_eq!(
            frame_path(Path::new("out/frame-%04d.png"), 42),
            PathBuf::from("out/frame-0042.png")
        );
        assert_eq!(frame_path(Path::new("f%d.png"), 7), PathBuf::from("f7.png"));
        assert!(!has_frame_pattern(Path::new("plain.png")));
        assert!(!has_frame_pattern(Path::new("odd%x.png")));
    }

    #[test]
    fn ranges_are_inclusive_and_checked() {
        assert_eq!(parse_range("1..900").ok(), Some((1, 900)));
        assert_eq!(parse_range("5..5").ok(), Some((5, 5)));
        assert!(parse_range("9..1").is_err());
        assert!(parse_range("a..b").is_err());
        assert!(parse_range("12").is_err());
        assert!(parse_range("0..4000000000").is_err());
    }
}
