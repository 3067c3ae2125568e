//! The command line as clap sees it: raw arguments, validated later into settings.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// rayforge renders scene files with a Whitted ray tracer built on the classic ray tracing
/// books (The Ray Tracer Challenge's YAML scene format).
#[derive(Debug, Parser)]
#[command(name = "rayforge", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene file to an image (.png, .ppm or .pfm, chosen by the output's extension).
    Render(RenderArgs),
}

/// Arguments of `rayforge render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene file (YAML, in the format of The Ray Tracer Challenge's appendix A1).
    pub scene: PathBuf,

    /// Where to write the image. The extension picks the format: .png (8-bit), .ppm (the
    /// book's plain P3) or .pfm (linear 32-bit float RGB, for exact comparisons).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// Image width in pixels, overriding the scene's camera (its field of view is kept; give
    /// only one of --width/--height and the other follows the camera's aspect ratio).
    #[arg(long, value_name = "PIXELS")]
    pub width: Option<u64>,

    /// Image height in pixels, overriding the scene's camera (see --width).
    #[arg(long, value_name = "PIXELS")]
    pub height: Option<u64>,

    /// Worker threads [default: all cores]. The image is the same for any number.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,

    /// Camera rays per pixel, overriding the camera's `samples`: a stratified, jittered grid of
    /// the smallest square with at least that many cells (4 → 2×2, 9 → 3×3); 1 is one ray
    /// through the centre.
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,

    /// Anti-alias adaptively instead (chapter 17): rays at each pixel's corners and centre,
    /// splitting the pixel where they differ by more than this (0 to 1, per channel).
    #[arg(long, value_name = "THRESHOLD")]
    pub adaptive: Option<f64>,

    /// How many reflection and refraction bounces to follow.
    #[arg(long, value_name = "N", default_value_t = rayforge::DEFAULT_MAX_DEPTH)]
    pub max_depth: u32,

    /// The largest image to accept, in pixels (width × height), as a guard against typos
    /// that would take hours or all memory.
    #[arg(long, value_name = "PIXELS", default_value_t = crate::settings::DEFAULT_MAX_PIXELS)]
    pub max_pixels: u64,

    /// Print nothing but errors: no progress bar, no summary.
    #[arg(short, long)]
    pub quiet: bool,
}
