//! The `rayforge` command. `main` only turns `run()`'s result into an exit code.

mod args;
mod atomic_write;
mod bench_command;
mod checkpoint;
mod diagnostics;
mod failure;
mod format;
mod frames;
mod interrupt;
mod progress;
mod render_command;
mod settings;
mod sizing;
mod summary;

use clap::Parser;
use failure::{Failure, EXIT_INTERNAL};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug: the default hook has printed its message; say so and exit 1, not 101.
    match catch_unwind(AssertUnwindSafe(run)) {
        Ok(Ok(code)) => code,
        Ok(Err(failure)) => failure.report(),
        Err(_) => {
            eprintln!("internal error: rayforge panicked (a bug; please report it with the scene)");
            ExitCode::from(EXIT_INTERNAL)
        }
    }
}

/// Parses the command line (clap prints help, or a usage error and exits 2, by itself), checks
/// it into settings, and runs the command; `rayforge bench` exits as `rayforge-bench` did.
fn run() -> Result<ExitCode, Failure> {
    diagnostics::install_handler();
    match args::Cli::parse().command {
        args::Command::Render(render) => {
            let settings = settings::RenderSettings::from_args(render)?;
            render_command::run(&settings).map(|()| ExitCode::SUCCESS)
        }
        args::Command::Bench(bench) => bench_command::run(&bench.args),
    }
}
