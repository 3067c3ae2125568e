//! The image size: the scene camera's, or what `--width`/`--height` ask for, within the
//! pixel limit. Messages name the flag that made the image too large.

use crate::failure::Failure;

/// Default pixel limit: 2²⁸ pixels (16384 × 16384), about 6 GiB of linear colour in memory.
pub const DEFAULT_MAX_PIXELS: u64 = 1 << 28;

/// The longest side accepted whatever `--max-pixels` says: PNG stores sides as 31-bit numbers.
pub const MAX_SIDE: usize = (1 << 31) - 1;

/// The highest `--max-pixels` accepted: more pixels than a canvas of linear colours can
/// address in memory (which would fail as an allocation, not as a message).
pub const MAX_PIXEL_LIMIT: u64 = isize::MAX as u64 / std::mem::size_of::<rayforge::Color>() as u64;

/// The size asked for on the command line, checked on its own before the scene is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SizeRequest {
    /// `--width`, if given.
    pub width: Option<usize>,
    /// `--height`, if given.
    pub height: Option<usize>,
    /// `--max-pixels`.
    pub max_pixels: u64,
}

impl SizeRequest {
    /// Checks the flags: each side at least 1 and at most [`MAX_SIDE`], the limit within
    /// [`MAX_PIXEL_LIMIT`], and both sides together (when both are given) within the limit.
    pub fn new(width: Option<u64>, height: Option<u64>, max_pixels: u64) -> Result<Self, Failure> {
        if !(1..=MAX_PIXEL_LIMIT).contains(&max_pixels) {
            return Err(Failure::usage(format!(
                "--max-pixels must be between 1 and {MAX_PIXEL_LIMIT}, found {max_pixels}"
            )));
        }
        let side = |flag: &str, v: Option<u64>| match v {
            None => Ok(None),
            Some(v) if v == 0 || v > MAX_SIDE as u64 => Err(Failure::usage(format!(
                "{flag} must be between 1 and {MAX_SIDE} pixels, found {v}"
            ))),
            Some(v) => Ok(Some(v as usize)),
        };
        let request = Self {
            width: side("--width", width)?,
            height: side("--height", height)?,
            max_pixels,
        };
        if let (Some(w), Some(h)) = (request.width, request.height) {
            request.check_pixels(w, h)?;
        }
        Ok(request)
    }

    /// The image size for a camera of `camera_width` × `camera_height`: the flags, the other
    /// side following the camera's aspect ratio when only one is given, or the camera's own.
    pub fn resolve(
        &self,
        camera_width: usize,
        camera_height: usize,
    ) -> Result<(usize, usize), Failure> {
        let follow = |given: usize, along: usize, across: usize| {
            // Rounded to the nearest pixel, at least 1; `as` saturates a huge result.
            (given as f64 * across as f64 / along as f64)
                .round()
                .max(1.0) as usize
        };
        let (w, h) = match (self.width, self.height) {
            (None, None) => (camera_width, camera_height),
            (Some(w), Some(h)) => (w, h),
            (Some(w), None) => (w, follow(w, camera_width, camera_height)),
            (None, Some(h)) => (follow(h, camera_height, camera_width), h),
        };
        if w > MAX_SIDE || h > MAX_SIDE {
            return Err(Failure::usage(format!(
                "{} asks for a {w}×{h} image; each side must be at most {MAX_SIDE} pixels",
                self.cause()
            )));
        }
        self.check_pixels(w, h)?;
        Ok((w, h))
    }

