//! The Phong material (chapters 6, 10 and 11).

use super::bump::Bump;
use super::metal_rough::{MetalRough, SurfacePoint};
use super::pattern::Pattern;
use super::physical::Physical;
use super::texture::UvPattern;
use super::texture_graph::{FloatInput, SurfaceTextures, TextureContext};
use crate::color::Color;
use crate::math::{Point3, SplitMix64, Vec3};
use std::sync::Arc;

/// Surface properties: Phong coefficients, a colour or pattern, reflection and refraction.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Base colour, used when there is no pattern.
    pub color: Color,
    /// A pattern that replaces `color` when present. Boxed, as the bumps are: most materials
    /// have neither, and a scene of many instances holds one material each.
    pub pattern: Option<Box<Pattern>>,
    /// Bumps that tilt the shading normal.
    pub bump: Option<Box<Bump>>,
    /// An image or UV pattern read with the surface's own texture coordinates (an OBJ model's
    /// `vt`), multiplying `color` (MTL's `map_Kd`). Surfaces without coordinates ignore it.
    /// Boxed like the pattern: inline it would be 128 of a material's bytes, and an object's
    /// size is what a scene of many instances pays for each.
    pub texture: Option<Box<UvPattern>>,
    /// Fraction of the light's colour reflected regardless of direction.
    pub ambient: f64,
    /// Weight of the Lambertian term.
    pub diffuse: f64,
    /// Weight of the specular highlight.
    pub specular: f64,
    /// Sharpness of the highlight (larger is smaller and tighter).
    pub shininess: f64,
    /// 0 for matte, 1 for a perfect mirror.
    pub reflective: f64,
    /// 0 for opaque, 1 for perfectly clear.
    pub transparency: f64,
    /// Index of refraction (1 for vacuum, 1.5 for glass).
    pub refractive_index: f64,
    /// The colour of mirror-like reflection (the optics model of Fundamentals of Ray Tracing;
    /// `color` is its matte colour there).
    pub gloss: Color,
    /// How much light the surface stops, from 0 (clear) to 1 (opaque), in the optics model.
    pub opacity: f64,
    /// Light the surface gives off, as radiance from the side its normal faces: what makes
    /// an object a light for the path tracer (the book's renderers ignore it).
    pub emission: Color,
    /// Which side of the surface gives off the emission.
    pub emission_side: EmissionSide,
    /// Whether the surface scatters light on both sides (the default, as the books' surfaces
    /// do) or only on the side its normal faces, its back black (as in Mitsuba and pbrt, where
    /// the back of a lamp gives nothing back): for the path tracer.
    pub two_sided: bool,
    /// The path tracer's material, when the scene names one; `None` gives the book's
    /// parameters their physical meaning (see [`super::Scattering`]).
    pub physical: Option<Physical>,
    /// Patterns that vary the physical material's parameters over the surface (a roughness
    /// map, a graded index), evaluated like the colour's pattern; `None` for fixed ones.
    pub physical_patterns: Option<Box<PhysicalPatterns>>,
    /// glTF's metallic-roughness material, for surfaces read from glTF files: when present it
    /// gives the surface colour (base colour × texture × vertex colour) to every renderer,
    /// and the path tracer its scattering, normal map, emission and alpha.
    pub metal_rough: Option<Arc<MetalRough>>,
    /// Textures for the physical material's parameters and the surface's alpha, as pbrt-v4
    /// scenes give them (see [`SurfaceTextures`]): read by the path tracer at each hit, where
    /// they replace the fixed colour, widths and shares. Boxed like the pattern.
    pub textures: Option<Box<SurfaceTextures>>,
}

/// Patterns for a physical material's parameters. Each pattern's value at a point is the mean
/// of its three channels, so a grey image gives its grey levels directly.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalPatterns {
    /// The GGX width (conductors, rough dielectrics, plastic), clamped to [0, 1].
    pub alpha: Option<Alpha>,
    /// The refractive index (dielectrics, thin dielectrics, plastic), clamped to [1, 9].
    pub eta: Option<Pattern>,
}

/// A pattern giving the GGX width: as it is, or as a roughness whose square is the width.
#[derive(Debug, Clone, PartialEq)]
pub struct Alpha {
    /// The pattern.
    pub pattern: Pattern,
    /// Whether its value is the roughness (alpha = roughness², as artists paint it).
    pub squared: bool,
}

