//! glTF 2.0's metallic-roughness material: factors and the textures that vary them over a
//! surface, read as the glTF specification reads them (sampler wrap and filter modes,
//! `KHR_texture_transform`, the blue channel metallic and the green roughness), and the
//! meaning each renderer gives it.
//!
//! The path tracer follows the specification's reference model (its appendix B) as three
//! layers (see [`Scattering::metal_rough`](super::Scattering::metal_rough)): a share
//! `metallic` of GGX conductor reflecting the base colour (Fresnel 1, tinted, as Mitsuba's
//! `roughconductor` without a named metal), and of the rest a share `transmission` of rough
//! glass of index `ior` tinted by the base colour (`KHR_materials_transmission`) and the
//! remainder a rough dielectric coat of index `ior` over a Lambertian base of the base colour
//! (the plastic of Mitsuba's `roughplastic`). Every layer has GGX width `roughness²`.
//!
//! Texture coordinates reach here in the book's convention (v up, as the mesh stores them for
//! every renderer); glTF's have v down, so a texture is read at `(u, 1 − v)`.

use super::texture::{Filter, Texture};
use crate::color::Color;
use crate::math::Vec3;
use std::sync::Arc;

/// How texture coordinates outside [0, 1] are brought back (glTF's sampler `wrapS`/`wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    /// The image tiles (glTF's default).
    #[default]
    Repeat,
    /// The edge texels stretch outwards.
    ClampToEdge,
    /// The image tiles, every other copy mirrored.
    MirroredRepeat,
}

impl Wrap {
    /// A texture coordinate brought into [0, 1] (NaN to 0).
    #[inline]
    pub fn unit(self, x: f64) -> f64 {
        if !x.is_finite() {
            return 0.0;
        }
        match self {
            Wrap::Repeat => x.rem_euclid(1.0),
            Wrap::ClampToEdge => x.clamp(0.0, 1.0),
            Wrap::MirroredRepeat => {
                let period = x.rem_euclid(2.0);
                if period <= 1.0 {
                    period
                } else {
                    2.0 - period
                }
            }
        }
    }

    /// The texel index `i` (any integer) brought into `0..n`.
    #[inline]
    fn index(self, i: i64, n: usize) -> usize {
        let n = n as i64;
        let wrapped = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let period = i.rem_euclid(2 * n);
                if period < n {
                    period
                } else {
                    2 * n - 1 - period
                }
            }
        };
        wrapped as usize
    }
}

/// An affine map of texture coordinates (`KHR_texture_transform`), in glTF's convention:
/// `(u', v') = rows · (u, v, 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform {
    /// The two rows of the 2 × 3 matrix.
    pub rows: [[f64; 3]; 2],
}

impl UvTransform {
    /// The extension's `offset`, `rotation` (radians) and `scale`: translation × rotation ×
    /// scale, with the rotation turning the coordinates as the extension defines it.
    pub fn new(offset: [f64; 2], rotation: f64, scale: [f64; 2]) -> Self {
        let (s, c) = rotation.sin_cos();
        Self {
            rows: [
                [c * scale[0], s * scale[1], offset[0]],
                [-s * scale[0], c * scale[1], offset[1]],
            ],
        }
    }

    /// The transformed coordinates.
    #[inline]
    pub fn apply(&self, u: f64, v: f64) -> (f64, f64) {
        let [a, b] = self.rows;
        (a[0] * u + a[1] * v + a[2], b[0] * u + b[1] * v + b[2])
    }
}

/// A texture as a glTF material uses it: the image, how it is sampled, and where on the
/// surface it is read.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureSlot {
    /// The image, in linear values (a colour texture was decoded from sRGB when it was read).
    pub texture: Arc<Texture>,
    /// The image's alpha channel, when it has one and the material needs it (base colour).
    pub alpha: Option<Arc<Texture>>,
    /// Wrapping across u and across v.
    pub wrap: [Wrap; 2],
    /// Magnification filter (nearest or bilinear).
    pub filter: Filter,
    /// `KHR_texture_transform`, when present.
    pub transform: Option<UvTransform>,
}

impl TextureSlot {
    /// The texel coordinates of book-convention `(u, v)`: glTF's `(u, 1 − v)`, transformed,
    /// scaled to the image (texel centres at half-integers).
    #[inline]
    fn texel_point(&self, u: f64, v: f64) -> (f64, f64) {
        let (s, t) = (u, 1.0 - v);
        let (s, t) = match &self.transform {
            Some(m) => m.apply(s, t),
            None => (s, t),
        };
        let (w, h) = (self.texture.width() as f64, self.texture.height() as f64);
        (s * w - 0.5, t * h - 0.5)
    }

