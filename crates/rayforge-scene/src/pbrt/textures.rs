//! pbrt-v4's `Texture` directives as rayforge's texture graph
//! ([`rayforge::shading::texture_graph`]): every texture of the scene is built once, in the
//! order the files make them (a texture may read only textures made before it, as in pbrt-v4),
//! into one graph that the materials and shapes then name nodes of.
//!
//! Classes read: `constant`, `scale`, `mix`, `directionmix`, `checkerboard` (`dimension` 2 or
//! 3), `bilerp`, `imagemap`; float and spectrum variants, in separate name spaces as in pbrt-v4.
//! 2D mappings: `uv` (`uscale`, `vscale`, `udelta`, `vdelta`), `spherical`, `cylindrical`,
//! `planar` (`v1`, `v2`, `udelta`, `vdelta`); the 3D ones read points through the inverse of
//! the transform in force where the texture is made.
//!
//! `imagemap`: PNG, TGA, JPEG, PNM (8 or 16 bits a channel) and EXR, PFM, Radiance HDR (linear
//! floats). `encoding` applies to the integer formats: `sRGB`, `linear` or `gamma G`; the
//! default is pbrt-v4's: `sRGB` for a `.png` file, `linear` for every other (so a TGA file is
//! read as linear unless the file says otherwise, as pbrt-v4 reads it). `filter`: `point`, or
//! bilinear for `bilinear`, `trilinear`, `ewa` (the path tracer has no ray footprints to pick a
//! MIP level by; see the graph's documentation). `wrap`: `repeat`, `black`, `clamp`,
//! `octahedralsphere`. `scale`, `invert`. A float image texture reads the image's first
//! channel. Image files are read as every file a scene names: regular files inside the scene's
//! folder, at most [`MAX_IMAGE_BYTES`] each, their pixels costed against the scene's image
//! memory before they are decoded; a file read the same way twice is read once.
//!
//! The noise textures (`fbm`, `wrinkled`, `windy` as floats, `marble` as a spectrum, `dots` as
//! either; `octaves` up to [`MAX_OCTAVES`], `roughness`, and marble's `scale`, `variation`) are
//! pbrt-v4's ([`rayforge::shading::texture_noise`]), every octave summed (the path tracer has no
//! footprints to leave fine ones out by). Refused, at the texture: `ptex`.

use super::input::Files;
use super::params::{Param, ParamType};
use super::reader::{Description, Entity, TextureEntity};
use super::spectra::{self, SpectrumUse};
use crate::error::SceneError;
use crate::files::read_bounded;
use crate::hdr::decode_hdr_image;
use crate::images::{self, ImageMemory, COLOR_BYTES, MAX_IMAGE_BYTES};
use glam::{DAffine3, DMat4, DVec3};
use rayforge::shading::texture_graph::{
    FloatInput, ImageFilter, Mapping2D, NodeId, TextureGraph, TextureImage, TextureNode, Wrap,
};
use rayforge::shading::texture_noise::MAX_OCTAVES;
use rayforge::Color;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// The scene's textures, built.
pub struct SceneTextures {
    /// Every texture's node, and the nodes they read.
    pub graph: Arc<TextureGraph>,
    /// The node of each texture, by its type (`float`, `spectrum`) and name.
    by_name: HashMap<(String, String), NodeId>,
    /// The scene's image memory after the textures' images (the sky's are counted on it).
    pub memory: ImageMemory,
}

impl SceneTextures {
    /// The node of the `kind` texture that the `texture` parameter `p` names.
    pub fn named(&self, p: &Param, kind: &str, desc: &Description) -> Result<NodeId, SceneError> {
        let name = texture_name(p)?;
        lookup(&self.by_name, desc, p, kind, name)
    }

