//! Textures as pbrt-v4 composes them: a small graph of nodes (constants, images, checkerboards,
//! bilinear patches, products and blends, and the noise textures of [`super::texture_noise`]), each read at a surface point through a mapping from
//! the point to texture coordinates, so that a material's reflectance or roughness can vary
//! over a surface as a scene file describes it.
//!
//! The graph is a list: a node names its inputs by their place in the list, and a node may
//! only name nodes before it, so the graph cannot loop and a lookup is a walk of at most
//! [`MAX_TEXTURE_DEPTH`] nested calls. The list is made once, when the scene loads, and shared
//! ([`Arc`]) by every material that reads it; reading it at a hit allocates nothing.
//!
//! pbrt-v4 has float and spectrum textures. Here both are one kind of node whose value is a
//! colour: a float texture is a grey one (its three channels equal), and where a float is
//! wanted (a roughness, a mix's amount, a cut-out's alpha) the red channel is read. pbrt-v4's
//! float image textures read an image's first channel, and so do these.
//!
//! What is not done as pbrt-v4 does: a path tracer traces no ray differentials, so there is no
//! footprint to filter over. Image lookups are point or bilinear on the full image; pbrt-v4's
//! `trilinear` and `ewa` MIP-map filters read as bilinear (the pixel's many samples average
//! what a MIP map would have prefiltered), and checkerboards are not antialiased (pbrt-v4's
//! box-filtered checkerboard with a zero footprint is exactly this one).

use super::material::MaterialMix;
use super::physical::{conductor_of_reflectance, HitParameters, Physical};
use super::texture_noise as noise;
use crate::color::Color;
use crate::math::{Point3, Vec3};
use glam::DAffine3;
use std::f64::consts::PI;
use std::sync::Arc;

/// The most nodes one scene's texture graph may have: each costs memory, and a file should not
/// make unbounded numbers of them.
pub const MAX_TEXTURE_NODES: usize = 1 << 16;

/// The longest chain of nodes a lookup walks (a mix of a scale of a checkerboard of …): the
/// depth of the recursion at a hit, so it is bounded.
pub const MAX_TEXTURE_DEPTH: usize = 64;

/// Where a texture is read: what pbrt-v4's `TextureEvalContext` holds, less the differentials.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureContext {
    /// The surface's (u, v) (for meshes without coordinates, pbrt-v4's defaults).
    pub uv: (f64, f64),
    /// The point, in the world.
    pub point: Point3,
    /// The surface's geometric normal, in the world (unit length).
    pub normal: Vec3,
}

/// A node of a [`TextureGraph`], by its place in the list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeId(u32);

/// How a surface point becomes 2D texture coordinates (s, t): pbrt-v4's `TextureMapping2D`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mapping2D {
    /// `(su · u + du, sv · v + dv)` (pbrt-v4's `uv`, with `uscale`, `vscale`, `udelta`,
    /// `vdelta`).
    Uv {
        /// `(su, sv)`.
        scale: (f64, f64),
        /// `(du, dv)`.
        delta: (f64, f64),
    },
    /// The point's direction from the texture space's origin: `s = θ / π` (θ from +z),
    /// `t = φ / 2π` (φ from +x towards +y, in `[0, 2π)`).
    Spherical {
        /// From the world into texture space (the inverse of the transform in force where the
        /// texture was made).
        texture_from_world: DAffine3,
    },
    /// Around the texture space's z axis: `s = (π + atan2(y, x)) / 2π`, `t = z`.
    Cylindrical {
        /// From the world into texture space.
        texture_from_world: DAffine3,
    },
    /// `s = ds + p · vs`, `t = dt + p · vt` with `p` the point in texture space.
    Planar {
        /// From the world into texture space.
        texture_from_world: DAffine3,
        /// `vs` (pbrt-v4's `v1`).
        vs: Vec3,
        /// `vt` (`v2`).
        vt: Vec3,
        /// `(ds, dt)` (`udelta`, `vdelta`).
        delta: (f64, f64),
    },
}

impl Mapping2D {
    /// The plain (u, v) mapping.
    pub const UV: Self = Mapping2D::Uv {
        scale: (1.0, 1.0),
        delta: (0.0, 0.0),
    };

    /// The texture coordinates of `ctx`.
    #[inline]
    pub fn map(&self, ctx: &TextureContext) -> (f64, f64) {
        match *self {
            Mapping2D::Uv { scale, delta } => {
                (scale.0 * ctx.uv.0 + delta.0, scale.1 * ctx.uv.1 + delta.1)
            }
            Mapping2D::Spherical { texture_from_world } => {
                let p = texture_from_world.transform_point3(ctx.point);
                let Some(d) = p.try_normalize() else {
                    return (0.0, 0.0);
                };
                let theta = d.z.clamp(-1.0, 1.0).acos();
                let mut phi = d.y.atan2(d.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                (theta / PI, phi / (2.0 * PI))
            }
            Mapping2D::Cylindrical { texture_from_world } => {
                let p = texture_from_world.transform_point3(ctx.point);
                ((PI + p.y.atan2(p.x)) / (2.0 * PI), p.z)
            }
            Mapping2D::Planar {
                texture_from_world,
                vs,
                vt,
                delta,
            } => {
                let p = texture_from_world.transform_point3(ctx.point);
                (delta.0 + p.dot(vs), delta.1 + p.dot(vt))
            }
        }
    }
}

/// What an image gives outside `[0, 1]²` (pbrt-v4's `wrap`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    /// The image tiles the plane (pbrt-v4's default).
    #[default]
    Repeat,
    /// Black outside.
    Black,
    /// The nearest edge pixel.
    Clamp,
    /// An equal-area octahedral map of the sphere: across an edge the image continues
    /// mirrored about the edge's middle, as the sphere does.
    OctahedralSphere,
}

