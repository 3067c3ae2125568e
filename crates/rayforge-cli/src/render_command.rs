//! `rayforge render`: load the scene, render it into a film on a thread pool (the ray tracer
//! saving finished rows to a checkpoint and stopping cleanly on Ctrl-C), develop the film into
//! the image, draw the scene's canvas items over it, write it, summarise.

use crate::atomic_write::{check_writable, write_atomically};
use crate::checkpoint::{self, Log, Logged, RenderKey};
use crate::diagnostics::{print_warning, scene_failure};
use crate::failure::Failure;
use crate::memory::reserve_for_render;
use crate::output_lock::OutputLock;
use crate::progress::row_bar;
use crate::settings::{Chosen, RenderSettings};
use crate::summary::{non_finite_warning, raster_summary_line, summary_line};
use rayforge::camera::Camera;
use rayforge::canvas::Canvas;
use rayforge::color::Color;
use rayforge::film::{develop, Film};
use rayforge::options::RasterOptions;
use rayforge::render::{render_rows, PartialImage, RenderOptions, RenderStats, Sampling};
use rayforge_scene::{LoadOptions, Scene};
use rayon::ThreadPool;
use std::path::Path;
use std::sync::atomic::Ordering::SeqCst;
use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::sync::{mpsc, Mutex, Once};
use std::time::Instant;

/// Runs the render command: one image, or with `--frames` every frame of an animation not
/// already on disk (so an interrupted sequence resumes where it stopped).
pub fn run(settings: &RenderSettings) -> Result<(), Failure> {
    let Some((first, last)) = settings.frames else {
        return render_frame(settings, &settings.output, 0);
    };
    for frame in first..=last {
        let output = crate::frames::frame_path(&settings.output, frame);
        if output.exists() {
            if !settings.quiet {
                eprintln!("frame {frame}: `{}` is already there", output.display());
            }
            continue;
        }
        render_frame(settings, &output, frame)?;
    }
    Ok(())
}

/// Renders animation frame `frame` of the scene (0 for a still) to `output`, holding the
/// output's lock throughout (released on every return).
fn render_frame(settings: &RenderSettings, output: &Path, frame: u64) -> Result<(), Failure> {
    // Cheap checks first: a long render must not end in "cannot write".
    check_writable(output)?;
    let _lock = OutputLock::acquire(output)?;
    let (scene, camera) = load_scene(settings, frame)?;
    let pool = thread_pool(settings)?;
    let (width, height) = (camera.hsize(), camera.vsize());
    match settings.choose(scene.raster, scene.path)? {
        Chosen::Raster(options) => {
            reserve_for_render(width, height, 1)?;
            return raster_render(settings, &scene, &camera, &pool, &options, output);
        }
        Chosen::Path(options) => {
            // The image's film and, with --aovs, the albedo's and the normal's.
            reserve_for_render(width, height, if settings.path.aovs { 3 } else { 1 })?;
            return crate::path_command::path_render(
                settings, &scene, &camera, &pool, options, output,
            );
        }
        Chosen::Ray => {}
    }
    // The render's film and, when resuming, the checkpoint's rows it starts from.
    reserve_for_render(width, height, if settings.resume { 2 } else { 1 })?;
    let options = ray_options(settings, &scene);
    if let Some((x, y)) = settings.trace_pixel {
        trace_pixel(settings, &scene, &camera, &options, x, y)?;
    }
    ray_render(settings, &scene, &camera, &pool, options, output, frame)
}

/// Reads the scene (printing its warnings) and the camera to render it through, resized to
/// `--width`/`--height` when they ask for another size.
fn load_scene(settings: &RenderSettings, frame: u64) -> Result<(Scene, Camera), Failure> {
    let load = LoadOptions {
        max_triangles: settings.max_triangles,
        allow_outside: settings.allow_outside,
        frame,
        ..LoadOptions::default()
    };
    let scene = rayforge_scene::load_file_with(&settings.scene, &load).map_err(scene_failure)?;
    if !settings.quiet {
        scene.warnings.iter().for_each(print_warning);
    }
    let (width, height) = settings
        .size
        .resolve(scene.camera.hsize(), scene.camera.vsize())?;
    let camera = if (width, height) == (scene.camera.hsize(), scene.camera.vsize()) {
        scene.camera.clone()
    } else {
        scene.camera.resized(width, height)
    };
    Ok((scene, camera))
}

/// The worker threads: `--threads` of them, or one per core.
fn thread_pool(settings: &RenderSettings) -> Result<ThreadPool, Failure> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = settings.threads {
        builder = builder.num_threads(n);
    }
    builder
        .build()
        .map_err(|e| Failure::internal(format!("cannot start worker threads: {e}")))
}