    /// The float parameter `name` of `entity`: a `texture` naming a float texture, or a
    /// `float`; `None` when absent.
    pub fn float(
        &self,
        entity: &Entity,
        name: &str,
        desc: &Description,
    ) -> Result<Option<FloatInput>, SceneError> {
        if let Some(p) = entity.params.find(name, &[ParamType::Texture]) {
            return Ok(Some(FloatInput::Texture(self.named(p, "float", desc)?)));
        }
        Ok(entity.params.float(name)?.map(FloatInput::Fixed))
    }
}

/// The one name a `texture` parameter gives.
fn texture_name(p: &Param) -> Result<&str, SceneError> {
    match &p.values {
        super::params::Values::Strings(s) if s.len() == 1 => Ok(&s[0]),
        _ => Err(p.error("takes one texture name")),
    }
}

/// The node of the `kind` texture `name` (named by `p`) among those built so far.
fn lookup(
    built: &HashMap<(String, String), NodeId>,
    desc: &Description,
    p: &Param,
    kind: &str,
    name: &str,
) -> Result<NodeId, SceneError> {
    let key = (kind.to_string(), name.to_string());
    if let Some(id) = built.get(&key) {
        return Ok(*id);
    }
    let shown = crate::error::clip_to(name, 60);
    let other = if kind == "float" { "spectrum" } else { "float" };
    let message = if desc.texture_index.contains_key(&key) {
        format!("the {kind} texture \"{shown}\" is made after this (a texture reads only those made before it)")
    } else if desc
        .texture_index
        .contains_key(&(other.to_string(), name.to_string()))
    {
        format!("\"{shown}\" is a {other} texture; a {kind} texture is wanted here")
    } else {
        format!("no {kind} texture is named \"{shown}\"")
    };
    Err(p.error(message))
}

/// Builds every texture of `desc` (image files found through `files`, their memory within
/// `max_image_memory` bytes).
pub fn build(
    desc: &Description,
    files: &Files,
    max_image_memory: u64,
) -> Result<SceneTextures, SceneError> {
    let mut builder = Builder {
        desc,
        files,
        graph: TextureGraph::new(),
        by_name: HashMap::new(),
        images: HashMap::new(),
        memory: ImageMemory::new(max_image_memory),
    };
    for texture in &desc.textures {
        let id = builder.texture(texture)?;
        builder
            .by_name
            .insert((texture.kind.clone(), texture.name.clone()), id);
    }
    Ok(SceneTextures {
        graph: Arc::new(builder.graph),
        by_name: builder.by_name,
        memory: builder.memory,
    })
}

/// How an integer image's values become linear (pbrt-v4's `ColorEncoding`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Encoding {
    Linear,
    Srgb,
    Gamma(f64),
}

impl Encoding {
    /// How a file named `name` is read when nothing says: sRGB for a PNG (as pbrt-v4 reads an
    /// 8-bit PNG), linear for every other.
    pub(crate) fn default_for(name: &str) -> Self {
        if name.to_ascii_lowercase().ends_with(".png") {
            Encoding::Srgb
        } else {
            Encoding::Linear
        }
    }

    /// The linear value of an encoded one in `[0, 1]`.
    fn decode(self, v: f64) -> f64 {
        match self {
            Encoding::Linear => v,
            Encoding::Srgb => {
                if v <= 0.04045 {
                    v / 12.92
                } else {
                    ((v + 0.055) / 1.055).powf(2.4)
                }
            }
            Encoding::Gamma(g) => v.max(0.0).powf(g),
        }
    }

    /// A key for the image cache.
    fn key(self) -> u64 {
        match self {
            Encoding::Linear => 0,
            Encoding::Srgb => 1,
            Encoding::Gamma(g) => g.to_bits() | 3,
        }
    }
}

/// An image read once, by file, encoding and whether only its first channel is kept.
type ImageKey = (PathBuf, u64, bool);

struct Builder<'d> {
    desc: &'d Description,
    files: &'d Files,
    graph: TextureGraph,
    by_name: HashMap<(String, String), NodeId>,
    images: HashMap<ImageKey, Arc<TextureImage>>,
    memory: ImageMemory,
}

