//! `rayforge-bench` (and `rayforge bench`, which runs it): rayforge measured against its peers
//! in one run on one machine, as ratios.
//!
//! A crate of its own so that the `rayforge` binary users ship carries none of it: not the
//! harness files, the JSON the Embree harness prints, nor the plotting. The library holds
//! everything; `main.rs` only parses the arguments and reports the outcome.
//!
//! Each part is a file: `primary.rs` (primary rays against Embree), `sweep.rs` (BVH build and
//! scaling with triangle count, with the plot), `scenes.rs` (whole renders against POV-Ray
//! and raytracer_rs), `cross.rs` (Don Cross's program on its own scenes), `pbr.rs` (the path
//! tracer against Mitsuba 3), `raster.rs` (the rasterizer against Mesa's llvmpipe, and its
//! frames per second orbiting the cover). They share the meshes (`shapes.rs`), the rays (`rays.rs`), rayforge's
//! tracing loop (`trace.rs`), the files handed to the Embree harness (`files.rs`, `embree.rs`)
//! and the report (`report.rs`). Peers are found in the directory `bench/peers/setup.sh`
//! fills, or where `--peer NAME=FILE` says (`peers.rs`); a missing one is a skipped row, never
//! an error.

// Every public item says what it measures or means: the tables are read by people who did not
// write them. Nothing here needs `unsafe`; the tracer's own unsafe code stays in `rayforge`.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod args;
mod cross;
mod embree;
mod files;
mod pbr;
pub mod peers;
mod plot;
mod pov_mesh;
mod primary;
mod raster;
mod rays;
mod report;
mod scenes;
mod shapes;
/// Writes the committed many-spheres scenes; only their test runs it (the files are committed).
#[cfg(test)]
mod spheres_scene;
mod sweep;
mod trace;

use args::{BenchArgs, BenchPart};
use peers::Peers;
use rayforge::geometry::Mesh;
use rayforge_cli::failure::Failure;
use rayon::ThreadPool;
use report::Report;
use std::path::{Path, PathBuf};

/// The most threads accepted (as for `render`).
const MAX_THREADS: usize = 1024;

/// The most passes per measurement accepted: more only adds time.
const MAX_REPEAT: u32 = 100;

/// The arguments, checked.
#[derive(Debug, Clone)]
pub struct BenchSettings {
    /// Run the primary-ray comparison.
    pub primary: bool,
    /// Print the BVH build table.
    pub build: bool,
    /// Print the scaling table and plot.
    pub scaling: bool,
    /// Run the whole-scene comparisons.
    pub scenes: bool,
    /// Run the comparison with Don Cross's program.
    pub cross: bool,
    /// Run the path tracer against Mitsuba 3.
    pub pbr: bool,
    /// Run the rasterizer against llvmpipe, and the orbit.
    pub raster: bool,
    /// Threads for both sides.
    pub threads: usize,
    /// Where the peers are.
    pub peers: PathBuf,
    /// Peers' binaries named with `--peer`, each checked to be a file.
    pub peer_binaries: Vec<peers::PeerBinary>,
    /// Where files go.
    pub out: PathBuf,
    /// Where the models beside the repository are.
    pub models: PathBuf,
    /// Where the POV-Ray scenes are.
    pub povray_scenes: PathBuf,
    /// The `rayforge` executable to time whole renders with, when given.
    pub rayforge: Option<PathBuf>,
    /// Passes per kernel measurement.
    pub repeat: u32,
    /// Runs per whole-scene measurement.
    pub scene_repeat: u32,
    /// A second place for the scaling plot.
    pub plot: Option<PathBuf>,
    /// Samples per pixel of the path tracer's renders.
    pub pbr_spp: u32,
    /// Rounds of the path tracer's renders.
    pub pbr_repeat: u32,
    /// Where the Mitsuba reference images are.
    pub pbr_reference: PathBuf,
    /// The Python with Mitsuba 3.
    pub python: PathBuf,
    /// Tiny sizes.
    pub quick: bool,
}

/// The most samples per pixel accepted for `--pbr-spp`.
const MAX_PBR_SPP: u32 = 1 << 16;

