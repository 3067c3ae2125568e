//! Validated settings: what the render command runs with, checked before any work starts.

use crate::args::{
    FilterArg, PixelFilterArg, RenderArgs, Renderer, SampleAllocationArg, SamplerArg, ShadingArg,
    DEFAULT_BAILOUT,
};
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::sizing::SizeRequest;
use crate::slice::{Cut, Slice, SliceRequest};
use rayforge::film::PixelFilter;
use rayforge::options::{
    LightSamplerKind, MirrorBallBudget, PathOptions, Roulette, SampleAllocation, SamplerKind,
    Techniques,
};
use rayforge::raster::{RasterOptions, Shading, TextureFilter};
use rayforge_scene::Scene;
use std::path::PathBuf;

/// Most samples per pixel the ray tracer accepts, from `--spp` as from the camera's
/// `samples`, as many as its grid of 64 × 64 (each a tree of rays); the path tracer's
/// references go further.
const MAX_RAY_SPP: u32 = rayforge_scene::MAX_RAY_SAMPLES;

/// Most samples per pixel the path tracer accepts, from `--spp` as from `samples` (2²⁰).
pub const MAX_PATH_SPP: u32 = rayforge_scene::MAX_PATH_SAMPLES;

/// The ray tracer's deepest recursion: every bounce can spawn two rays, so deep limits
/// explode (the scene's `max-depth` has the same limit). The path tracer's is
/// [`PathOptions::MAX_DEPTH`].
const MAX_RAY_DEPTH: u32 = rayforge_scene::MAX_RAY_DEPTH as u32;

/// Most worker threads accepted. Rendering is bound by the CPU, so threads beyond the cores
/// only add overhead; a number past this is a typo, and a pool of tens of thousands of
/// threads takes minutes just to start.
const MAX_THREADS: usize = 1024;

/// Sphere resolutions accepted: 4096 divisions is 33 M triangles per sphere.
const SPHERE_DIVISIONS: std::ops::RangeInclusive<u32> = 3..=4096;

/// Everything `rayforge render` needs, validated.
#[derive(Debug, Clone)]
pub struct RenderSettings {
    /// The scene file.
    pub scene: PathBuf,
    /// The image to write.
    pub output: PathBuf,
    /// Its format, from the extension.
    pub format: ImageFormat,
    /// The size asked for, and the pixel limit.
    pub size: SizeRequest,
    /// Worker threads; `None` for all cores.
    pub threads: Option<usize>,
    /// Recursion limit asked for on the command line.
    pub max_depth: Option<u32>,
    /// Samples per pixel asked for on the command line.
    pub spp: Option<u32>,
    /// The ray tracer's adaptive anti-aliasing threshold, when asked for (`--adaptive-aa`).
    pub adaptive_aa: Option<f64>,
    /// Subsampling threshold, when asked for.
    pub subsample: Option<f64>,
    /// Adaptive depth control's weight (0: off): `--bailout`, else [`DEFAULT_BAILOUT`].
    pub bailout: f64,
    /// Whether `--bailout` was given (the renderers that do not use it refuse it).
    pub bailout_given: bool,
    /// The animation frames to render, first and last, when asked for.
    pub frames: Option<(u64, u64)>,
    /// The pixel whose rays to print, when asked for.
    pub trace_pixel: Option<(usize, usize)>,
    /// No progress or summary.
    pub quiet: bool,
    /// The mesh size limit.
    pub max_triangles: usize,
    /// The most rays one camera ray may lead to: `--max-rays-per-sample`, else
    /// [`rayforge::render::DEFAULT_MAX_RAYS_PER_SAMPLE`].
    pub max_rays_per_sample: u64,
    /// Whether `--max-rays-per-sample` was given (the renderers that do not use it warn).
    pub max_rays_given: bool,
    /// `--display-server`: where tev listens.
    pub display_server: Option<String>,
    /// `--display-timeout`: how long the viewer may take a packet.
    pub display_timeout: std::time::Duration,
    /// Whether the scene may name files outside its folder.
    pub allow_outside: bool,
    /// What a pbrt-v4 scene's files may hold (`--max-pbrt-*`).
    pub pbrt_limits: rayforge_scene::pbrt::PbrtLimits,
    /// The most samples one medium's grid may hold (`--max-grid-samples`).
    pub max_grid_samples: usize,
    /// The most optical depth one pass through a grid or cloud medium crosses
    /// (`--max-optical-depth`).
    pub max_optical_depth: f64,
    /// `--camera`: a glTF model's camera.
    pub camera: Option<String>,
    /// Continue from the checkpoint.
    pub resume: bool,
    /// Wait for an interrupt once this many rows are finished (a testing aid).
    pub pause_after_rows: Option<usize>,
    /// The renderer and raster options asked for on the command line.
    pub raster: RasterRequest,
    /// The path tracer's options asked for on the command line.
    pub path: PathRequest,
    /// The slice to render to a part file (`--slice`), when asked for.
    pub slice: Option<Slice>,
    /// The warnings printed so far, each said once however many frames repeat it.
    pub said: Said,
    /// `--force`: a slice may replace an output file that is not a part file.
    pub force: bool,
}

/// The warnings a command has printed: one about the flags (a guard the renderer ignores) or
/// about the scene (a key it reads as something else) holds for every frame of `--frames`
/// alike, so it is said at the first and not again. Shared by the settings' clones.
#[derive(Debug, Clone, Default)]
pub struct Said(std::sync::Arc<std::sync::Mutex<std::collections::HashSet<String>>>);