impl Builder<'_> {
    /// Adds a node, the graph's limits said at `entity`.
    fn add(&mut self, entity: &Entity, node: TextureNode) -> Result<NodeId, SceneError> {
        self.graph
            .add(node)
            .map_err(|e| entity.error(e.to_string()))
    }

    /// A constant node.
    fn constant(&mut self, entity: &Entity, c: Color) -> Result<NodeId, SceneError> {
        self.add(entity, TextureNode::Constant(c))
    }

    /// The float input `name` of `entity`: a float texture, a `float`, or `default`.
    fn float_input(
        &mut self,
        entity: &Entity,
        name: &str,
        default: f64,
    ) -> Result<NodeId, SceneError> {
        if let Some(p) = entity.params.find(name, &[ParamType::Texture]) {
            return lookup(&self.by_name, self.desc, p, "float", texture_name(p)?);
        }
        let v = entity.params.float_or(name, default)?;
        if !v.is_finite() {
            return Err(entity.error(format!("\"{name}\" is a finite number, found {v}")));
        }
        self.constant(entity, Color::new(v, v, v))
    }

    /// The input `name` of a `kind` texture: a texture of that kind, or a value (a float, or
    /// for a spectrum texture an rgb or spectrum), or `default` (grey).
    fn input(
        &mut self,
        entity: &Entity,
        kind: &str,
        name: &str,
        default: f64,
    ) -> Result<NodeId, SceneError> {
        if kind == "float" {
            return self.float_input(entity, name, default);
        }
        if let Some(p) = entity.params.find(name, &[ParamType::Texture]) {
            return lookup(&self.by_name, self.desc, p, kind, texture_name(p)?);
        }
        let c = self.spectrum_value(entity, name)?;
        let c = c.unwrap_or(Color::new(default, default, default));
        self.constant(entity, c)
    }

    /// A spectrum texture's value parameter: rgb, spectrum or blackbody.
    fn spectrum_value(&self, entity: &Entity, name: &str) -> Result<Option<Color>, SceneError> {
        match entity.params.find(
            name,
            &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
        ) {
            Some(p) => Ok(Some(spectra::color(p, SpectrumUse::Albedo)?)),
            None => Ok(None),
        }
    }

    /// A value of the texture's kind (for `bilerp`'s corners and `constant`'s value).
    fn value(
        &self,
        entity: &Entity,
        kind: &str,
        name: &str,
        default: f64,
    ) -> Result<Color, SceneError> {
        if kind == "float" {
            let v = entity.params.float_or(name, default)?;
            return Ok(Color::new(v, v, v));
        }
        Ok(self
            .spectrum_value(entity, name)?
            .unwrap_or(Color::new(default, default, default)))
    }

    fn texture(&mut self, texture: &TextureEntity) -> Result<NodeId, SceneError> {
        let entity = &texture.entity;
        let kind = texture.kind.as_str();
        let params = &entity.params;
        let node = match entity.name.as_str() {
            "constant" => TextureNode::Constant(self.value(entity, kind, "value", 1.0)?),
            "scale" => TextureNode::Scale {
                tex: self.input(entity, kind, "tex", 1.0)?,
                scale: self.float_input(entity, "scale", 1.0)?,
            },
            "mix" => TextureNode::Mix {
                tex1: self.input(entity, kind, "tex1", 0.0)?,
                tex2: self.input(entity, kind, "tex2", 1.0)?,
                amount: self.float_input(entity, "amount", 0.5)?,
            },
            "directionmix" => {
                let dir = vector3(entity, "dir", DVec3::Y)?;
                let dir = texture
                    .world_from_texture
                    .transform_vector3(dir)
                    .try_normalize()
                    .ok_or_else(|| entity.error("a directionmix's \"dir\" is not zero"))?;
                TextureNode::DirectionMix {
                    tex1: self.input(entity, kind, "tex1", 0.0)?,
                    tex2: self.input(entity, kind, "tex2", 1.0)?,
                    dir,
                }
            }
            "checkerboard" => {
                let dimension = params.integer("dimension")?.map_or(2, |(d, _)| d);
                let tex1 = self.input(entity, kind, "tex1", 1.0)?;
                let tex2 = self.input(entity, kind, "tex2", 0.0)?;
                match dimension {
                    2 => TextureNode::Checkerboard2D {
                        mapping: mapping(texture)?,
                        tex1,
                        tex2,
                    },
                    3 => TextureNode::Checkerboard3D {
                        texture_from_world: texture_from_world(texture)?,
                        tex1,
                        tex2,
                    },
                    d => {
                        return Err(
                            entity.error(format!("a checkerboard's dimension is 2 or 3, not {d}"))
                        )
                    }
                }
            }
            "bilerp" => TextureNode::Bilerp {
                mapping: mapping(texture)?,
                corners: [
                    self.value(entity, kind, "v00", 0.0)?,
                    self.value(entity, kind, "v01", 1.0)?,
                    self.value(entity, kind, "v10", 0.0)?,
                    self.value(entity, kind, "v11", 1.0)?,
                ],
            },
            "imagemap" => self.image(texture)?,
            "dots" => TextureNode::Dots {
                mapping: mapping(texture)?,
                inside: self.input(entity, kind, "inside", 1.0)?,
                outside: self.input(entity, kind, "outside", 0.0)?,
            },
            class @ ("fbm" | "wrinkled" | "windy") => {
                if kind != "float" {
                    return Err(entity.error(format!(
                        "\"{class}\" is a float texture in pbrt-v4, not a {kind} one"
                    )));
                }
                let texture_from_world = texture_from_world(texture)?;
                match class {
                    "windy" => TextureNode::Windy { texture_from_world },
                    "fbm" => TextureNode::Fbm {
                        texture_from_world,
                        omega: finite(entity, "roughness", 0.5)?,
                        octaves: octaves(entity)?,
                    },
                    _ => TextureNode::Wrinkled {
                        texture_from_world,
                        omega: finite(entity, "roughness", 0.5)?,
                        octaves: octaves(entity)?,
                    },
                }
            }
            "marble" => {
                if kind != "spectrum" {
                    return Err(entity
                        .error("\"marble\" is a spectrum texture in pbrt-v4, not a float one"));
                }
                TextureNode::Marble {
                    texture_from_world: texture_from_world(texture)?,
                    omega: finite(entity, "roughness", 0.5)?,
                    octaves: octaves(entity)?,
                    scale: finite(entity, "scale", 1.0)?,
                    variation: finite(entity, "variation", 0.2)?,
                }
            }
            "ptex" => {
                return Err(entity.error(
                    "the texture class \"ptex\" is not one rayforge reads (no Ptex reader); \
                     convert the texture to an image and use \"imagemap\"",
                ))
            }
            other => {
                return Err(entity.error(format!(
                    "\"{}\" is not a pbrt-v4 texture class",
                    crate::error::clip_to(other, 60)
                )))
            }
        };
        self.add(entity, node)
    }

    /// An `imagemap` texture's node.
    fn image(&mut self, texture: &TextureEntity) -> Result<TextureNode, SceneError> {
        let entity = &texture.entity;
        let params = &entity.params;
        let Some((name, file_param)) = params.string("filename")? else {
            return Err(entity.error("an imagemap names its image: \"string filename\""));
        };
        let path = self.files.resolve(name);
        self.files.check(&path, &file_param.loc, "filename")?;
        let encoding = match params.string("encoding")? {
            None => Encoding::default_for(name),
            Some((e, p)) => parse_encoding(e).ok_or_else(|| {
                p.error(format!(
                    "an encoding is \"linear\", \"sRGB\" or \"gamma G\" (G above 0), not \"{}\"",
                    crate::error::clip_to(e, 40)
                ))
            })?,
        };
        let filter = match params.string("filter")? {
            None => ImageFilter::Bilinear,
            Some(("point", _)) => ImageFilter::Point,
            Some(("bilinear" | "trilinear" | "ewa" | "EWA", _)) => ImageFilter::Bilinear,
            Some((f, p)) => {
                return Err(p.error(format!(
                    "a filter is \"point\", \"bilinear\", \"trilinear\" or \"ewa\", not \"{}\"",
                    crate::error::clip_to(f, 40)
                )))
            }
        };
        // Read for its place; the filters rayforge uses have no anisotropy to bound.
        let _ = params.float("maxanisotropy")?;
        let wrap = match params.string("wrap")? {
            None | Some(("repeat", _)) => Wrap::Repeat,
            Some(("black", _)) => Wrap::Black,
            Some(("clamp", _)) => Wrap::Clamp,
            Some(("octahedralsphere", _)) => Wrap::OctahedralSphere,
            Some((w, p)) => {
                return Err(p.error(format!(
                    "a wrap mode is \"repeat\", \"black\", \"clamp\" or \"octahedralsphere\", \
                     not \"{}\"",
                    crate::error::clip_to(w, 40)
                )))
            }
        };
        let scale = params.float_or("scale", 1.0)?;
        if !scale.is_finite() {
            return Err(entity.error(format!("an imagemap's scale is finite, found {scale}")));
        }
        let invert = params.bool_or("invert", false)?;
        let first_channel = texture.kind == "float";
        let key = (path.clone(), encoding.key(), first_channel);
        let image = match self.images.get(&key) {
            Some(image) => image.clone(),
            None => {
                let image = Arc::new(self.read_image(&path, encoding, first_channel).map_err(
                    |e| file_param.error(format!("cannot read `{}`: {e}", path.display())),
                )?);
                self.images.insert(key, image.clone());
                image
            }
        };
        Ok(TextureNode::Image {
            image,
            mapping: mapping(texture)?,
            filter,
            wrap,
            scale,
            invert,
        })
    }

    /// The image at `path` in linear colour (integer formats decoded by `encoding`), only its
    /// first channel (spread over three) where `first_channel`; the error is the reason.
    fn read_image(
        &mut self,
        path: &std::path::Path,
        encoding: Encoding,
        first_channel: bool,
    ) -> Result<TextureImage, String> {
        let (width, height, mut texels) = read_linear(path, encoding, &mut self.memory)?;
        if first_channel {
            for c in &mut texels {
                *c = Color::new(c.red, c.red, c.red);
            }
        }
        TextureImage::new(width, height, texels).ok_or_else(|| "the image is empty".to_string())
    }
}

