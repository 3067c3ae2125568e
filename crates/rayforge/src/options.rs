//! What the rasterizer can be asked to do differently (how surfaces are shaded, how finely
//! curved shapes are cut into triangles, how textures are filtered) and how the path tracer
//! samples.
//!
//! Plain data, below the renderers, so that a scene reader can say which renderer a scene
//! asks for and with which options (`Option<RasterOptions>`, `Option<PathOptions>`) without
//! depending on the renderers themselves. The [`raster`](crate::raster) module re-exports them.

use crate::film::PixelFilter;

/// Where the lighting equation is evaluated (the book's "Shading" chapter).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shading {
    /// Once per triangle, at its centre, with the face's own normal: faceted.
    Flat,
    /// Once per vertex, with the vertex normal, blended across the triangle (Gouraud, 1971):
    /// smooth, but highlights that fall between vertices are lost.
    Gouraud,
    /// Once per pixel, with the normal blended from the vertices (Phong, 1973): what the ray
    /// tracer computes, short of shadows.
    #[default]
    Phong,
}

/// How texels are read (the book leaves filtering and MIP maps "TO DO").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TextureFilter {
    /// The texel nearest the sample: blocky when magnified, shimmering when minified.
    Nearest,
    /// A blend of the four texels around the sample (smooth when magnified).
    Bilinear,
    /// Bilinear in the two MIP levels whose texel size brackets the pixel's footprint, blended
    /// (smooth when minified too).
    #[default]
    Trilinear,
}

/// Options for the rasterizer's `render`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterOptions {
    /// Flat, Gouraud or Phong shading.
    pub shading: Shading,
    /// Sphere tessellation: `divisions + 1` rings of `divisions` vertices (the book's
    /// `GenerateSphere(divs)`); cylinders and cones use as many segments around. At least 3.
    pub sphere_divisions: u32,
    /// How textures are filtered.
    pub filter: TextureFilter,
    /// Draw only the triangles' edges (the book's `DrawWireframeTriangle`), each in its
    /// material's colour, hidden edges included.
    pub wireframe: bool,
    /// Skip triangles facing away from the camera on closed shapes (spheres, cubes, capped
    /// cylinders and cones) seen from outside: there a back face is always behind a front
    /// face, so skipping it changes nothing but the time. Open surfaces, meshes (whose winding
    /// is whatever the file had), CSG primitives (a difference shows the inside of what it
    /// cuts away) and shapes the eye is inside of are never culled.
    pub backface_culling: bool,
    /// Distance of the near clipping plane in front of the eye. The ray tracer has none; the
    /// rasterizer must not divide by z ≈ 0, so this is small.
    pub near: f64,
    /// The most triangles a frame may hold, all objects' tessellations together (each
    /// placement counted: its vertices are transformed into the frame's own arrays). About
    /// 100 bytes each, so the default bounds a frame at about 3.4 GB.
    pub max_triangles: u64,
}

impl RasterOptions {
    /// The sphere resolution used unless asked otherwise: round to about a pixel on a sphere
    /// 500 pixels across.
    pub const DEFAULT_SPHERE_DIVISIONS: u32 = 48;
    /// The default near-plane distance.
    pub const DEFAULT_NEAR: f64 = 1e-3;
    /// The default of [`RasterOptions::max_triangles`]: 2²⁵, as many as one sphere at the
    /// largest resolution (4096 divisions); the Stanford dragon has 871 thousand.
    pub const DEFAULT_MAX_TRIANGLES: u64 = 1 << 25;
}

impl Default for RasterOptions {
    fn default() -> Self {
        Self {
            shading: Shading::Phong,
            sphere_divisions: Self::DEFAULT_SPHERE_DIVISIONS,
            filter: TextureFilter::Trilinear,
            wireframe: false,
            backface_culling: true,
            near: Self::DEFAULT_NEAR,
            max_triangles: Self::DEFAULT_MAX_TRIANGLES,
        }
    }
}

/// Where a path tracer's random numbers come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SamplerKind {
    /// Independent uniform numbers, hashed from the pixel, the sample index and the dimension:
    /// the plain Monte Carlo baseline.
    Independent,
    /// Owen-scrambled Sobol points (Burley 2020), a different scramble per pixel and per four
    /// dimensions: the error falls faster than with independent numbers.
    #[default]
    Sobol,
}

