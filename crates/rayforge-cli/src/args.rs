//! The command line as clap sees it: raw arguments, validated later into settings.

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// The weight below which secondary rays are not traced, unless `--bailout` says otherwise.
pub const DEFAULT_BAILOUT: f64 = 1.0 / 512.0;

/// Usage examples and exit statuses, shown under both `--help` pages.
macro_rules! examples {
    () => {
        "\
Examples:
  rayforge render scenes/trtc/cover.yml -o cover.png
  rayforge render scenes/trtc/cover.yml -o preview.png --width 200 --threads 2
  rayforge render scene.yml -o linear.pfm --max-depth 8 --quiet
  rayforge render scenes/trtc/cover.yml -o fast.png --renderer raster --shading gouraud
  rayforge render scene.yml -o part-2.rfpart --slice 2/4      # one of 4 slices (docs/distributed.md)
  rayforge merge part-*.rfpart -o merged.png                   # the 4 slices, one image
  rayforge slurm scene.yml -o frame.exr --tasks 64 --spp 4096 -- --partition=render

Ctrl-C (or SIGTERM) stops a render after the rows in progress; the finished rows are kept in
<FILE>.rayforge-checkpoint, and the same command with --resume finishes the image.

Exit status: 0 on success, 2 for bad input (arguments, the scene file, the output path),
1 for an internal error, 130 when interrupted."
    };
}