impl Said {
    /// Whether `text` is new, remembering it: a warning is printed only when it is.
    pub fn first(&self, text: &str) -> bool {
        let mut said = self
            .0
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        said.insert(text.to_owned())
    }

    /// Prints `warning: TEXT` on stderr unless it was said before.
    pub fn warn(&self, text: &str) {
        if self.first(text) {
            eprintln!("warning: {text}");
        }
    }
}

/// The renderer that draws a scene, with its options: the command line's choice, else the
/// scene's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Chosen {
    /// The Whitted ray tracer.
    Ray,
    /// The rasterizer.
    Raster(RasterOptions),
    /// The path tracer.
    Path(PathOptions),
}

/// The path tracer's flags given on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PathRequest {
    /// `--seed`.
    pub seed: Option<u64>,
    /// `--sampler`.
    pub sampler: Option<SamplerKind>,
    /// `--filter` with `--filter-radius`.
    pub filter: Option<PixelFilter>,
    /// `--roulette-scale`.
    pub roulette: Option<Roulette>,
    /// `--sample-allocation`.
    pub allocation: Option<SampleAllocation>,
    /// `--light-sampler`.
    pub light_sampler: Option<LightSamplerKind>,
    /// The techniques' switches and the mirror balls' budget.
    pub techniques: TechniquesRequest,
    /// `--roulette-predictions`.
    pub roulette_predictions: Option<bool>,
    /// `--aovs`.
    pub aovs: bool,
    /// `--denoise`.
    pub denoise: bool,
    /// `--time`: render in passes within this budget (the ray tracer too; not the
    /// rasterizer, which draws in one).
    pub time: Option<std::time::Duration>,
}

impl PathRequest {
    /// The path flag given, if any.
    fn flag(&self) -> Option<&'static str> {
        first_given([
            ("--seed", self.seed.is_some()),
            ("--sampler", self.sampler.is_some()),
            ("--filter", self.filter.is_some()),
            ("--roulette-scale", self.roulette.is_some()),
            ("--sample-allocation", self.allocation.is_some()),
            ("--light-sampler", self.light_sampler.is_some()),
            ("--next-event", self.techniques.next_event.is_some()),
            ("--mis", self.techniques.mis.is_some()),
            ("--roulette", self.techniques.roulette.is_some()),
            ("--glass-split", self.techniques.glass_split.is_some()),
            ("--mirror-balls", self.techniques.mirror_balls.is_some()),
            (
                "--mirror-ball-cap",
                self.techniques.mirror_ball_cap.is_some(),
            ),
            (
                "--mirror-ball-cull",
                self.techniques.mirror_ball_cull.is_some(),
            ),
            ("--sphere-cones", self.techniques.sphere_cones.is_some()),
            ("--equiangular", self.techniques.equiangular.is_some()),
            (
                "--equiangular-lights",
                self.techniques.equiangular_lights.is_some(),
            ),
            (
                "--roulette-predictions",
                self.roulette_predictions.is_some(),
            ),
            ("--aovs", self.aovs),
            ("--denoise", self.denoise),
        ])
    }
}

/// The path tracer's techniques as the command line sets them (`None`: as the scene says).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TechniquesRequest {
    /// `--next-event`.
    pub next_event: Option<bool>,
    /// `--mis`.
    pub mis: Option<bool>,
    /// `--roulette`.
    pub roulette: Option<bool>,
    /// `--glass-split`.
    pub glass_split: Option<bool>,
    /// `--mirror-balls`.
    pub mirror_balls: Option<bool>,
    /// `--mirror-ball-cap`.
    pub mirror_ball_cap: Option<u32>,
    /// `--mirror-ball-cull`.
    pub mirror_ball_cull: Option<f64>,
    /// `--sphere-cones`.
    pub sphere_cones: Option<bool>,
    /// `--equiangular`.
    pub equiangular: Option<bool>,
    /// `--equiangular-lights`.
    pub equiangular_lights: Option<u32>,
}

impl TechniquesRequest {
    /// The flags, checked.
    fn from_args(args: &RenderArgs) -> Result<Self, Failure> {
        let on = |flag: &Option<String>| flag.as_deref().map(|v| v == "on");
        if args.mirror_ball_cap == Some(0) {
            return Err(Failure::usage(
                "--mirror-ball-cap takes at least 1 (--mirror-balls off turns the sampling off)",
            ));
        }
        let cull = args
            .mirror_ball_cull
            .map(|share| {
                MirrorBallBudget::cull(share).ok_or_else(|| {
                    Failure::usage(format!(
                        "--mirror-ball-cull takes a share of the sky's light from 0 to below 1, \
                         found {share}"
                    ))
                })
            })
            .transpose()?;
        let equiangular_lights = args
            .equiangular_lights
            .map(|count| {
                Techniques::equiangular_lights(count.into()).ok_or_else(|| {
                    Failure::usage(format!(
                        "--equiangular-lights takes from 1 to {} lights (the fixed arrays a \
                         ray's sampler holds; --equiangular off turns the sampling off), \
                         found {count}",
                        Techniques::MAX_EQUIANGULAR_LIGHTS
                    ))
                })
            })
            .transpose()?;
        let roulette = on(&args.roulette);
        if roulette == Some(false) && args.roulette_scale.is_some() {
            return Err(Failure::usage(
                "--roulette-scale scales the roulette that --roulette off turns off",
            ));
        }
        Ok(Self {
            next_event: on(&args.next_event),
            mis: on(&args.mis),
            roulette,
            glass_split: on(&args.glass_split),
            mirror_balls: on(&args.mirror_balls),
            mirror_ball_cap: args.mirror_ball_cap,
            mirror_ball_cull: cull,
            sphere_cones: on(&args.sphere_cones),
            equiangular: on(&args.equiangular),
            equiangular_lights,
        })
    }

