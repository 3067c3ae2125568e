//! Validated settings: what the render command runs with, checked before any work starts.

use crate::args::RenderArgs;
use crate::failure::Failure;
use crate::output::ImageFormat;
use std::path::PathBuf;

/// Default pixel limit: 2²⁸ pixels (16384 × 16384), about 6 GiB of linear colour in memory.
pub const DEFAULT_MAX_PIXELS: u64 = 1 << 28;

/// Most camera rays per pixel accepted on the command line.
const MAX_SPP: u32 = 4096;

/// Deepest recursion accepted: every bounce can spawn two rays, so deep limits explode.
const MAX_DEPTH_LIMIT: u32 = 64;

/// Everything `rayforge render` needs, validated.
#[derive(Debug, Clone)]
pub struct RenderSettings {
    /// The scene file.
    pub scene: PathBuf,
    /// The image to write.
    pub output: PathBuf,
    /// Its format, from the extension.
    pub format: ImageFormat,
    /// Size overrides.
    pub width: Option<usize>,
    /// Size overrides.
    pub height: Option<usize>,
    /// Worker threads; `None` for all cores.
    pub threads: Option<usize>,
    /// Recursion limit.
    pub max_depth: u32,
    /// Samples per pixel asked for on the command line.
    pub spp: Option<u32>,
    /// Adaptive anti-aliasing threshold, when asked for.
    pub adaptive: Option<f64>,
    /// Largest image accepted.
    pub max_pixels: u64,
    /// No progress or summary.
    pub quiet: bool,
}

impl RenderSettings {
    /// Checks the raw arguments.
    pub fn from_args(args: RenderArgs) -> Result<Self, Failure> {
        let format = ImageFormat::from_path(&args.output)?;
        let size = |flag: &str, v: Option<u64>| -> Result<Option<usize>, Failure> {
            match v {
                Some(0) => Err(Failure::usage(format!("{flag} must be at least 1"))),
                Some(v) if v > args.max_pixels => Err(Failure::usage(format!(
                    "{flag} {v} exceeds the pixel limit {} (see --max-pixels)",
                    args.max_pixels
                ))),
                Some(v) => Ok(Some(v as usize)),
                None => Ok(None),
            }
        };
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
        if args.threads == Some(0) {
            return Err(Failure::usage("--threads must be at least 1"));
        }
        if args.max_depth > MAX_DEPTH_LIMIT {
            return Err(Failure::usage(format!(
                "--max-depth {} is more than the limit {MAX_DEPTH_LIMIT}",
                args.max_depth
            )));
        }
        Ok(Self {
            width: size("--width", args.width)?,
            height: size("--height", args.height)?,
            scene: args.scene,
            output: args.output,
            format,
            threads: args.threads,
            max_depth: args.max_depth,
            spp: args.spp,
            adaptive: args.adaptive,
            max_pixels: args.max_pixels,
            quiet: args.quiet,
        })
    }
}