/// How the path tracer's Russian roulette weighs a path's chance to go on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Roulette {
    /// Chosen for the scene before the render by a short pilot pass that weighs the light a
    /// path still has to gather against what gathering it costs (see
    /// `render::path::learn_roulette`).
    #[default]
    Learned,
    /// A path survives with probability `scale × throughput` (at most 0.95): 1 is the classic
    /// rule of Mitsuba and pbrt, larger lets paths live longer.
    Scale(f64),
}

impl Roulette {
    /// The largest scale a scene or the pilot may choose: past it a path's weight barely
    /// changes and only its cost grows.
    pub const MAX_SCALE: f64 = 64.0;
    /// The smallest: below it the roulette would end paths while their light is still
    /// a large part of the pixel's.
    pub const MIN_SCALE: f64 = 0.25;

    /// The roulette of the fixed scale `k`, if it lies from [`MIN_SCALE`](Self::MIN_SCALE) to
    /// [`MAX_SCALE`](Self::MAX_SCALE) (what a scene or the command line may ask for).
    pub fn scale(k: f64) -> Option<Self> {
        (Self::MIN_SCALE..=Self::MAX_SCALE)
            .contains(&k)
            .then_some(Self::Scale(k))
    }
}

/// How the path tracer renders: its random numbers, its pixel filter, how deep paths go and
/// the seed that picks one of many equally good images.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathOptions {
    /// Where the random numbers come from.
    pub sampler: SamplerKind,
    /// How samples are weighed within their pixel (each sample belongs to one pixel, drawn
    /// over the filter's support and weighed by it).
    pub filter: PixelFilter,
    /// The most bounces a path takes (Russian roulette ends most long before).
    pub max_depth: u32,
    /// Bounces before Russian roulette may end a path.
    pub roulette_depth: u32,
    /// How the roulette chooses, past `roulette_depth`, whether a path goes on.
    pub roulette: Roulette,
    /// The seed: renders with different seeds are independent estimates of the same image.
    pub seed: u64,
    /// How a render's samples are shared among its pixels.
    pub allocation: SampleAllocation,
    /// How next-event estimation picks the light it samples at a vertex.
    pub light_sampler: LightSamplerKind,
    /// Which of the integrator's techniques run.
    pub techniques: Techniques,
    /// Whether a learned roulette ([`Roulette::Learned`]) also learns where the light a path
    /// still gathers past a diffuse surface is predictable, and ends paths there into the
    /// prediction (`render::path::ContinuationCache`); without, it learns the scale alone.
    pub roulette_predictions: bool,
}

/// The path tracer's techniques, each of which can be turned off: to see what one buys, or
/// to find which one a problem comes from. The image stays unbiased with any combination;
/// only its noise and its cost change. With a technique off, the light it would have found
/// is found by another at full weight:
/// - without next-event estimation, lights and the sky count where a path's BSDF sampling
///   meets them, at weight 1;
/// - without MIS, a light sampled by next-event estimation counts at weight 1 and one met by
///   BSDF sampling at weight 0 where light sampling could have drawn it (at 1 where it could
///   not: a light it does not sample, the sky where it is not sampled);
/// - without Russian roulette, no path ends before the most bounces (nor is a pilot run to
///   learn the roulette);
/// - without the glass split, a path that meets smooth glass takes one of its two lobes by
///   chance, as at any other vertex;
/// - without the mirror-ball sampling, the sky in a polished metal ball reaches a surface
///   only by the surface's own BSDF sampling meeting the ball;
/// - without the sphere cones, a glowing ball is sampled by area, as every other shape
///   (about half its points on the side facing away, which give no light);
/// - without equiangular sampling, the light a homogeneous medium scatters from a lamp is
///   found only at the points where distance sampling (by transmittance) makes the path
///   scatter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Techniques {
    /// Next-event estimation: a light (or the sky) sampled at every vertex that is not a
    /// perfect mirror or smooth glass.
    pub next_event: bool,
    /// Multiple importance sampling: light sampling and BSDF sampling weighed against each
    /// other by the power heuristic (Veach 1997), where both can find the same light.
    pub mis: bool,
    /// Russian roulette: paths that carry little light end with a probability, survivors
    /// carrying more.
    pub roulette: bool,
    /// Where the camera first sees smooth glass, both the reflected and the transmitted
    /// half are followed, each weighed by its Fresnel share.
    pub glass_split: bool,
    /// The sky seen in polished metal balls, sampled from the surfaces they light
    /// (`crate::lights::MirrorBall`), within [`MirrorBallBudget`].
    pub mirror_balls: bool,
    /// How many balls the mirror-ball sampling solves at a vertex, and which it leaves out.
    pub mirror_ball_budget: MirrorBallBudget,
    /// A glowing ball seen from outside (a sphere that its transform keeps round) is sampled
    /// uniformly in the cone of directions it subtends (`crate::geometry::sphere::SubtendedCone`),
    /// every sample on the cap that faces the vertex, rather than by area.
    pub sphere_cones: bool,
    /// In a homogeneous medium, one more point per ray segment drawn towards the lights
    /// (`crate::media::equiangular`, Kulla and Fajardo 2012) and lit by next-event
    /// estimation, weighed by MIS against the points distance sampling finds (with MIS
    /// off, it replaces their light sampling there); it needs next-event estimation.
    pub equiangular: bool,
    /// How many lights (the most powerful that have a place) equiangular sampling draws
    /// towards, from 1 to [`MAX_EQUIANGULAR_LIGHTS`](Self::MAX_EQUIANGULAR_LIGHTS): more
    /// spreads the points over more lamps, each segment costing a little more per light.
    pub equiangular_lights: u32,
}