    /// `techniques` with these flags over them.
    fn apply(&self, techniques: &mut Techniques) {
        let set = |field: &mut bool, flag: Option<bool>| {
            if let Some(on) = flag {
                *field = on;
            }
        };
        set(&mut techniques.next_event, self.next_event);
        set(&mut techniques.mis, self.mis);
        set(&mut techniques.roulette, self.roulette);
        set(&mut techniques.glass_split, self.glass_split);
        set(&mut techniques.mirror_balls, self.mirror_balls);
        set(&mut techniques.sphere_cones, self.sphere_cones);
        set(&mut techniques.equiangular, self.equiangular);
        if let Some(count) = self.equiangular_lights {
            techniques.equiangular_lights = count;
        }
        if let Some(cap) = self.mirror_ball_cap {
            techniques.mirror_ball_budget.cap = cap;
        }
        if let Some(cull) = self.mirror_ball_cull {
            techniques.mirror_ball_budget.cull = cull;
        }
    }
}

/// The first of `flags` (each a flag's name and whether it was given) that was given: what a
/// refusal of flags that belong to another renderer names.
fn first_given<const N: usize>(flags: [(&'static str, bool); N]) -> Option<&'static str> {
    flags
        .into_iter()
        .find_map(|(flag, given)| given.then_some(flag))
}

/// The path tracer's flags, checked.
fn path_request(args: &RenderArgs) -> Result<PathRequest, Failure> {
    let radius = args
        .filter_radius
        .unwrap_or(PathOptions::DEFAULT_FILTER_RADIUS);
    if !(radius > 0.0 && radius <= rayforge::film::MAX_FILTER_RADIUS) {
        return Err(Failure::usage(format!(
            "--filter-radius must be above 0 and at most {}, found {radius}",
            rayforge::film::MAX_FILTER_RADIUS
        )));
    }
    let filter = match args.filter {
        None if args.filter_radius.is_some() => {
            return Err(Failure::usage(
                "--filter-radius needs --filter tent or --filter gaussian",
            ))
        }
        None => None,
        Some(PixelFilterArg::Box) if args.filter_radius.is_some() => {
            return Err(Failure::usage(
                "the box filter is one pixel wide: --filter-radius needs --filter tent or gaussian",
            ))
        }
        Some(PixelFilterArg::Box) => Some(PixelFilter::Box),
        Some(PixelFilterArg::Tent) => Some(PixelFilter::Tent { radius }),
        Some(PixelFilterArg::Gaussian) => Some(PixelFilter::Gaussian { radius }),
    };
    let roulette = args
        .roulette_scale
        .as_deref()
        .map(|text| {
            let (low, high) = (Roulette::MIN_SCALE, Roulette::MAX_SCALE);
            match text.parse::<f64>().ok().and_then(Roulette::scale) {
                _ if text == "auto" => Ok(Roulette::Learned),
                Some(roulette) => Ok(roulette),
                None => Err(Failure::usage(format!(
                    "--roulette-scale takes auto or a number from {low} to {high}, found `{}`",
                    rayforge_scene::clip(text)
                ))),
            }
        })
        .transpose()?;
    Ok(PathRequest {
        seed: args.seed,
        sampler: args.sampler.map(|s| match s {
            SamplerArg::Sobol => SamplerKind::Sobol,
            SamplerArg::Independent => SamplerKind::Independent,
        }),
        filter,
        roulette,
        allocation: args.sample_allocation.map(|a| match a {
            SampleAllocationArg::ByNoise => SampleAllocation::ByNoise,
            SampleAllocationArg::ByNoiseTrusted => SampleAllocation::ByNoiseTrusted,
            SampleAllocationArg::Uniform => SampleAllocation::Uniform,
            SampleAllocationArg::Adaptive => {
                if !args.quiet {
                    eprintln!(
                        "warning: `--sample-allocation adaptive` is the old name of \
                         `--sample-allocation by-noise` (the ray tracer's --adaptive-aa is \
                         another thing): write by-noise"
                    );
                }
                SampleAllocation::ByNoise
            }
        }),
        light_sampler: args
            .light_sampler
            .as_deref()
            .and_then(LightSamplerKind::from_name),
        techniques: TechniquesRequest::from_args(args)?,
        roulette_predictions: args.roulette_predictions.as_deref().map(|v| v == "on"),
        aovs: args.aovs,
        denoise: args.denoise,
        time: args.time.as_deref().map(parse_duration).transpose()?,
    })
}

/// A duration as `--time` takes it: a number and a unit (`ms`, `s`, `m` or `h`; seconds when
/// none), above zero and at most a year.
fn parse_duration(text: &str) -> Result<std::time::Duration, Failure> {
    let bad = || {
        Failure::usage(format!(
            "--time takes a duration such as 30s, 5m, 1h or 500ms, found `{}`",
            rayforge_scene::clip(text)
        ))
    };
    let text = text.trim();
    let split = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let number: f64 = number.parse().map_err(|_| bad())?;
    let seconds = match unit.trim() {
        "ms" => number / 1000.0,
        "" | "s" => number,
        "m" | "min" => number * 60.0,
        "h" => number * 3600.0,
        _ => return Err(bad()),
    };
    if !(seconds > 0.0 && seconds <= 366.0 * 24.0 * 3600.0) {
        return Err(bad());
    }
    Ok(std::time::Duration::from_secs_f64(seconds))
}

impl RenderSettings {
    /// The renderer that draws `scene` (the command line's `--renderer`, else the scene's
    /// `world:` item's `renderer:`), with the command line's options over the scene's. Each
    /// renderer's flags are refused with another renderer, and the sample counts of the
    /// command line and of the scene's camera are held to its limits.
    pub fn choose(&self, scene: &Scene) -> Result<Chosen, Failure> {
        let (scene_raster, scene_path) = (scene.raster, scene.path);
        let (renderer, by) = match self.raster.renderer {
            Some(renderer) => (renderer, ChosenBy::Flag),
            None if scene_raster.is_some() => (Renderer::Raster, ChosenBy::Scene),
            None if scene_path.is_some() => (Renderer::Path, ChosenBy::Scene),
            None => (Renderer::Ray, ChosenBy::Default),
        };
        let drawn_by = Drawn { renderer, by };
        self.check_limits(drawn_by)?;
        self.check_scene_samples(drawn_by, scene)?;
        self.check_scene_depth(drawn_by, scene)?;
        self.refuse_unused(drawn_by)?;
        if !self.quiet {
            for warning in self.ignored(drawn_by) {
                self.said.warn(&warning);
            }
        }
        if renderer != Renderer::Path {
            if let Some(flag) = self.path.flag() {
                return Err(Failure::usage(format!(
                    "{flag} applies to the path tracer: add --renderer path"
                )));
            }
        }
        if renderer == Renderer::Raster && self.path.time.is_some() {
            return Err(Failure::usage(
                "--time refines the ray tracer's and the path tracer's samples in passes; the \
                 rasterizer draws its image in one: add --renderer ray or path",
            ));
        }
        match renderer {
            Renderer::Ray => self.raster.resolve(None, false).map(|_| Chosen::Ray),
            Renderer::Raster => self
                .raster
                .resolve(scene_raster, true)
                .map(|o| Chosen::Raster(o.unwrap_or_default())),
            Renderer::Path => {
                self.raster.resolve(None, false)?;
                let mut options = scene_path.unwrap_or_default();
                if let Some(depth) = self.max_depth {
                    options.max_depth = depth;
                }
                if let Some(seed) = self.path.seed {
                    options.seed = seed;
                }
                if let Some(sampler) = self.path.sampler {
                    options.sampler = sampler;
                }
                if let Some(filter) = self.path.filter {
                    options.filter = filter;
                }
                if let Some(roulette) = self.path.roulette {
                    options.roulette = roulette;
                }
                if let Some(allocation) = self.path.allocation {
                    options.allocation = allocation;
                }
                if let Some(light_sampler) = self.path.light_sampler {
                    options.light_sampler = light_sampler;
                }
                self.path.techniques.apply(&mut options.techniques);
                if !options.techniques.roulette && self.path.roulette.is_some() {
                    return Err(Failure::usage(
                        "--roulette-scale scales the roulette that the scene's `roulette: off` \
                         turns off: add --roulette on",
                    ));
                }
                if let Some(predictions) = self.path.roulette_predictions {
                    options.roulette_predictions = predictions;
                }
                Ok(Chosen::Path(options))
            }
        }
    }

    /// `--spp` and `--max-depth` within the limits of the renderer that draws the scene.
    fn check_limits(&self, drawn: Drawn) -> Result<(), Failure> {
        let (most_spp, most_depth) = match drawn.renderer {
            Renderer::Ray => (MAX_RAY_SPP, MAX_RAY_DEPTH),
            Renderer::Path => (MAX_PATH_SPP, PathOptions::MAX_DEPTH),
            // The rasterizer takes neither: `--spp` is refused, `--max-depth` ignored.
            Renderer::Raster => return Ok(()),
        };
        // Where the path tracer would take it, a ray-traced scene's refusal says so.
        let path_too = |most: u32| match drawn.renderer {
            Renderer::Ray => format!(" (the path tracer's limit is {most})"),
            _ => String::new(),
        };
        if let Some(spp) = self.spp.filter(|&spp| spp > most_spp) {
            return Err(Failure::usage(format!(
                "--spp {spp} is more than {most_spp}, the most samples per pixel {drawn} \
                 takes{}",
                path_too(MAX_PATH_SPP)
            )));
        }
        if let Some(depth) = self.max_depth.filter(|&depth| depth > most_depth) {
            return Err(Failure::usage(format!(
                "--max-depth {depth} is more than {most_depth}, the most bounces {drawn} \
                 follows{}",
                path_too(PathOptions::MAX_DEPTH)
            )));
        }
        Ok(())
    }

    /// The camera's `samples` within the limit of the renderer that draws the scene, where it
    /// counts (`--spp` replaces it, `--adaptive-aa` samples otherwise, the rasterizer draws one
    /// sample): the scene's reader could hold it only to the most any renderer takes, not
    /// knowing the command line's `--renderer`. The error points at the key, as the reader's.
    fn check_scene_samples(&self, drawn: Drawn, scene: &Scene) -> Result<(), Failure> {
        if drawn.renderer != Renderer::Ray || self.spp.is_some() || self.adaptive_aa.is_some() {
            return Ok(());
        }
        let (samples, Some(at)) = (scene.samples, &scene.samples_at) else {
            return Ok(());
        };
        if samples <= MAX_RAY_SPP {
            return Ok(());
        }
        let error = at.error(format!(
            "{samples} samples per pixel is more than {MAX_RAY_SPP}, the most {drawn} takes (the \
             path tracer's limit is {MAX_PATH_SPP})"
        ));
        Err(crate::diagnostics::scene_failure(error))
    }

    /// The scene's `max-depth` within the limit of the ray tracer when the command line picks
    /// it for a scene of the path tracer, whose reader held the key to the path tracer's
    /// larger limit (`--max-depth` replaces the key, checked by [`Self::check_limits`]).
    fn check_scene_depth(&self, drawn: Drawn, scene: &Scene) -> Result<(), Failure> {
        if drawn.renderer != Renderer::Ray || self.max_depth.is_some() {
            return Ok(());
        }
        let (Some(depth), Some(at)) = (scene.max_depth, &scene.max_depth_at) else {
            return Ok(());
        };
        if depth <= MAX_RAY_DEPTH {
            return Ok(());
        }
        let error = at.error(format!(
            "{depth} bounces is more than {MAX_RAY_DEPTH}, the most {drawn} follows (the path \
             tracer's limit is {})",
            PathOptions::MAX_DEPTH
        ));
        Err(crate::diagnostics::scene_failure(error))
    }

    /// Refuses the ray tracer's flags for a technique the renderer that draws the scene does
    /// not have: they would change nothing, silently (the path tracer's and the rasterizer's
    /// own flags are refused with the others in [`Self::choose`] and [`RasterRequest`]).
    fn refuse_unused(&self, drawn: Drawn) -> Result<(), Failure> {
        let why = match drawn.renderer {
            Renderer::Ray => return Ok(()),
            // The rasterizer's refusal of `--spp` and `--adaptive-aa` says why itself.
            Renderer::Raster => "which traces no rays",
            Renderer::Path => "whose paths end by Russian roulette (--roulette-scale)",
        };
        let ray_only = [
            ("--bailout", self.bailout_given),
            (
                "--adaptive-aa",
                self.adaptive_aa.is_some() && drawn.renderer == Renderer::Path,
            ),
            ("--subsample", self.subsample.is_some()),
            ("--trace-pixel", self.trace_pixel.is_some()),
        ];
        match first_given(ray_only) {
            Some(flag) => Err(Failure::usage(format!(
                "{flag} applies to the ray tracer, not to {drawn}, {why}"
            ))),
            None => Ok(()),
        }
    }

    /// What a guard the renderer that draws the scene cannot exceed says when it is given:
    /// the limits are ignored, not refused, so that one set of limits serves a batch of
    /// scenes that mixes renderers (as `--max-pixels` and `--max-triangles` serve all).
    fn ignored(&self, drawn: Drawn) -> Vec<String> {
        let mut ignored = Vec::new();
        let mut ignore = |flag: &str, why: &str| {
            ignored.push(format!("{flag} is ignored: {drawn} {why}"));
        };
        match drawn.renderer {
            Renderer::Ray => {}
            Renderer::Path => {
                if self.max_rays_given {
                    ignore(
                        "--max-rays-per-sample",
                        "follows one path a sample, at most --max-depth bounces, no tree of \
                         rays to bound",
                    );
                }
            }
            Renderer::Raster => {
                if self.max_rays_given {
                    ignore("--max-rays-per-sample", "traces no rays");
                }
                if self.max_depth.is_some() {
                    ignore("--max-depth", "follows no reflections or refractions");
                }
            }
        }
        if drawn.renderer != Renderer::Raster && self.raster.max_triangles.is_some() {
            ignore(
                "--max-raster-triangles",
                "draws no triangles (--max-triangles bounds the models)",
            );
        }
        ignored
    }
}

/// Who chose the renderer that draws the scene, for the messages that name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ChosenBy {
    /// `--renderer`.
    Flag,
    /// The scene's `world:` item, `renderer:`.
    Scene,
    /// Nobody: the ray tracer.
    Default,
}

/// The renderer that draws the scene and who chose it; shown as, e.g., "the path tracer (the
/// scene's `renderer: path`)".
#[derive(Debug, Clone, Copy)]
struct Drawn {
    renderer: Renderer,
    by: ChosenBy,
}

impl std::fmt::Display for Drawn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (name, arg) = match self.renderer {
            Renderer::Ray => ("the ray tracer", "ray"),
            Renderer::Raster => ("the rasterizer", "raster"),
            Renderer::Path => ("the path tracer", "path"),
        };
        match self.by {
            ChosenBy::Flag => write!(f, "{name} (--renderer {arg})"),
            ChosenBy::Scene => write!(f, "{name} (the scene's `renderer: {arg}`)"),
            ChosenBy::Default => write!(f, "{name} (the default renderer)"),
        }
    }
}

