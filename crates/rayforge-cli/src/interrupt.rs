//! Ctrl-C and termination signals: the first asks the render to stop after the rows in
//! progress (so they can be saved); a second stops the process at once.

use crate::failure::EXIT_INTERRUPTED;
use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);
static QUIET: AtomicBool = AtomicBool::new(false);

/// The flag an interrupt sets, with the handler installed (once per process). Without a
/// handler (the system refused one) the flag is never set and Ctrl-C stops the process as
/// usual.
pub fn stop_flag(quiet: bool) -> &'static AtomicBool {
    QUIET.store(quiet, Ordering::Relaxed);
    // Fails only when a handler is already installed (then it is ours) or the system refuses.
    let _ = ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted again: stopping now");
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        if !QUIET.load(Ordering::Relaxed) {
            eprintln!(
                "\nstopping after the rows in progress to save them (Ctrl-C again stops at once)"
            );
        }
    });
    &STOP
}
