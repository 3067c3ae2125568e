//! Texture mapping (the bonus chapter "Texture mapping"): 2D patterns on (u, v), the mappings
//! that turn a 3D point into (u, v), cube maps, and image textures.

use crate::color::Color;
use crate::math::Point3;
use std::f64::consts::PI;
use std::sync::Arc;

/// A pattern over the unit square of texture coordinates.
#[derive(Debug, Clone, PartialEq)]
pub enum UvPattern {
    /// `width × height` checkers of two colours (the book's `uv_checkers`).
    Checkers {
        /// Squares across u.
        width: f64,
        /// Squares across v.
        height: f64,
        /// The colour at (0, 0).
        a: Color,
        /// The other colour.
        b: Color,
    },
    /// The book's `uv_align_check`: a main colour with a marker in each corner, to check
    /// orientation.
    AlignCheck {
        /// The colour of the middle.
        main: Color,
        /// Upper left.
        ul: Color,
        /// Upper right.
        ur: Color,
        /// Bottom left.
        bl: Color,
        /// Bottom right.
        br: Color,
    },
    /// An image, (0, 0) at its bottom-left corner.
    Image(Arc<Texture>),
    /// A game board (Fundamentals of Ray Tracing's chess board): `squares × squares` squares
    /// inside a plain border `border` wide (a fraction of the face on each side). Square (0, 0)
    /// at the low-u, low-v corner is dark, and so is every square whose indices sum to an even
    /// number.
    Board {
        /// Squares per side.
        squares: u32,
        /// Width of the border on each side, as a fraction of the face (below 0.5).
        border: f64,
        /// The light squares' colour.
        light: Color,
        /// The dark squares' colour.
        dark: Color,
        /// The border's colour.
        edge: Color,
    },
}

impl UvPattern {
    /// The book's `uv_pattern_at(pattern, u, v)`.
    pub fn uv_pattern_at(&self, u: f64, v: f64) -> Color {
        match self {
            UvPattern::Checkers {
                width,
                height,
                a,
                b,
            } => {
                let (u2, v2) = ((u * width).floor(), (v * height).floor());
                if (u2 + v2).rem_euclid(2.0) == 0.0 {
                    *a
                } else {
                    *b
                }
            }
            UvPattern::AlignCheck {
                main,
                ul,
                ur,
                bl,
                br,
            } => {
                if v > 0.8 {
                    if u < 0.2 {
                        return *ul;
                    }
                    if u > 0.8 {
                        return *ur;
                    }
                } else if v < 0.2 {
                    if u < 0.2 {
                        return *bl;
                    }
                    if u > 0.8 {
                        return *br;
                    }
                }
                *main
            }
            UvPattern::Image(texture) => texture.sample(u, v),
            UvPattern::Board {
                squares,
                border,
                light,
                dark,
                edge,
            } => {
                let inner = 1.0 - 2.0 * border;
                let inside = |t: f64| t > *border && t < 1.0 - border;
                if !(inside(u) && inside(v)) || inner <= 0.0 {
                    return *edge;
                }
                let n = f64::from((*squares).max(1));
                let index = |t: f64| (n * (t - border) / inner).floor().clamp(0.0, n - 1.0);
                if (index(u) + index(v)).rem_euclid(2.0) == 0.0 {
                    *dark
                } else {
                    *light
                }
            }
        }
    }
}

/// How texels are read between pixel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filter {
    /// The nearest pixel (the book's `uv_image`).
    Nearest,
    /// A blend of the four nearest pixels: smooth when magnified.
    #[default]
    Bilinear,
}

/// An image in linear colour, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    pixels: Vec<Color>,
    /// How it is sampled.
    pub filter: Filter,
}

impl Texture {
    /// A texture from pixels, row-major from the top-left; `None` when the sizes disagree or
    /// the image is empty.
    pub fn new(width: usize, height: usize, pixels: Vec<Color>, filter: Filter) -> Option<Self> {
        (width > 0 && height > 0 && pixels.len() == width * height).then_some(Self {
            width,
            height,
            pixels,
            filter,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The pixels, row-major from the top-left (the rasterizer builds MIP maps from them).
    pub fn pixels(&self) -> &[Color] {
        &self.pixels
    }

    /// The pixels, row-major from the top-left, given up (a reader that keeps them in
    /// another form need not copy them).
    pub fn into_pixels(self) -> Vec<Color> {
        self.pixels
    }

    /// The pixels as an image to sample.
    fn image(&self) -> TexelGrid<'_> {
        TexelGrid {
            texels: &self.pixels,
            width: self.width,
            height: self.height,
        }
    }

    /// The colour at (u, v), u to the right and v up, both clamped into [0, 1].
    pub fn sample(&self, u: f64, v: f64) -> Color {
        match self.filter {
            Filter::Nearest => self.image().nearest(u, v),
            Filter::Bilinear => self.image().bilinear(u, v),
        }
    }
}

/// A `width × height` grid of linear colours, row-major from the top-left, read at texture
/// coordinates: what a [`Texture`] and each level of the rasterizer's MIP maps sample, by the
/// same functions so that the two agree to the bit.
///
/// The book's convention: u = 0 is the left column, v = 0 the bottom row, and the ends of the
/// range land on the centres of the edge texels; coordinates outside [0, 1] (and NaN) clamp to
/// the nearest edge.
#[derive(Debug, Clone, Copy)]
pub struct TexelGrid<'a> {
    /// The texels, row-major from the top-left (at least `width × height` of them).
    pub texels: &'a [Color],
    /// Texels per row (at least 1).
    pub width: usize,
    /// Rows (at least 1).
    pub height: usize,
}

impl TexelGrid<'_> {
    /// The texel at (x, y), clamped to the grid.
    #[inline]
    fn texel(&self, x: usize, y: usize) -> Color {
        self.texels[y.min(self.height - 1) * self.width + x.min(self.width - 1)]
    }