impl Techniques {
    /// The default number of lights equiangular sampling draws towards: enough for the
    /// lamps of a room, few enough that a segment's mixture stays cheap to evaluate.
    pub const DEFAULT_EQUIANGULAR_LIGHTS: u32 = 8;
    /// The most lights equiangular sampling may draw towards: the compile-time size of the
    /// fixed arrays a ray's sampler holds (`crate::media::Equiangular`), so that drawing a
    /// point allocates nothing per ray.
    pub const MAX_EQUIANGULAR_LIGHTS: u32 = 16;

    /// `count` as a number of equiangular lights, if it lies from 1 to
    /// [`MAX_EQUIANGULAR_LIGHTS`](Self::MAX_EQUIANGULAR_LIGHTS) (what a scene or the command
    /// line may ask for).
    pub fn equiangular_lights(count: u64) -> Option<u32> {
        (1..=u64::from(Self::MAX_EQUIANGULAR_LIGHTS))
            .contains(&count)
            .then_some(count as u32)
    }
}

/// What the mirror-ball sampling may spend at a vertex. Each ball has a share of the sky's
/// light there: `ρ Ω / π`, its reflectance `ρ` times the solid angle `Ω` it subtends over
/// the π of a cosine-weighted hemisphere (what the ball adds to an even sky's light at the
/// vertex, at most). Balls whose share is below `cull` are left out (the light they reflect
/// is still found by BSDF sampling, at full weight there); of the rest, when there are more
/// than `cap`, `cap` are chosen at random in proportion to their shares, each weighed by
/// one over its expected number of choices (so the mean is unchanged).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorBallBudget {
    /// The most balls solved at a vertex (at least 1).
    pub cap: u32,
    /// The smallest share of the sky's light a ball must have to be solved, from 0 (none
    /// left out) to below 1.
    pub cull: f64,
}

impl MirrorBallBudget {
    /// The default cap: a solve casts up to two shadow rays, against a vertex's own two (its
    /// bounce and its light's shadow ray), so two solves bound the technique's rays at about
    /// what the vertex casts without it (measured on 200 mirror balls against 200 diffuse
    /// ones: about 1.5 times the time, see docs/performance.md).
    pub const DEFAULT_CAP: u32 = 2;
    /// The default cull: a ball that adds under a thousandth of an even sky's light at a
    /// vertex (a ball of radius `R` farther than about `30 R` away) is left to BSDF sampling.
    pub const DEFAULT_CULL: f64 = 1e-3;

    /// `share` as a cull, if it lies from 0 to below 1 (what a scene or the command line may
    /// ask for).
    pub fn cull(share: f64) -> Option<f64> {
        (0.0..1.0).contains(&share).then_some(share)
    }
}

impl Default for MirrorBallBudget {
    fn default() -> Self {
        Self {
            cap: Self::DEFAULT_CAP,
            cull: Self::DEFAULT_CULL,
        }
    }
}

