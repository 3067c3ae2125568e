//! The command line as clap sees it: raw arguments, checked later into
//! [`BenchSettings`](crate::BenchSettings). `rayforge bench ARGS` runs `rayforge-bench ARGS`, so
//! these are the arguments of both.

use clap::{Parser, ValueEnum};
use std::path::PathBuf;

/// The examples under `--help`.
const EXAMPLES: &str = "\
Examples:
  bench/peers/setup.sh                        # once: Debian's peers and our harnesses
  rayforge bench                              # everything, on 2 threads
  rayforge bench primary --repeat 5
  rayforge bench scaling --plot docs/images/scaling.png
  rayforge bench pbr --pbr-reference /work/fidelity-data   # the path tracer against Mitsuba 3
  rayforge bench --quick                      # tiny sizes: checks the command, measures nothing
  rayforge bench cross --peer cross-raytrace=/opt/raytrace/raytrace   # a peer you built

`rayforge bench ARGS` runs this program, `rayforge-bench ARGS`, found beside `rayforge`; build
both with `cargo build --release -p rayforge-cli -p rayforge-bench`.

A peer that is not installed is reported as skipped. Peers: embree_primary, povray and
llvmpipe_frame (bench/peers/setup.sh: Debian's packages and our harnesses), raytracer_rs-cover,
raytracer_rs-dragons and cross-raytrace (binaries you build yourself and name with --peer; this
repository builds no other project's program). Exit status: 0 when every comparison ran
(whether or not rayforge met its targets), 2 for bad arguments, 1 when a peer or a file failed.";

/// Measure rayforge against its peers (Embree, POV-Ray, Mesa's llvmpipe, Mitsuba 3, and
/// raytracer_rs and Don Cross's program where you name their binaries) and print the tables of
/// times and ratios (bench/peers/setup.sh installs Debian's peers and builds our harnesses).
#[derive(Debug, Parser)]
#[command(name = "rayforge-bench", version, long_about = None, after_help = EXAMPLES)]
pub struct BenchArgs {
    /// Which comparison to run.
    #[arg(value_enum, default_value = "all")]
    pub part: BenchPart,

    /// Threads for both sides of every comparison (rayforge's pool, Embree's device and
    /// tracing threads, POV-Ray's +WT, raytracer_rs's RAYON_NUM_THREADS).
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub threads: usize,

    /// Where bench/peers/setup.sh put the peers (embree_primary, povray, llvmpipe_frame); a
    /// peer is looked for here by its NAME unless --peer names its binary.
    #[arg(long, value_name = "DIR", default_value = "bench/peers/build")]
    pub peers: PathBuf,

    /// A peer's binary, wherever it is (repeat for several): NAME is embree_primary, povray,
    /// llvmpipe_frame, raytracer_rs-cover (renders cover.yml at 1080×1080, one sample),
    /// raytracer_rs-dragons (renders bounding-boxes.yml at 1920×1080 with Samples::grid(4))
    /// or cross-raytrace (Don Cross's program). Wins over the file in --peers.
    #[arg(long = "peer", value_name = "NAME=FILE", value_parser = crate::peers::parse_peer_binary)]
    pub peer_binaries: Vec<crate::peers::PeerBinary>,

    /// Where to write meshes, rays, images, the plot and bench.md (the tables).
    #[arg(long, value_name = "DIR", default_value = "target/bench")]
    pub out: PathBuf,

    /// Where the models beside the repository are (dragon.obj, bounding-boxes.yml); comparisons
    /// that need one that is missing are skipped.
    #[arg(long, value_name = "DIR", default_value = "../shared/models")]
    pub models: PathBuf,

    /// The POV-Ray scenes (cover.pov, chessboard.pov, spheres.pov, dragons.pov).
    #[arg(long, value_name = "DIR", default_value = "bench/povray")]
    pub povray_scenes: PathBuf,

    /// The `rayforge` executable whose whole renders are timed [default: the one beside
    /// rayforge-bench, else `rayforge` on PATH].
    #[arg(long, value_name = "FILE")]
    pub rayforge: Option<PathBuf>,

    /// Traces of each mesh per side; the fastest counts.
    #[arg(long, value_name = "R", default_value_t = 3)]
    pub repeat: u32,

    /// Runs of each whole-scene render per side; the fastest counts (renders take seconds to
    /// minutes, so one run each unless asked).
    #[arg(long, value_name = "R", default_value_t = 1)]
    pub scene_repeat: u32,

    /// Also copy the scaling plot here (e.g. docs/images/scaling.png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,

    /// pbr: samples per pixel of every render timed (Mitsuba's equal-time renders take as
    /// many as fit in rayforge's time for these).
    #[arg(long, value_name = "N", default_value_t = 64)]
    pub pbr_spp: u32,

    /// pbr: rounds of renders (every configuration once per round, in turn); the median counts.
    #[arg(long, value_name = "R", default_value_t = 3)]
    pub pbr_repeat: u32,

    /// pbr: the Mitsuba reference images, NAME.mitsuba-hi.b0.pfm (preferred) or
    /// NAME.mitsuba.mean.pfm (see tools/fidelity/README.md).
    #[arg(long, value_name = "DIR", default_value = "../fidelity-data")]
    pub pbr_reference: PathBuf,

    /// pbr: the Python that imports Mitsuba 3 and runs tools/fidelity/bench_mitsuba.py.
    #[arg(long, value_name = "FILE", default_value = "python3")]
    pub python: PathBuf,

    /// Tiny meshes and images, one trace each: checks that every step runs in seconds; the
    /// numbers mean nothing.
    #[arg(long)]
    pub quick: bool,
}

/// Which comparisons to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BenchPart {
    /// Primary-ray throughput on meshes of a million triangles and more, against Embree.
    Primary,
    /// BVH build rate and bytes per triangle on large meshes (Embree's build for reference).
    Build,
    /// Time per primary ray from a thousand to ten million triangles, with a plot.
    Scaling,
    /// Whole renders of scenes against POV-Ray and raytracer_rs, as processes.
    Scenes,
    /// Don Cross's program (Fundamentals of Ray Tracing) against rayforge on its scenes, one
    /// thread each.
    Cross,
    /// The path tracer against Mitsuba 3: samples per second and error at equal time on the
    /// five scenes of scenes/pbr (skipped when Python cannot import mitsuba).
    Pbr,
    /// The rasterizer against Mesa's llvmpipe on a million-triangle frame, and its frames per
    /// second orbiting the cover at 640×360.
    Raster,
    /// All of the above (pbr only where Mitsuba is found).
    All,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peers_are_named_one_flag_each() {
        let args = BenchArgs::try_parse_from([
            "rayforge-bench",
            "--peer",
            "cross-raytrace=/opt/raytrace",
            "--peer",
            "raytracer_rs-cover=/opt/cover",
        ])
        .unwrap();
        let names: Vec<_> = args
            .peer_binaries
            .iter()
            .map(|p| p.peer.file_name())
            .collect();
        assert_eq!(names, ["cross-raytrace", "raytracer_rs-cover"]);
        assert!(BenchArgs::try_parse_from(["rayforge-bench", "--peer", "nobody=/x"]).is_err());
    }

    #[test]
    fn the_command_line_definition_is_consistent() {
        use clap::CommandFactory;
        BenchArgs::command().debug_assert();
    }

    #[test]
    fn the_defaults_are_those_of_rayforge_bench() {
        let args = BenchArgs::try_parse_from(["rayforge-bench"]).unwrap();
        assert_eq!(args.part, BenchPart::All);
        assert_eq!((args.threads, args.repeat, args.scene_repeat), (2, 3, 1));
        assert_eq!(args.peers, PathBuf::from("bench/peers/build"));
        assert!(args.peer_binaries.is_empty());
        assert!(!args.quick && args.plot.is_none() && args.rayforge.is_none());
        assert_eq!((args.pbr_spp, args.pbr_repeat), (64, 3));
    }
}
