//! The `rayforge` command as a library: the binary (`main.rs`) only turns [`run`]'s result into
//! an exit code. Its file writing ([`atomic_write`]), failures and exit codes ([`failure`]) and
//! render summary ([`summary`]) are public so that the benchmark program, `rayforge-bench`,
//! writes its reports and reads `rayforge render`'s summary line the same way, from one copy;
//! [`untrusted`] gives the fuzzer (`rayforge-fuzz`) the command's readers of outside bytes.

mod args;
pub mod atomic_write;
mod bench_command;
mod checkpoint;
mod checkpointed;
mod denoise;
mod denoise_command;
mod diagnostics;
pub mod failure;
mod finite;
mod format;
mod frames;
mod interrupt;
mod live_denoise;
mod memory;
mod merge_command;
mod output_lock;
mod part_file;
mod path_command;
mod path_output;
mod progress;
mod render_command;
mod serve;
mod settings;
mod sizing;
mod slice;
mod slice_render;
mod slurm_command;
mod slurm_script;
pub mod summary;
mod tev;
pub mod untrusted;

use clap::Parser;
use failure::Failure;
use std::process::ExitCode;

/// Parses the command line (clap prints help, or a usage error and exits 2, by itself), checks
/// it into settings, and runs the command; `rayforge bench` exits as `rayforge-bench` did.
pub fn run() -> Result<ExitCode, Failure> {
    diagnostics::install_handler();
    match args::Cli::parse().command {
        args::Command::Render(render) => {
            let settings = settings::RenderSettings::from_args(render)?;
            render_command::run(&settings).map(|()| ExitCode::SUCCESS)
        }
        args::Command::Bench(bench) => bench_command::run(&bench.args),
        args::Command::Merge(merge) => merge_command::run(&merge).map(|()| ExitCode::SUCCESS),
        args::Command::Slurm(slurm) => slurm_command::run(&slurm).map(|()| ExitCode::SUCCESS),
        args::Command::Serve(serve) => serve::run(serve),
        args::Command::Denoise(denoise) => {
            denoise_command::run(&denoise).map(|()| ExitCode::SUCCESS)
        }
    }
}
