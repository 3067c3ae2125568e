//! A render whose finished rows are saved as they come: the checkpoint opened (continued with
//! `--resume`, else new), the render run with hooks that hand each row to the checkpoint's
//! writer thread, show progress and heed Ctrl-C, and the message of an interrupted render.
//! The ray tracer and the path tracer both render this way; what a row holds is theirs to say.

use crate::checkpoint::{self, FinishedRow, Log, Logged, RenderKey};
use crate::failure::Failure;
use crate::progress::row_bar;
use crate::settings::RenderSettings;
use crate::tev::Display;
use rayforge::canvas::Canvas;
use rayforge::color::Color;
use rayforge::render::{PartialImage, RowCallback};
use std::path::Path;
use std::sync::atomic::Ordering::SeqCst;
use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::sync::{mpsc, Mutex, Once};

/// What a render is given to save its rows: call `on_row` with each finished row, `progress`
/// with the number of rows just finished, and stop when `stop` is set.
pub struct Hooks<'a> {
    /// Hands a finished row (its index and values) to the checkpoint.
    pub on_row: &'a RowCallback<'a>,
    /// Advances the progress bar.
    pub progress: &'a (dyn Fn(usize) + Sync),
    /// Set by Ctrl-C or a termination signal.
    pub stop: &'a AtomicBool,
    /// Starts the progress bar again (a render in passes, at each pass).
    pub restart_progress: &'a (dyn Fn() + Sync),
    /// Shows a whole image as a layer of the viewer's image (after the rows sent before it),
    /// from any thread: a pass denoised beside the render. Nothing without a viewer.
    pub show_layer: &'a (dyn Fn(&'static str, Canvas) + Sync),
}