/// The highest `--max-triangles` accepted: meshes index their vertices with 32-bit numbers.
const MAX_TRIANGLE_LIMIT: usize = u32::MAX as usize - 1;

/// The image to write: `-o`, else a pbrt scene's `Film` filename (in the current folder).
/// The film is read as the render reads the scene: under `--allow-outside`, `--max-triangles`
/// and the `--max-pbrt-*` limits.
fn output(args: &RenderArgs, pbrt: rayforge_scene::pbrt::PbrtLimits) -> Result<PathBuf, Failure> {
    if let Some(output) = &args.output {
        return Ok(output.clone());
    }
    if rayforge_scene::pbrt::is_scene_file(&args.scene) {
        let options = rayforge_scene::LoadOptions {
            max_triangles: args.max_triangles,
            allow_outside: args.allow_outside,
            pbrt,
            ..rayforge_scene::LoadOptions::default()
        };
        return rayforge_scene::pbrt::film_output(&args.scene, &options)
            .map_err(crate::diagnostics::scene_failure);
    }
    Err(Failure::usage(
        "-o/--output names the image to write (only a pbrt scene's film names a default)",
    ))
}

/// `--display-timeout`'s seconds: above 0, at most an hour.
fn display_timeout(seconds: f64) -> Result<std::time::Duration, Failure> {
    if seconds > 0.0 && seconds <= 3600.0 {
        Ok(std::time::Duration::from_secs_f64(seconds))
    } else {
        Err(Failure::usage(format!(
            "--display-timeout takes seconds above 0 and at most 3600, found {seconds}"
        )))
    }
}