    /// Texel-space position of (u, v).
    #[inline]
    fn position(&self, u: f64, v: f64) -> (f64, f64) {
        (
            clamp_unit(u) * (self.width - 1) as f64,
            (1.0 - clamp_unit(v)) * (self.height - 1) as f64,
        )
    }

    /// The texel nearest to (u, v).
    #[inline]
    pub fn nearest(&self, u: f64, v: f64) -> Color {
        let (x, y) = self.position(u, v);
        self.texel(x.round() as usize, y.round() as usize)
    }

    /// The four texels around (u, v), blended by distance (bilinear filtering).
    #[inline]
    pub fn bilinear(&self, u: f64, v: f64) -> Color {
        let (x, y) = self.position(u, v);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as usize, y0 as usize);
        let top = self.texel(x0, y0).lerp(self.texel(x0 + 1, y0), fx);
        let bottom = self.texel(x0, y0 + 1).lerp(self.texel(x0 + 1, y0 + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// Coordinates outside [0, 1] (and NaN) clamp to the nearest edge.
fn clamp_unit(t: f64) -> f64 {
    if t.is_nan() {
        0.0
    } else {
        t.clamp(0.0, 1.0)
    }
}

/// How a 3D point (in pattern space) becomes (u, v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UvMapping {
    /// Longitude and latitude on the unit sphere.
    Spherical,
    /// The xz plane, repeating every unit.
    Planar,
    /// Around the y axis, repeating every unit of height.
    Cylindrical,
    /// Around the y axis and around the tube of a torus whose centre circle has this radius.
    Toroidal {
        /// The torus's major radius (the centre circle of its tube).
        major: f64,
    },
}

impl UvMapping {
    /// The (u, v) of a point.
    pub fn map(self, p: Point3) -> (f64, f64) {
        match self {
            UvMapping::Spherical => spherical_map(p),
            UvMapping::Planar => planar_map(p),
            UvMapping::Cylindrical => cylindrical_map(p),
            UvMapping::Toroidal { major } => crate::geometry::toroidal_map(p, major),
        }
    }
}

/// The book's `spherical_map(p)`.
pub fn spherical_map(p: Point3) -> (f64, f64) {
    let theta = p.x.atan2(p.z);
    let radius = p.length();
    let phi = if radius > 0.0 {
        (p.y / radius).clamp(-1.0, 1.0).acos()
    } else {
        0.0
    };
    let raw_u = theta / (2.0 * PI);
    (1.0 - (raw_u + 0.5), 1.0 - phi / PI)
}

/// The book's `planar_map(p)`.
pub fn planar_map(p: Point3) -> (f64, f64) {
    (p.x.rem_euclid(1.0), p.z.rem_euclid(1.0))
}

/// The book's `cylindrical_map(p)`.
pub fn cylindrical_map(p: Point3) -> (f64, f64) {
    let theta = p.x.atan2(p.z);
    let raw_u = theta / (2.0 * PI);
    (1.0 - (raw_u + 0.5), p.y.rem_euclid(1.0))
}

/// A face of the cube, for cube maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CubeFace {
    /// -x
    Left,
    /// +z
    Front,
    /// +x
    Right,
    /// -z
    Back,
    /// +y
    Up,
    /// -y
    Down,
}

impl CubeFace {
    /// The book's `face_from_point(p)`: the face whose axis the point is furthest along.
    pub fn from_point(p: Point3) -> Self {
        let coord = p.abs().max_element();
        if coord == p.x {
            CubeFace::Right
        } else if coord == -p.x {
            CubeFace::Left
        } else if coord == p.y {
            CubeFace::Up
        } else if coord == -p.y {
            CubeFace::Down
        } else if coord == p.z {
            CubeFace::Front
        } else {
            CubeFace::Back
        }
    }

    /// The book's `cube_uv_<face>(p)`: (u, v) on this face, each face seen from outside with
    /// up towards +y (or, for the top and bottom, towards -z and +z).
    pub fn uv(self, p: Point3) -> (f64, f64) {
        let m = |a: f64| (a + 1.0).rem_euclid(2.0) / 2.0;
        match self {
            CubeFace::Front => (m(p.x), m(p.y)),
            CubeFace::Back => (m(-p.x), m(p.y)),
            CubeFace::Left => (m(p.z), m(p.y)),
            CubeFace::Right => (m(-p.z), m(p.y)),
            CubeFace::Up => (m(p.x), m(-p.z)),
            CubeFace::Down => (m(p.x), m(p.z)),
        }
    }

    /// The face's position in [`CubeFace::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Every face, in the order cube maps store them: left, front, right, back, up, down.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::Left,
        CubeFace::Front,
        CubeFace::Right,
        CubeFace::Back,
        CubeFace::Up,
        CubeFace::Down,
    ];
}
