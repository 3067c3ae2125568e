//! Linear RGB colours (chapter 2).

use std::ops::{Add, AddAssign, Div, Mul, Sub};

/// A linear RGB colour. Components are unbounded while rendering; clamping happens at output.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Color {
    /// Red.
    pub red: f64,
    /// Green.
    pub green: f64,
    /// Blue.
    pub blue: f64,
}

impl Color {
    /// Black, the colour of nothing.
    pub const BLACK: Self = Self::new(0.0, 0.0, 0.0);
    /// White.
    pub const WHITE: Self = Self::new(1.0, 1.0, 1.0);

    /// The book's `color(r, g, b)`.
    #[inline]
    pub const fn new(red: f64, green: f64, blue: f64) -> Self {
        Self { red, green, blue }
    }

    /// The Hadamard (component-wise) product, the book's `c1 * c2`.
    #[inline]
    pub fn hadamard(self, o: Self) -> Self {
        Self::new(self.red * o.red, self.green * o.green, self.blue * o.blue)
    }

    /// The luminance of linear Rec. 709 RGB: how bright the colour looks, which is what
    /// importance sampling (of lights, of skies) should follow.
    #[inline]
    pub fn luminance(self) -> f64 {
        0.2126 * self.red + 0.7152 * self.green + 0.0722 * self.blue
    }

    /// The largest of the three channels.
    pub fn max_channel(self) -> f64 {
        self.red.max(self.green).max(self.blue)
    }

    /// Linear interpolation: `self` at 0, `other` at 1.
    #[inline]
    pub fn lerp(self, other: Self, fraction: f64) -> Self {
        self + (other - self) * fraction
    }

    /// The channels as an array.
    pub fn to_array(self) -> [f64; 3] {
        [self.red, self.green, self.blue]
    }
}

/// A colour from the book's function name, so scenarios read as printed.
#[inline]
pub const fn color(red: f64, green: f64, blue: f64) -> Color {
    Color::new(red, green, blue)
}

impl Add for Color {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.red + o.red, self.green + o.green, self.blue + o.blue)
    }
}

impl AddAssign for Color {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Sub for Color {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.red - o.red, self.green - o.green, self.blue - o.blue)
    }
}

impl Mul<f64> for Color {
    type Output = Self;
    #[inline]
    fn mul(self, s: f64) -> Self {
        Self::new(self.red * s, self.green * s, self.blue * s)
    }
}

impl Mul for Color {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        self.hadamard(o)
    }
}

impl Div<f64> for Color {
    type Output = Self;
    #[inline]
    fn div(self, s: f64) -> Self {
        Self::new(self.red / s, self.green / s, self.blue / s)
    }
}

impl std::iter::Sum for Color {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::BLACK, Add::add)
    }
}