/// `X,Y`, as `--trace-pixel` takes it.
fn parse_pixel(text: &str) -> Result<(usize, usize), Failure> {
    let bad = || {
        Failure::usage(format!(
            "--trace-pixel takes X,Y, two whole numbers (from the top-left corner), found `{text}`"
        ))
    };
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    Ok((
        x.trim().parse().map_err(|_| bad())?,
        y.trim().parse().map_err(|_| bad())?,
    ))
}

impl RenderSettings {
    /// Checks the raw arguments; each refusal names the flag.
    pub fn from_args(args: RenderArgs) -> Result<Self, Failure> {
        // The scene's limits first: a pbrt scene's film, which names the default output, is
        // read under them.
        if args.max_triangles == 0 || args.max_triangles > MAX_TRIANGLE_LIMIT {
            return Err(Failure::usage(format!(
                "--max-triangles must be between 1 and {MAX_TRIANGLE_LIMIT}, found {}",
                args.max_triangles
            )));
        }
        let pbrt_limits = rayforge_scene::pbrt::PbrtLimits {
            file_bytes: args.max_pbrt_file_bytes,
            total_bytes: args.max_pbrt_total_bytes,
            include_depth: args.max_pbrt_include_depth,
            values: args.max_pbrt_values,
            lens_rows: args.max_pbrt_lens_rows,
            radiances: args.max_pbrt_radiances,
        };
        for (flag, value) in [
            ("--max-pbrt-file-bytes", pbrt_limits.file_bytes),
            ("--max-pbrt-total-bytes", pbrt_limits.total_bytes),
            ("--max-pbrt-include-depth", pbrt_limits.include_depth as u64),
            ("--max-pbrt-values", pbrt_limits.values),
            ("--max-pbrt-lens-rows", pbrt_limits.lens_rows as u64),
            ("--max-pbrt-radiances", pbrt_limits.radiances as u64),
        ] {
            if value == 0 {
                return Err(Failure::usage(format!(
                    "{flag} must be at least 1, found 0"
                )));
            }
        }
        let most = rayforge::media::MAX_GRID_SAMPLES;
        if args.max_grid_samples == 0 || args.max_grid_samples > most {
            return Err(Failure::usage(format!(
                "--max-grid-samples must be between 1 and {most} (512³), found {}",
                args.max_grid_samples
            )));
        }
        if !(args.max_optical_depth > 0.0 && args.max_optical_depth.is_finite()) {
            return Err(Failure::usage(format!(
                "--max-optical-depth must be a finite number above 0, found {}",
                args.max_optical_depth
            )));
        }
        let output = output(&args, pbrt_limits)?;
        let slice = slice(&args)?;
        let format = match (slice, args.exr_half) {
            // A slice writes a part file whatever the extension; this format is never used
            // (with --frames, a slice is a share of the frames, each a whole image).
            (Some(_), _) if args.frames.is_none() => ImageFormat::Pfm,
            (_, half) => match (ImageFormat::from_path(&output)?, half) {
                (ImageFormat::Exr, true) => ImageFormat::ExrHalf,
                (_, true) => {
                    return Err(Failure::usage(format!(
                        "--exr-half needs an .exr output, not `{}`",
                        output.display()
                    )))
                }
                (format, false) => format,
            },
        };
        let frames = match &args.frames {
            None => None,
            Some(text) => {
                if !crate::frames::has_frame_pattern(&output) {
                    return Err(Failure::usage(format!(
                        "--frames needs a frame number in the output name, such as \
                         `out/frame-%04d.png`; found `{}`",
                        output.display()
                    )));
                }
                if args.resume {
                    return Err(Failure::usage(
                        "--frames resumes by itself (frames already written are skipped); \
                         drop --resume",
                    ));
                }
                Some(crate::frames::parse_range(text)?)
            }
        };
        let size = SizeRequest::new(args.width, args.height, args.max_pixels)?;
        // The limits of --spp and --max-depth are the renderer's, known once the scene is
        // read ([`Self::choose`]).
        if args.spp == Some(0) {
            return Err(Failure::usage("--spp must be at least 1, found 0"));
        }
        let adaptive_aa = adaptive_aa(&args)?;
        if let Some(t) = adaptive_aa {
            if !(t.is_finite() && t > 0.0) {
                return Err(Failure::usage(format!(
                    "--adaptive-aa takes a threshold above 0, found {t}"
                )));
            }
            if args.spp.is_some() {
                return Err(Failure::usage("give --spp or --adaptive-aa, not both"));
            }
        }
        if let Some(t) = args.subsample {
            if !(0.0..=1.0).contains(&t) {
                return Err(Failure::usage(format!(
                    "--subsample takes a threshold from 0 to 1, found {t}"
                )));
            }
        }
        let bailout = args.bailout.unwrap_or(DEFAULT_BAILOUT);
        if !(0.0..=1.0).contains(&bailout) {
            return Err(Failure::usage(format!(
                "--bailout takes a weight from 0 to 1, found {bailout}"
            )));
        }
        if let Some(threads) = args.threads {
            if threads == 0 || threads > MAX_THREADS {
                return Err(Failure::usage(format!(
                    "--threads must be between 1 and {MAX_THREADS}, found {threads}"
                )));
            }
        }
        if args.max_rays_per_sample == Some(0) {
            return Err(Failure::usage(
                "--max-rays-per-sample must be at least 1, found 0",
            ));
        }
        let raster = raster_request(&args)?;
        let path = path_request(&args)?;
        Ok(Self {
            scene: args.scene,
            output,
            format,
            size,
            threads: args.threads,
            max_depth: args.max_depth,
            spp: args.spp,
            adaptive_aa,
            subsample: args.subsample,
            bailout,
            bailout_given: args.bailout.is_some(),
            frames,
            trace_pixel: match &args.trace_pixel {
                None => None,
                Some(text) => Some(parse_pixel(text)?),
            },
            quiet: args.quiet,
            max_triangles: args.max_triangles,
            max_rays_per_sample: args
                .max_rays_per_sample
                .unwrap_or(rayforge::render::DEFAULT_MAX_RAYS_PER_SAMPLE),
            max_rays_given: args.max_rays_per_sample.is_some(),
            display_server: args.display_server.clone(),
            display_timeout: display_timeout(args.display_timeout)?,
            allow_outside: args.allow_outside,
            pbrt_limits,
            max_grid_samples: args.max_grid_samples,
            max_optical_depth: args.max_optical_depth,
            camera: args.camera.clone(),
            resume: args.resume,
            pause_after_rows: args.pause_after_rows,
            raster,
            path,
            slice,
            said: Said::default(),
            force: args.force,
        })
    }
}