impl Default for Techniques {
    fn default() -> Self {
        Self {
            next_event: true,
            mis: true,
            roulette: true,
            glass_split: true,
            mirror_balls: true,
            mirror_ball_budget: MirrorBallBudget::default(),
            sphere_cones: true,
            equiangular: true,
            equiangular_lights: Self::DEFAULT_EQUIANGULAR_LIGHTS,
        }
    }
}

/// How the path tracer picks, at each vertex, the one light it samples
/// (`crate::lights::LightSampler`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightSamplerKind {
    /// Every light equally likely.
    Uniform,
    /// In proportion to each light's power, wherever the vertex is.
    Power,
    /// By a light tree: lights near the vertex and facing it are likelier (hundreds of small
    /// lamps); lights at infinity apart, by power.
    Bvh,
    /// By power where a scene has few lights with a place, by the tree where it has
    /// [`LightSamplerKind::TREE_FROM`] or more.
    #[default]
    Auto,
}

impl LightSamplerKind {
    /// From how many lights with a place `auto` builds the tree. Measured (docs/performance.md,
    /// "Light sampling"): from 4 lamps on, spread over a floor or packed together, the tree's
    /// error at equal time is below power's (0.45× and 0.89× at 4 lamps), its walk costing a
    /// vertex less than its better picks save; a scene of one or two lights (the five
    /// reference scenes) keeps picking by power, where the tree has next to nothing to choose.
    pub const TREE_FROM: usize = 4;

    /// The sampler a scene or the command line names: `uniform`, `power`, `bvh` or `auto`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "uniform" => Some(Self::Uniform),
            "power" => Some(Self::Power),
            "bvh" => Some(Self::Bvh),
            "auto" => Some(Self::Auto),
            _ => None,
        }
    }
}

/// How the path tracer shares a render's samples among its pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SampleAllocation {
    /// Each pixel takes samples as it is noisy for what they cost there, as a pilot pass of
    /// the render's first samples finds it, the render costing what the samples per pixel
    /// everywhere would (`render::path::prepare_render`). A render in one pass of at least 16
    /// samples per pixel, or in slices of one; renders in passes share samples evenly, and
    /// so does a scene whose noise is about even. (Named apart from the ray tracer's adaptive
    /// anti-aliasing, which splits pixels, not the render's budget.)
    #[default]
    ByNoise,
    /// As [`Self::ByNoise`], with the pilot's map of the noise trusted whole: no share of the
    /// budget is held back for the pixels where the pilot may have missed rare paths (the
    /// plan's defence, `render::path::adaptive`). A little less error where the map is
    /// right; far more where a scene's light comes by rare bright paths the pilot missed.
    ByNoiseTrusted,
    /// Every pixel takes the same number.
    Uniform,
}

impl SampleAllocation {
    /// The allocation a scene or the command line names: `by-noise`, `by-noise-trusted` or
    /// `uniform`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "by-noise" => Some(Self::ByNoise),
            "by-noise-trusted" => Some(Self::ByNoiseTrusted),
            "uniform" => Some(Self::Uniform),
            _ => None,
        }
    }
}

impl PathOptions {
    /// The deepest path by default: in practice unbounded (Russian roulette ends paths long
    /// before), but a limit all the same, so that no scene can trap a path forever.
    pub const DEFAULT_MAX_DEPTH: u32 = 1024;

    /// The deepest path a scene or the command line may ask for: the default, as a path's
    /// cost grows only linearly with its depth (a ray tracer's tree doubles per bounce).
    pub const MAX_DEPTH: u32 = Self::DEFAULT_MAX_DEPTH;

    /// The radius of a tent or Gaussian pixel filter when the scene or the command line gives
    /// none, in pixels.
    pub const DEFAULT_FILTER_RADIUS: f64 = 1.5;
}

impl Default for PathOptions {
    fn default() -> Self {
        Self {
            sampler: SamplerKind::Sobol,
            filter: PixelFilter::Box,
            max_depth: Self::DEFAULT_MAX_DEPTH,
            roulette_depth: 5,
            roulette: Roulette::Learned,
            seed: 0,
            allocation: SampleAllocation::ByNoise,
            light_sampler: LightSamplerKind::Auto,
            techniques: Techniques::default(),
            roulette_predictions: true,
        }
    }
}