/// How an image is read between pixel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ImageFilter {
    /// The pixel the point falls in (pbrt-v4's `point`).
    Point,
    /// The four nearest pixel centres, blended (pbrt-v4's `bilinear`, and what its
    /// `trilinear` and `ewa` are read as: see the [module](self)).
    #[default]
    Bilinear,
}

/// An image for textures, in linear colour, row 0 at the top, read as pbrt-v4 reads its
/// images: pixel `(x, y)` has its centre at `((x + ½) / W, (y + ½) / H)`.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureImage {
    width: usize,
    height: usize,
    texels: Vec<Color>,
}

impl TextureImage {
    /// An image from its pixels, row by row from the top; `None` when the sizes disagree, the
    /// image is empty, or it is too large to index.
    pub fn new(width: usize, height: usize, texels: Vec<Color>) -> Option<Self> {
        let ok = width > 0
            && height > 0
            && width <= i32::MAX as usize
            && height <= i32::MAX as usize
            && width.checked_mul(height) == Some(texels.len());
        ok.then_some(Self {
            width,
            height,
            texels,
        })
    }

    /// Pixels across.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Pixels down.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The pixel at column `x`, row `y` (either may be outside the image), as `wrap` says.
    #[inline]
    pub fn texel(&self, x: i64, y: i64, wrap: Wrap) -> Color {
        let (w, h) = (self.width as i64, self.height as i64);
        let (x, y) = match wrap {
            Wrap::Repeat => (x.rem_euclid(w), y.rem_euclid(h)),
            Wrap::Clamp => (x.clamp(0, w - 1), y.clamp(0, h - 1)),
            Wrap::Black => {
                if x < 0 || y < 0 || x >= w || y >= h {
                    return Color::BLACK;
                }
                (x, y)
            }
            Wrap::OctahedralSphere => {
                let (mut x, mut y) = (x, y);
                // Each step mirrors across one edge; far outside, repeat the folding (a point
                // is never more than an image away for lookups between centres).
                for _ in 0..4 {
                    if x < 0 {
                        x = -x - 1;
                        y = h - 1 - y;
                    } else if x >= w {
                        x = 2 * w - 1 - x;
                        y = h - 1 - y;
                    }
                    if y < 0 {
                        x = w - 1 - x;
                        y = -y - 1;
                    } else if y >= h {
                        x = w - 1 - x;
                        y = 2 * h - 1 - y;
                    }
                }
                (x.clamp(0, w - 1), y.clamp(0, h - 1))
            }
        };
        self.texels[y as usize * self.width + x as usize]
    }

    /// The image at `(s, t)`, `t` down from the top row, read by `filter`.
    #[inline]
    pub fn lookup(&self, s: f64, t: f64, filter: ImageFilter, wrap: Wrap) -> Color {
        if !(s.is_finite() && t.is_finite()) {
            return Color::BLACK;
        }
        // Far-off coordinates (a huge `uscale`) stay inside what `i64` holds.
        const FAR: f64 = 1e15;
        let x = (s * self.width as f64).clamp(-FAR, FAR);
        let y = (t * self.height as f64).clamp(-FAR, FAR);
        match filter {
            ImageFilter::Point => self.texel(x.floor() as i64, y.floor() as i64, wrap),
            ImageFilter::Bilinear => {
                let (x, y) = (x - 0.5, y - 0.5);
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                let top = self
                    .texel(x0, y0, wrap)
                    .lerp(self.texel(x0 + 1, y0, wrap), fx);
                let bottom = self
                    .texel(x0, y0 + 1, wrap)
                    .lerp(self.texel(x0 + 1, y0 + 1, wrap), fx);
                top.lerp(bottom, fy)
            }
        }
    }
}