/// Which side of an emitting surface gives off light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EmissionSide {
    /// The side the normal faces (out of a closed shape): a lamp.
    #[default]
    Front,
    /// The other side (into a closed shape): a glowing room seen from inside.
    Back,
    /// Both sides (a thin glowing sheet).
    Both,
}

impl EmissionSide {
    /// Whether light leaves towards a direction whose cosine with the surface's normal is
    /// `cos`.
    #[inline]
    pub fn emits_towards(self, cos: f64) -> bool {
        match self {
            EmissionSide::Front => cos > 0.0,
            EmissionSide::Back => cos < 0.0,
            EmissionSide::Both => cos != 0.0,
        }
    }
}

impl Material {
    /// The book's default material (SEED-NOTES.md lists the values).
    pub const DEFAULT: Self = Self {
        color: Color::WHITE,
        pattern: None,
        bump: None,
        texture: None,
        ambient: 0.1,
        diffuse: 0.9,
        specular: 0.9,
        shininess: 200.0,
        reflective: 0.0,
        transparency: 0.0,
        refractive_index: 1.0,
        gloss: Color::BLACK,
        opacity: 1.0,
        emission: Color::BLACK,
        emission_side: EmissionSide::Front,
        two_sided: true,
        physical: None,
        physical_patterns: None,
        metal_rough: None,
        textures: None,
    };

    /// The book's `glass_sphere()` material: fully transparent, index 1.5.
    pub fn glass() -> Self {
        Self {
            transparency: 1.0,
            refractive_index: 1.5,
            ..Self::DEFAULT
        }
    }
}

impl Material {
    /// The surface colour: glTF's base colour (factor, texture and vertex colour) for a
    /// metallic-roughness material; else the texture at the surface's own coordinates when both
    /// exist, else the pattern at the object-space point `object_point` gives (asked only
    /// then), else the plain colour.
    #[inline]
    pub fn surface_color(&self, at: &SurfacePoint, object_point: impl FnOnce() -> Point3) -> Color {
        if let Some(m) = &self.metal_rough {
            return m.base_at(at).0;
        }
        let uv = at.uv;
        if let (Some(texture), Some((u, v))) = (&self.texture, uv) {
            return texture.uv_pattern_at(u, v) * self.color;
        }
        match &self.pattern {
            Some(pattern) => pattern.nested_at(object_point()),
            None => self.color,
        }
    }
}

/// pbrt-v4's `MixMaterial`: at each hit one of two materials scatters, the second with
/// probability `amount` there (a number or a float texture; at most 0 always the first, at
/// least 1 always the second). Which one is a pure function of the hit (pbrt-v4 hashes the
/// point and the direction back along the path), so the same hit always scatters alike,
/// whatever the thread or sample order; a mix of mixes picks again at each level with a new
/// hash. Held in the outer material's [`SurfaceTextures`], whose graph `amount` reads.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialMix {
    /// The second material's share.
    pub amount: FloatInput,
    /// The two materials.
    pub materials: [Material; 2],
}

/// A number in [0, 1) that is a hash of `point` and `wo`, as pbrt-v4's `HashFloat(p, wo)`.
#[inline]
fn hit_hash(point: Point3, wo: Vec3) -> u64 {
    let seed = point.x.to_bits()
        ^ point.y.to_bits().rotate_left(21)
        ^ point.z.to_bits().rotate_left(42)
        ^ wo.x.to_bits().rotate_left(11)
        ^ wo.y.to_bits().rotate_left(32)
        ^ wo.z.to_bits().rotate_left(53);
    SplitMix64::new(seed).next_u64()
}

