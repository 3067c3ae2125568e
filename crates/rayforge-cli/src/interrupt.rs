//! Ctrl-C and termination signals: the first asks the render to stop after the rows in
//! progress (so they can be saved); a second stops the process at once.

use crate::failure::EXIT_INTERRUPTED;
use rayforge_scene::StopFlag;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, LazyLock};

/// Shared, so that the scene reader (which holds its flag by [`StopFlag`]) stops at it too.
static STOP: LazyLock<Arc<AtomicBool>> = LazyLock::new(Arc::default);
static QUIET: AtomicBool = AtomicBool::new(false);

/// The flag an interrupt sets, as the scene reader takes it, with the handler installed: a
/// reading stops part-way, and the command exits 130 having written nothing.
pub fn load_stop(quiet: bool) -> StopFlag {
    stop_flag(quiet);
    StopFlag::new(Arc::clone(&STOP))
}

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
            eprintln!("\nstopping (Ctrl-C again stops at once)");
        }
    });
    &STOP
}