/// The options of `rayforge render`, in brief, for `rayforge --help` (each is described in full
/// by `rayforge render --help`; a test checks both list every flag).
const OVERVIEW: &str = concat!(
    "\
Render options (`rayforge render --help` describes each in full):
  -o, --output <FILE>       the image to write: .png, .ppm, .pfm or .exr, by extension
      --width <PIXELS>      image width (keeps the camera's field of view; alone, its aspect ratio)
      --height <PIXELS>     image height (likewise)
      --threads <N>         worker threads [default: all cores]
      --spp <N>             ray and path: samples per pixel, N for either renderer (the ray
                            tracer's a grid when N is a square) [default: the camera's `samples`]
      --adaptive-aa <T>     ray only: the chapter's adaptive anti-aliasing, this threshold
      --subsample <T>       ray only: trace every other pixel, interpolate where neighbours agree
      --frames <A..B>       render animation frames A to B to a %04d-numbered output
      --trace-pixel <X,Y>   ray only: print every ray that pixel casts, then render as usual
      --max-depth <N>       bounces: ray at most 64 [default: the scene's, else 5], path at
                            most 1024 [default: the scene's, else 1024]
      --bailout <WEIGHT>    ray only: leave out rays weighing less than this [default: 1/512]
      --max-pixels <PIXELS> the largest image accepted [default: 268435456, 2^28]
      --max-triangles <N>   the most triangles the scene's models may hold [default: 10000000]
      --max-rays-per-sample <N> ray: the most rays one camera ray may lead to [default: 4194304]
      --max-pbrt-file-bytes <N>    a pbrt scene's largest file [default: 67108864, 64 MiB]
      --max-pbrt-total-bytes <N>   a pbrt scene's files together [default: 1073741824, 1 GiB]
      --max-pbrt-include-depth <N> how deep a pbrt scene's Include/Import nest [default: 32]
      --max-pbrt-values <N>        a pbrt scene's parameter values together [default: 67108864]
      --max-pbrt-lens-rows <N>     rows of a pbrt realistic camera's lens file [default: 64]
      --max-pbrt-radiances <N>     radiances an emitting pbrt mesh with power gets [default: 1024]
      --max-grid-samples <N> the most samples one medium's grid holds [default: 134217728, 512^3]
      --max-optical-depth <D> the most optical depth one pass through a grid or cloud
                            medium crosses [default: 1000000]
      --allow-outside       let the scene name files outside its folder
      --camera <N|NAME>     a glTF model's camera, by index or name [default: its first]
      --resume              continue an interrupted render from its checkpoint
      --slice <I/N>         render slice I (from 0) of N to a part file for `rayforge merge`;
                            auto/N takes I from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX
      --slice-by <CUT>      rows (interleaved; any renderer) or samples (path only) [default: rows]
      --force               with --slice, replace an output file that is not a part file
  -q, --quiet               no progress bar and no summary
      --renderer <NAME>     ray (the ray tracer), raster (triangles; no shadows, mirrors
                            or glass) or path (the path tracer) [default: ray]
      --seed <N>            path only: the seed of its random numbers [default: 0]
      --sampler <NAME>      path only: sobol or independent [default: sobol]
      --filter <NAME>       path only: box, tent or gaussian pixel filter [default: box]
      --filter-radius <PX>  path only: the tent or Gaussian filter's radius [default: 1.5]
      --roulette-scale <K>  path only: auto (learned for the scene) or 0.25 to 64; 1 is the
                            classic Russian roulette [default: auto]
      --sample-allocation <NAME> path only: by-noise (samples where the noise is; --spp
                            is the mean), by-noise-trusted (no even floor) or uniform
                            [default: by-noise]
      --light-sampler <NAME> path only: uniform, power, bvh (a light tree) or auto (the
                            tree from 4 lights with a place) [default: auto]
      --next-event <on|off> path only: next-event estimation (lights sampled) [default: on]
      --mis <on|off>        path only: MIS between light and BSDF sampling [default: on]
      --roulette <on|off>   path only: Russian roulette (off: paths go to --max-depth)
                            [default: on]
      --glass-split <on|off> path only: follow both halves where the camera sees glass
                            [default: on]
      --mirror-balls <on|off> path only: the sky sampled through mirror balls [default: on]
      --mirror-ball-cap <K> path only: the most mirror balls solved a vertex [default: 2]
      --mirror-ball-cull <SHARE> path only: balls adding less of the sky's light are left
                            to BSDF sampling [default: 0.001]
      --sphere-cones <on|off> path only: glowing balls sampled in the cone they subtend
                            (off: by area) [default: on]
      --equiangular <on|off> path only: in homogeneous media, points drawn towards the
                            lamps, weighed by MIS (off: distance sampling alone) [default: on]
      --equiangular-lights <N> path only: how many of the most powerful lamps those points
                            are drawn towards, 1 to 16 [default: 8]
      --roulette-predictions <on|off> path only: whether the learned roulette ends paths
                            into learned predictions of the light to come [default: on]
      --aovs                path only: also write the first hit's albedo and normal
      --denoise             path only: denoise with Intel Open Image Denoise, guided by the
                            albedo and normals (tools/oidn/install.sh installs it)
      --time <DURATION>     ray and path: refine in passes until this time is spent (30s, 5m)
      --display-server <HOST:PORT> show the image in the tev viewer while it renders
      --display-timeout <SECONDS> how long the viewer may take a packet [default: 5]
      --exr-half            write the .exr output in 16-bit half floats
      --shading <MODE>      raster only: flat, gouraud or phong [default: phong]
      --sphere-divisions <N> raster only: sphere resolution (N+1 rings of N) [default: 48]
      --max-raster-triangles <N> raster: the most triangles a frame may hold [default: 2^25]
      --texture-filter <F>  raster only: nearest, bilinear or trilinear [default: trilinear]
      --wireframe           raster only: draw the triangles' edges

A flag for one renderer given to another is refused (`ray only`), except the guards
(--max-rays-per-sample, --max-raster-triangles, and --max-depth with the rasterizer): those
are ignored with a warning, so one set of limits serves a batch of scenes that mixes renderers.
Limits are the renderer's that draws the scene, the scene's own `renderer:` included.

",
    examples!()
);

/// The examples under `rayforge render --help`.
const RENDER_EXAMPLES: &str = examples!();

/// rayforge renders scene files with a Whitted ray tracer built on the classic ray tracing
/// books (The Ray Tracer Challenge's YAML scene format).
#[derive(Debug, Parser)]
#[command(name = "rayforge", version, about, long_about = None, after_help = OVERVIEW)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
// Parsed once per run: the render arguments' size beside `bench`'s one vector costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene file to an image (.png, .ppm, .pfm or .exr, chosen by the output's extension).
    #[command(after_help = RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Measure rayforge against its peers (Embree, POV-Ray, raytracer_rs) and print the tables
    /// of times and ratios: runs the separate `rayforge-bench` program beside this one
    /// (`rayforge bench --help` shows its options).
    // The benchmarks live in their own crate so that this binary carries none of them; every
    // argument, `--help` included, goes to `rayforge-bench` unread.
    #[command(disable_help_flag = true)]
    Bench(BenchArgs),
    /// Merge the part files of a render's slices (`rayforge render --slice I/N`) into its image
    /// (.png, .ppm, .pfm or .exr), the same bytes as the render done in one process.
    Merge(MergeArgs),
    /// Render on a Slurm cluster: write a job array of slices and a merge job that waits for
    /// them, into `<FILE>.slurm/` beside the image, and submit both with sbatch.
    #[command(after_help = SLURM_EXAMPLES)]
    Slurm(SlurmArgs),
    /// Show the scene on a live page in the browser: a local web server that renders it pass
    /// by pass, re-renders when the scene file or a file it names changes, and lets you pick the
    /// renderer, lighting, samples and size and orbit the camera with the mouse.
    #[command(after_help = SERVE_EXAMPLES)]
    Serve(ServeArgs),
    /// Denoise a linear image (.exr or .pfm, as `rayforge render` writes them) with Intel Open
    /// Image Denoise, guided by its albedo and normals, into an image (.png, .ppm, .pfm or
    /// .exr). `tools/oidn/install.sh` installs the library.
    #[command(after_help = DENOISE_EXAMPLES)]
    Denoise(DenoiseArgs),
}

/// The examples under `rayforge denoise --help`.
const DENOISE_EXAMPLES: &str = "\
Examples:
  rayforge render scenes/pbr/cornell.yml -o noisy.exr --renderer path --spp 16 --aovs
  rayforge denoise noisy.exr -o clean.png          # guided by noisy.exr's albedo and normal layers
  rayforge denoise noisy.pfm --albedo noisy.albedo.pfm --normal noisy.normal.pfm -o clean.pfm

Exit status: 0 on success, 2 for bad input (the images, the output path, or no Intel Open
Image Denoise), 1 for an internal error.";

/// Arguments of `rayforge denoise`.
#[derive(Debug, Args)]
pub struct DenoiseArgs {
    /// The noisy image: linear OpenEXR or PFM. An OpenEXR file's own `albedo` and `normal`
    /// layers (`rayforge render --aovs`) guide the denoiser unless --albedo or --normal names
    /// another file.
    pub input: PathBuf,

    /// The first surfaces' albedo, an OpenEXR (its R, G, B) or PFM image of the same size.
    #[arg(long, value_name = "FILE")]
    pub albedo: Option<PathBuf>,

    /// Their normals in [-1, 1], an OpenEXR or PFM image of the same size; needs an albedo.
    #[arg(long, value_name = "FILE")]
    pub normal: Option<PathBuf>,

    /// The denoised image; the extension picks the format, as for `rayforge render`. It may
    /// not be one of the inputs.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// The denoiser's threads [default: all cores]; the image is the same for any number.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,

    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// The examples under `rayforge slurm --help`.
const SLURM_EXAMPLES: &str = "\
Examples:
  rayforge slurm scenes/trtc/cover.yml -o cover.png --tasks 8 --width 3840 --height 2160
  rayforge slurm scene.yml -o frame.exr --tasks 64 --slice-by samples --renderer path --spp 4096 \\
      -- --partition=render --cpus-per-task=16 --time=1:00:00
  rayforge slurm scene.yml -o frame.exr --tasks 64 --dry-run   # write the scripts, submit nothing

rayforge slurm's own options (-o, --tasks, --slice-by, --dry-run) come first, then the render
flags, then `--` and the sbatch options, which go to both submissions.
Submitting the same command again re-runs only the slices whose parts are missing or damaged.";

/// Arguments of `rayforge slurm`.
#[derive(Debug, Args)]
pub struct SlurmArgs {
    /// The scene file, read by every task (it must be at the same path on the cluster's nodes).
    pub scene: PathBuf,

    /// The image the merge job writes (.png, .ppm, .pfm or .exr). The scripts, the part files
    /// and the logs go in `<FILE>.slurm/` beside it.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// How many slices to cut the render into: one task of the job array each.
    #[arg(long, value_name = "N")]
    pub tasks: u64,

    /// How the render is cut: `rows` (any renderer) or `samples` (the path tracer), as for
    /// `rayforge render --slice-by` [default: rows].
    #[arg(long, value_name = "CUT", value_enum)]
    pub slice_by: Option<SliceBy>,

    /// Write the scripts and print the sbatch commands that would submit them; submit nothing.
    #[arg(long)]
    pub dry_run: bool,

    /// `rayforge render`'s flags, given to every slice as they are (--width, --spp,
    /// --renderer, …; not -o, --slice or --slice-by, which this command sets), after this
    /// command's own options. Without --threads, a task uses the CPUs Slurm gives it
    /// (--cpus-per-task), else all the node's.
    #[arg(value_name = "RENDER FLAGS", allow_hyphen_values = true, num_args = 0..)]
    pub render_flags: Vec<String>,

    /// Options for sbatch, given to both submissions (--partition, --account, --time,
    /// --cpus-per-task, …).
    #[arg(last = true, value_name = "SBATCH OPTIONS")]
    pub sbatch: Vec<String>,
}

/// Arguments of `rayforge merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The part files, one per slice, in any order (`rayforge render --slice I/N` wrote them).
    #[arg(value_name = "PARTS", required_unless_present = "list")]
    pub parts: Vec<PathBuf>,

    /// A file naming more part files, one per line (relative names from the list's folder):
    /// however many slices there are, without an argument list's limit. `rayforge slurm`'s
    /// merge job reads its parts so.
    #[arg(long, value_name = "FILE")]
    pub list: Option<PathBuf>,

    /// The image to write; the extension picks the format, as for `rayforge render`. It may
    /// not be one of the merge's inputs.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// The scene file the slices were rendered from, read only when the image has canvas
    /// items, which the merge draws over it (it must be the very file, and the files it names
    /// the same, as the parts' fingerprint says). A part names its scene only for messages:
    /// the merge opens no path a part holds.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,

    /// Let that scene name files outside its folder, as `rayforge render --allow-outside`
    /// (the merge's own choice: never taken from a part).
    #[arg(long)]
    pub allow_outside: bool,

    /// The most triangles that scene's models may hold, as `rayforge render --max-triangles`.
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::DEFAULT_MAX_TRIANGLES)]
    pub max_triangles: usize,

    /// Path tracer: write the merged AOVs (albedo, normal, depth, sample count) as
    /// `rayforge render --aovs` does, beside the image or as layers of an OpenEXR output; the
    /// slices must have been rendered with --aovs, which keeps them in the parts.
    #[arg(long)]
    pub aovs: bool,

    /// Path tracer: denoise the merged image with Intel Open Image Denoise as `rayforge
    /// render --denoise` does, guided by the merged albedo and normals when the slices were
    /// rendered with --aovs (else unguided, with a warning); with --aovs the raw image is kept
    /// too (`out.noisy.png`, or the layer `noisy` of an OpenEXR output).
    #[arg(long)]
    pub denoise: bool,

    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// The examples under `rayforge serve --help`.
const SERVE_EXAMPLES: &str = "\
Examples:
  rayforge serve scenes/trtc/cover.yml
  rayforge serve scene.yml --port 0 --max-pixels 2000000

The page is served from the binary itself (nothing from the network, no file from disk but
the scene's); it listens on 127.0.0.1, this machine only, unless --listen says otherwise.
Ctrl-C stops the server.";

/// The port `rayforge serve` listens on unless `--port` says otherwise.
pub const DEFAULT_SERVE_PORT: u16 = 8765;

/// Arguments of `rayforge serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// The scene file, watched: saving it (or a file it names) re-renders the page's image.
    pub scene: PathBuf,

    /// The port to listen on; 0 takes any free port. The page's address is printed.
    #[arg(long, value_name = "PORT", default_value_t = DEFAULT_SERVE_PORT)]
    pub port: u16,

    /// The address to listen on. The default, 127.0.0.1, lets only this machine in; another
    /// address (0.0.0.0 for every network) shows the scene to whoever reaches it.
    #[arg(long, value_name = "ADDRESS", default_value = "127.0.0.1")]
    pub listen: std::net::IpAddr,

    /// Worker threads for rendering [default: all cores].
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,

    /// The largest image the page may ask for, in pixels (width × height), as `rayforge render
    /// --max-pixels`.
    #[arg(long, value_name = "PIXELS", default_value_t = crate::sizing::DEFAULT_MAX_PIXELS)]
    pub max_pixels: u64,

    /// Let the scene name files outside its own folder (see `rayforge render --help`).
    #[arg(long)]
    pub allow_outside: bool,

    /// Pages open at once: a page past it is told so and its socket closed. As many HTTP
    /// requests (the page, a socket's opening) are answered at once: one past them is answered
    /// 503 and closed.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_CONNECTIONS,
          value_parser = clap::value_parser!(u32).range(1..=MAX_SERVE_LIMIT))]
    pub max_connections: u32,

    /// Seconds a connection has to send its HTTP request and take the answer (a page's open
    /// socket is not limited by it): one that sends nothing is dropped after it.
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_REQUEST_TIMEOUT_SECONDS,
          value_parser = clap::value_parser!(u64).range(1..=3600))]
    pub request_timeout: u64,

    /// Renders at once, every page's together, each on the rendering threads (one per page at
    /// most; a page's request past it waits for one to end).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_RENDERS,
          value_parser = clap::value_parser!(u32).range(1..=MAX_SERVE_LIMIT))]
    pub max_renders: u32,

    /// Memory the renders in flight may hold together, in MiB (their films and images, as
    /// `rayforge render` counts them): one that needs more alone is refused, one that does not
    /// fit beside the others waits for them.
    #[arg(long, value_name = "MIB", default_value_t = DEFAULT_MAX_RENDER_MEMORY_MIB,
          value_parser = clap::value_parser!(u64).range(1..=1 << 40))]
    pub max_render_memory: u64,
}

