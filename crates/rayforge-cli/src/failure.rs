//! Why the command failed, and the exit code that says so: 2 for bad input, 1 for the rest.

use std::process::ExitCode;

/// A failure to report to the user.
#[derive(Debug)]
pub enum Failure {
    /// Bad arguments, scene or file: the user can fix it (exit 2).
    Input(miette::Report),
    /// Something that should not happen (exit 1).
    Internal(miette::Report),
}

impl Failure {
    /// A bad-argument failure with a one-line message.
    pub fn usage(message: impl Into<String>) -> Self {
        Failure::Input(miette::miette!("{}", message.into()))
    }

    /// Prints the failure on stderr and returns its exit code.
    pub fn report(self) -> ExitCode {
        match self {
            Failure::Input(report) => {
                eprintln!("{report:?}");
                ExitCode::from(2)
            }
            Failure::Internal(report) => {
                eprintln!("{report:?}");
                ExitCode::from(1)
            }
        }
    }
}