impl BenchSettings {
    /// Checks the arguments; each refusal names the flag.
    pub fn from_args(args: BenchArgs) -> Result<Self, Failure> {
        if !(1..=MAX_THREADS).contains(&args.threads) {
            return Err(Failure::usage(format!(
                "--threads must be from 1 to {MAX_THREADS}, found {}",
                args.threads
            )));
        }
        for (flag, value) in [
            ("--repeat", args.repeat),
            ("--scene-repeat", args.scene_repeat),
            ("--pbr-repeat", args.pbr_repeat),
        ] {
            if !(1..=MAX_REPEAT).contains(&value) {
                return Err(Failure::usage(format!(
                    "{flag} must be from 1 to {MAX_REPEAT}, found {value}"
                )));
            }
        }
        if !(1..=MAX_PBR_SPP).contains(&args.pbr_spp) {
            return Err(Failure::usage(format!(
                "--pbr-spp must be from 1 to {MAX_PBR_SPP}, found {}",
                args.pbr_spp
            )));
        }
        if let Some(path) = args.rayforge.as_deref().filter(|p| !p.is_file()) {
            return Err(Failure::usage(format!(
                "--rayforge `{}` is not a file",
                path.display()
            )));
        }
        if let Some(given) = args.peer_binaries.iter().find(|g| !g.path.is_file()) {
            return Err(Failure::usage(format!(
                "--peer {}=`{}` is not a file",
                given.peer.file_name(),
                given.path.display()
            )));
        }
        let all = args.part == BenchPart::All;
        Ok(Self {
            primary: all || args.part == BenchPart::Primary,
            build: all || args.part == BenchPart::Build,
            scaling: all || args.part == BenchPart::Scaling,
            scenes: all || args.part == BenchPart::Scenes,
            cross: all || args.part == BenchPart::Cross,
            pbr: all || args.part == BenchPart::Pbr,
            raster: all || args.part == BenchPart::Raster,
            threads: args.threads,
            peers: args.peers,
            peer_binaries: args.peer_binaries,
            out: args.out,
            models: args.models,
            povray_scenes: args.povray_scenes,
            rayforge: args.rayforge,
            repeat: if args.quick { 1 } else { args.repeat },
            scene_repeat: args.scene_repeat,
            plot: args.plot,
            pbr_spp: if args.quick { 2 } else { args.pbr_spp },
            pbr_repeat: if args.quick { 1 } else { args.pbr_repeat },
            pbr_reference: args.pbr_reference,
            python: args.python,
            quick: args.quick,
        })
    }
}

/// What every part needs: the settings, the peers found and the thread pool.
pub(crate) struct Bench<'a> {
    /// The checked arguments.
    pub settings: &'a BenchSettings,
    /// The peers found.
    pub peers: Peers,
    /// rayforge's threads, as many as the peers get.
    pub pool: ThreadPool,
}

impl Bench<'_> {
    /// A file in the output directory.
    pub fn out(&self, name: &str) -> PathBuf {
        self.settings.out.join(name)
    }

    /// The primary rays' image size: 1920×1080, or a thumbnail for `--quick`.
    pub fn image_size(&self) -> (usize, usize) {
        if self.settings.quick {
            (64, 36)
        } else {
            (1920, 1080)
        }
    }

    /// A line on stderr saying what is being measured (the tables go to stdout).
    pub fn progress(&self, message: &str) {
        eprintln!("… {message}");
    }

    /// rayforge's BVH over a soup, built on the benchmark's threads.
    pub fn build_mesh(&self, soup: &shapes::Soup) -> Result<Mesh, Failure> {
        self.pool
            .install(|| soup.to_mesh())
            .map_err(|e| Failure::internal(format!("the generated mesh is invalid: {e}")))
    }

    /// A file that could not be written, as a failure naming it.
    pub fn write_error(&self, path: &Path, e: std::io::Error) -> Failure {
        Failure::usage(format!("cannot write `{}`: {e}", path.display()))
    }
}

/// Runs the parts asked for, printing each table as it is done and a summary of the targets.
pub fn run(settings: &BenchSettings) -> Result<(), Failure> {
    std::fs::create_dir_all(&settings.out).map_err(|e| {
        Failure::usage(format!(
            "cannot create --out `{}`: {e}",
            settings.out.display()
        ))
    })?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.threads)
        .build()
        .map_err(|e| {
            Failure::internal(format!("cannot start {} threads: {e}", settings.threads))
        })?;
    let bench = Bench {
        settings,
        peers: Peers::find(&settings.peers, &settings.peer_binaries),
        pool,
    };
    let mut preamble = String::from("## rayforge bench\n\n");
    preamble += &format!(
        "Machine: {}, {} threads for every side{}.\n\n",
        cpu_name(),
        settings.threads,
        if settings.quick {
            "; --quick: tiny sizes, the numbers mean nothing"
        } else {
            ""
        }
    );
    for line in bench.peers.describe() {
        preamble += &format!("- {line}\n");
    }
    let mut report = Report::new(&preamble);
    if settings.primary {
        primary::run(&bench, &mut report)?;
    }
    if settings.build || settings.scaling {
        sweep::run(&bench, &mut report, settings.build, settings.scaling)?;
    }
    if settings.scenes {
        scenes::run(&bench, &mut report)?;
    }
    if settings.cross {
        cross::run(&bench, &mut report)?;
    }
    if settings.pbr {
        pbr::run(&bench, &mut report)?;
    }
    if settings.raster {
        raster::run(&bench, &mut report)?;
    }
    let path = bench.out("bench.md");
    report.finish(&path)?;
    Ok(())
}

/// The processor's name from /proc/cpuinfo, or "unknown CPU" where there is none.
fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, name)| name.split_whitespace().collect::<Vec<_>>().join(" "))
        })
        .unwrap_or_else(|| "unknown CPU".to_string())
}
