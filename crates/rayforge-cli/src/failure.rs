//! Why the command failed, and the exit code that says so: 2 for bad input, 1 for the rest.

use rayforge_scene::clip_to;
use std::process::ExitCode;

/// How many characters of a one-line message are printed at most: messages quote arguments
/// and paths, which may be any length.
const MAX_MESSAGE_CHARS: usize = 2000;

/// Exit status for input the user can fix: arguments, the scene file, the output path.
pub const EXIT_INPUT: u8 = 2;

/// Exit status for failures that are not the user's doing (a bug, or the system refusing).
pub const EXIT_INTERNAL: u8 = 1;

/// Exit status after an interrupt (Ctrl-C or a termination signal): 128 + SIGINT, as shells
/// report a process stopped by it.
pub const EXIT_INTERRUPTED: u8 = 130;

/// A failure to report to the user.
#[derive(Debug)]
pub enum Failure {
    /// Bad arguments, scene or output path, explained in one line (exit 2).
    Input(String),
    /// A scene error with the offending line of the file to show (exit 2).
    Scene(miette::Report),
    /// Something that should not happen (exit 1).
    Internal(String),
    /// The render was interrupted; the message says where its rows were saved (exit 130).
    Interrupted(String),
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
                eprintln!("error: {}", clip_to(&message, MAX_MESSAGE_CHARS));
                ExitCode::from(EXIT_INPUT)
            }
            Failure::Scene(report) => {
                eprintln!("{report:?}");
                ExitCode::from(EXIT_INPUT)
            }
            Failure::Internal(message) => {
                eprintln!("internal error: {}", clip_to(&message, MAX_MESSAGE_CHARS));
                ExitCode::from(EXIT_INTERNAL)
            }
            Failure::Interrupted(message) => {
                eprintln!("interrupted: {message}");
                ExitCode::from(EXIT_INTERRUPTED)
            }
        }
    }
}