/// `--adaptive-aa`, or its old name `--adaptive` with a deprecation warning.
fn adaptive_aa(args: &RenderArgs) -> Result<Option<f64>, Failure> {
    match (args.adaptive_aa, args.adaptive) {
        (Some(_), Some(_)) => Err(Failure::usage(
            "give --adaptive-aa once: --adaptive is its old name",
        )),
        (None, Some(threshold)) => {
            if !args.quiet {
                eprintln!(
                    "warning: --adaptive is the old name of --adaptive-aa (the ray tracer's \
                     adaptive anti-aliasing; the path tracer's --sample-allocation by-noise is \
                     another thing): write --adaptive-aa"
                );
            }
            Ok(Some(threshold))
        }
        (new, None) => Ok(new),
    }
}

/// `--slice` and `--slice-by`, checked, the index read from the environment for `auto`; the
/// flags a slice cannot take refused.
fn slice(args: &RenderArgs) -> Result<Option<Slice>, Failure> {
    let Some(text) = &args.slice else {
        return Ok(None);
    };
    // With --frames, a slice is a share of the frames, each rendered as a whole image: the
    // flags of a whole render apply.
    let part = args.frames.is_none();
    if part && args.denoise {
        // A denoiser sees the whole image: a slice's rows or samples alone would be denoised
        // as another image (its noise and edges), and the merge would add denoised slices.
        return Err(Failure::usage(
            "--denoise cannot be used with --slice: a slice is not the image. Render the \
             slices with --aovs (each part then keeps its albedo and normals) and denoise when \
             merging: `rayforge merge PARTS --denoise -o OUT` (rayforge slurm does both for \
             --denoise)",
        ));
    }
    if let Some(flag) = first_given([
        // A slice is not checkpointed: a requeued slice renders again (a complete part is kept).
        ("--resume", part && args.resume),
        ("--trace-pixel", part && args.trace_pixel.is_some()),
        (
            "--pause-after-rows",
            part && args.pause_after_rows.is_some(),
        ),
        // A part is linear f64 whatever the output; the merge writes the image.
        ("--exr-half", part && args.exr_half),
        // Passes for a time budget or a viewer: a slice renders its share in one pass.
        ("--time", part && args.time.is_some()),
        ("--display-server", part && args.display_server.is_some()),
    ]) {
        return Err(Failure::usage(format!(
            "{flag} cannot be used with --slice"
        )));
    }
    let request = SliceRequest::parse(text)?;
    let cut = Cut::from_arg(args.slice_by);
    // With --frames, a slice is a share of the frames, each rendered whole.
    if args.frames.is_some() && cut != Cut::Rows {
        return Err(Failure::usage(
            "with --frames, --slice picks the task's frames (each rendered whole): \
             --slice-by samples cannot be used with --frames",
        ));
    }
    request
        .resolve(cut, |name| std::env::var(name).ok())
        .map(Some)
}

