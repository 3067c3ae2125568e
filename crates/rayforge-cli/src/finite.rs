//! Finite output: no image rayforge writes holds a NaN or an infinity.
//!
//! Extreme but accepted scenes (a light of intensity 1e308 on a colour of 1e308, a refractive
//! index of 1e308) can overflow a pixel's arithmetic. The 8-bit encoders would turn NaN into 0
//! and an infinity into 255, and the float formats would store them as they are, which breaks
//! every program that averages or compares the image. So each developed image passes through
//! [`blacken_non_finite`] before it is encoded: a pixel with a channel that is not a finite
//! number is written black in every format, and the count is reported to the user, who then
//! knows the scene overflowed instead of seeing a plausible image.

use rayforge::{Canvas, Color};

/// Sets every pixel of `canvas` with a NaN or infinite channel to black, and returns how many
/// there were.
pub fn blacken_non_finite(canvas: &mut Canvas) -> usize {
    let mut count = 0;
    for pixel in canvas.pixels_mut() {
        if !pixel.to_array().iter().all(|v| v.is_finite()) {
            *pixel = Color::BLACK;
            count += 1;
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_pixels_with_a_non_finite_channel_turn_black() {
        let mut canvas = Canvas::new(4, 1);
        canvas.write_pixel(0, 0, Color::new(f64::NAN, 0.5, 0.5));
        canvas.write_pixel(1, 0, Color::new(0.5, f64::INFINITY, 0.5));
        canvas.write_pixel(2, 0, Color::new(0.5, 0.5, f64::NEG_INFINITY));
        canvas.write_pixel(3, 0, Color::new(1e308, -1e308, 0.25));
        assert_eq!(blacken_non_finite(&mut canvas), 3);
        for x in 0..3 {
            assert_eq!(canvas.pixel_at(x, 0), Color::BLACK);
        }
        assert_eq!(canvas.pixel_at(3, 0), Color::new(1e308, -1e308, 0.25));
        assert_eq!(blacken_non_finite(&mut canvas), 0);
    }
}
