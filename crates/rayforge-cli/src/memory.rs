//! Memory for the image, asked for before the render: a refusal is a clear error, not an abort.
//!
//! The renderers allocate their films infallibly (an allocation failure aborts the process
//! with no useful message, exit 134), and a render's largest allocations are all sized by the
//! image: its films, the developed image and the encoded file. So before any of them, and
//! before the checkpoint is written, the command reserves as much memory as the render will
//! hold at its peak with [`Vec::try_reserve_exact`], and gives it back at once: when the
//! system (an address-space limit, `ulimit -v`, or the kernel's overcommit heuristic) refuses
//! that, the render is refused, saying how much it needed. The reservation is not touched, so
//! it costs no time and no real memory.

use crate::failure::Failure;

/// A film: each pixel's sum of weighted colours (three f64) and sum of weights (an f64).
const FILM_BYTES_PER_PIXEL: u64 = 32;
/// The developed image (three f64 a pixel) and the encoded file, at most as large again (a
/// PPM's text, a PFM's or OpenEXR's floats, a PNG's bytes and their compression).
const OUTPUT_BYTES_PER_PIXEL: u64 = 2 * 24;

/// Checks that a `width` × `height` render holding `films` films at once (the render's own,
/// a resumed checkpoint's, the path tracer's AOVs) can have its memory, by reserving it.
pub fn reserve_for_render(width: usize, height: usize, films: u64) -> Result<(), Failure> {
    let per_pixel = films * FILM_BYTES_PER_PIXEL + OUTPUT_BYTES_PER_PIXEL;
    let bytes = (width as u64)
        .checked_mul(height as u64)
        .and_then(|pixels| pixels.checked_mul(per_pixel))
        .and_then(|bytes| usize::try_from(bytes).ok());
    let refused = || {
        let gib = width as f64 * height as f64 * per_pixel as f64 / f64::from(1u32 << 30);
        Failure::usage(format!(
            "not enough memory for a {width}×{height} render: it needs about {gib:.1} GiB at \
             its peak, and the system refused that much; a smaller --width or --height needs less"
        ))
    };
    let bytes = bytes.ok_or_else(refused)?;
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
    fn more_than_memory_can_address_is_refused_with_its_size() {
        let Err(Failure::Input(message)) = reserve_for_render(1 << 31, 1 << 31, 1) else {
            panic!("an exabyte was granted");
        };
        assert!(message.contains("2147483648×2147483648"), "{message}");
        assert!(message.contains("GiB"), "{message}");
    }
}
