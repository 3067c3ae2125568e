//! Validated settings: what the render command runs with, checked before any work starts.

use crate::args::RenderArgs;
use crate::failure::Failure;
use crate::output::ImageFormat;
use std::path::PathBuf;

/// Default pixel limit: 2²⁸ pixels (16384 × 16384), about 6 GiB of linear colour in memory.
pub const DEFAULT_MAX_PIXELS: u64 = 1 << 28;

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
            max_pixels: args.max_pixels,
            quiet: args.quiet,
        })
    }
}