/// The renderer and raster options asked for on the command line, to be merged with the
/// scene's own choice (its `world:` item may pick the rasterizer) when the scene is read.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RasterRequest {
    /// `--renderer`, when given.
    pub renderer: Option<Renderer>,
    /// `--shading`, when given.
    pub shading: Option<Shading>,
    /// `--sphere-divisions`, when given.
    pub sphere_divisions: Option<u32>,
    /// `--max-raster-triangles`, when given.
    pub max_triangles: Option<u64>,
    /// `--texture-filter`, when given.
    pub filter: Option<TextureFilter>,
    /// `--wireframe`.
    pub wireframe: bool,
    /// Whether `--spp` or `--adaptive-aa` was given (the rasterizer does not anti-alias).
    pub sampling_flag: Option<&'static str>,
}

impl RasterRequest {
    /// The raster flag given, if any.
    fn raster_flag(&self) -> Option<&'static str> {
        first_given([
            ("--shading", self.shading.is_some()),
            ("--sphere-divisions", self.sphere_divisions.is_some()),
            ("--texture-filter", self.filter.is_some()),
            ("--wireframe", self.wireframe),
        ])
    }

    /// The rasterizer's options when `raster` (the rasterizer draws the scene), `None` for
    /// the other renderers. The command line's raster flags win over the scene's; they are
    /// refused with the other renderers (`--max-raster-triangles`, a guard, is ignored there
    /// with a warning), and the sampling flags with the rasterizer.
    fn resolve(
        &self,
        scene: Option<RasterOptions>,
        raster: bool,
    ) -> Result<Option<RasterOptions>, Failure> {
        if !raster {
            if let Some(flag) = self.raster_flag() {
                return Err(Failure::usage(format!(
                    "{flag} applies to the rasterizer: add --renderer raster"
                )));
            }
            return Ok(None);
        }
        if let Some(flag) = self.sampling_flag {
            return Err(Failure::usage(format!(
                "{flag} applies to the {}; the rasterizer does not anti-alias",
                if flag == "--spp" {
                    "ray tracer and the path tracer"
                } else {
                    "ray tracer"
                }
            )));
        }
        let mut options = scene.unwrap_or_default();
        if let Some(shading) = self.shading {
            options.shading = shading;
        }
        if let Some(divisions) = self.sphere_divisions {
            options.sphere_divisions = divisions;
        }
        if let Some(max_triangles) = self.max_triangles {
            options.max_triangles = max_triangles;
        }
        if let Some(filter) = self.filter {
            options.filter = filter;
        }
        options.wireframe |= self.wireframe;
        Ok(Some(options))
    }
}