/// `rayforge serve --max-connections`'s default: pages open at once.
pub const DEFAULT_MAX_CONNECTIONS: u32 = 16;
/// `rayforge serve --request-timeout`'s default, in seconds.
pub const DEFAULT_REQUEST_TIMEOUT_SECONDS: u64 = 10;
/// `rayforge serve --max-renders`'s default: renders at once, all pages together.
pub const DEFAULT_MAX_RENDERS: u32 = 2;
/// `rayforge serve --max-render-memory`'s default, in MiB: 2 GiB, a 26-megapixel image.
pub const DEFAULT_MAX_RENDER_MEMORY_MIB: u64 = 2048;
/// The most `--max-connections` and `--max-renders` take.
pub const MAX_SERVE_LIMIT: i64 = 4096;

/// Arguments of `rayforge bench`: everything after `bench`, passed to `rayforge-bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The arguments of `rayforge-bench` (see `rayforge bench --help`).
    #[arg(
        trailing_var_arg = true,
        allow_hyphen_values = true,
        value_name = "ARGS"
    )]
    pub args: Vec<std::ffi::OsString>,
}

/// Arguments of `rayforge render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene file (YAML, in the format of The Ray Tracer Challenge's appendix A1).
    pub scene: PathBuf,

    /// Where to write the image. The extension picks the format: .png (8-bit), .ppm (the
    /// book's plain P3), .pfm (linear 32-bit float RGB, for exact comparisons) or .exr
    /// (OpenEXR, linear 32-bit float RGB, for compositors, viewers and denoisers). Needed
    /// except for a pbrt scene, whose `Film` filename is then written in the current folder.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

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

    /// Samples per pixel, overriding the camera's `samples`: N for every renderer that
    /// samples. The ray tracer casts N camera rays, a stratified, jittered grid when N is a
    /// square (4 → 2×2, 9 → 3×3) and N-rooks otherwise (one ray in each of N columns and N
    /// rows); 1 is one ray through the centre; at most 4096. The path tracer takes N samples
    /// (their mean, with --sample-allocation by-noise), at most 1048576. Not with the
    /// rasterizer, which does not anti-alias.
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,

    /// Ray tracer: anti-alias adaptively instead (the adaptive supersampling of the "next
    /// steps" chapter): rays at each pixel's corners and centre, splitting the pixel where
    /// they differ by more than this threshold (above 0, per channel), down to 3 levels.
    /// The zoom camera's N × N grid is its `anti-alias` key.
    #[arg(long, value_name = "THRESHOLD")]
    pub adaptive_aa: Option<f64>,

    /// The old name of --adaptive-aa, read with a deprecation warning. Hidden from the help.
    #[arg(long, value_name = "THRESHOLD", hide = true)]
    pub adaptive: Option<f64>,

    /// Print the tree of rays pixel X,Y (from the image's top-left corner) casts: each ray,
    /// what it hits (object, point, normal, media), the light and the colour it brings back.
    /// The image is rendered and written as usual.
    #[arg(long, value_name = "X,Y")]
    pub trace_pixel: Option<String>,

    /// Render the frames FIRST..LAST (inclusive) of an animated scene (items with
    /// `per-frame`), each to the output name with `%04d` (or `%d`) replaced by its number.
    /// Frames already written are skipped, so an interrupted sequence resumes.
    #[arg(long, value_name = "FIRST..LAST")]
    pub frames: Option<String>,

    /// Computer Graphics from Scratch's subsampling: trace every other pixel of each row and
    /// fill the ones between with their neighbours' average where those differ by at most this
    /// (0 to 1, per channel); faster, slightly less exact.
    #[arg(long, value_name = "THRESHOLD")]
    pub subsample: Option<f64>,

    /// How many bounces to follow: the ray tracer's reflections and refractions, at most 64
    /// (every bounce can double the rays) [default: the scene's `max-depth`, else 5]; the path
    /// tracer's path length, at most 1024 [default: the scene's `max-depth`, else 1024]. The
    /// rasterizer follows none: ignored there, with a warning.
    #[arg(long, value_name = "N")]
    pub max_depth: Option<u32>,

    /// Ray tracer: adaptive depth control (Phong lighting): a reflected or refracted ray that
    /// would bring less than this fraction of its light to the pixel (the product of the
    /// reflectivities and transparencies on its way) is not traced. The default, 1/512,
    /// changes no 8-bit pixel by more than a step and saves the long chains of faint
    /// reflections; 0 traces every bounce up to --max-depth, as the book does. Refused with
    /// the path tracer (its paths end by Russian roulette, --roulette-scale) and the
    /// rasterizer [default: 1/512].
    #[arg(long, value_name = "WEIGHT")]
    pub bailout: Option<f64>,

    /// The largest image to accept, in pixels (width × height), as a guard against typos
    /// that would take hours or all memory.
    #[arg(long, value_name = "PIXELS", default_value_t = crate::sizing::DEFAULT_MAX_PIXELS)]
    pub max_pixels: u64,

    /// The most triangles the scene's OBJ models may hold together (a model used twice counts
    /// once; a model may also have at most three times as many vertices, normals or texture
    /// coordinates): a guard against models that would take all memory.
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::DEFAULT_MAX_TRIANGLES)]
    pub max_triangles: usize,

    /// The most rays one camera ray may lead to, its reflections, refractions and shadow rays
    /// all counted, in every lighting model: a guard against ray trees that would never end
    /// (a box of mirrors and glass many bounces deep doubles at every bounce). A render that
    /// needs more stops with an error naming the pixel. The ray tracer's guard: the path
    /// tracer (one path a sample, at most --max-depth bounces) and the rasterizer ignore it,
    /// with a warning [default: 4194304].
    #[arg(long, value_name = "N")]
    pub max_rays_per_sample: Option<u64>,

    /// Let the scene name files outside its own folder (models, material libraries, images,
    /// environment maps). Without it, an absolute path, a `..` that climbs out of the scene
    /// file's folder or a symbolic link that leads out is an error, so that a scene from
    /// elsewhere cannot make rayforge read other files.
    #[arg(long)]
    pub allow_outside: bool,

    /// The most bytes one file of a pbrt-v4 scene may hold (a `.gz` before and after
    /// inflating).
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::pbrt::PbrtLimits::DEFAULT.file_bytes)]
    pub max_pbrt_file_bytes: u64,

    /// The most bytes all the files of a pbrt-v4 scene may hold together, after inflating (a
    /// file included again counts again).
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::pbrt::PbrtLimits::DEFAULT.total_bytes)]
    pub max_pbrt_total_bytes: u64,

    /// How deep a pbrt-v4 scene's `Include` and `Import` may nest.
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::pbrt::PbrtLimits::DEFAULT.include_depth)]
    pub max_pbrt_include_depth: usize,

    /// The most parameter values (numbers, strings, booleans) a pbrt-v4 scene's files may hold
    /// together, counted as they are read, before any is kept.
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::pbrt::PbrtLimits::DEFAULT.values)]
    pub max_pbrt_values: u64,

    /// The most rows (lens interfaces) a pbrt-v4 realistic camera's lens file may hold: each
    /// row costs the exit pupil's million rays one more intersection apiece.
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::pbrt::PbrtLimits::DEFAULT.lens_rows)]
    pub max_pbrt_lens_rows: usize,

    /// The most radiances one emitting pbrt-v4 mesh with `power` is given: pbrt-v4 makes each
    /// triangle a light of that power, and rayforge a piece of the mesh per size of triangle;
    /// past this many sizes, this many bands of sizes share a radiance each, with a warning.
    #[arg(long, value_name = "N", default_value_t = rayforge_scene::pbrt::PbrtLimits::DEFAULT.radiances)]
    pub max_pbrt_radiances: usize,

    /// The most samples one grid of a participating medium may hold (a YAML grid's `size`, a
    /// `.vol` file's, a pbrt-v4 `uniformgrid` or `rgbgrid`'s nx × ny × nz), four bytes each
    /// or more: checked from the sizes before the grid is read. At most 134217728 (512^3).
    #[arg(long, value_name = "N", default_value_t = rayforge::media::MAX_GRID_SAMPLES)]
    pub max_grid_samples: usize,

    /// The most optical depth one straight pass through a grid or cloud medium may cross:
    /// its largest extinction times its box's diagonal in the world. Tracking a ray through
    /// such a medium takes about one step per unit, so a denser one is refused at its line
    /// rather than left to stall the render. Above 0.
    #[arg(long, value_name = "D", default_value_t = rayforge::media::MAX_OPTICAL_DEPTH)]
    pub max_optical_depth: f64,

    /// For a glTF model rendered directly: which of its cameras to look through, by index
    /// (0 is the first in node order) or by name; without it, its first camera, or one that
    /// frames the model when it has none.
    #[arg(long, value_name = "N|NAME")]
    pub camera: Option<String>,

    /// Continue an interrupted render: the rows saved in <FILE>.rayforge-checkpoint are kept
    /// and only the others are rendered, giving the same image as an uninterrupted run. Refused
    /// when the checkpoint was made from another scene file or other settings.
    #[arg(long)]
    pub resume: bool,

    /// For testing interruption: once this many rows are finished (the rasterizer's: drawn
    /// in its bands of tiles, inside the frame), the render waits for Ctrl-C (or a
    /// termination signal) before it goes on, so a test can interrupt it at a known point
    /// whatever the machine's speed. Hidden from the help.
    #[arg(long, value_name = "ROWS", hide = true)]
    pub pause_after_rows: Option<usize>,

    /// Render only slice I (counted from 0) of N and write it to a part file at --output
    /// (whatever its extension), for `rayforge merge` to join with the others into the image
    /// (see docs/distributed.md). `auto/N` takes I from the scheduler: SLURM_ARRAY_TASK_ID
    /// (Slurm job arrays, `--array=0-(N-1)`) or JOB_COMPLETION_INDEX (Kubernetes Indexed
    /// Jobs). A part already there and complete for the same render is kept, not rendered
    /// again.
    #[arg(long, value_name = "I/N")]
    pub slice: Option<String>,

    /// With --slice, replace an --output file that is not a part file (a part of another
    /// render or a damaged one is replaced without it). The scene and the files it names are
    /// never replaced.
    #[arg(long, requires = "slice")]
    pub force: bool,

    /// How --slice cuts the render: `rows`, every Nth row from row I (any renderer; the
    /// interleaving balances the slices' costs), or `samples`, a range of each pixel's sample
    /// sequence (the path tracer only).
    #[arg(long, value_name = "CUT", value_enum, requires = "slice")]
    pub slice_by: Option<SliceBy>,

    /// Print nothing but errors: no progress bar, no summary.
    #[arg(short, long)]
    pub quiet: bool,

    /// Which renderer draws the scene: `ray`, the Whitted ray tracer; `raster`, a software
    /// rasterizer (Computer Graphics from Scratch, part II) that draws every shape as
    /// triangles, much faster, with the same camera, materials and lights but no shadows,
    /// reflection, refraction or anti-aliasing; or `path`, a physically based path tracer
    /// (indirect light, glossy and rough materials, emitting surfaces, environment maps).
    /// [default: the scene's `renderer`, else ray]
    #[arg(long, value_name = "NAME", value_enum)]
    pub renderer: Option<Renderer>,

    /// Path tracer: the seed of its random numbers [default: the scene's `seed`, else 0].
    /// Renders with different seeds are independent estimates of the same image.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,

    /// Path tracer: `sobol` (Owen-scrambled Sobol points) or `independent` random numbers
    /// [default: the scene's `sampler`, else sobol].
    #[arg(long, value_name = "NAME", value_enum)]
    pub sampler: Option<SamplerArg>,

    /// Path tracer: how samples are weighed in their pixel: `box` (a plain average over the
    /// pixel), `tent` or `gaussian` [default: the scene's `filter`, else box].
    #[arg(long, value_name = "NAME", value_enum)]
    pub filter: Option<PixelFilterArg>,

    /// Path tracer: the tent or Gaussian filter's radius in pixels, above 0 and at most 8
    /// [default: 1.5].
    #[arg(long, value_name = "PIXELS")]
    pub filter_radius: Option<f64>,

    /// Path tracer: how long Russian roulette lets paths live, `auto` (learned for the
    /// scene by a pilot pass) or a number from 0.25 to 64 (a path goes on with probability
    /// the number × its throughput; 1 is the classic rule) [default: the scene's
    /// `roulette-scale`, else auto].
    #[arg(long, value_name = "K")]
    pub roulette_scale: Option<String>,

    /// Path tracer: how a render's samples are shared among its pixels: `by-noise` (each
    /// pixel takes samples as it is noisy, as a pilot pass finds it, --spp being the mean;
    /// renders in passes and of fewer than 16 samples per pixel share them evenly; as far as
    /// the pilot's two halves disagree, a share of the budget is spread evenly, a floor for
    /// pixels where it may have missed rare paths), `by-noise-trusted` (the same without that
    /// floor) or `uniform` (--spp each) [default: the scene's `sample-allocation`, else
    /// by-noise].
    #[arg(long, value_name = "NAME", value_enum)]
    pub sample_allocation: Option<SampleAllocationArg>,

    /// Path tracer: how a vertex picks the light it samples: `uniform`, `power`, `bvh` (a
    /// light tree, for many small lights) or `auto` (the tree from 4 lights with a place,
    /// else power) [default: the scene's `light-sampler`, else auto].
    #[arg(long, value_name = "NAME", value_parser = ["uniform", "power", "bvh", "auto"])]
    pub light_sampler: Option<String>,

    /// Path tracer: next-event estimation, a light sampled at every vertex; `off` leaves
    /// lights to be found by BSDF sampling [default: the scene's `next-event`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub next_event: Option<String>,

    /// Path tracer: multiple importance sampling between light sampling and BSDF sampling;
    /// `off` counts a light at full weight where light sampling finds it and not where BSDF
    /// sampling does [default: the scene's `mis`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub mis: Option<String>,

    /// Path tracer: Russian roulette; `off` ends no path before the most bounces
    /// (--max-depth) [default: the scene's `roulette`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub roulette: Option<String>,

    /// Path tracer: where the camera first sees smooth glass, follow both the reflected and
    /// the transmitted half; `off` takes one by chance [default: the scene's `glass-split`,
    /// else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub glass_split: Option<String>,

    /// Path tracer: the sky sampled through polished metal balls onto the surfaces they
    /// light [default: the scene's `mirror-balls`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub mirror_balls: Option<String>,

    /// Path tracer: the most mirror balls solved at a vertex, chosen by their shares of the
    /// sky's light where more qualify [default: the scene's `mirror-ball-cap`, else 2].
    #[arg(long, value_name = "K")]
    pub mirror_ball_cap: Option<u32>,

    /// Path tracer: mirror balls adding less than this share of the sky's light at a vertex
    /// are left to BSDF sampling, from 0 to below 1 [default: the scene's
    /// `mirror-ball-cull`, else 0.001].
    #[arg(long, value_name = "SHARE")]
    pub mirror_ball_cull: Option<f64>,

    /// Path tracer: a glowing ball seen from outside sampled uniformly in the cone of
    /// directions it subtends; `off` samples it by area, as every other shape [default: the
    /// scene's `sphere-cones`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub sphere_cones: Option<String>,

    /// Path tracer: in a homogeneous medium, a point per ray segment drawn towards the lamps
    /// (equiangular sampling) and weighed by MIS against distance sampling; `off` finds
    /// their scattered light by distance sampling alone [default: the scene's
    /// `equiangular`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub equiangular: Option<String>,

    /// Path tracer: how many lights (the most powerful that have a place) equiangular
    /// sampling draws its points towards, from 1 to 16 (the size of the fixed arrays a ray's
    /// sampler holds) [default: the scene's `equiangular-lights`, else 8].
    #[arg(long, value_name = "N")]
    pub equiangular_lights: Option<u32>,

    /// Path tracer: whether the learned roulette (`--roulette-scale auto`) also learns where
    /// the light a path still gathers past a diffuse surface is predictable, and ends paths
    /// there into the prediction (unbiased); `off` learns the scale alone [default: the
    /// scene's `roulette-predictions`, else on].
    #[arg(long, value_name = "on|off", value_parser = ["on", "off"])]
    pub roulette_predictions: Option<String>,

    /// Path tracer: also write the albedo and the normal of the first surface each pixel
    /// sees, for denoisers, beside the image (`out.albedo.pfm` and `out.normal.pfm` for
    /// `out.pfm`; the normals as (n + 1) / 2 in an 8-bit image), or in an OpenEXR output as
    /// its layers `albedo.R/G/B` and `normal.R/G/B`.
    #[arg(long)]
    pub aovs: bool,

    /// Path tracer: denoise the image with Intel Open Image Denoise (its `RT` filter on the
    /// linear radiance, guided by the first surfaces' albedo and normals, themselves denoised
    /// first); with --aovs the raw image is kept beside it, as `out.noisy.png` for `out.png`
    /// or the layer `noisy.R/G/B` of an OpenEXR output. With --display-server the viewer's
    /// image is the layer `denoised` (each pass's, denoised beside the render, then the
    /// final) and the rows fill the layer `noisy`. The library is loaded when rayforge
    /// runs: `tools/oidn/install.sh` installs it, and without it the render is refused before
    /// it starts.
    #[arg(long)]
    pub denoise: bool,

    /// Render in passes that refine the whole image, and stop before the pass that would go
    /// past this time, e.g. `30s`, `5m`, `1h` or `500ms`. The path tracer adds 1, 1, 2, 4, …
    /// samples per pixel to one film (with --spp, at most that many in all); the ray tracer
    /// renders 1, 4, 16, … camera rays per pixel, each pass afresh (up to --spp, --adaptive or
    /// the camera's anti-aliasing when given). The image is the one a render at the samples
    /// reached makes in one pass (the path tracer's with --sample-allocation uniform: passes
    /// share samples evenly). Not with the rasterizer.
    #[arg(long, value_name = "DURATION")]
    pub time: Option<String>,

    /// Show the image in the tev HDR viewer while it renders, over tev's TCP protocol
    /// (`HOST:PORT`, or `HOST` for tev's port 14158), rows as they finish, and with the path
    /// tracer each pass; the render goes on, after one warning, if the viewer is absent or
    /// goes away. The image is the viewer's unnamed layer (R, G, B); with --aovs the layers
    /// `albedo`, `normal`, `depth` and `samples` come beside it; with --denoise the rows fill
    /// `noisy` and the denoised image is `denoised`.
    #[arg(long, value_name = "HOST:PORT")]
    pub display_server: Option<String>,

    /// How long, in seconds, connecting to the viewer of --display-server and sending it one
    /// packet (at most 2^20 samples) may take before it counts as gone: it is then dropped
    /// with a warning and the render goes on, so a viewer that stops reading cannot hold the
    /// render. Above 0, at most 3600.
    #[arg(long, value_name = "SECONDS", default_value_t = crate::tev::DEFAULT_TIMEOUT.as_secs_f64())]
    pub display_timeout: f64,

    /// Write the OpenEXR output in 16-bit half floats instead of 32-bit ones (half the size;
    /// about three decimal digits; values past 65504 saturate). Needs an .exr output.
    #[arg(long)]
    pub exr_half: bool,

    /// How the rasterizer shades: `flat` (one colour per triangle), `gouraud` (lit at the
    /// vertices, blended) or `phong` (lit at every pixel). Needs --renderer raster.
    #[arg(long, value_name = "MODE", value_enum)]
    pub shading: Option<ShadingArg>,

    /// How finely the rasterizer cuts spheres into triangles: N+1 rings of N vertices (the
    /// book's GenerateSphere); cylinders and cones get N segments around. 3 to 4096 [default:
    /// 48]. Needs --renderer raster.
    #[arg(long, value_name = "N")]
    pub sphere_divisions: Option<u32>,

    /// The most triangles the rasterizer may hold for one frame, all objects' tessellations
    /// together (each placement counted), about 100 bytes each: a guard against sphere
    /// resolutions that would take all memory [default: 33554432, 2^25]. The rasterizer's
    /// guard: the other renderers ignore it, with a warning.
    #[arg(long, value_name = "N")]
    pub max_raster_triangles: Option<u64>,

    /// How the rasterizer filters textures: `nearest`, `bilinear` or `trilinear` (MIP-mapped)
    /// [default: trilinear]. Needs --renderer raster.
    #[arg(long, value_name = "FILTER", value_enum)]
    pub texture_filter: Option<FilterArg>,

    /// Draw only the edges of the triangles, each in its material's colour, hidden edges
    /// included (the book's wireframe). Needs --renderer raster.
    #[arg(long)]
    pub wireframe: bool,
}

