//! glTF materials as rayforge materials: the metallic-roughness model for the path tracer
//! ([`MetalRough`]), and the book's Phong parameters approximating it for the Whitted ray
//! tracer and the rasterizer (see [`book_material`]). Images are decoded once each, within
//! the scene's image memory; colour textures (base colour, emissive) from sRGB to linear,
//! data textures (metallic-roughness, normal, occlusion, transmission) as they are.

use super::buffers::{resource, Buffers};
use super::paths::error;
use crate::error::SceneError;
use crate::files::Folder;
use crate::images::{decode_with_alpha, ImageMemory, COLOR_BYTES};
use rayforge::shading::metal_rough::{
    AlphaMode, MetalRough, NormalMap, TextureSlot, UvTransform, Wrap,
};
use rayforge::shading::{Filter, Texture, UvPattern};
use rayforge::{Color, Material};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The materials of a model, each read once, and the images they use.
pub(crate) struct Materials<'a> {
    path: &'a Path,
    buffers: &'a Buffers,
    folder: &'a Folder,
    memory: &'a mut ImageMemory,
    /// Decoded images, by (image index, whether from sRGB): the colour and the alpha.
    images: HashMap<(usize, bool), Decoded>,
    /// Built materials, by index (`None`: the default material).
    built: HashMap<Option<usize>, Built>,
    /// What was left out, for warnings.
    pub notes: Vec<String>,
}

/// A material as a primitive needs it.
#[derive(Clone)]
pub(crate) struct Built {
    /// The material.
    pub material: Material,
    /// Whether it has a normal map (its meshes then need tangents).
    pub normal_mapped: bool,
    /// The texture coordinate set its textures read.
    pub uv_set: u32,
}

impl<'a> Materials<'a> {
    pub fn new(
        path: &'a Path,
        buffers: &'a Buffers,
        folder: &'a Folder,
        memory: &'a mut ImageMemory,
    ) -> Self {
        Self {
            path,
            buffers,
            folder,
            memory,
            images: HashMap::new(),
            built: HashMap::new(),
            notes: Vec::new(),
        }
    }

    /// The material of a primitive.
    pub fn get(&mut self, material: &::gltf::Material<'_>) -> Result<Built, SceneError> {
        if let Some(b) = self.built.get(&material.index()) {
            return Ok(b.clone());
        }
        let built = self.build(material)?;
        self.built.insert(material.index(), built.clone());
        Ok(built)
    }

