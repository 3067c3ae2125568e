//! The `world:` item: settings of the whole scene.
//!
//! ```yaml
//! - world:
//!     lighting: cgfs          # phong (the default), flat or cgfs
//!     background: [0, 0, 0]   # the colour of rays that hit nothing (default black)
//!     max-depth: 3            # reflection and refraction bounces (default 5; `--max-depth` wins)
//!     renderer: raster        # ray (the default), raster or path; raster then optionally
//!                             # `shading`, `sphere-divisions`, `wireframe` and
//!                             # `texture-filter`; path `sampler`, `filter`, `filter-radius`,
//!                             # `seed`, `roulette-depth`, `roulette-scale`,
//!                             # `sample-allocation` (`by-noise` or `uniform`),
//!                             # `light-sampler` and the techniques' switches
//!                             # (`next-event`, `mis`, `roulette`, `glass-split`,
//!                             # `mirror-balls`, `sphere-cones`, `equiangular`: `on` or
//!                             # `off`) with the
//!                             # mirror balls' `mirror-ball-cap` and `mirror-ball-cull`,
//!                             # `equiangular-lights` (1 to 16, default 8) and
//!                             # `roulette-predictions`
//! ```

use crate::assets::Assets;
use crate::environment::environment;
use crate::error::{clip, SceneError, Span};
use crate::material::color;
use crate::source::{check_keys, describe, Entry, Node, Source};
use rayforge::film::{PixelFilter, MAX_FILTER_RADIUS};
use rayforge::options::{
    LightSamplerKind, MirrorBallBudget, PathOptions, RasterOptions, Roulette, SampleAllocation,
    SamplerKind, Shading, Techniques, TextureFilter,
};
use rayforge::{LightingModel, World};

/// The deepest recursion a scene for the ray tracer may ask for (as `--max-depth` allows it):
/// every bounce can spawn two rays, so deep limits explode. A scene for the path tracer may ask
/// for up to [`PathOptions::MAX_DEPTH`], one path a sample.
pub const MAX_DEPTH: u64 = 64;

/// What a `world:` item says besides what goes into the world.
#[derive(Debug, Default)]
pub struct Settings {
    /// `max-depth`, if given.
    pub max_depth: Option<u32>,
    /// Where `max-depth` is written, when it is: a scene for the path tracer may ask more
    /// bounces than the ray tracer follows, which the command line's `--renderer ray` refuses
    /// there.
    pub max_depth_at: Option<Span>,
    /// The rasterizer's options, when `renderer: raster`.
    pub raster: Option<RasterOptions>,
    /// The path tracer's options, when `renderer: path` (its `max_depth` is `max-depth`, or
    /// [`PathOptions::DEFAULT_MAX_DEPTH`]).
    pub path: Option<PathOptions>,
}

/// The keys every renderer reads.
const WORLD_KEYS: &[&str] = &[
    "lighting",
    "background",
    "max-depth",
    "ambient-index",
    "renderer",
    "environment",
    "medium",
];

/// The keys that only the rasterizer reads.
const RASTER_KEYS: &[&str] = &["shading", "sphere-divisions", "wireframe", "texture-filter"];

/// The keys that only the path tracer reads.
const PATH_KEYS: &[&str] = &[
    "sampler",
    "filter",
    "filter-radius",
    "seed",
    "roulette-depth",
    "roulette-scale",
    "sample-allocation",
    "light-sampler",
    "next-event",
    "mis",
    "roulette",
    "glass-split",
    "mirror-balls",
    "mirror-ball-cap",
    "mirror-ball-cull",
    "sphere-cones",
    "equiangular",
    "equiangular-lights",
    "roulette-predictions",
];

/// The largest `seed` (every whole number up to it is exact in a YAML float too).
const MAX_SEED: f64 = 9_007_199_254_740_992.0; // 2^53