/// The renderers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Renderer {
    /// The Whitted ray tracer.
    Ray,
    /// The software rasterizer.
    Raster,
    /// The physically based path tracer.
    Path,
}

/// How `--slice` cuts a render.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SliceBy {
    /// Interleaved rows: slice I takes rows I, I + N, I + 2N, …
    Rows,
    /// Each pixel's samples: slice I takes the I-th of N ranges of the sample sequence.
    Samples,
}

/// The path tracer's samplers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SamplerArg {
    /// Owen-scrambled Sobol points.
    Sobol,
    /// Independent random numbers.
    Independent,
}

/// How the path tracer shares samples among pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SampleAllocationArg {
    /// As each pixel is noisy, from a pilot pass.
    ByNoise,
    /// As by-noise, the pilot's map trusted whole (no even share held back).
    ByNoiseTrusted,
    /// The same in every pixel.
    Uniform,
    /// The old name of `by-noise`, read with a deprecation warning.
    #[value(hide = true)]
    Adaptive,
}

/// The path tracer's pixel filters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PixelFilterArg {
    /// Each sample within its pixel, weight 1.
    Box,
    /// A pyramid.
    Tent,
    /// A Gaussian.
    Gaussian,
}

/// Shading modes of the rasterizer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ShadingArg {
    /// One colour per triangle.
    Flat,
    /// Lit at the vertices, blended across.
    Gouraud,
    /// Lit at every pixel.
    Phong,
}