    /// Refuses a `w` × `h` image over the pixel limit, naming what asked for it.
    fn check_pixels(&self, w: usize, h: usize) -> Result<(), Failure> {
        let pixels = (w as u64).saturating_mul(h as u64);
        if pixels <= self.max_pixels {
            return Ok(());
        }
        let remedy = match (self.width, self.height) {
            (Some(_), Some(_)) => "raise the limit with --max-pixels if you mean it",
            (Some(_), None) => "use a smaller --width, or raise the limit with --max-pixels",
            (None, Some(_)) => "use a smaller --height, or raise the limit with --max-pixels",
            (None, None) => {
                "render it smaller with --width or --height, or raise the limit with --max-pixels"
            }
        };
        Err(Failure::usage(format!(
            "{} asks for a {w}×{h} image, {pixels} pixels, more than the limit of {}; {remedy}",
            self.cause(),
            self.max_pixels
        )))
    }

    /// What chose the size, for messages.
    fn cause(&self) -> String {
        match (self.width, self.height) {
            (Some(w), Some(h)) => format!("--width {w} --height {h}"),
            (Some(w), None) => format!("--width {w} (the camera's aspect ratio sets the height)"),
            (None, Some(h)) => format!("--height {h} (the camera's aspect ratio sets the width)"),
            (None, None) => "the scene's camera".to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(failure: Failure) -> String {
        match failure {
            Failure::Input(m) => m,
            other => panic!("expected an input failure, got {other:?}"),
        }
    }

    #[test]
    fn no_flags_keep_the_cameras_size() {
        let r = SizeRequest::new(None, None, DEFAULT_MAX_PIXELS)
            .ok()
            .unwrap();
        assert_eq!(r.resolve(400, 200).ok(), Some((400, 200)));
    }

    #[test]
    fn one_side_keeps_the_aspect_ratio_rounded_and_at_least_one() {
        let width = SizeRequest::new(Some(64), None, DEFAULT_MAX_PIXELS)
            .ok()
            .unwrap();
        assert_eq!(width.resolve(400, 200).ok(), Some((64, 32)));
        assert_eq!(width.resolve(300, 200).ok(), Some((64, 43)));
        assert_eq!(width.resolve(10_000, 1).ok(), Some((64, 1)));
        let height = SizeRequest::new(None, Some(50), DEFAULT_MAX_PIXELS)
            .ok()
            .unwrap();
        assert_eq!(height.resolve(400, 200).ok(), Some((100, 50)));
    }

    #[test]
    fn zero_and_huge_sides_are_refused_naming_the_flag() {
        let m = message(SizeRequest::new(Some(0), None, DEFAULT_MAX_PIXELS).unwrap_err());
        assert!(m.contains("--width"), "{m}");
        let m = message(SizeRequest::new(None, Some(u64::MAX), u64::MAX).unwrap_err());
        assert!(m.contains("--max-pixels"), "{m}");
        let m = message(SizeRequest::new(None, Some(1 << 40), MAX_PIXEL_LIMIT).unwrap_err());
        assert!(m.contains("--height"), "{m}");
    }

    #[test]
    fn the_pixel_limit_names_the_flags_that_broke_it() {
        let m =
            message(SizeRequest::new(Some(20_000), Some(20_000), DEFAULT_MAX_PIXELS).unwrap_err());
        assert!(m.contains("--width 20000 --height 20000"), "{m}");
        assert!(m.contains("--max-pixels"), "{m}");
        let r = SizeRequest::new(Some(100_000), None, DEFAULT_MAX_PIXELS)
            .ok()
            .unwrap();
        let m = message(r.resolve(2, 1).unwrap_err());
        assert!(
            m.contains("--width 100000") && m.contains("100000×50000"),
            "{m}"
        );
        let r = SizeRequest::new(None, None, 100).ok().unwrap();
        let m = message(r.resolve(11, 10).unwrap_err());
        assert!(m.contains("the scene's camera"), "{m}");
    }

    #[test]
    fn a_derived_side_past_the_format_limit_is_refused() {
        let r = SizeRequest::new(Some(1 << 30), None, MAX_PIXEL_LIMIT)
            .ok()
            .unwrap();
        let m = message(r.resolve(1, 4).unwrap_err());
        assert!(m.contains("at most"), "{m}");
    }
}