/// The image at `path` in linear colour, its width, height and texels (row by row from the
/// top): an HDR format as it is, an integer format decoded by `encoding`, within the room
/// `memory` has left and held there; the error is the reason, for the caller to name the file.
/// Textures and the lights with images read through it.
pub(crate) fn read_linear(
    path: &std::path::Path,
    encoding: Encoding,
    memory: &mut ImageMemory,
) -> Result<(usize, usize, Vec<Color>), String> {
    let bytes = read_bounded(path, MAX_IMAGE_BYTES)?;
    let room = memory.room();
    let (width, height, texels) = match decode_hdr_image(&bytes, room, COLOR_BYTES) {
        Some(image) => {
            let image = image?;
            (image.width, image.height, image.texels)
        }
        None => {
            let tga = path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("tga"));
            let fallback = tga.then_some(image::ImageFormat::Tga);
            let texture = images::decode_as(&bytes, room, fallback)?;
            let (w, h) = (texture.width(), texture.height());
            let mut texels = texture.into_pixels();
            if encoding != Encoding::Linear {
                for c in &mut texels {
                    *c = Color::new(
                        encoding.decode(c.red),
                        encoding.decode(c.green),
                        encoding.decode(c.blue),
                    );
                }
            }
            (w, h, texels)
        }
    };
    memory.hold(texels.len() as u64 * COLOR_BYTES);
    Ok((width, height, texels))
}