/// One texture of a graph.
#[derive(Debug, Clone, PartialEq)]
pub enum TextureNode {
    /// The same value everywhere.
    Constant(Color),
    /// An image read through a mapping (pbrt-v4's `imagemap`): `scale` times the image at
    /// `(s, 1 − t)` (pbrt-v4 puts t = 0 at the image's bottom), then, where `invert`, one less
    /// that; never below zero.
    Image {
        /// The pixels (shared between the textures that read the same file the same way).
        image: Arc<TextureImage>,
        /// How the point becomes (s, t).
        mapping: Mapping2D,
        /// How pixels are blended.
        filter: ImageFilter,
        /// What lies outside the image.
        wrap: Wrap,
        /// A factor on the image's values.
        scale: f64,
        /// Whether the value is `1 − value`.
        invert: bool,
    },
    /// Squares of `tex1` and `tex2` in (s, t), `tex1` where `⌊s⌋ + ⌊t⌋` is even (pbrt-v4's
    /// 2D `checkerboard`).
    Checkerboard2D {
        /// How the point becomes (s, t).
        mapping: Mapping2D,
        /// The even squares' texture.
        tex1: NodeId,
        /// The odd squares'.
        tex2: NodeId,
    },
    /// Cubes of `tex1` and `tex2` in texture space, `tex1` where `⌊x⌋ + ⌊y⌋ + ⌊z⌋` is even
    /// (pbrt-v4's `checkerboard` of `dimension` 3).
    Checkerboard3D {
        /// From the world into texture space.
        texture_from_world: DAffine3,
        /// The even cubes' texture.
        tex1: NodeId,
        /// The odd cubes'.
        tex2: NodeId,
    },
    /// The bilinear blend of four corner values over (s, t) (pbrt-v4's `bilerp`): `v00` at
    /// (0, 0), `v10` at (1, 0), `v01` at (0, 1), `v11` at (1, 1), and beyond them the same
    /// formula continued.
    Bilerp {
        /// How the point becomes (s, t).
        mapping: Mapping2D,
        /// `[v00, v01, v10, v11]`.
        corners: [Color; 4],
    },
    /// `tex × scale` (pbrt-v4's `scale`; `scale` is read as a float).
    Scale {
        /// The texture.
        tex: NodeId,
        /// The float factor.
        scale: NodeId,
    },
    /// `(1 − amount) tex1 + amount tex2` (pbrt-v4's `mix`; `amount` is a float).
    Mix {
        /// Where the amount is 0.
        tex1: NodeId,
        /// Where it is 1.
        tex2: NodeId,
        /// The float amount.
        amount: NodeId,
    },
    /// pbrt-v4's `fbm` (a float): fractional Brownian motion of `octaves` octaves, each `omega`
    /// times the last, at the point in texture space.
    Fbm {
        /// From the world into texture space.
        texture_from_world: DAffine3,
        /// pbrt-v4's `roughness`.
        omega: f64,
        /// `octaves`.
        octaves: u32,
    },
    /// pbrt-v4's `wrinkled` (a float): turbulence, the sum of the octaves' magnitudes.
    Wrinkled {
        /// From the world into texture space.
        texture_from_world: DAffine3,
        /// pbrt-v4's `roughness`.
        omega: f64,
        /// `octaves`.
        octaves: u32,
    },
    /// pbrt-v4's `windy` (a float): wave heights scaled by a slower wind strength.
    Windy {
        /// From the world into texture space.
        texture_from_world: DAffine3,
    },
    /// pbrt-v4's `marble` (a spectrum): bands of its grey spline, disturbed by fBm.
    Marble {
        /// From the world into texture space.
        texture_from_world: DAffine3,
        /// pbrt-v4's `roughness`.
        omega: f64,
        /// `octaves`.
        octaves: u32,
        /// A factor on the point (`scale`).
        scale: f64,
        /// The fBm's weight (`variation`).
        variation: f64,
    },
    /// pbrt-v4's `dots`: `inside` in the polka dots of the (s, t) plane, `outside` elsewhere.
    Dots {
        /// How the point becomes (s, t).
        mapping: Mapping2D,
        /// The dots' texture.
        inside: NodeId,
        /// The rest's.
        outside: NodeId,
    },
    /// `a tex1 + (1 − a) tex2` with `a = |n · dir|`, the normal's alignment with `dir`
    /// (pbrt-v4's `directionmix`).
    DirectionMix {
        /// Where the surface faces along `dir`.
        tex1: NodeId,
        /// Where it is edge-on to it.
        tex2: NodeId,
        /// The direction, in the world (unit length).
        dir: Vec3,
    },
}

impl TextureNode {
    /// The nodes this one reads.
    fn inputs(&self) -> impl Iterator<Item = NodeId> {
        let list: [Option<NodeId>; 3] = match *self {
            TextureNode::Constant(_)
            | TextureNode::Image { .. }
            | TextureNode::Bilerp { .. }
            | TextureNode::Fbm { .. }
            | TextureNode::Wrinkled { .. }
            | TextureNode::Windy { .. }
            | TextureNode::Marble { .. } => [None; 3],
            TextureNode::Dots {
                inside, outside, ..
            } => [Some(inside), Some(outside), None],
            TextureNode::Checkerboard2D { tex1, tex2, .. }
            | TextureNode::Checkerboard3D { tex1, tex2, .. }
            | TextureNode::DirectionMix { tex1, tex2, .. } => [Some(tex1), Some(tex2), None],
            TextureNode::Scale { tex, scale } => [Some(tex), Some(scale), None],
            TextureNode::Mix { tex1, tex2, amount } => [Some(tex1), Some(tex2), Some(amount)],
        };
        list.into_iter().flatten()
    }
}

/// Why a node cannot join a graph.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TextureError {
    /// The graph is full.
    #[error("a scene may have at most {MAX_TEXTURE_NODES} textures (nodes of its texture graph)")]
    TooManyNodes,
    /// The chain of textures reading textures is too long.
    #[error("textures may read textures at most {MAX_TEXTURE_DEPTH} deep")]
    TooDeep,
    /// An input that is not (yet) in the graph.
    #[error("a texture reads a texture that is not made before it")]
    UnknownInput,
}

/// The textures of a scene: nodes that read only nodes before them (see the [module](self)).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TextureGraph {
    nodes: Vec<TextureNode>,
    /// How deep each node's lookup goes (1 for a node without inputs).
    depths: Vec<usize>,
}