/// Applies a `world:` mapping to `world`; returns the rest of what it says.
pub fn apply(
    source: &Source<'_>,
    node: &Node<'_>,
    world: &mut World,
    assets: &mut Assets,
) -> Result<Settings, SceneError> {
    let entries = source.entries(node, "world")?;
    let (mut raster, mut path) = (None, None);
    if let Some(e) = entries.iter().find(|e| e.name == "renderer") {
        match source.string(e.value, "renderer")? {
            "ray" => {}
            "raster" => raster = Some(raster_options(source, &entries)?),
            "path" => path = Some(path_options(source, &entries)?),
            other => {
                return Err(source.error(
                    e.value,
                    "renderer",
                    format!("unknown renderer `{other}`; expected ray, raster or path"),
                ))
            }
        }
    }
    let foreign = [
        (raster.is_none(), RASTER_KEYS, "the rasterizer", "raster"),
        (path.is_none(), PATH_KEYS, "the path tracer", "path"),
    ];
    for (absent, keys, renderer, name) in foreign {
        if !absent {
            continue;
        }
        if let Some(e) = entries.iter().find(|e| keys.contains(&e.name)) {
            return Err(source.error(
                e.key,
                e.name,
                format!("`{}` applies to {renderer}: add `renderer: {name}`", e.name),
            ));
        }
    }
    let known: Vec<&str> = (WORLD_KEYS.iter().chain(RASTER_KEYS).chain(PATH_KEYS))
        .copied()
        .collect();
    check_keys(source, &entries, "`world`", &known)?;
    let (mut max_depth, mut max_depth_at) = (None, None);
    for e in &entries {
        match e.name {
            "lighting" => {
                world.lighting = match source.string(e.value, "lighting")? {
                    "phong" => LightingModel::Phong,
                    "flat" => LightingModel::Flat,
                    "cgfs" => LightingModel::Cgfs,
                    "optics" => LightingModel::Optics,
                    other => {
                        return Err(source.error(
                            e.value,
                            "lighting",
                            format!(
                        "unknown lighting model `{other}`; expected phong, flat, cgfs or optics"
                    ),
                        ))
                    }
                }
            }
            "environment" => world.environment = Some(environment(source, e.value, assets)?),
            "background" => world.background = color(source, e.value, "background")?,
            "ambient-index" => {
                let index = source.number(e.value, "ambient-index")?;
                if !(1.0..=9.0).contains(&index) {
                    return Err(source.error(
                        e.value,
                        "ambient-index",
                        "a refractive index lies between 1 and 9",
                    ));
                }
                world.ambient_index = index;
            }
            "max-depth" => {
                let depth = source.integer(e.value, "max-depth", 0)?;
                let (most, renderer) = match path {
                    Some(_) => (u64::from(PathOptions::MAX_DEPTH), "the path tracer"),
                    None => (MAX_DEPTH, "the ray tracer"),
                };
                if depth > most {
                    return Err(source.error(
                        e.value,
                        "max-depth",
                        format!("{depth} bounces is more than the limit {most} of {renderer}"),
                    ));
                }
                max_depth = Some(depth as u32);
                max_depth_at = Some(source.span(e.value));
            }
            _ => {} // the renderer's keys, read above
        }
    }
    if let Some(path) = &mut path {
        path.max_depth = max_depth.unwrap_or(PathOptions::DEFAULT_MAX_DEPTH);
    }
    Ok(Settings {
        max_depth,
        max_depth_at,
        raster,
        path,
    })
}