/// The float parameter `name` of `entity` (`default` when absent), finite.
fn finite(entity: &Entity, name: &str, default: f64) -> Result<f64, SceneError> {
    let v = entity.params.float_or(name, default)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(entity.error(format!("\"{name}\" is a finite number, found {v}")))
    }
}

/// A noise texture's `octaves` (pbrt-v4's default 8), from 0 to [`MAX_OCTAVES`].
fn octaves(entity: &Entity) -> Result<u32, SceneError> {
    match entity.params.integer("octaves")? {
        None => Ok(8),
        Some((n, _)) if (0..=i64::from(MAX_OCTAVES)).contains(&n) => Ok(n as u32),
        Some((n, p)) => Err(p.error(format!(
            "octaves are from 0 to {MAX_OCTAVES} (each costs a noise at every hit), found {n}"
        ))),
    }
}

/// pbrt-v4's encodings: `linear`, `sRGB`, `gamma G`.
fn parse_encoding(text: &str) -> Option<Encoding> {
    match text {
        "linear" => Some(Encoding::Linear),
        "sRGB" => Some(Encoding::Srgb),
        _ => {
            let g: f64 = text.strip_prefix("gamma ")?.trim().parse().ok()?;
            (g > 0.0 && g.is_finite()).then_some(Encoding::Gamma(g))
        }
    }
}