    /// Reads `image` at texel point `(x, y)` with this slot's wrap and filter.
    #[inline]
    fn read(&self, image: &Texture, x: f64, y: f64) -> Color {
        let (w, h) = (image.width(), image.height());
        let pixels = image.pixels();
        let at = |i: i64, j: i64| pixels[self.wrap[1].index(j, h) * w + self.wrap[0].index(i, w)];
        if !(x.is_finite() && y.is_finite()) {
            return at(0, 0);
        }
        // Far outside the image, only the position within the wrap's period matters; keep
        // the integers small.
        let limit = 1.0e15;
        let (x, y) = (x.clamp(-limit, limit), y.clamp(-limit, limit));
        match self.filter {
            Filter::Nearest => at((x + 0.5).floor() as i64, (y + 0.5).floor() as i64),
            Filter::Bilinear => {
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (i, j) = (x0 as i64, y0 as i64);
                let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
                let bottom = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
                top * (1.0 - fy) + bottom * fy
            }
        }
    }

    /// Book-convention texture coordinates carried through this slot's transform and wrap
    /// modes into the unit square (still in the book's convention): where a sampler that
    /// clamps (the rasterizer's MIP maps) must read the image to follow glTF's wrapping.
    #[inline]
    pub fn wrapped_uv(&self, u: f64, v: f64) -> (f64, f64) {
        let (s, t) = match &self.transform {
            Some(m) => m.apply(u, 1.0 - v),
            None => (u, 1.0 - v),
        };
        (self.wrap[0].unit(s), 1.0 - self.wrap[1].unit(t))
    }

    /// The texture's value at book-convention texture coordinates.
    #[inline]
    pub fn sample(&self, u: f64, v: f64) -> Color {
        let (x, y) = self.texel_point(u, v);
        self.read(&self.texture, x, y)
    }

    /// The alpha channel's value there (1 when the image has none).
    #[inline]
    pub fn sample_alpha(&self, u: f64, v: f64) -> f64 {
        match &self.alpha {
            Some(alpha) => {
                let (x, y) = self.texel_point(u, v);
                self.read(alpha, x, y).red
            }
            None => 1.0,
        }
    }
}

/// How a material's alpha is used (glTF's `alphaMode`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored.
    #[default]
    Opaque,
    /// The surface is there where alpha is at least `cutoff`, and absent elsewhere.
    Mask {
        /// glTF's `alphaCutoff` (0.5 by default).
        cutoff: f64,
    },
    /// The surface lets a share `1 − alpha` of light through unchanged: every ray passes with
    /// that probability (stochastic transparency, which averages to the blend over samples).
    Blend,
}

/// The surface at a hit as the material reads it: texture coordinates (book convention) and
/// the mesh's vertex colour.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfacePoint {
    /// Texture coordinates, when the surface has them.
    pub uv: Option<(f64, f64)>,
    /// Linear RGBA vertex colour, when the mesh has one.
    pub vertex_color: Option<[f64; 4]>,
}

/// A normal map in the tangent space of the surface (glTF's `normalTexture`).
#[derive(Debug, Clone, PartialEq)]
pub struct NormalMap {
    /// The map (linear values; x, y, z stored as `(n + 1) / 2`).
    pub slot: TextureSlot,
    /// glTF's `scale`, multiplying the x and y of the map's normal.
    pub scale: f64,
}

