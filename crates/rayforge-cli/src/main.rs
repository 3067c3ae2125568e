//! The `rayforge` command. `main` only turns `run()`'s result into an exit code.

use rayforge_cli::failure::EXIT_INTERNAL;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug: the default hook has printed its message; say so and exit 1, not 101.
    match catch_unwind(AssertUnwindSafe(rayforge_cli::run)) {
        Ok(Ok(code)) => code,
        Ok(Err(failure)) => failure.report(),
        Err(_) => {
            eprintln!("internal error: rayforge panicked (a bug; please report it with the scene)");
            ExitCode::from(EXIT_INTERNAL)
        }
    }
}