/// The path tracer's options from `sampler`, `filter`, `filter-radius`, `seed`,
/// `roulette-depth`, `roulette-scale`, `sample-allocation`, `light-sampler` and the
/// techniques' keys (`max-depth` is read with the other renderers' keys).
fn path_options(source: &Source<'_>, entries: &[Entry<'_, '_>]) -> Result<PathOptions, SceneError> {
    let mut options = PathOptions::default();
    let radius = entries.iter().find(|e| e.name == "filter-radius");
    if let Some(r) = radius.filter(|_| !entries.iter().any(|e| e.name == "filter")) {
        return Err(source.error(
            r.key,
            "filter-radius",
            "`filter-radius` needs `filter: tent` or `filter: gaussian`",
        ));
    }
    for e in entries {
        match e.name {
            "sampler" => {
                options.sampler = match source.string(e.value, "sampler")? {
                    "sobol" => SamplerKind::Sobol,
                    "independent" => SamplerKind::Independent,
                    other => {
                        return Err(source.error(
                            e.value,
                            "sampler",
                            format!("unknown sampler `{other}`; expected sobol or independent"),
                        ))
                    }
                }
            }
            "filter" => {
                let name = source.string(e.value, "filter")?;
                if !matches!(name, "box" | "tent" | "gaussian") {
                    return Err(source.error(
                        e.value,
                        "filter",
                        format!("unknown pixel filter `{name}`; expected box, tent or gaussian"),
                    ));
                }
                let radius = match radius {
                    Some(r) if name == "box" => {
                        return Err(source.error(
                            r.key,
                            "filter-radius",
                            "the box filter has no radius (it is the pixel itself)",
                        ))
                    }
                    Some(r) => {
                        let v = source.number(r.value, "filter-radius")?;
                        if !(v > 0.0 && v <= MAX_FILTER_RADIUS) {
                            return Err(source.error(
                                r.value,
                                "filter-radius",
                                format!(
                                    "a filter's radius is above 0 and at most \
                                     {MAX_FILTER_RADIUS} pixels"
                                ),
                            ));
                        }
                        v
                    }
                    None => PathOptions::DEFAULT_FILTER_RADIUS,
                };
                options.filter = match name {
                    "tent" => PixelFilter::Tent { radius },
                    "gaussian" => PixelFilter::Gaussian { radius },
                    _ => PixelFilter::Box,
                };
            }
            "seed" => {
                let v = source.number(e.value, "seed")?;
                if v.fract() != 0.0 || !(0.0..=MAX_SEED).contains(&v) {
                    return Err(source.error(
                        e.value,
                        "seed",
                        format!("expected a whole number from 0 to 2^53, found {v}"),
                    ));
                }
                options.seed = v as u64;
            }
            "roulette-depth" => {
                options.roulette_depth = source.integer(e.value, "roulette-depth", 1)? as u32;
            }
            "roulette-scale" => {
                options.roulette = roulette(source, e.value)?;
            }
            "sample-allocation" => {
                let name = source.string(e.value, "sample-allocation")?;
                // The old name, from before the ray tracer's adaptive anti-aliasing and this
                // were told apart; the repository's scenes and docs use `by-noise`.
                if name == "adaptive" {
                    source.warn(
                        e.value,
                        "sample-allocation",
                        "`adaptive` is the old name of `by-noise` (the ray tracer's adaptive \
                         anti-aliasing is another thing); write `sample-allocation: by-noise`",
                    );
                    options.allocation = SampleAllocation::ByNoise;
                    continue;
                }
                options.allocation = SampleAllocation::from_name(name).ok_or_else(|| {
                    source.error(
                        e.value,
                        "sample-allocation",
                        format!(
                            "expected `by-noise`, `by-noise-trusted` or `uniform`, found `{}`",
                            clip(name)
                        ),
                    )
                })?;
            }
            "light-sampler" => {
                let name = source.string(e.value, "light-sampler")?;
                options.light_sampler = LightSamplerKind::from_name(name).ok_or_else(|| {
                    source.error(
                        e.value,
                        "light-sampler",
                        format!(
                            "expected `uniform`, `power`, `bvh` or `auto`, found `{}`",
                            clip(name)
                        ),
                    )
                })?;
            }
            "next-event" => options.techniques.next_event = switch(source, e.value, e.name)?,
            "mis" => options.techniques.mis = switch(source, e.value, e.name)?,
            "roulette" => options.techniques.roulette = switch(source, e.value, e.name)?,
            "glass-split" => options.techniques.glass_split = switch(source, e.value, e.name)?,
            "mirror-balls" => options.techniques.mirror_balls = switch(source, e.value, e.name)?,
            "sphere-cones" => options.techniques.sphere_cones = switch(source, e.value, e.name)?,
            "equiangular" => options.techniques.equiangular = switch(source, e.value, e.name)?,
            "equiangular-lights" => {
                let count = source.integer(e.value, "equiangular-lights", 1)?;
                options.techniques.equiangular_lights = Techniques::equiangular_lights(count)
                    .ok_or_else(|| {
                        source.error(
                            e.value,
                            "equiangular-lights",
                            format!(
                                "from 1 to {} lights (the fixed arrays a ray's equiangular \
                                 sampler holds), found {count}",
                                Techniques::MAX_EQUIANGULAR_LIGHTS
                            ),
                        )
                    })?;
            }
            "mirror-ball-cap" => {
                let cap = source.integer(e.value, "mirror-ball-cap", 1)?;
                options.techniques.mirror_ball_budget.cap = cap as u32;
            }
            "mirror-ball-cull" => {
                let cull = source.number(e.value, "mirror-ball-cull")?;
                options.techniques.mirror_ball_budget.cull = MirrorBallBudget::cull(cull)
                    .ok_or_else(|| {
                        source.error(
                            e.value,
                            "mirror-ball-cull",
                            format!("a share of the sky's light from 0 to below 1, found {cull}"),
                        )
                    })?;
            }
            "roulette-predictions" => {
                options.roulette_predictions = source.boolean(e.value, "roulette-predictions")?;
            }
            _ => {}
        }
    }
    if !options.techniques.roulette {
        if let Some(e) = entries.iter().find(|e| e.name == "roulette-scale") {
            return Err(source.error(
                e.key,
                "roulette-scale",
                "`roulette-scale` scales the roulette that `roulette: off` turns off",
            ));
        }
    }
    Ok(options)
}