impl TextureGraph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `node`, whose inputs must be in the graph already, and gives its place.
    pub fn add(&mut self, node: TextureNode) -> Result<NodeId, TextureError> {
        if self.nodes.len() >= MAX_TEXTURE_NODES {
            return Err(TextureError::TooManyNodes);
        }
        let mut depth = 1;
        for input in node.inputs() {
            let d = self
                .depths
                .get(input.0 as usize)
                .ok_or(TextureError::UnknownInput)?;
            depth = depth.max(d + 1);
        }
        if depth > MAX_TEXTURE_DEPTH {
            return Err(TextureError::TooDeep);
        }
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(node);
        self.depths.push(depth);
        Ok(id)
    }

    /// Nodes in the graph.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the graph has no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node at `id`.
    pub fn node(&self, id: NodeId) -> Option<&TextureNode> {
        self.nodes.get(id.0 as usize)
    }

    /// The value of node `id` at `ctx` (black for a node not in the graph).
    pub fn evaluate(&self, id: NodeId, ctx: &TextureContext) -> Color {
        let Some(node) = self.nodes.get(id.0 as usize) else {
            return Color::BLACK;
        };
        match node {
            TextureNode::Constant(c) => *c,
            TextureNode::Image {
                image,
                mapping,
                filter,
                wrap,
                scale,
                invert,
            } => {
                let (s, t) = mapping.map(ctx);
                let v = image.lookup(s, 1.0 - t, *filter, *wrap) * *scale;
                let v = if *invert { Color::WHITE - v } else { v };
                Color::new(v.red.max(0.0), v.green.max(0.0), v.blue.max(0.0))
            }
            TextureNode::Checkerboard2D {
                mapping,
                tex1,
                tex2,
            } => {
                let (s, t) = mapping.map(ctx);
                let odd = (s.floor() + t.floor()).rem_euclid(2.0) != 0.0;
                self.evaluate(if odd { *tex2 } else { *tex1 }, ctx)
            }
            TextureNode::Checkerboard3D {
                texture_from_world,
                tex1,
                tex2,
            } => {
                let p = texture_from_world.transform_point3(ctx.point);
                let odd = (p.x.floor() + p.y.floor() + p.z.floor()).rem_euclid(2.0) != 0.0;
                self.evaluate(if odd { *tex2 } else { *tex1 }, ctx)
            }
            TextureNode::Bilerp { mapping, corners } => {
                let (s, t) = mapping.map(ctx);
                let [v00, v01, v10, v11] = *corners;
                v00 * ((1.0 - s) * (1.0 - t))
                    + v10 * (s * (1.0 - t))
                    + v01 * ((1.0 - s) * t)
                    + v11 * (s * t)
            }
            TextureNode::Scale { tex, scale } => {
                let k = self.evaluate(*scale, ctx).red;
                if k == 0.0 {
                    return Color::BLACK;
                }
                self.evaluate(*tex, ctx) * k
            }
            TextureNode::Mix { tex1, tex2, amount } => {
                let a = self.evaluate(*amount, ctx).red;
                self.blend(*tex1, *tex2, a, ctx)
            }
            TextureNode::DirectionMix { tex1, tex2, dir } => {
                let a = ctx.normal.dot(*dir).abs();
                self.blend(*tex2, *tex1, a, ctx)
            }
            TextureNode::Fbm {
                texture_from_world,
                omega,
                octaves,
            } => grey(noise::fbm(
                texture_from_world.transform_point3(ctx.point),
                *omega,
                *octaves,
            )),
            TextureNode::Wrinkled {
                texture_from_world,
                omega,
                octaves,
            } => grey(noise::turbulence(
                texture_from_world.transform_point3(ctx.point),
                *omega,
                *octaves,
            )),
            TextureNode::Windy { texture_from_world } => {
                grey(noise::windy(texture_from_world.transform_point3(ctx.point)))
            }
            TextureNode::Marble {
                texture_from_world,
                omega,
                octaves,
                scale,
                variation,
            } => noise::marble(
                texture_from_world.transform_point3(ctx.point) * *scale,
                *omega,
                *octaves,
                *variation,
            ),
            TextureNode::Dots {
                mapping,
                inside,
                outside,
            } => {
                let (s, t) = mapping.map(ctx);
                let id = if noise::inside_polka_dot(s, t) {
                    *inside
                } else {
                    *outside
                };
                self.evaluate(id, ctx)
            }
        }
    }

    /// `(1 − a) · tex1 + a · tex2`, reading only the textures whose weight is not zero (as
    /// pbrt-v4 does).
    #[inline]
    fn blend(&self, tex1: NodeId, tex2: NodeId, a: f64, ctx: &TextureContext) -> Color {
        let one = if a != 1.0 {
            self.evaluate(tex1, ctx) * (1.0 - a)
        } else {
            Color::BLACK
        };
        let two = if a != 0.0 {
            self.evaluate(tex2, ctx) * a
        } else {
            Color::BLACK
        };
        one + two
    }
}

/// A float as a grey colour (how float textures hold their values).
#[inline]
fn grey(v: f64) -> Color {
    Color::new(v, v, v)
}

/// A float parameter: a fixed number, or a float texture's value (its red channel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FloatInput {
    /// The same everywhere.
    Fixed(f64),
    /// Read from this node.
    Texture(NodeId),
}

impl FloatInput {
    /// The value at `ctx`.
    #[inline]
    pub fn at(self, graph: &TextureGraph, ctx: &TextureContext) -> f64 {
        match self {
            FloatInput::Fixed(v) => v,
            FloatInput::Texture(id) => graph.evaluate(id, ctx).red,
        }
    }
}