/// What goes to the viewer's thread: a finished row, or a whole layer.
enum Shown {
    Row(FinishedRow),
    Layer(&'static str, Canvas),
}

/// The rows of the checkpoint to resume from (with `--resume`) and the log that saves new
/// rows: the same checkpoint continued, or a new one. `width` is the width of a saved row
/// (the image's, times the layers a row holds); `described` names every setting besides the
/// scene file and the size that changes a pixel.
pub fn open(
    settings: &RenderSettings,
    output: &Path,
    width: usize,
    height: usize,
    described: &str,
) -> Result<(Option<PartialImage>, Log), Failure> {
    let scene_bytes = rayforge_scene::read_scene_file(&settings.scene)
        .map_err(|e| Failure::usage(format!("cannot read `{}`: {e}", settings.scene.display())))?;
    let key = RenderKey::new(&scene_bytes, width, height, described);
    let path = checkpoint::path_for(output);
    if settings.resume {
        let (image, valid_end) = checkpoint::read(&path, &key)?;
        if !settings.quiet {
            eprintln!(
                "resuming: {} of {} rows from `{}`",
                image.finished_rows(),
                height,
                path.display()
            );
        }
        let saved = image.finished_rows();
        let log = Log::append_at(&path, valid_end, saved, settings.quiet)?;
        return Ok((Some(image), log));
    }
    if path.exists() && !settings.quiet {
        eprintln!(
            "note: starting afresh, replacing the checkpoint `{}` of an earlier render \
             (--resume continues it instead)",
            path.display()
        );
    }
    Ok((None, Log::create(&path, &key, settings.quiet)?))
}

/// Runs `render` with [`Hooks`] that save each finished row to `log` (when there is one) on a
/// thread of its own and show it in `display` (when there is one) on another, with a progress
/// bar over `height` rows (`already` of them done before), Ctrl-C setting the stop flag, and
/// `--pause-after-rows` holding the render until an interrupt. `render` returns its result and
/// whether the image is complete (its last rows then need no saving). Returns the result, how
/// the saving went and the display, for the finished image.
pub fn render<R>(
    settings: &RenderSettings,
    height: usize,
    already: usize,
    log: Option<Log>,
    display: Option<Display>,
    render: impl FnOnce(Hooks<'_>) -> (R, bool),
) -> (R, Logged, Option<Display>) {
    let stop = crate::interrupt::stop_flag(settings.quiet);
    let bar = row_bar(height, settings.quiet);
    bar.set_position(already as u64);
    let progress = |rows: usize| bar.inc(rows as u64);
    let restart_progress = || bar.set_position(0);
    let finished_rows: Mutex<Vec<FinishedRow>> = Mutex::new(Vec::new());
    let (render_running, render_over) = mpsc::channel::<()>();
    let (to_display, shown) = mpsc::channel::<Shown>();
    // Set when the render returns whole, before the log learns the render is over.
    let complete = AtomicBool::new(false);
    let (rendered, logged, display) = std::thread::scope(|scope| {
        let (complete, finished_rows) = (&complete, &finished_rows);
        let saving = log.is_some();
        let logger = log.map(|log| {
            scope.spawn(move || log.record(finished_rows, render_over, || complete.load(SeqCst)))
        });
        let viewer = display.map(|mut display| {
            // An interrupted render does not wait for a viewer that is slow to read.
            display.stop_on(stop);
            scope.spawn(move || {
                // Rows come in bursts; each burst goes out as few packets as it can.
                let show = |display: &mut Display, shown| match shown {
                    Shown::Row((y, row)) => display.row(y, &row),
                    Shown::Layer(layer, canvas) => display.layer(layer, &canvas),
                };
                while let Ok(first) = shown.recv() {
                    show(&mut display, first);
                    while let Ok(next) = shown.try_recv() {
                        show(&mut display, next);
                    }
                    display.flush();
                }
                display
            })
        });
        let rendered = {
            // Dropped after the render, which ends the log and the display's thread.
            let running = render_running;
            let to_display = viewer.is_some().then_some(to_display);
            let rows_done = AtomicUsize::new(0);
            // `--pause-after-rows` says when it starts waiting, once, so that a test can time
            // what happens from then on.
            let paused = Once::new();
            let on_row = |y: usize, row: &[Color]| {
                if saving {
                    if let Ok(mut rows) = finished_rows.lock() {
                        rows.push((y, row.to_vec()));
                    }
                }
                if let Some(to_display) = &to_display {
                    // Fails only once the display's thread is gone, which it never is first.
                    let _ = to_display.send(Shown::Row((y, row.to_vec())));
                }
                let done = rows_done.fetch_add(1, SeqCst) + 1;
                if let Some(n) = settings.pause_after_rows.filter(|&n| done >= n) {
                    paused.call_once(|| eprintln!("paused after {n} rows until interrupted"));
                    wait_for_interrupt(stop);
                }
            };
            let show_layer = |layer: &'static str, canvas: Canvas| {
                if let Some(to_display) = &to_display {
                    let _ = to_display.send(Shown::Layer(layer, canvas));
                }
            };
            let (rendered, whole) = render(Hooks {
                on_row: &on_row,
                progress: &progress,
                stop,
                restart_progress: &restart_progress,
                show_layer: &show_layer,
            });
            complete.store(whole, SeqCst);
            drop(running);
            rendered
        };
        let logged = match logger {
            Some(logger) => logger.join().unwrap_or_else(|_| Logged {
                saved: 0,
                failure: Some("the checkpoint writer failed".into()),
            }),
            None => Logged {
                saved: 0,
                failure: None,
            },
        };
        let display = viewer.and_then(|viewer| viewer.join().ok());
        (rendered, logged, display)
    });
    bar.finish_and_clear();
    (rendered, logged, display)
}

/// Holds the calling worker until `stop` is set (`--pause-after-rows`): the render then starts
/// no more rows, so a test knows exactly which rows an interrupt saves.
pub(crate) fn wait_for_interrupt(stop: &AtomicBool) {
    while !stop.load(SeqCst) {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

/// The failure of an interrupted render of `height` rows: where its rows are saved, or that
/// none are, and why writing the checkpoint failed when it did (no message claims rows the
/// file does not hold); then the `work` it had done (`12 samples, 345 rays`), which says how
/// soon it stopped whatever the machine's speed.
pub fn interrupted(height: usize, logged: &Logged, checkpoint: &Path, work: &str) -> Failure {
    let failed = logged
        .failure
        .as_ref()
        .map(|why| format!(" ({why})"))
        .unwrap_or_default();
    if logged.saved == 0 {
        return Failure::Interrupted(format!(
            "no row is saved{failed}, so there is nothing to resume; nothing was written \
             (stopped after {work})"
        ));
    }
    Failure::Interrupted(format!(
        "{} of {} rows are saved in `{}`{failed}; run the same command with --resume to finish \
         (stopped after {work})",
        logged.saved,
        height,
        checkpoint.display()
    ))
}
