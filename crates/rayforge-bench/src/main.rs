//! The `rayforge-bench` executable (also run by `rayforge bench`). `main` only turns
//! [`rayforge_bench::run`]'s result into an exit code.

use clap::Parser;
use rayforge_bench::args::BenchArgs;
use rayforge_bench::BenchSettings;
use rayforge_cli::failure::{Failure, EXIT_INTERNAL};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug: the default hook has printed its message; say so and exit 1, not 101.
    match catch_unwind(AssertUnwindSafe(run)) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(failure)) => failure.report(),
        Err(_) => {
            eprintln!("internal error: rayforge-bench panicked (a bug; please report it)");
            ExitCode::from(EXIT_INTERNAL)
        }
    }
}

/// Parses the command line (clap prints help, or a usage error and exits 2, by itself), checks
/// it into settings, and runs the comparisons.
fn run() -> Result<(), Failure> {
    let settings = BenchSettings::from_args(BenchArgs::parse())?;
    rayforge_bench::run(&settings)
}