impl Material {
    /// The material that scatters at the world-space `point` seen along `wo` (unit, back
    /// along the path), with the textures read at `ctx`: this one, or where it is a
    /// [`MaterialMix`], the one the mix picks there (down through mixes of mixes).
    #[inline]
    pub fn chosen(&self, ctx: &TextureContext, point: Point3, wo: Vec3) -> &Material {
        let mut material = self;
        let mut hash = hit_hash(point, wo);
        while let Some(textures) = material.textures.as_deref() {
            let Some(mix) = textures.mix.as_deref() else {
                break;
            };
            let amount = mix.amount.at(&textures.graph, ctx);
            let u = (hash >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
            hash = SplitMix64::new(hash).next_u64();
            // pbrt-v4: `amt < u ? materials[0] : materials[1]`, so the second with chance amt.
            material = if amount <= 0.0 || (amount < 1.0 && amount < u) {
                &mix.materials[0]
            } else {
                &mix.materials[1]
            };
        }
        material
    }
}

impl Material {
    /// The physical material at a point: its parameters as the patterns give them there
    /// (`object_point` is asked only when there are patterns).
    pub fn physical_at(&self, object_point: impl FnOnce() -> Point3) -> Option<Physical> {
        let physical = self.physical?;
        let Some(patterns) = &self.physical_patterns else {
            return Some(physical);
        };
        let point = object_point();
        let value = |pattern: &Pattern| {
            let c = pattern.nested_at(point);
            (c.red + c.green + c.blue) / 3.0
        };
        let alpha = patterns.alpha.as_ref().map(|a| {
            let v = value(&a.pattern).clamp(0.0, 1.0);
            if a.squared {
                v * v
            } else {
                v
            }
        });
        let eta = patterns.eta.as_ref().map(|p| value(p).clamp(1.0, 9.0));
        Some(physical.with_parameters(alpha, eta))
    }
}

impl Default for Material {
    fn default() -> Self {
        Self::DEFAULT
    }
}

#[cfg(test)]
mod mix_tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::shading::texture_graph::TextureGraph;

    /// A mix of a red and a blue material, the blue's share `amount`.
    fn mix(amount: f64) -> Material {
        let plain = |color: Color| Material {
            color,
            ..Material::DEFAULT
        };
        let mut surface = SurfaceTextures::new(Arc::new(TextureGraph::new()));
        surface.mix = Some(Arc::new(MaterialMix {
            amount: FloatInput::Fixed(amount),
            materials: [
                plain(Color::new(1.0, 0.0, 0.0)),
                plain(Color::new(0.0, 0.0, 1.0)),
            ],
        }));
        Material {
            textures: Some(Box::new(surface)),
            ..Material::DEFAULT
        }
    }

    fn ctx(point: Point3) -> TextureContext {
        TextureContext {
            uv: (0.0, 0.0),
            point,
            normal: Vec3::Z,
        }
    }

    /// The share of `n` random hits at which `material` picks a blue one.
    fn blue_share(material: &Material, n: usize) -> f64 {
        let mut random = SplitMix64::new(3);
        let mut blue = 0;
        for _ in 0..n {
            let p = Point3::new(
                random.next_offset(),
                random.next_offset(),
                random.next_offset(),
            );
            let wo = Vec3::new(random.next_offset() - 0.5, 0.3, 1.0).normalize();
            let chosen = material.chosen(&ctx(p), p, wo);
            // The same hit always picks the same.
            assert!(std::ptr::eq(chosen, material.chosen(&ctx(p), p, wo)));
            if chosen.color.blue > 0.0 {
                blue += 1;
            }
        }
        blue as f64 / n as f64
    }

    #[test]
    fn a_mix_picks_its_second_material_with_chance_amount() {
        let n = 40_000;
        for amount in [0.1, 0.5, 0.85] {
            let share = blue_share(&mix(amount), n);
            let se = (amount * (1.0 - amount) / n as f64).sqrt();
            assert!((share - amount).abs() < 4.0 * se, "{amount}: {share}");
        }
        assert_eq!(blue_share(&mix(0.0), 1000), 0.0);
        assert_eq!(blue_share(&mix(-1.0), 1000), 0.0);
        assert_eq!(blue_share(&mix(1.0), 1000), 1.0);
        // A material that is no mix is itself.
        let plain = Material::DEFAULT;
        let p = Point3::ONE;
        assert!(std::ptr::eq(plain.chosen(&ctx(p), p, Vec3::Z), &plain));
    }

    #[test]
    fn a_mix_of_mixes_picks_again_at_each_level() {
        // The outer mix's second material is a mix of red and blue at 0.5: blue with chance
        // 0.6 · 0.5 = 0.3, which one coin reused at both levels would not give (0.5).
        let mut outer = mix(0.6);
        if let Some(t) = outer.textures.as_deref_mut() {
            let m = t.mix.as_mut().map(Arc::make_mut).expect("a mix");
            m.materials[1] = mix(0.5);
        }
        let n = 40_000;
        let share = blue_share(&outer, n);
        let se = (0.3f64 * 0.7 / n as f64).sqrt();
        assert!((share - 0.3).abs() < 4.0 * se, "{share}");
    }
}
