//! Validated settings: what the render command runs with, checked before any work starts.

use crate::args::RenderArgs;
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::sizing::SizeRequest;
use std::path::PathBuf;

/// Most camera rays per pixel accepted on the command line.
const MAX_SPP: u32 = 4096;

/// Deepest recursion accepted: every bounce can spawn two rays, so deep limits explode.
const MAX_DEPTH_LIMIT: u32 = 64;

/// Most worker threads accepted. Rendering is bound by the CPU, so threads beyond the cores
/// only add overhead; a number past this is a typo, and a pool of tens of thousands of
/// threads takes minutes just to start.
const MAX_THREADS: usize = 1024;

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
    /// No progress or summary.
    pub quiet: bool,
    /// The mesh size limit.
    pub max_triangles: usize,
    /// Continue from the checkpoint.
    pub resume: bool,
}

/// The highest `--max-triangles` accepted: meshes index their vertices with 32-bit numbers.
const MAX_TRIANGLE_LIMIT: usize = u32::MAX as usize - 1;

impl RenderSettings {
    /// Checks the raw arguments; each refusal names the flag.
    pub fn from_args(args: RenderArgs) -> Result<Self, Failure> {
        let format = ImageFormat::from_path(&args.output)?;
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
            quiet: args.quiet,
            max_triangles: args.max_triangles,
            resume: args.resume,
        })
    }
}
