//! Why a run failed, and the exit code that says so: 2 for what the user can fix (arguments,
//! paths), 1 for the rest; the same statuses as the `rayforge` command's.

use std::process::ExitCode;

/// Exit status for input the user can fix: arguments, an output path.
pub const EXIT_INPUT: u8 = 2;

/// Exit status for failures that are not the user's doing (a bug, or the system refusing).
pub const EXIT_INTERNAL: u8 = 1;

/// A failure to report to the user, explained in one line.
#[derive(Debug)]
pub enum Failure {
    /// Bad arguments or an unwritable path (exit 2).
    Input(String),
    /// Something that should not happen (exit 1).
    Internal(String),
}

impl Failure {
    /// A bad-input failure with a one-line message.
    pub fn usage(message: impl Into<String>) -> Self {
        Failure::Input(message.into())
    }

    /// An internal failure with a one-line message.
    pub fn internal(message: impl Into<String>) -> Self {
        Failure::Internal(message.into())
    }

    /// Prints the failure on stderr and returns its exit code.
    pub fn report(self) -> ExitCode {
        match self {
            Failure::Input(message) => {
                eprintln!("error: {message}");
                ExitCode::from(EXIT_INPUT)
            }
            Failure::Internal(message) => {
                eprintln!("internal error: {message}");
                ExitCode::from(EXIT_INTERNAL)
            }
        }
    }
}