/// glTF's metallic-roughness material (see the [module](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct MetalRough {
    /// `baseColorFactor`'s colour (linear).
    pub base_color: Color,
    /// `baseColorFactor`'s alpha.
    pub base_alpha: f64,
    /// `baseColorTexture` (decoded from sRGB), multiplying the factor.
    pub base_texture: Option<TextureSlot>,
    /// `metallicFactor`.
    pub metallic: f64,
    /// `roughnessFactor`.
    pub roughness: f64,
    /// `metallicRoughnessTexture`: blue is metallic, green roughness, multiplying the factors.
    pub metal_rough_texture: Option<TextureSlot>,
    /// `normalTexture`.
    pub normal_map: Option<NormalMap>,
    /// `occlusionTexture` (red channel) and its `strength`: darkens the ambient term of the
    /// book's renderers; the path tracer finds occlusion by tracing and does not use it, as
    /// pbrt and Mitsuba do not.
    pub occlusion: Option<(TextureSlot, f64)>,
    /// `emissiveFactor` times `KHR_materials_emissive_strength`.
    pub emissive: Color,
    /// `emissiveTexture` (decoded from sRGB), multiplying `emissive`.
    pub emissive_texture: Option<TextureSlot>,
    /// `KHR_materials_transmission`'s factor.
    pub transmission: f64,
    /// Its texture (red channel), multiplying the factor.
    pub transmission_texture: Option<TextureSlot>,
    /// `KHR_materials_ior` (1.5 by default).
    pub ior: f64,
    /// `alphaMode` and `alphaCutoff`.
    pub alpha_mode: AlphaMode,
    /// `doubleSided`: when false, the back of the surface is not there at all (as a
    /// rasterizer culls it), unless light passes through the material (transmission).
    pub double_sided: bool,
}