/// A `vector3` parameter of one vector, `default` when absent.
fn vector3(entity: &Entity, name: &str, default: DVec3) -> Result<DVec3, SceneError> {
    match entity.params.points3(name, ParamType::Vector3)? {
        None => Ok(default),
        Some((v, _)) if v.len() == 1 && v[0].is_finite() => Ok(v[0]),
        Some((_, p)) => Err(p.error("takes one finite vector")),
    }
}

/// From the world into the texture's space: the inverse of the transform where it was made.
fn texture_from_world(texture: &TextureEntity) -> Result<DAffine3, SceneError> {
    let m: DMat4 = texture.world_from_texture;
    let d = m.determinant();
    if d == 0.0 || !d.is_finite() {
        return Err(texture
            .entity
            .error("the texture is made under a singular transform"));
    }
    Ok(DAffine3::from_mat4(m.inverse()))
}

/// The texture's 2D mapping (`mapping`, default `uv`).
fn mapping(texture: &TextureEntity) -> Result<Mapping2D, SceneError> {
    let entity = &texture.entity;
    let params = &entity.params;
    let finite = |name: &str, default: f64| -> Result<f64, SceneError> {
        let v = params.float_or(name, default)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(entity.error(format!("\"{name}\" is a finite number, found {v}")))
        }
    };
    Ok(match params.string("mapping")? {
        None | Some(("uv", _)) => Mapping2D::Uv {
            scale: (finite("uscale", 1.0)?, finite("vscale", 1.0)?),
            delta: (finite("udelta", 0.0)?, finite("vdelta", 0.0)?),
        },
        Some(("spherical", _)) => Mapping2D::Spherical {
            texture_from_world: texture_from_world(texture)?,
        },
        Some(("cylindrical", _)) => Mapping2D::Cylindrical {
            texture_from_world: texture_from_world(texture)?,
        },
        Some(("planar", _)) => Mapping2D::Planar {
            texture_from_world: texture_from_world(texture)?,
            vs: vector3(entity, "v1", DVec3::X)?,
            vt: vector3(entity, "v2", DVec3::Y)?,
            delta: (finite("udelta", 0.0)?, finite("vdelta", 0.0)?),
        },
        Some((m, p)) => {
            return Err(p.error(format!(
                "a mapping is \"uv\", \"spherical\", \"cylindrical\" or \"planar\", not \"{}\"",
                crate::error::clip_to(m, 40)
            )))
        }
    })
}