/// GGX widths read from two float parameters (along the tangent and across it), at least one
/// of them a texture, each a roughness made a width as pbrt-v4's `RoughnessToAlpha` makes it
/// (`√r`) unless `remap` is false, and held in `[0, 1]` (rayforge's widest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexturedWidths {
    /// pbrt-v4's `uroughness` (or `roughness`).
    pub u: FloatInput,
    /// `vroughness` (or `roughness`).
    pub v: FloatInput,
    /// `remaproughness`.
    pub remap: bool,
}

impl TexturedWidths {
    /// The two widths at `ctx`.
    #[inline]
    pub fn at(&self, graph: &TextureGraph, ctx: &TextureContext) -> (f64, f64) {
        let width = |input: FloatInput| {
            let r = input.at(graph, ctx).max(0.0);
            let alpha = if self.remap { r.sqrt() } else { r };
            alpha.min(1.0)
        };
        (width(self.u), width(self.v))
    }
}

/// A metal's index from textures: `eta` and `k` (each where textured), or a `reflectance`
/// read as pbrt-v4 reads it ([`conductor_of_reflectance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MetalTextures {
    /// The index's parts, each a spectrum texture where given.
    Index {
        /// The real part.
        eta: Option<NodeId>,
        /// The extinction coefficient.
        k: Option<NodeId>,
    },
    /// The reflectance at normal incidence.
    Reflectance(NodeId),
}

/// A layered material's slab from textures, each where given.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LayerTextures {
    /// The thickness (a float).
    pub thickness: Option<FloatInput>,
    /// The medium's albedo (a spectrum).
    pub albedo: Option<NodeId>,
    /// The medium's asymmetry (a float).
    pub g: Option<FloatInput>,
}

/// The textures a material's parameters are read from, each replacing the fixed value where
/// given: the material's colour (a diffuse or coated surface's reflectance), the outer
/// interface's GGX widths (a conductor's, a dielectric's, a coat's), a coated conductor's
/// metal's widths, a diffuse transmitter's two shares, and the surface's alpha (where it is
/// below one, rays pass through that share of the time: a cut-out).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceTextures {
    /// The scene's textures.
    pub graph: Arc<TextureGraph>,
    /// The surface colour (the albedo of diffuse and coated-diffuse surfaces).
    pub color: Option<NodeId>,
    /// The widths of the interface on top.
    pub widths: Option<TexturedWidths>,
    /// A coated conductor's metal's widths.
    pub base_widths: Option<TexturedWidths>,
    /// A diffuse transmitter's reflectance.
    pub reflectance: Option<NodeId>,
    /// A diffuse transmitter's transmittance.
    pub transmittance: Option<NodeId>,
    /// A metal's textured index (a conductor's, a coated conductor's base).
    pub metal: Option<MetalTextures>,
    /// A layered material's textured slab (`thickness`, `albedo`, `g`).
    pub layers: Option<LayerTextures>,
    /// The surface's alpha (a float): where it is `a < 1`, a ray passes through with
    /// probability `1 − a` (always where `a ≤ 0`).
    pub alpha: Option<FloatInput>,
    /// pbrt-v4's `mix`: the two materials one of which scatters at each hit, and by how much
    /// (see [`Material::chosen`](super::Material::chosen)).
    pub mix: Option<Arc<MaterialMix>>,
}

impl SurfaceTextures {
    /// Textures of `graph` for nothing yet.
    pub fn new(graph: Arc<TextureGraph>) -> Self {
        Self {
            graph,
            color: None,
            widths: None,
            base_widths: None,
            reflectance: None,
            transmittance: None,
            metal: None,
            layers: None,
            alpha: None,
            mix: None,
        }
    }

    /// Whether any of the material's parameters (not the alpha) is textured.
    pub fn textures_parameters(&self) -> bool {
        self.color.is_some()
            || self.widths.is_some()
            || self.base_widths.is_some()
            || self.reflectance.is_some()
            || self.transmittance.is_some()
            || self.metal.is_some()
            || self.layers.is_some()
    }

    /// The surface colour at `ctx`, where it is textured.
    #[inline]
    pub fn color_at(&self, ctx: &TextureContext) -> Option<Color> {
        self.color.map(|id| self.graph.evaluate(id, ctx))
    }

    /// `physical` with its textured parameters read at `ctx`.
    #[inline]
    pub fn physical_at(&self, physical: Physical, ctx: &TextureContext) -> Physical {
        if !self.textures_parameters() {
            return physical;
        }
        let g = &*self.graph;
        let spectrum = |id: Option<NodeId>| id.map(|id| g.evaluate(id, ctx));
        let (eta, k) = match self.metal {
            None => (None, None),
            Some(MetalTextures::Index { eta, k }) => (spectrum(eta), spectrum(k)),
            Some(MetalTextures::Reflectance(r)) => {
                let (eta, k) = conductor_of_reflectance(g.evaluate(r, ctx));
                (Some(eta), Some(k))
            }
        };
        let layers = self.layers.unwrap_or_default();
        physical.with_textured(&HitParameters {
            widths: self.widths.map(|w| w.at(g, ctx)),
            base_widths: self.base_widths.map(|w| w.at(g, ctx)),
            reflectance: spectrum(self.reflectance),
            transmittance: spectrum(self.transmittance),
            eta,
            k,
            thickness: layers.thickness.map(|t| t.at(g, ctx)),
            albedo: spectrum(layers.albedo),
            g: layers.g.map(|v| v.at(g, ctx)),
        })
    }