    fn build(&mut self, m: &::gltf::Material<'_>) -> Result<Built, SceneError> {
        let at = match m.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".to_string(),
        };
        let pbr = m.pbr_metallic_roughness();
        let mut uv_sets = Vec::new();
        let mut slot = |this: &mut Self,
                        info: Option<Use<'_>>,
                        name: &str,
                        srgb: bool,
                        alpha: bool|
         -> Result<Option<TextureSlot>, SceneError> {
            let Some((texture, set, transform)) = info else {
                return Ok(None);
            };
            let set = transform
                .as_ref()
                .and_then(|t| t.tex_coord())
                .unwrap_or(set);
            uv_sets.push(set);
            this.slot(&format!("{at}.{name}"), &texture, srgb, alpha, transform)
                .map(Some)
        };
        let alpha_mode = match m.alpha_mode() {
            ::gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            ::gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: f64::from(m.alpha_cutoff().unwrap_or(0.5)),
            },
            ::gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let wants_alpha = alpha_mode != AlphaMode::Opaque;
        let base_texture = slot(
            self,
            info(pbr.base_color_texture()),
            "pbrMetallicRoughness.baseColorTexture",
            true,
            wants_alpha,
        )?;
        let metal_rough_texture = slot(
            self,
            info(pbr.metallic_roughness_texture()),
            "pbrMetallicRoughness.metallicRoughnessTexture",
            false,
            false,
        )?;
        let normal_map = match m.normal_texture() {
            Some(n) => {
                let scale = f64::from(n.scale());
                slot(
                    self,
                    Some((n.texture(), n.tex_coord(), None)),
                    "normalTexture",
                    false,
                    false,
                )?
                .map(|slot| NormalMap { slot, scale })
            }
            None => None,
        };
        let occlusion = match m.occlusion_texture() {
            Some(o) => {
                let strength = f64::from(o.strength());
                slot(
                    self,
                    Some((o.texture(), o.tex_coord(), None)),
                    "occlusionTexture",
                    false,
                    false,
                )?
                .map(|s| (s, strength))
            }
            None => None,
        };
        let emissive_texture = slot(
            self,
            info(m.emissive_texture()),
            "emissiveTexture",
            true,
            false,
        )?;
        let (transmission, transmission_texture) = match m.transmission() {
            Some(t) => (
                f64::from(t.transmission_factor()),
                slot(
                    self,
                    info(t.transmission_texture()),
                    "extensions.KHR_materials_transmission.transmissionTexture",
                    false,
                    false,
                )?,
            ),
            None => (0.0, None),
        };
        let strength = m.emissive_strength().map_or(1.0, f64::from);
        let [r, g, b, a] = pbr.base_color_factor();
        let [er, eg, eb] = m.emissive_factor();
        let metal_rough = MetalRough {
            base_color: Color::new(r.into(), g.into(), b.into()),
            base_alpha: a.into(),
            base_texture,
            metallic: pbr.metallic_factor().into(),
            roughness: pbr.roughness_factor().into(),
            metal_rough_texture,
            normal_map,
            occlusion,
            emissive: Color::new(er.into(), eg.into(), eb.into()) * strength,
            emissive_texture,
            transmission,
            transmission_texture,
            ior: m.ior().map_or(1.5, f64::from),
            alpha_mode,
            double_sided: m.double_sided(),
        };
        let uv_set = uv_sets.first().copied().unwrap_or(0);
        if uv_sets.iter().any(|&s| s != uv_set) {
            self.notes.push(format!(
                "{at} reads textures through more than one texture coordinate set; all are read through TEXCOORD_{uv_set}"
            ));
        }
        let normal_mapped = metal_rough.normal_map.is_some();
        Ok(Built {
            material: book_material(Arc::new(metal_rough)),
            normal_mapped,
            uv_set,
        })
    }

    /// A texture slot: the image decoded (once), the sampler's modes and the transform.
    fn slot(
        &mut self,
        at: &str,
        texture: &::gltf::texture::Texture<'_>,
        srgb: bool,
        alpha: bool,
        transform: Option<::gltf::texture::TextureTransform<'_>>,
    ) -> Result<TextureSlot, SceneError> {
        let (image, alpha_image) = self.image(at, &texture.source(), srgb)?;
        let sampler = texture.sampler();
        let wrap = |mode: ::gltf::texture::WrappingMode| match mode {
            ::gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
            ::gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
            ::gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        };
        let filter = match sampler.mag_filter() {
            Some(::gltf::texture::MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Bilinear,
        };
        Ok(TextureSlot {
            texture: image,
            alpha: if alpha { alpha_image } else { None },
            wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
            filter,
            transform: transform.map(|t| {
                let [ox, oy] = t.offset();
                let [sx, sy] = t.scale();
                UvTransform::new(
                    [ox.into(), oy.into()],
                    t.rotation().into(),
                    [sx.into(), sy.into()],
                )
            }),
        })
    }

    /// An image decoded (from sRGB to linear when `srgb`), with its alpha when it has one.
    fn image(
        &mut self,
        at: &str,
        image: &::gltf::image::Image<'_>,
        srgb: bool,
    ) -> Result<Decoded, SceneError> {
        let key = (image.index(), srgb);
        if let Some(found) = self.images.get(&key) {
            return Ok(found.clone());
        }
        let here = format!("images[{}]", image.index());
        let bytes = match image.source() {
            ::gltf::image::Source::View { view, .. } => {
                let buffer = &self.buffers[view.buffer().index()];
                buffer[view.offset()..view.offset() + view.length()].to_vec()
            }
            ::gltf::image::Source::Uri { uri, .. } => {
                resource(self.path, &format!("{here}.uri"), uri, self.folder)?
            }
        };
        let (colour, alpha) = decode_with_alpha(&bytes, self.memory.room(), true).map_err(|e| {
            error(
                self.path,
                format!("{here} (used by {at})"),
                format!("cannot read the image: {e}"),
            )
        })?;
        let held = colour.width() * colour.height() * if alpha.is_some() { 2 } else { 1 };
        self.memory.hold(held as u64 * COLOR_BYTES);
        let colour = if srgb { to_linear(colour) } else { colour };
        let found = (Arc::new(colour), alpha.map(Arc::new));
        self.images.insert(key, found.clone());
        Ok(found)
    }
}

/// An image's colours and, when it has one, its alpha.
type Decoded = (Arc<Texture>, Option<Arc<Texture>>);

/// A texture as a material uses it: the texture, its coordinate set, its transform.
type Use<'a> = (
    ::gltf::texture::Texture<'a>,
    u32,
    Option<::gltf::texture::TextureTransform<'a>>,
);

