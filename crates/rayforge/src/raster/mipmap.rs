//! Texture filtering for the rasterizer: nearest, bilinear, and trilinear over a MIP map (the
//! filtering the book's "Textures" chapter leaves "TO DO").
//!
//! A texture minified on screen (many texels per pixel) aliases when sampled at one point per
//! pixel. A MIP map keeps the image at every power-of-two reduction, each level the average of
//! the one above; a sample reads the level whose texels are about one pixel in size, bilinearly
//! in the two levels around it, and blends them (trilinear filtering).
//!
//! Coordinates follow [`Texture::sample`]: u to the right, v up, both clamped to [0, 1], and
//! the ends of the range on the centres of the edge texels; so the level-0 bilinear sample is
//! exactly the ray tracer's.

use crate::color::Color;
use crate::options::TextureFilter;
use crate::shading::{TexelGrid, Texture};

/// One level: a `width × height` image, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
struct Level {
    width: usize,
    height: usize,
    texels: Vec<Color>,
}

impl Level {
    #[inline]
    fn texel(&self, x: usize, y: usize) -> Color {
        self.texels[y.min(self.height - 1) * self.width + x.min(self.width - 1)]
    }

    /// The level below: each texel the average of a 2×2 block (edge texels repeat when a side
    /// is odd).
    fn reduced(&self) -> Self {
        let (width, height) = (self.width.div_ceil(2), self.height.div_ceil(2));
        let mut texels = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                let (sx, sy) = (2 * x, 2 * y);
                let sum = self.texel(sx, sy)
                    + self.texel(sx + 1, sy)
                    + self.texel(sx, sy + 1)
                    + self.texel(sx + 1, sy + 1);
                texels.push(sum * 0.25);
            }
        }
        Self {
            width,
            height,
            texels,
        }
    }

    /// The level as a grid to sample.
    fn grid(&self) -> TexelGrid<'_> {
        TexelGrid {
            texels: &self.texels,
            width: self.width,
            height: self.height,
        }
    }

    fn nearest(&self, u: f64, v: f64) -> Color {
        self.grid().nearest(u, v)
    }

    fn bilinear(&self, u: f64, v: f64) -> Color {
        self.grid().bilinear(u, v)
    }
}

/// A texture and its reductions down to one texel.
#[derive(Debug, Clone, PartialEq)]
pub struct MipChain {
    levels: Vec<Level>,
}

impl MipChain {
    /// Builds every level of `texture` (a third more memory than the image).
    pub fn new(texture: &Texture) -> Self {
        let mut levels = vec![Level {
            width: texture.width(),
            height: texture.height(),
            texels: texture.pixels().to_vec(),
        }];
        while let Some(last) = levels.last() {
            if last.width == 1 && last.height == 1 {
                break;
            }
            let next = last.reduced();
            levels.push(next);
        }
        Self { levels }
    }

    /// How many levels there are (1 for a single texel).
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// The size of level `level`.
    pub fn level_size(&self, level: usize) -> (usize, usize) {
        let l = &self.levels[level.min(self.levels.len() - 1)];
        (l.width, l.height)
    }

    /// The level of detail for a pixel whose footprint spans `(du_dx, dv_dx)` and
    /// `(du_dy, dv_dy)` in texture coordinates: log2 of its longer side in level-0 texels.
    pub fn level_of_detail(&self, du_dx: f64, dv_dx: f64, du_dy: f64, dv_dy: f64) -> f64 {
        let base = &self.levels[0];
        let (sx, sy) = (
            (base.width - 1).max(1) as f64,
            (base.height - 1).max(1) as f64,
        );
        let along_x = (du_dx * sx).hypot(dv_dx * sy);
        let along_y = (du_dy * sx).hypot(dv_dy * sy);
        let rho = along_x.max(along_y);
        if rho.is_finite() && rho > 1.0 {
            rho.log2()
        } else {
            0.0
        }
    }

    /// The colour at (u, v) with a filter; `lod` (see [`MipChain::level_of_detail`]) matters
    /// only to trilinear filtering.
    pub fn sample(&self, u: f64, v: f64, lod: f64, filter: TextureFilter) -> Color {
        match filter {
            TextureFilter::Nearest => self.levels[0].nearest(u, v),
            TextureFilter::Bilinear => self.levels[0].bilinear(u, v),
            TextureFilter::Trilinear => {
                let top = (self.levels.len() - 1) as f64;
                let lod = lod.clamp(0.0, top);
                let fine = lod.floor();
                let blend = lod - fine;
                let fine = fine as usize;
                let a = self.levels[fine].bilinear(u, v);
                if blend == 0.0 {
                    a
                } else {
                    a.lerp(self.levels[fine + 1].bilinear(u, v), blend)
                }
            }
        }
    }
}