    /// The chance the surface is there at `ctx` ([`is_there`](Self::is_there)'s): the alpha
    /// held in `[0, 1]`, 1 without one.
    #[inline]
    pub fn coverage(&self, ctx: &TextureContext) -> f64 {
        match self.alpha {
            None => 1.0,
            Some(alpha) => {
                let a = alpha.at(&self.graph, ctx);
                if a.is_nan() {
                    0.0
                } else {
                    a.clamp(0.0, 1.0)
                }
            }
        }
    }

    /// Whether the surface is there at `ctx` for a ray whose coin (uniform in `[0, 1)`, a
    /// hash of the ray) is `coin`: pbrt-v4's stochastic alpha test. Always there without an
    /// alpha texture or where the alpha is at least 1; never where it is 0 or below.
    #[inline]
    pub fn is_there(&self, ctx: &TextureContext, coin: f64) -> bool {
        let Some(alpha) = self.alpha else {
            return true;
        };
        let a = alpha.at(&self.graph, ctx);
        if a >= 1.0 {
            return true;
        }
        if a <= 0.0 || a.is_nan() {
            return false;
        }
        coin < a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(u: f64, v: f64) -> TextureContext {
        TextureContext {
            uv: (u, v),
            point: Point3::new(u, v, 0.0),
            normal: Vec3::Z,
        }
    }

    fn grey(v: f64) -> Color {
        Color::new(v, v, v)
    }

    fn close(a: Color, b: Color) -> bool {
        (a - b).to_array().iter().all(|d| d.abs() < 1e-12)
    }

    /// A 2×2 image: red, green on top; blue, white below.
    fn four() -> Arc<TextureImage> {
        Arc::new(
            TextureImage::new(
                2,
                2,
                vec![
                    Color::new(1.0, 0.0, 0.0),
                    Color::new(0.0, 1.0, 0.0),
                    Color::new(0.0, 0.0, 1.0),
                    Color::WHITE,
                ],
            )
            .unwrap(),
        )
    }

    fn image(graph: &mut TextureGraph, filter: ImageFilter, wrap: Wrap) -> NodeId {
        graph
            .add(TextureNode::Image {
                image: four(),
                mapping: Mapping2D::UV,
                filter,
                wrap,
                scale: 1.0,
                invert: false,
            })
            .unwrap()
    }

    #[test]
    fn an_image_is_read_with_t_up_from_its_bottom_row() {
        let mut g = TextureGraph::new();
        let point = image(&mut g, ImageFilter::Point, Wrap::Repeat);
        // (s, t) = (0.25, 0.25) is the bottom-left pixel: blue.
        assert_eq!(
            g.evaluate(point, &at(0.25, 0.25)),
            Color::new(0.0, 0.0, 1.0)
        );
        assert_eq!(
            g.evaluate(point, &at(0.75, 0.75)),
            Color::new(0.0, 1.0, 0.0)
        );
        // Bilinear at a pixel centre is the pixel; at the middle, the mean of four.
        let bilinear = image(&mut g, ImageFilter::Bilinear, Wrap::Clamp);
        assert!(close(
            g.evaluate(bilinear, &at(0.25, 0.75)),
            Color::new(1.0, 0.0, 0.0)
        ));
        assert!(close(g.evaluate(bilinear, &at(0.5, 0.5)), grey(0.5)));
    }

    #[test]
    fn wrap_modes_say_what_lies_outside() {
        let mut g = TextureGraph::new();
        let repeat = image(&mut g, ImageFilter::Point, Wrap::Repeat);
        let black = image(&mut g, ImageFilter::Point, Wrap::Black);
        let clamp = image(&mut g, ImageFilter::Point, Wrap::Clamp);
        let octa = image(&mut g, ImageFilter::Point, Wrap::OctahedralSphere);
        // One image to the right of the bottom-left pixel's centre.
        let p = at(1.25, 0.25);
        assert_eq!(g.evaluate(repeat, &p), Color::new(0.0, 0.0, 1.0));
        assert_eq!(g.evaluate(black, &p), Color::BLACK);
        assert_eq!(g.evaluate(clamp, &p), Color::WHITE);
        // Across the right edge the octahedral map continues mirrored: column 1, row flipped.
        assert_eq!(g.evaluate(octa, &at(1.25, 0.25)), Color::new(0.0, 1.0, 0.0));
        assert_eq!(
            g.evaluate(octa, &at(-0.25, 0.75)),
            Color::new(0.0, 0.0, 1.0)
        );
        // Bilinear with repeat blends across the seam: at s = 0 the two columns' mean.
        let bilinear = image(&mut g, ImageFilter::Bilinear, Wrap::Repeat);
        assert!(close(
            g.evaluate(bilinear, &at(0.0, 0.75)),
            Color::new(0.5, 0.5, 0.0)
        ));
        // Non-finite coordinates read black rather than an arbitrary pixel.
        assert_eq!(g.evaluate(repeat, &at(f64::NAN, 0.0)), Color::BLACK);
    }

    #[test]
    fn scale_and_invert_apply_as_pbrt_orders_them() {
        let mut g = TextureGraph::new();
        let id = g
            .add(TextureNode::Image {
                image: four(),
                mapping: Mapping2D::UV,
                filter: ImageFilter::Point,
                wrap: Wrap::Repeat,
                scale: 0.5,
                invert: true,
            })
            .unwrap();
        // Red scaled to 0.5 then inverted: (0.5, 1, 1).
        assert_eq!(g.evaluate(id, &at(0.25, 0.75)), Color::new(0.5, 1.0, 1.0));
        let big = g
            .add(TextureNode::Image {
                image: four(),
                mapping: Mapping2D::UV,
                filter: ImageFilter::Point,
                wrap: Wrap::Repeat,
                scale: 3.0,
                invert: true,
            })
            .unwrap();
        // Never below zero.
        assert_eq!(g.evaluate(big, &at(0.75, 0.25)), Color::BLACK);
    }

    #[test]
    fn mappings_give_pbrts_coordinates() {
        let ctx = TextureContext {
            uv: (0.2, 0.4),
            point: Point3::new(0.0, 2.0, 2.0),
            normal: Vec3::Z,
        };
        let uv = Mapping2D::Uv {
            scale: (2.0, 3.0),
            delta: (0.5, -1.0),
        };
        let (s, t) = uv.map(&ctx);
        assert!((s - 0.9).abs() < 1e-12 && (t - 0.2).abs() < 1e-12);
        let id = DAffine3::IDENTITY;
        // (0, 2, 2): θ = 45°, φ = 90°.
        let (s, t) = Mapping2D::Spherical {
            texture_from_world: id,
        }
        .map(&ctx);
        assert!(
            (s - 0.25).abs() < 1e-12 && (t - 0.25).abs() < 1e-12,
            "{s} {t}"
        );
        let (s, t) = Mapping2D::Cylindrical {
            texture_from_world: id,
        }
        .map(&ctx);
        assert!(
            (s - 0.75).abs() < 1e-12 && (t - 2.0).abs() < 1e-12,
            "{s} {t}"
        );
        let (s, t) = Mapping2D::Planar {
            texture_from_world: DAffine3::from_translation(Vec3::new(1.0, 0.0, 0.0)),
            vs: Vec3::X,
            vt: Vec3::Y,
            delta: (0.5, 0.0),
        }
        .map(&ctx);
        assert!(
            (s - 1.5).abs() < 1e-12 && (t - 2.0).abs() < 1e-12,
            "{s} {t}"
        );
    }

    #[test]
    fn checkerboards_bilerp_scale_and_mixes_have_their_values() {
        let mut g = TextureGraph::new();
        let a = g.add(TextureNode::Constant(grey(0.25))).unwrap();
        let b = g.add(TextureNode::Constant(grey(1.0))).unwrap();
        let board = g
            .add(TextureNode::Checkerboard2D {
                mapping: Mapping2D::Uv {
                    scale: (4.0, 4.0),
                    delta: (0.0, 0.0),
                },
                tex1: a,
                tex2: b,
            })
            .unwrap();
        assert_eq!(g.evaluate(board, &at(0.1, 0.1)), grey(0.25));
        assert_eq!(g.evaluate(board, &at(0.3, 0.1)), grey(1.0));
        assert_eq!(g.evaluate(board, &at(0.3, 0.3)), grey(0.25));
        assert_eq!(g.evaluate(board, &at(-0.1, 0.1)), grey(1.0));
        let cubes = g
            .add(TextureNode::Checkerboard3D {
                texture_from_world: DAffine3::IDENTITY,
                tex1: a,
                tex2: b,
            })
            .unwrap();
        let p = |x, y, z| TextureContext {
            uv: (0.0, 0.0),
            point: Point3::new(x, y, z),
            normal: Vec3::Z,
        };
        assert_eq!(g.evaluate(cubes, &p(0.5, 0.5, 0.5)), grey(0.25));
        assert_eq!(g.evaluate(cubes, &p(0.5, 0.5, 1.5)), grey(1.0));
        assert_eq!(g.evaluate(cubes, &p(1.5, 1.5, -0.5)), grey(1.0));
        let bilerp = g
            .add(TextureNode::Bilerp {
                mapping: Mapping2D::UV,
                corners: [grey(0.0), grey(1.0), grey(2.0), grey(4.0)],
            })
            .unwrap();
        // v00 0, v01 1 (at t = 1), v10 2 (at s = 1), v11 4.
        assert!(close(g.evaluate(bilerp, &at(1.0, 0.0)), grey(2.0)));
        assert!(close(g.evaluate(bilerp, &at(0.0, 1.0)), grey(1.0)));
        assert!(close(g.evaluate(bilerp, &at(0.5, 0.5)), grey(1.75)));
        let scaled = g
            .add(TextureNode::Scale {
                tex: board,
                scale: a,
            })
            .unwrap();
        assert_eq!(g.evaluate(scaled, &at(0.3, 0.1)), grey(0.25));
        let mix = g
            .add(TextureNode::Mix {
                tex1: a,
                tex2: b,
                amount: bilerp,
            })
            .unwrap();
        // Amount 0.5 at (0, 0.5): the mean.
        assert!(close(g.evaluate(mix, &at(0.0, 0.5)), grey(0.625)));
        let dir = g
            .add(TextureNode::DirectionMix {
                tex1: a,
                tex2: b,
                dir: Vec3::new(0.0, 0.6, 0.8),
            })
            .unwrap();
        // |n · dir| = 0.8 of tex1, 0.2 of tex2.
        assert!(close(
            g.evaluate(dir, &at(0.0, 0.0)),
            grey(0.8 * 0.25 + 0.2)
        ));
    }

    #[test]
    fn the_graph_is_bounded_and_cannot_loop() {
        let mut g = TextureGraph::new();
        let mut last = g.add(TextureNode::Constant(grey(0.5))).unwrap();
        for _ in 1..MAX_TEXTURE_DEPTH {
            last = g
                .add(TextureNode::Scale {
                    tex: last,
                    scale: last,
                })
                .unwrap();
        }
        assert_eq!(
            g.add(TextureNode::Scale {
                tex: last,
                scale: last
            }),
            Err(TextureError::TooDeep)
        );
        // A node can only read the nodes before it.
        let ahead = NodeId(g.len() as u32);
        assert_eq!(
            g.add(TextureNode::Scale {
                tex: ahead,
                scale: last
            }),
            Err(TextureError::UnknownInput)
        );
        let mut full = TextureGraph::new();
        for _ in 0..MAX_TEXTURE_NODES {
            full.add(TextureNode::Constant(Color::BLACK)).unwrap();
        }
        assert_eq!(
            full.add(TextureNode::Constant(Color::BLACK)),
            Err(TextureError::TooManyNodes)
        );
    }

    #[test]
    fn widths_and_alpha_are_read_from_floats() {
        let mut g = TextureGraph::new();
        let r = g.add(TextureNode::Constant(grey(0.25))).unwrap();
        let big = g.add(TextureNode::Constant(grey(4.0))).unwrap();
        let half = g.add(TextureNode::Constant(grey(0.5))).unwrap();
        let g = Arc::new(g);
        let w = TexturedWidths {
            u: FloatInput::Texture(r),
            v: FloatInput::Texture(big),
            remap: true,
        };
        assert_eq!(w.at(&g, &at(0.0, 0.0)), (0.5, 1.0));
        let w = TexturedWidths { remap: false, ..w };
        assert_eq!(w.at(&g, &at(0.0, 0.0)), (0.25, 1.0));
        let w = TexturedWidths {
            u: FloatInput::Fixed(0.09),
            ..w
        };
        assert_eq!(w.at(&g, &at(0.0, 0.0)), (0.09, 1.0));
        let mut t = SurfaceTextures::new(g);
        assert!(t.is_there(&at(0.0, 0.0), 0.99));
        t.alpha = Some(FloatInput::Texture(half));
        assert!(t.is_there(&at(0.0, 0.0), 0.49));
        assert!(!t.is_there(&at(0.0, 0.0), 0.5));
        t.alpha = Some(FloatInput::Texture(big));
        assert!(t.is_there(&at(0.0, 0.0), 0.999));
        assert_eq!(t.coverage(&at(0.0, 0.0)), 1.0);
        t.alpha = Some(FloatInput::Fixed(0.0));
        assert!(!t.is_there(&at(0.0, 0.0), 0.0));
        assert_eq!(t.coverage(&at(0.0, 0.0)), 0.0);
        t.alpha = Some(FloatInput::Texture(half));
        assert_eq!(t.coverage(&at(0.0, 0.0)), 0.5);
    }

    #[test]
    fn noise_nodes_read_the_point_in_texture_space() {
        let mut g = TextureGraph::new();
        let shift = DAffine3::from_translation(Vec3::new(0.5, -1.0, 2.0));
        let fbm = g
            .add(TextureNode::Fbm {
                texture_from_world: shift,
                omega: 0.5,
                octaves: 4,
            })
            .unwrap();
        let wrinkled = g
            .add(TextureNode::Wrinkled {
                texture_from_world: shift,
                omega: 0.5,
                octaves: 4,
            })
            .unwrap();
        let windy = g
            .add(TextureNode::Windy {
                texture_from_world: shift,
            })
            .unwrap();
        let marble = g
            .add(TextureNode::Marble {
                texture_from_world: shift,
                omega: 0.5,
                octaves: 8,
                scale: 2.0,
                variation: 0.2,
            })
            .unwrap();
        let one = g.add(TextureNode::Constant(grey(1.0))).unwrap();
        let zero = g.add(TextureNode::Constant(grey(0.0))).unwrap();
        let dots = g
            .add(TextureNode::Dots {
                mapping: Mapping2D::UV,
                inside: one,
                outside: zero,
            })
            .unwrap();
        let ctx = at(0.3, 0.7);
        let q = ctx.point + Vec3::new(0.5, -1.0, 2.0);
        assert_eq!(g.evaluate(fbm, &ctx), grey(noise::fbm(q, 0.5, 4)));
        assert_eq!(
            g.evaluate(wrinkled, &ctx),
            grey(noise::turbulence(q, 0.5, 4))
        );
        assert_eq!(g.evaluate(windy, &ctx), grey(noise::windy(q)));
        assert_eq!(
            g.evaluate(marble, &ctx),
            noise::marble(q * 2.0, 0.5, 8, 0.2)
        );
        for (u, v) in [(0.1, 0.2), (3.3, -1.7), (10.0, 4.5)] {
            let want = if noise::inside_polka_dot(u, v) {
                1.0
            } else {
                0.0
            };
            assert_eq!(g.evaluate(dots, &at(u, v)), grey(want));
        }
    }
}