/// The raster flags, checked.
fn raster_request(args: &RenderArgs) -> Result<RasterRequest, Failure> {
    if let Some(divisions) = args.sphere_divisions {
        if !SPHERE_DIVISIONS.contains(&divisions) {
            return Err(Failure::usage(format!(
                "--sphere-divisions must be between {} and {}, found {divisions}",
                SPHERE_DIVISIONS.start(),
                SPHERE_DIVISIONS.end()
            )));
        }
    }
    if args.max_raster_triangles == Some(0) {
        return Err(Failure::usage(
            "--max-raster-triangles must be at least 1, found 0",
        ));
    }
    Ok(RasterRequest {
        renderer: args.renderer,
        shading: args.shading.map(|s| match s {
            ShadingArg::Flat => Shading::Flat,
            ShadingArg::Gouraud => Shading::Gouraud,
            ShadingArg::Phong => Shading::Phong,
        }),
        sphere_divisions: args.sphere_divisions,
        max_triangles: args.max_raster_triangles,
        filter: args.texture_filter.map(|f| match f {
            FilterArg::Nearest => TextureFilter::Nearest,
            FilterArg::Bilinear => TextureFilter::Bilinear,
            FilterArg::Trilinear => TextureFilter::Trilinear,
        }),
        wireframe: args.wireframe,
        sampling_flag: if args.spp.is_some() {
            Some("--spp")
        } else if args.adaptive_aa.is_some() || args.adaptive.is_some() {
            Some("--adaptive-aa")
        } else {
            None
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::{Cli, Command};
    use clap::Parser;

    /// The technique flags of `rayforge render scene.yml -o out.pfm FLAGS…`, checked.
    fn techniques(flags: &[&str]) -> Result<TechniquesRequest, Failure> {
        let line = ["rayforge", "render", "scene.yml", "-o", "out.pfm"];
        let cli = Cli::try_parse_from(line.iter().chain(flags)).expect("parses");
        let Command::Render(args) = cli.command else {
            panic!("render")
        };
        TechniquesRequest::from_args(&args)
    }

    #[test]
    fn the_equiangular_lights_flag_sets_the_count_within_the_arrays() {
        let mut t = Techniques::default();
        techniques(&[]).expect("no flags").apply(&mut t);
        assert_eq!(t.equiangular_lights, Techniques::DEFAULT_EQUIANGULAR_LIGHTS);
        for count in [1, 3, Techniques::MAX_EQUIANGULAR_LIGHTS] {
            let mut t = Techniques::default();
            techniques(&["--equiangular-lights", &count.to_string()])
                .expect("in range")
                .apply(&mut t);
            assert_eq!(t.equiangular_lights, count);
        }
        for bad in ["0", "17"] {
            let Err(Failure::Input(message)) = techniques(&["--equiangular-lights", bad]) else {
                panic!("{bad} is refused as a usage error")
            };
            assert!(
                message.contains("--equiangular-lights takes from 1 to 16")
                    && message.contains(&format!("found {bad}")),
                "{message}"
            );
        }
    }
}
