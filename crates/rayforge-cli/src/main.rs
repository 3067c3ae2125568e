//! The `rayforge` command. `main` only turns `run()`'s result into an exit code.

mod args;
mod diagnostics;
mod failure;
mod output;
mod progress;
mod render_command;
mod settings;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => failure.report(),
    }
}

fn run(cli: args::Cli) -> Result<(), failure::Failure> {
    match cli.command {
        args::Command::Render(render) => {
            let settings = settings::RenderSettings::from_args(render)?;
            render_command::run(&settings)
        }
    }
}