/// Texture filters of the rasterizer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FilterArg {
    /// The nearest texel.
    Nearest,
    /// Four texels blended.
    Bilinear,
    /// Bilinear in two MIP levels, blended.
    Trilinear,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overview_states_the_real_defaults() {
        let depth = format!(
            "[default: the scene's, else {}]",
            rayforge::DEFAULT_MAX_DEPTH
        );
        let pixels = format!("[default: {}, 2^28]", crate::sizing::DEFAULT_MAX_PIXELS);
        let triangles = format!("[default: {}]", rayforge_scene::DEFAULT_MAX_TRIANGLES);
        assert!(OVERVIEW.contains(&triangles), "{triangles}");
        assert!(OVERVIEW.contains(&depth), "{depth}");
        assert!(OVERVIEW.contains(&pixels), "{pixels}");
    }

    #[test]
    fn the_overview_states_the_equiangular_lights_and_their_bound() {
        use rayforge::options::Techniques;
        let lights = format!(
            "1 to {} [default: {}]",
            Techniques::MAX_EQUIANGULAR_LIGHTS,
            Techniques::DEFAULT_EQUIANGULAR_LIGHTS
        );
        assert!(OVERVIEW.contains(&lights), "{lights}");
    }

    #[test]
    fn the_overview_states_the_raster_defaults() {
        let divisions = format!(
            "[default: {}]",
            rayforge::raster::RasterOptions::DEFAULT_SPHERE_DIVISIONS
        );
        assert!(OVERVIEW.contains(&divisions), "{divisions}");
        let defaults = rayforge::raster::RasterOptions::default();
        assert_eq!(defaults.shading, rayforge::raster::Shading::Phong);
        assert_eq!(defaults.filter, rayforge::raster::TextureFilter::Trilinear);
    }

    #[test]
    fn the_command_line_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
