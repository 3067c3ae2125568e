//! Memory for the image, asked for before the render: a refusal is a clear error, not an abort.
//!
//! The renderers allocate their films infallibly (an allocation failure aborts the process
//! with no useful message, exit 134), and a render's largest allocations are all sized by the
//! image: its films, the developed image and the encoded file (a slice's by its rows: its film
//! holds only them, and it develops nothing). So before any of them, and before the checkpoint
//! is written, the command reserves as much memory as the render will hold at its peak with
//! [`Vec::try_reserve_exact`], and gives it back at once: when the system (an address-space
//! limit, `ulimit -v`, or the kernel's overcommit heuristic) refuses that, the render is
//! refused, saying how much it needed. The reservation is not touched, so it costs no time and
//! no real memory.

use crate::failure::Failure;

/// A film: each pixel's sum of weighted colours (three f64) and sum of weights (an f64).
const FILM_BYTES_PER_PIXEL: u64 = 32;
/// The developed image (three f64 a pixel) and the encoded file, at most as large again (a
/// PPM's text, a PFM's or OpenEXR's floats, a PNG's bytes and their compression).
const OUTPUT_BYTES_PER_PIXEL: u64 = 2 * 24;

/// The bytes a `width` × `height` render holding `films` films holds at its peak, as
/// [`reserve_for_render`] counts them; `None` past what a `u64` counts.
pub fn render_bytes(width: usize, height: usize, films: u64) -> Option<u64> {
    let per_pixel = films * FILM_BYTES_PER_PIXEL + OUTPUT_BYTES_PER_PIXEL;
    (width as u64)
        .checked_mul(height as u64)?
        .checked_mul(per_pixel)
}

/// Checks that a `width` × `height` render holding `films` films at once (the render's own,
/// a resumed checkpoint's, the path tracer's AOVs) can have its memory, by reserving it.
pub fn reserve_for_render(width: usize, height: usize, films: u64) -> Result<(), Failure> {
    let per_pixel = films * FILM_BYTES_PER_PIXEL + OUTPUT_BYTES_PER_PIXEL;
    let what = || format!("a {width}×{height} render");
    reserve(&[(width, height, per_pixel)], what, SMALLER)
}

/// Checks that a slice of `rows` rows of a `width` × `height` image, of `films` films (the
/// image's and its AOVs'), can have its memory, by reserving it. A slice holds films of its
/// rows only (see `crate::slice_render`), and the films made of them for its part file as
/// blocks, for a moment both: twice its films of its rows. It develops no image and writes
/// its part as it goes.
pub fn reserve_for_slice(
    width: usize,
    height: usize,
    rows: usize,
    films: u64,
) -> Result<(), Failure> {
    let what = || format!("a slice of {rows} rows of a {width}×{height} render");
    let remedy = "more slices cut by rows, or a smaller --width or --height, need less";
    reserve(
        &[(width, rows, 2 * films * FILM_BYTES_PER_PIXEL)],
        what,
        remedy,
    )
}

/// Checks that merging the parts of a `width` × `height` image of `films` films each (the
/// image's and its AOVs'), the largest part of `part_rows` rows, can have its memory, by
/// reserving it: the image's films, one part's films at a time, and the developed images
/// (the image, or with AOVs also the denoised image and each AOV) with their encoded files.
pub fn reserve_for_merge(
    width: usize,
    height: usize,
    part_rows: usize,
    films: u64,
) -> Result<(), Failure> {
    let image = films * (FILM_BYTES_PER_PIXEL + OUTPUT_BYTES_PER_PIXEL) + OUTPUT_BYTES_PER_PIXEL;
    let part = (width, part_rows, films * FILM_BYTES_PER_PIXEL);
    let what = || format!("merging a {width}×{height} render");
    reserve(&[(width, height, image), part], what, SMALLER)
}

/// The remedy for most refusals.
const SMALLER: &str = "a smaller --width or --height needs less";

/// Reserves the sum of `blocks` (each `width` × `height` pixels of so many bytes) and gives
/// it back at once; the refusal says how much `what` needs, and `remedy`.
fn reserve(
    blocks: &[(usize, usize, u64)],
    what: impl Fn() -> String,
    remedy: &str,
) -> Result<(), Failure> {
    let bytes = blocks
        .iter()
        .try_fold(0u64, |sum, &(width, height, per_pixel)| {
            (width as u64)
                .checked_mul(height as u64)?
                .checked_mul(per_pixel)?
                .checked_add(sum)
        });
    let refused = || {
        let bytes: f64 = blocks
            .iter()
            .map(|&(width, height, per_pixel)| width as f64 * height as f64 * per_pixel as f64)
            .sum();
        let gib = bytes / f64::from(1u32 << 30);
        Failure::usage(format!(
            "not enough memory for {}: it needs about {gib:.1} GiB at its peak, and the system \
             refused that much; {remedy}",
            what()
        ))
    };
    let bytes = bytes
        .and_then(|bytes| usize::try_from(bytes).ok())
        .ok_or_else(refused)?;
    Vec::<u8>::new()
        .try_reserve_exact(bytes)
        .map_err(|_| refused())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_render_gets_its_memory() {
        assert!(reserve_for_render(640, 480, 3).is_ok());
    }

    #[test]
    fn slices_and_merges_are_refused_naming_what_they_hold() {
        let Err(Failure::Input(message)) = reserve_for_slice(1 << 40, 1 << 40, 1 << 30, 1) else {
            panic!("an absurd slice was granted");
        };
        assert!(
            message.contains("a slice of 1073741824 rows of a 1099511627776×1099511627776"),
            "{message}"
        );
        let Err(Failure::Input(message)) = reserve_for_merge(1 << 31, 1 << 31, 1, 1) else {
            panic!("an absurd merge was granted");
        };
        assert!(
            message.contains("merging a 2147483648×2147483648"),
            "{message}"
        );
        assert!(reserve_for_slice(640, 480, 60, 5).is_ok());
        assert!(reserve_for_merge(640, 480, 60, 5).is_ok());
    }

    #[test]
    fn more_than_memory_can_address_is_refused_with_its_size() {
        let Err(Failure::Input(message)) = reserve_for_render(1 << 31, 1 << 31, 1) else {
            panic!("an exabyte was granted");
        };
        assert!(message.contains("2147483648×2147483648"), "{message}");
        assert!(message.contains("GiB"), "{message}");
    }
}