/// The rasterizer's render: the film drawn, developed and written, and a summary line.
fn raster_render(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    pool: &ThreadPool,
    options: &RasterOptions,
    output: &Path,
) -> Result<(), Failure> {
    let started = Instant::now();
    let (film, stats) = pool
        .install(|| rayforge::raster::render_film(camera, &scene.world, options))
        .map_err(|e| Failure::usage(e.to_string()))?;
    let (canvas, non_finite) = develop_with_overlay(scene, camera, &film);
    let elapsed = started.elapsed();
    write_image(settings, &canvas, output)?;
    if !settings.quiet {
        eprintln!(
            "{}",
            raster_summary_line(
                canvas.width(),
                canvas.height(),
                elapsed,
                stats.triangles,
                stats.drawn,
                output
            )
        );
        if let Some(warning) = non_finite_warning(non_finite, output) {
            eprintln!("{warning}");
        }
    }
    Ok(())
}

/// The ray tracer's options that change pixels: depth, bailout, sampling, subsampling (the
/// same for `--trace-pixel` and the render, so the traced pixel is the rendered one).
fn ray_options<'p>(settings: &RenderSettings, scene: &Scene) -> RenderOptions<'p> {
    RenderOptions {
        max_depth: settings
            .max_depth
            .or(scene.max_depth)
            .unwrap_or(rayforge::DEFAULT_MAX_DEPTH),
        bailout: settings.bailout,
        sampling: sampling(settings, scene),
        subsample: settings.subsample,
        max_rays_per_sample: settings.max_rays_per_sample,
        ..RenderOptions::default()
    }
}

/// Where in each pixel the camera rays go: `--adaptive`, `--spp`, or the scene camera's own
/// grid (`anti-alias`) or sample count.
fn sampling(settings: &RenderSettings, scene: &Scene) -> Sampling {
    match settings.adaptive {
        // Three levels of splitting: at most 64 sub-squares, about 4 rays each, per pixel.
        Some(threshold) => Sampling::Adaptive {
            threshold,
            depth: 3,
        },
        None => match (settings.spp, scene.anti_alias) {
            (None, Some(per_side)) => Sampling::Grid { per_side },
            (spp, _) => Sampling::with_samples(spp.unwrap_or(scene.samples)),
        },
    }
}

/// `--trace-pixel`: prints every ray the pixel's samples cast, and its colour.
fn trace_pixel(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions<'_>,
    x: usize,
    y: usize,
) -> Result<(), Failure> {
    let (width, height) = (camera.hsize(), camera.vsize());
    if x >= width || y >= height {
        return Err(Failure::usage(format!(
            "--trace-pixel {x},{y} is outside the {width}×{height} image"
        )));
    }
    let (color, lines) = rayforge::render::trace_pixel(camera, &scene.world, options, x, y);
    println!("pixel ({x}, {y}) of `{}`:", settings.scene.display());
    for line in lines {
        println!("  {line}");
    }
    println!(
        "  pixel colour [{:.4}, {:.4}, {:.4}]",
        color.red, color.green, color.blue
    );
    Ok(())
}

/// The ray tracer's render: resumed from the checkpoint with `--resume`, saving finished rows
/// to it, stopping cleanly on Ctrl-C; once complete, the image written, the checkpoint
/// removed and a summary printed.
fn ray_render(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    pool: &ThreadPool,
    options: RenderOptions<'_>,
    output: &Path,
    frame: u64,
) -> Result<(), Failure> {
    let (width, height) = (camera.hsize(), camera.vsize());
    let (finished, log) =
        open_checkpoint(settings, output, frame, width, height, &options.sampling)?;
    let started = Instant::now();
    let (image, stats, logged) = render_logged(
        settings,
        scene,
        camera,
        pool,
        RenderOptions {
            finished: finished.as_ref(),
            ..options
        },
        log,
    );
    let elapsed = started.elapsed();
    let checkpoint = checkpoint::path_for(output);
    if let Some((x, y)) = stats.over_budget {
        let saved = if logged.saved == 0 {
            "no row is saved".to_string()
        } else {
            format!(
                "{} of {} rows are saved in `{}`: --resume with a higher \
                 --max-rays-per-sample continues from them",
                logged.saved,
                image.height(),
                checkpoint.display()
            )
        };
        return Err(Failure::usage(format!(
            "pixel ({x}, {y}): a camera ray there leads to more than {} rays (reflections, \
             refractions and shadow rays), the limit set by --max-rays-per-sample (lower \
             --max-depth or raise --bailout); {saved}",
            settings.max_rays_per_sample,
        )));
    }
    if !image.is_complete() {
        return Err(interrupted(&image, &logged, &checkpoint));
    }
    let (canvas, non_finite) = develop_with_overlay(scene, camera, image.film());
    write_image(settings, &canvas, output)?;
    // The image is complete: its checkpoint has done its job.
    let _ = std::fs::remove_file(&checkpoint);
    if !settings.quiet {
        eprintln!(
            "{}",
            summary_line(canvas.width(), canvas.height(), elapsed, stats.rays, output)
        );
        if let Some(warning) = non_finite_warning(non_finite, output) {
            eprintln!("{warning}");
        }
        if stats.ambiguous > 0 {
            eprintln!(
                "{} ambiguous pixels (two surfaces at the same distance) were filled from their neighbours",
                stats.ambiguous
            );
        }
    }
    Ok(())
}