impl Default for MetalRough {
    /// The specification's defaults: white, fully metallic, fully rough, opaque.
    fn default() -> Self {
        Self {
            base_color: Color::WHITE,
            base_alpha: 1.0,
            base_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metal_rough_texture: None,
            normal_map: None,
            occlusion: None,
            emissive: Color::BLACK,
            emissive_texture: None,
            transmission: 0.0,
            transmission_texture: None,
            ior: 1.5,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

/// The parameters of the material at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetalRoughSample {
    /// Base colour (linear, each channel in [0, 1]).
    pub base: Color,
    /// Metallic share, in [0, 1].
    pub metallic: f64,
    /// Perceptual roughness, in [0, 1] (the GGX width is its square).
    pub roughness: f64,
    /// Transmitted share of the non-metal part, in [0, 1].
    pub transmission: f64,
}

impl MetalRough {
    /// The base colour and alpha at a point: factor × texture × vertex colour.
    #[inline]
    pub fn base_at(&self, at: &SurfacePoint) -> (Color, f64) {
        let mut colour = self.base_color;
        let mut alpha = self.base_alpha;
        if let (Some(slot), Some((u, v))) = (&self.base_texture, at.uv) {
            colour = colour.hadamard(slot.sample(u, v));
            alpha *= slot.sample_alpha(u, v);
        }
        if let Some(c) = at.vertex_color {
            colour = colour.hadamard(Color::new(c[0], c[1], c[2]));
            alpha *= c[3];
        }
        (colour, alpha)
    }

    /// Whether a ray meets the surface at this point: always for opaque materials; where
    /// alpha reaches the cutoff for masked ones; with probability alpha for blended ones,
    /// decided by `u`, uniform in [0, 1).
    #[inline]
    pub fn is_there(&self, at: &SurfacePoint, u: f64) -> bool {
        match self.alpha_mode {
            AlphaMode::Opaque => true,
            AlphaMode::Mask { cutoff } => self.base_at(at).1 >= cutoff,
            AlphaMode::Blend => u < self.base_at(at).1,
        }
    }

    /// Whether some points of the surface may be absent (see [`MetalRough::is_there`]).
    pub fn has_holes(&self) -> bool {
        self.alpha_mode != AlphaMode::Opaque
    }

    /// Whether rays pass through the back of the surface: a single-sided material that lets
    /// no light through (a transmissive one keeps both sides, or light could not leave it).
    pub fn culls_back(&self) -> bool {
        !self.double_sided && self.transmission <= 0.0 && self.transmission_texture.is_none()
    }

    /// Every parameter at a point, each clamped into its range.
    #[inline]
    pub fn sample_at(&self, at: &SurfacePoint) -> MetalRoughSample {
        let (base, _) = self.base_at(at);
        let (mut metallic, mut roughness) = (self.metallic, self.roughness);
        let mut transmission = self.transmission;
        if let Some((u, v)) = at.uv {
            if let Some(slot) = &self.metal_rough_texture {
                let texel = slot.sample(u, v);
                metallic *= texel.blue;
                roughness *= texel.green;
            }
            if let Some(slot) = &self.transmission_texture {
                transmission *= slot.sample(u, v).red;
            }
        }
        MetalRoughSample {
            base: Color::new(
                base.red.clamp(0.0, 1.0),
                base.green.clamp(0.0, 1.0),
                base.blue.clamp(0.0, 1.0),
            ),
            metallic: unit(metallic),
            roughness: unit(roughness),
            transmission: unit(transmission),
        }
    }

    /// The radiance given off at a point: `emissive` × the emissive texture.
    #[inline]
    pub fn emission_at(&self, at: &SurfacePoint) -> Color {
        match (&self.emissive_texture, at.uv) {
            (Some(slot), Some((u, v))) => self.emissive.hadamard(slot.sample(u, v)),
            _ => self.emissive,
        }
    }

    /// The ambient occlusion at a point, 1 for none: `1 + strength · (texel − 1)`.
    #[inline]
    pub fn occlusion_at(&self, at: &SurfacePoint) -> f64 {
        match (&self.occlusion, at.uv) {
            (Some((slot, strength)), Some((u, v))) => {
                unit(1.0 + strength * (slot.sample(u, v).red - 1.0))
            }
            _ => 1.0,
        }
    }

    /// The shading normal with the normal map applied, from the unit world-space `normal` and
    /// the world-space `tangent` (not necessarily unit or perpendicular) with the bitangent's
    /// sign; `normal` itself where there is no map, no texture coordinate or no usable tangent.
    #[inline]
    pub fn mapped_normal(
        &self,
        at: &SurfacePoint,
        normal: Vec3,
        tangent: Option<(Vec3, f64)>,
    ) -> Vec3 {
        let (Some(map), Some((u, v)), Some((tangent, sign))) = (&self.normal_map, at.uv, tangent)
        else {
            return normal;
        };
        // Gram–Schmidt: the tangent made perpendicular to the interpolated normal.
        let Some(t) = (tangent - normal * normal.dot(tangent)).try_normalize() else {
            return normal;
        };
        let b = normal.cross(t) * sign;
        let texel = map.slot.sample(u, v);
        let x = (texel.red * 2.0 - 1.0) * map.scale;
        let y = (texel.green * 2.0 - 1.0) * map.scale;
        let z = texel.blue * 2.0 - 1.0;
        (t * x + b * y + normal * z)
            .try_normalize()
            .unwrap_or(normal)
    }
}

/// `x` clamped into [0, 1] (NaN to 0).
#[inline]
fn unit(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slot(pixels: Vec<Color>, width: usize, wrap: Wrap, filter: Filter) -> TextureSlot {
        let height = pixels.len() / width;
        TextureSlot {
            texture: Arc::new(Texture::new(width, height, pixels, Filter::Nearest).unwrap()),
            alpha: None,
            wrap: [wrap; 2],
            filter,
            transform: None,
        }
    }

    #[test]
    fn wrap_modes_bring_indices_back_as_gltf_says() {
        assert_eq!(Wrap::Repeat.index(-1, 4), 3);
        assert_eq!(Wrap::Repeat.index(9, 4), 1);
        assert_eq!(Wrap::ClampToEdge.index(-7, 4), 0);
        assert_eq!(Wrap::ClampToEdge.index(9, 4), 3);
        // Mirrored: 0 1 2 3 | 3 2 1 0 | 0 1 …
        let mirrored: Vec<usize> = (-2..10).map(|i| Wrap::MirroredRepeat.index(i, 4)).collect();
        assert_eq!(mirrored, [1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0, 1]);
    }

    #[test]
    fn wrapped_coordinates_land_in_the_unit_square_as_the_modes_say() {
        assert_eq!(Wrap::Repeat.unit(1.25), 0.25);
        assert_eq!(Wrap::Repeat.unit(-0.25), 0.75);
        assert_eq!(Wrap::ClampToEdge.unit(1.25), 1.0);
        assert_eq!(Wrap::MirroredRepeat.unit(1.25), 0.75);
        assert_eq!(Wrap::MirroredRepeat.unit(-0.25), 0.25);
        let s = TextureSlot {
            wrap: [Wrap::Repeat, Wrap::MirroredRepeat],
            ..slot(vec![Color::WHITE], 1, Wrap::Repeat, Filter::Nearest)
        };
        // Book v 1.25 is glTF v −0.25, mirrored to 0.25, which is book v 0.75.
        let (u, v) = s.wrapped_uv(2.5, 1.25);
        assert!(
            (u - 0.5).abs() < 1e-12 && (v - 0.75).abs() < 1e-12,
            "{u} {v}"
        );
    }

    #[test]
    fn the_top_left_texel_is_at_gltf_uv_zero_which_is_book_v_one() {
        // A 2 × 2 image: red at the top left.
        let (r, g, b, w) = (
            Color::new(1.0, 0.0, 0.0),
            Color::new(0.0, 1.0, 0.0),
            Color::new(0.0, 0.0, 1.0),
            Color::WHITE,
        );
        let s = slot(vec![r, g, b, w], 2, Wrap::ClampToEdge, Filter::Nearest);
        assert_eq!(s.sample(0.25, 0.75), r);
        assert_eq!(s.sample(0.75, 0.75), g);
        assert_eq!(s.sample(0.25, 0.25), b);
        assert_eq!(s.sample(0.75, 0.25), w);
    }

    #[test]
    fn bilinear_filtering_blends_across_the_wrapped_edge() {
        let s = slot(
            vec![Color::BLACK, Color::WHITE],
            2,
            Wrap::Repeat,
            Filter::Bilinear,
        );
        // u = 0 lies halfway between the last texel (white) and the first (black).
        let c = s.sample(0.0, 0.5);
        assert!((c.red - 0.5).abs() < 1e-12, "{c:?}");
        let clamped = slot(
            vec![Color::BLACK, Color::WHITE],
            2,
            Wrap::ClampToEdge,
            Filter::Bilinear,
        );
        assert_eq!(clamped.sample(0.0, 0.5), Color::BLACK);
    }

    #[test]
    fn texture_transform_offsets_rotates_and_scales() {
        let m = UvTransform::new([0.5, 0.0], 0.0, [2.0, 2.0]);
        assert_eq!(m.apply(0.25, 0.25), (1.0, 0.5));
        // A quarter turn takes (1, 0) to (0, −1) in the extension's convention.
        let r = UvTransform::new([0.0, 0.0], std::f64::consts::FRAC_PI_2, [1.0, 1.0]);
        let (u, v) = r.apply(1.0, 0.0);
        assert!(u.abs() < 1e-12 && (v + 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_flat_normal_map_keeps_the_normal_and_a_tilted_one_leans_along_the_tangent() {
        let flat = Color::new(0.5, 0.5, 1.0);
        let mut m = MetalRough {
            normal_map: Some(NormalMap {
                slot: slot(vec![flat], 1, Wrap::Repeat, Filter::Nearest),
                scale: 1.0,
            }),
            ..MetalRough::default()
        };
        let at = SurfacePoint {
            uv: Some((0.5, 0.5)),
            vertex_color: None,
        };
        let n = Vec3::Z;
        let tangent = Some((Vec3::new(2.0, 0.0, 0.3), 1.0));
        assert!((m.mapped_normal(&at, n, tangent) - n).length() < 1e-12);
        let tilted = Color::new(1.0, 0.5, 0.5);
        m.normal_map.as_mut().unwrap().slot = slot(vec![tilted], 1, Wrap::Repeat, Filter::Nearest);
        let mapped = m.mapped_normal(&at, n, tangent);
        assert!((mapped - Vec3::X).length() < 1e-12, "{mapped:?}");
        // No tangent: the normal as it is.
        assert_eq!(m.mapped_normal(&at, n, None), n);
    }

    #[test]
    fn occlusion_darkens_by_its_strength() {
        let half = Color::new(0.5, 0.5, 0.5);
        let m = MetalRough {
            occlusion: Some((slot(vec![half], 1, Wrap::Repeat, Filter::Nearest), 0.5)),
            ..MetalRough::default()
        };
        let at = SurfacePoint {
            uv: Some((0.5, 0.5)),
            vertex_color: None,
        };
        assert!((m.occlusion_at(&at) - 0.75).abs() < 1e-12);
        assert_eq!(MetalRough::default().occlusion_at(&at), 1.0);
    }

    #[test]
    fn masks_cut_below_the_cutoff_and_blends_pass_by_probability() {
        let at = SurfacePoint {
            uv: None,
            vertex_color: Some([1.0, 1.0, 1.0, 0.4]),
        };
        let mask = MetalRough {
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..MetalRough::default()
        };
        assert!(!mask.is_there(&at, 0.0));
        let blend = MetalRough {
            alpha_mode: AlphaMode::Blend,
            ..MetalRough::default()
        };
        assert!(blend.is_there(&at, 0.39) && !blend.is_there(&at, 0.41));
        assert!(MetalRough::default().is_there(&at, 0.99));
    }
}