/// A texture reference's parts.
fn info(i: Option<::gltf::texture::Info<'_>>) -> Option<Use<'_>> {
    i.map(|i| (i.texture(), i.tex_coord(), i.texture_transform()))
}

/// The texture with its texels decoded from sRGB to linear.
fn to_linear(texture: Texture) -> Texture {
    let decode = |c: f64| {
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let pixels = texture
        .pixels()
        .iter()
        .map(|c| Color::new(decode(c.red), decode(c.green), decode(c.blue)))
        .collect();
    Texture::new(texture.width(), texture.height(), pixels, texture.filter).unwrap_or(texture)
}

/// The material of a primitive without one: the specification's default (white, fully
/// metallic and rough), as a [`Material`].
pub(crate) fn default_material() -> Material {
    book_material(std::sync::Arc::new(rayforge::shading::MetalRough {
        double_sided: false,
        ..Default::default()
    }))
}

/// A glTF material as a rayforge [`Material`]: the metallic-roughness model itself for the
/// path tracer, and for the book's Phong model (the Whitted ray tracer and the rasterizer):
///
/// - the colour is the base colour (factor × texture × vertex colour, read through the glTF
///   material by the ray tracer; the rasterizer reads the base texture as a plain image);
/// - `diffuse` 0.9 × (1 − reflective), `ambient` 0.1: a rough metal scatters much as a
///   matte surface does;
/// - `specular` from 0.04 (a dielectric's head-on reflectance) up to 1 for metals, times
///   (1 − roughness), and `shininess` the Blinn–Phong exponent of GGX width roughness²
///   (`2 / α² − 2`, between 2 and 1000);
/// - `reflective` metallic × (1 − roughness)²: polished metals mirror, rough ones do not;
/// - `transparency` the transmission of the non-metal part, with `refractive-index` the ior;
/// - `emission` the emissive factor (for the path tracer's list of lights).
pub(crate) fn book_material(m: Arc<MetalRough>) -> Material {
    let metallic = m.metallic.clamp(0.0, 1.0);
    let roughness = m.roughness.clamp(0.0, 1.0);
    let alpha = (roughness * roughness).max(1e-3);
    let transparency = (m.transmission * (1.0 - metallic)).clamp(0.0, 1.0);
    let reflective = metallic * (1.0 - roughness) * (1.0 - roughness);
    Material {
        color: m.base_color,
        texture: m
            .base_texture
            .as_ref()
            .map(|s| Box::new(UvPattern::Image(s.texture.clone()))),
        ambient: 0.1,
        diffuse: 0.9 * (1.0 - reflective),
        specular: (0.04 + 0.96 * metallic) * (1.0 - roughness),
        shininess: (2.0 / (alpha * alpha) - 2.0).clamp(2.0, 1000.0),
        reflective,
        transparency,
        refractive_index: if transparency > 0.0 { m.ior } else { 1.0 },
        emission: m.emissive,
        emission_side: if m.double_sided {
            rayforge::shading::EmissionSide::Both
        } else {
            rayforge::shading::EmissionSide::Front
        },
        metal_rough: Some(m),
        ..Material::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_texels_become_linear() {
        let t = Texture::new(
            2,
            1,
            vec![Color::new(0.0, 0.5, 1.0), Color::new(0.04, 0.2, 0.8)],
            Filter::Nearest,
        )
        .unwrap();
        let l = to_linear(t);
        let c = l.pixels()[0];
        assert_eq!(c.red, 0.0);
        assert!((c.green - 0.214_041).abs() < 1e-5, "{c:?}");
        assert!((c.blue - 1.0).abs() < 1e-12);
        assert!((l.pixels()[1].red - 0.04 / 12.92).abs() < 1e-12);
    }

    #[test]
    fn a_polished_metal_mirrors_and_a_rough_dielectric_is_diffuse_under_the_book_model() {
        let metal = book_material(Arc::new(MetalRough {
            metallic: 1.0,
            roughness: 0.0,
            ..Default::default()
        }));
        assert_eq!((metal.reflective, metal.diffuse), (1.0, 0.0));
        let rough_metal = book_material(Arc::new(MetalRough {
            metallic: 1.0,
            roughness: 1.0,
            ..Default::default()
        }));
        assert_eq!((rough_metal.reflective, rough_metal.diffuse), (0.0, 0.9));
        let matte = book_material(Arc::new(MetalRough {
            metallic: 0.0,
            roughness: 1.0,
            ..Default::default()
        }));
        assert_eq!((matte.reflective, matte.specular), (0.0, 0.0));
        assert!((matte.diffuse - 0.9).abs() < 1e-12);
    }
}