/// The failure of an interrupted render: where its rows are saved, or that none are, and why
/// writing the checkpoint failed when it did (no message claims rows the file does not hold).
fn interrupted(image: &PartialImage, logged: &Logged, checkpoint: &Path) -> Failure {
    let failed = logged
        .failure
        .as_ref()
        .map(|why| format!(" ({why})"))
        .unwrap_or_default();
    if logged.saved == 0 {
        return Failure::Interrupted(format!(
            "no row is saved{failed}, so there is nothing to resume; nothing was written"
        ));
    }
    Failure::Interrupted(format!(
        "{} of {} rows are saved in `{}`{failed}; run the same command with --resume to finish",
        logged.saved,
        image.height(),
        checkpoint.display()
    ))
}

/// Renders on `pool` with a progress bar, handing each finished row to `log`, which saves
/// them on a thread of its own; Ctrl-C stops the render between rows (`--pause-after-rows`
/// holds it until then). Returns the image, the statistics and how the saving went.
fn render_logged(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    pool: &ThreadPool,
    options: RenderOptions<'_>,
    log: Log,
) -> (PartialImage, RenderStats, Logged) {
    let stop = crate::interrupt::stop_flag(settings.quiet);
    let bar = row_bar(camera.vsize(), settings.quiet);
    if let Some(f) = options.finished {
        bar.set_position(f.finished_rows() as u64);
    }
    let progress = |rows: usize| bar.inc(rows as u64);
    let finished_rows = Mutex::new(Vec::new());
    let (render_running, render_over) = mpsc::channel::<()>();
    // Set when the render returns whole, before the log learns the render is over.
    let complete = AtomicBool::new(false);
    let ((image, stats), logged) = std::thread::scope(|scope| {
        let (complete, finished_rows) = (&complete, &finished_rows);
        let logger =
            scope.spawn(move || log.record(finished_rows, render_over, || complete.load(SeqCst)));
        let rendered = {
            // Dropped after the render, which ends the log.
            let running = render_running;
            let rows_done = AtomicUsize::new(0);
            // `--pause-after-rows` says when it starts waiting, once, so that a test can time
            // what happens from then on.
            let paused = Once::new();
            let on_row = |y: usize, row: &[Color]| {
                if let Ok(mut rows) = finished_rows.lock() {
                    rows.push((y, row.to_vec()));
                }
                let done = rows_done.fetch_add(1, SeqCst) + 1;
                if let Some(n) = settings.pause_after_rows.filter(|&n| done >= n) {
                    paused.call_once(|| eprintln!("paused after {n} rows until interrupted"));
                    wait_for_interrupt(stop);
                }
            };
            let options = RenderOptions {
                progress: Some(&progress),
                cancel: Some(stop),
                on_row: Some(&on_row),
                ..options
            };
            let rendered = pool.install(|| render_rows(camera, &scene.world, &options));
            complete.store(rendered.0.is_complete(), SeqCst);
            drop(running);
            rendered
        };
        let logged = logger.join().unwrap_or_else(|_| Logged {
            saved: 0,
            failure: Some("the checkpoint writer failed".into()),
        });
        (rendered, logged)
    });
    bar.finish_and_clear();
    (image, stats, logged)
}

/// The film developed (the optics model's exposure when the scene asks for it), its pixels
/// that are not finite blackened (their count returned, see [`crate::finite`]), with the
/// scene's canvas items drawn over it: after the exposure, as their colours are the scene's
/// own.
fn develop_with_overlay(scene: &Scene, camera: &Camera, film: &Film) -> (Canvas, usize) {
    let mut canvas = develop(film, rayforge::render::exposure(&scene.world));
    let non_finite = crate::finite::blacken_non_finite(&mut canvas);
    scene.overlay.draw(&mut canvas, camera);
    (canvas, non_finite)
}

/// Encodes the image in the output's format and writes it atomically.
fn write_image(settings: &RenderSettings, canvas: &Canvas, output: &Path) -> Result<(), Failure> {
    let bytes = settings.format.encode(canvas)?;
    write_atomically(output, &bytes)
}

/// Holds the calling worker until `stop` is set (`--pause-after-rows`): the render then starts
/// no more rows, so a test knows exactly which rows an interrupt saves.
fn wait_for_interrupt(stop: &AtomicBool) {
    while !stop.load(SeqCst) {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

/// The rows of the checkpoint to resume from (with `--resume`) and the log that saves new
/// rows: the same checkpoint continued, or a new one.
fn open_checkpoint(
    settings: &RenderSettings,
    output: &Path,
    frame: u64,
    width: usize,
    height: usize,
    sampling: &Sampling,
) -> Result<(Option<PartialImage>, Log), Failure> {
    // The scene was just read and checked (a regular file within the size limit).
    let scene_bytes = std::fs::read(&settings.scene)
        .map_err(|e| Failure::usage(format!("cannot read `{}`: {e}", settings.scene.display())))?;
    // Everything that changes a pixel; the thread count does not.
    let described = format!(
        "{sampling:?}; max depth {:?}; subsample {:?}; bailout {}; frame {frame}; rayforge {}",
        settings.max_depth,
        settings.subsample,
        settings.bailout,
        env!("CARGO_PKG_VERSION")
    );
    let key = RenderKey::new(&scene_bytes, width, height, &described);
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
