//! Validated settings: what the render command runs with, checked before any work starts.

use crate::args::{FilterArg, RenderArgs, Renderer, ShadingArg};
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::sizing::SizeRequest;
use rayforge::raster::{RasterOptions, Shading, TextureFilter};
use std::path::PathBuf;

/// Most camera rays per pixel accepted on the command line.
const MAX_SPP: u32 = 4096;

/// Deepest recursion accepted: every bounce can spawn two rays, so deep limits explode.
const MAX_DEPTH_LIMIT: u32 = 64;

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
    /// Adaptive anti-aliasing threshold, when asked for.
    pub adaptive: Option<f64>,
    /// Subsampling threshold, when asked for.
    pub subsample: Option<f64>,
    /// Adaptive depth control's weight (0: off).
    pub bailout: f64,
    /// The animation frames to render, first and last, when asked for.
    pub frames: Option<(u64, u64)>,
    /// The pixel whose rays to print, when asked for.
    pub trace_pixel: Option<(usize, usize)>,
    /// No progress or summary.
    pub quiet: bool,
    /// The mesh size limit.
    pub max_triangles: usize,
    /// Continue from the checkpoint.
    pub resume: bool,
    /// Wait for an interrupt once this many rows are finished (a testing aid).
    pub pause_after_rows: Option<usize>,
    /// The renderer and raster options asked for on the command line.
    pub raster: RasterRequest,
}

/// The highest `--max-triangles` accepted: meshes index their vertices with 32-bit numbers.
const MAX_TRIANGLE_LIMIT: usize = u32::MAX as usize - 1;

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
        let format = ImageFormat::from_path(&args.output)?;
        let frames = match &args.frames {
            None => None,
            Some(text) => {
                if !crate::frames::has_frame_pattern(&args.output) {
                    return Err(Failure::usage(format!(
                        "--frames needs a frame number in the output name, such as \
                         `out/frame-%04d.png`; found `{}`",
                        args.output.display()
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
        if let Some(spp) = args.spp {
            if spp == 0 || spp > MAX_SPP {
                return Err(Failure::usage(format!(
                    "--spp must be between 1 and {MAX_SPP}, found {spp}"
                )));
            }
        }
        if let Some(t) = args.adaptive {
            if !(t.is_finite() && t > 0.0) {
                return Err(Failure::usage(format!(
                    "--adaptive takes a threshold above 0, found {t}"
                )));
            }
            if args.spp.is_some() {
                return Err(Failure::usage("give --spp or --adaptive, not both"));
            }
        }
        if let Some(t) = args.subsample {
            if !(0.0..=1.0).contains(&t) {
                return Err(Failure::usage(format!(
                    "--subsample takes a threshold from 0 to 1, found {t}"
                )));
            }
        }
        if !(0.0..=1.0).contains(&args.bailout) {
            return Err(Failure::usage(format!(
                "--bailout takes a weight from 0 to 1, found {}",
                args.bailout
            )));
        }
        if let Some(threads) = args.threads {
            if threads == 0 || threads > MAX_THREADS {
                return Err(Failure::usage(format!(
                    "--threads must be between 1 and {MAX_THREADS}, found {threads}"
                )));
            }
        }
        if let Some(depth) = args.max_depth.filter(|&d| d > MAX_DEPTH_LIMIT) {
            return Err(Failure::usage(format!(
                "--max-depth must be at most {MAX_DEPTH_LIMIT}, found {depth}"
            )));
        }
        if args.max_triangles == 0 || args.max_triangles > MAX_TRIANGLE_LIMIT {
            return Err(Failure::usage(format!(
                "--max-triangles must be between 1 and {MAX_TRIANGLE_LIMIT}, found {}",
                args.max_triangles
            )));
        }
        let raster = raster_request(&args)?;
        Ok(Self {
            scene: args.scene,
            output: args.output,
            format,
            size,
            threads: args.threads,
            max_depth: args.max_depth,
            spp: args.spp,
            adaptive: args.adaptive,
            subsample: args.subsample,
            bailout: args.bailout,
            frames,
            trace_pixel: match &args.trace_pixel {
                None => None,
                Some(text) => Some(parse_pixel(text)?),
            },
            quiet: args.quiet,
            max_triangles: args.max_triangles,
            resume: args.resume,
            pause_after_rows: args.pause_after_rows,
            raster,
        })
    }
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
    /// `--texture-filter`, when given.
    pub filter: Option<TextureFilter>,
    /// `--wireframe`.
    pub wireframe: bool,
    /// Whether `--spp` or `--adaptive` was given (the rasterizer does not anti-alias).
    pub sampling_flag: Option<&'static str>,
}

impl RasterRequest {
    /// The raster flag given, if any.
    fn raster_flag(&self) -> Option<&'static str> {
        [
            ("--shading", self.shading.is_some()),
            ("--sphere-divisions", self.sphere_divisions.is_some()),
            ("--texture-filter", self.filter.is_some()),
            ("--wireframe", self.wireframe),
        ]
        .into_iter()
        .find_map(|(flag, given)| given.then_some(flag))
    }

    /// The rasterizer's options when the rasterizer draws the scene (`--renderer raster`, or
    /// the scene's choice when the command line makes none), `None` for the ray tracer. The
    /// command line's raster flags win over the scene's; they are refused with the ray tracer,
    /// and the ray tracer's sampling flags with the rasterizer.
    pub fn resolve(&self, scene: Option<RasterOptions>) -> Result<Option<RasterOptions>, Failure> {
        let raster = match self.renderer {
            Some(Renderer::Ray) => false,
            Some(Renderer::Raster) => true,
            None => scene.is_some(),
        };
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
                "{flag} applies to the ray tracer; the rasterizer does not anti-alias"
            )));
        }
        let mut options = scene.unwrap_or_default();
        if let Some(shading) = self.shading {
            options.shading = shading;
        }
        if let Some(divisions) = self.sphere_divisions {
            options.sphere_divisions = divisions;
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
    Ok(RasterRequest {
        renderer: args.renderer,
        shading: args.shading.map(|s| match s {
            ShadingArg::Flat => Shading::Flat,
            ShadingArg::Gouraud => Shading::Gouraud,
            ShadingArg::Phong => Shading::Phong,
        }),
        sphere_divisions: args.sphere_divisions,
        filter: args.texture_filter.map(|f| match f {
            FilterArg::Nearest => TextureFilter::Nearest,
            FilterArg::Bilinear => TextureFilter::Bilinear,
            FilterArg::Trilinear => TextureFilter::Trilinear,
        }),
        wireframe: args.wireframe,
        sampling_flag: if args.spp.is_some() {
            Some("--spp")
        } else if args.adaptive.is_some() {
            Some("--adaptive")
        } else {
            None
        },
    })
}