/// A technique's switch: `on` or `off` (`true` and `false` too).
fn switch(source: &Source<'_>, value: &Node<'_>, key: &str) -> Result<bool, SceneError> {
    if let Ok(on) = source.boolean(value, key) {
        return Ok(on);
    }
    match source.string(value, key) {
        Ok("on") => Ok(true),
        Ok("off") => Ok(false),
        Ok(other) => Err(source.error(
            value,
            key,
            format!("expected `on` or `off`, found `{}`", clip(other)),
        )),
        Err(_) => Err(source.error(
            value,
            key,
            format!("expected `on` or `off`, found {}", describe(value)),
        )),
    }
}

/// `roulette-scale`: `auto` (learned for the scene) or a number from
/// [`Roulette::MIN_SCALE`] to [`Roulette::MAX_SCALE`].
fn roulette(source: &Source<'_>, value: &Node<'_>) -> Result<Roulette, SceneError> {
    if source
        .string(value, "roulette-scale")
        .is_ok_and(|s| s == "auto")
    {
        return Ok(Roulette::Learned);
    }
    let (low, high) = (Roulette::MIN_SCALE, Roulette::MAX_SCALE);
    match source.number(value, "roulette-scale").map(Roulette::scale) {
        Ok(Some(roulette)) => Ok(roulette),
        _ => Err(source.error(
            value,
            "roulette-scale",
            format!("expected `auto` or a number from {low} to {high}"),
        )),
    }
}

/// The rasterizer's options from `shading`, `sphere-divisions`, `wireframe`, `texture-filter`.
fn raster_options(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
) -> Result<RasterOptions, SceneError> {
    let mut options = RasterOptions::default();
    for e in entries {
        match e.name {
            "shading" => {
                options.shading = match source.string(e.value, "shading")? {
                    "flat" => Shading::Flat,
                    "gouraud" => Shading::Gouraud,
                    "phong" => Shading::Phong,
                    other => {
                        return Err(source.error(
                            e.value,
                            "shading",
                            format!("unknown shading `{other}`; expected flat, gouraud or phong"),
                        ))
                    }
                }
            }
            "sphere-divisions" => {
                let n = source.integer(e.value, "sphere-divisions", 3)?;
                if n > 4096 {
                    return Err(source.error(e.value, "sphere-divisions", "at most 4096"));
                }
                options.sphere_divisions = n as u32;
            }
            "wireframe" => options.wireframe = source.boolean(e.value, "wireframe")?,
            "texture-filter" => {
                options.filter = match source.string(e.value, "texture-filter")? {
                    "nearest" => TextureFilter::Nearest,
                    "bilinear" => TextureFilter::Bilinear,
                    "trilinear" => TextureFilter::Trilinear,
                    other => {
                        return Err(source.error(
                            e.value,
                            "texture-filter",
                            format!(
                        "unknown texture filter `{other}`; expected nearest, bilinear or trilinear"
                    ),
                        ))
                    }
                }
            }
            _ => {}
        }
    }
    Ok(options)
}
