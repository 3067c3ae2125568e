//! `rayforge render`: load the scene, render it into a film on a thread pool (the ray tracer
//! saving finished rows to a checkpoint and stopping cleanly on Ctrl-C), develop the film into
//! the image, draw the scene's canvas items over it, write it, summarise.

use crate::atomic_write::{check_writable, not_an_input, write_atomically};
use crate::checkpoint::{self, Log, Logged};
use crate::checkpointed;
use crate::diagnostics::{print_warning, scene_failure};
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::memory::reserve_for_render;
use crate::output_lock::OutputLock;
use crate::settings::{Chosen, RenderSettings};
use crate::summary::{non_finite_warning, raster_summary_line, summary_line};
use crate::tev::{Display, Layout};
use rayforge::camera::Camera;
use rayforge::canvas::Canvas;
use rayforge::draw2d::Overlay;
use rayforge::film::{develop, Exposure, Film};
use rayforge::options::RasterOptions;
use rayforge::raster::RasterError;
use rayforge::render::{render_rows, PartialImage, RenderOptions, RenderStats, Sampling};
use rayforge_scene::gltf::CameraChoice;
use rayforge_scene::{LoadOptions, Scene};
use rayon::ThreadPool;
use std::path::Path;
use std::time::Instant;

/// Runs the render command: one image, or with `--frames` every frame of an animation not
/// already on disk (so an interrupted sequence resumes where it stopped).
pub fn run(settings: &RenderSettings) -> Result<(), Failure> {
    let Some((first, last)) = settings.frames else {
        if let Some(slice) = &settings.slice {
            return crate::slice_render::run(settings, slice);
        }
        return render_frame(settings, &settings.output, 0);
    };
    // With --slice I/N, the task's share of the animation: every N-th frame from the I-th.
    let (index, count) = settings.slice.map_or((0, 1), |s| (s.index, s.count));
    let frames = (first..=last).filter(|frame| (frame - first) % count == index);
    for frame in frames {
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
    output_not_an_input(settings, &scene, output)?;
    let pool = thread_pool(settings)?;
    let (width, height) = (camera.hsize(), camera.vsize());
    let chosen = settings.choose(&scene)?;
    let scene = match chosen {
        Chosen::Path(_) => scene,
        _ => without_media(settings, scene),
    };
    match chosen {
        Chosen::Raster(options) => {
            reserve_for_render(width, height, 1)?;
            return raster_render(settings, &scene, &camera, &pool, &options, output);
        }
        Chosen::Path(options) => {
            let films = crate::path_command::films_held(settings, &scene, &options);
            reserve_for_render(width, height, films)?;
            return crate::path_command::path_render(
                settings, &scene, &camera, &pool, options, output,
            );
        }
        Chosen::Ray => {}
    }
    // The render's film and, when resuming, the checkpoint's rows it starts from, or on a time
    // budget the last pass's image kept while the next renders.
    let images = if settings.resume || settings.path.time.is_some() {
        2
    } else {
        1
    };
    reserve_for_render(width, height, images)?;
    let options = ray_options(settings, &scene);
    if let Some((x, y)) = settings.trace_pixel {
        trace_pixel(settings, &scene, &camera, &options, x, y)?;
    }
    ray_render(settings, &scene, &camera, &pool, options, output, frame)
}

/// The scene as the Whitted ray tracer and the rasterizer draw it: they render no
/// participating media, which the user is told once (never silently); the surfaces that only
/// separate media (index-matched, invisible) are left out, every other surface drawn as if in
/// vacuum.
fn without_media(settings: &RenderSettings, mut scene: Scene) -> Scene {
    if !has_media(&scene) {
        return scene;
    }
    if !settings.quiet {
        settings.said.warn(MEDIA_IGNORED);
    }
    strip_media(&mut scene);
    scene
}

/// What the Whitted ray tracer and the rasterizer say of a scene with media (`rayforge
/// render` on the terminal, `rayforge serve` on the page).
pub(crate) const MEDIA_IGNORED: &str = "the scene's participating media are rendered by the \
     path tracer only (`renderer: path` or `--renderer path`); this renderer ignores them and \
     leaves out the surfaces that only bound them";

/// Whether a surface only separates media.
fn is_boundary(o: &rayforge::Object) -> bool {
    o.media.is_some_and(|m| m.index_matched)
}

/// Whether `scene` has media, or surfaces that only bound them.
pub(crate) fn has_media(scene: &Scene) -> bool {
    scene.world.has_media() || scene.world.objects.iter().any(is_boundary)
}

/// `scene` in vacuum: its media and the surfaces that only bound them taken out.
pub(crate) fn strip_media(scene: &mut Scene) {
    scene.world.objects.retain(|o| !is_boundary(o));
    scene.world.media = rayforge::media::Media::NONE;
    scene.world.camera_medium = None;
}

/// Reads the scene (printing its warnings) and the camera to render it through, resized to
/// `--width`/`--height` when they ask for another size.
pub(crate) fn load_scene(
    settings: &RenderSettings,
    frame: u64,
) -> Result<(Scene, Camera), Failure> {
    // Ctrl-C and SIGTERM stop the reading of a scene of millions of parts within one part.
    let options = LoadOptions {
        stop: crate::interrupt::load_stop(settings.quiet),
        ..load_options(settings, frame)
    };
    let scene = rayforge_scene::load_file_with(&settings.scene, &options).map_err(scene_failure)?;
    if !settings.quiet {
        // Once each: the frames of `--frames` read the same file.
        for warning in &scene.warnings {
            if settings.said.first(&warning.to_string()) {
                print_warning(warning);
            }
        }
    }
    let camera = sized_camera(settings, &scene)?;
    Ok((scene, camera))
}

/// Refuses to write `output` over the scene file or a file the scene read (a model, an image,
/// an environment map): see [`not_an_input`].
pub(crate) fn output_not_an_input(
    settings: &RenderSettings,
    scene: &Scene,
    output: &Path,
) -> Result<(), Failure> {
    let scene_file = std::iter::once((settings.scene.as_path(), "the scene file"));
    let read = scene
        .files
        .iter()
        .map(|file| (file.as_path(), "a file the scene reads"));
    not_an_input(output, scene_file.chain(read))
}

/// The limits of reading the scene, and the frame to build (shared with `rayforge serve`,
/// which reads the scene again after every edit).
pub(crate) fn load_options(settings: &RenderSettings, frame: u64) -> LoadOptions {
    LoadOptions {
        max_triangles: settings.max_triangles,
        allow_outside: settings.allow_outside,
        pbrt: settings.pbrt_limits,
        max_grid_samples: settings.max_grid_samples,
        max_optical_depth: settings.max_optical_depth,
        frame,
        camera: settings
            .camera
            .as_deref()
            .map_or(CameraChoice::First, CameraChoice::parse),
        ..LoadOptions::default()
    }
}

/// The scene's camera, resized to `--width`/`--height` when they ask for another size.
pub(crate) fn sized_camera(settings: &RenderSettings, scene: &Scene) -> Result<Camera, Failure> {
    let (width, height) = settings
        .size
        .resolve(scene.camera.hsize(), scene.camera.vsize())?;
    Ok(camera_at(scene, width, height))
}

/// The scene's camera at `width` × `height` (its own, when that is its size).
pub(crate) fn camera_at(scene: &Scene, width: usize, height: usize) -> Camera {
    if (width, height) == (scene.camera.hsize(), scene.camera.vsize()) {
        scene.camera.clone()
    } else {
        scene.camera.resized(width, height)
    }
}

/// The worker threads: `--threads` of them, or one per core.
pub(crate) fn thread_pool(settings: &RenderSettings) -> Result<ThreadPool, Failure> {
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
    let stop = crate::interrupt::stop_flag(settings.quiet);
    // `--pause-after-rows` (a testing aid) waits, inside the frame, once that many rows of
    // tiles are drawn, for the interrupt a test sends then.
    let rows_done = std::sync::atomic::AtomicUsize::new(0);
    let paused = std::sync::Once::new();
    let on_band = |rows: usize| {
        let done = rows_done.fetch_add(rows, std::sync::atomic::Ordering::SeqCst) + rows;
        if let Some(n) = settings.pause_after_rows.filter(|&n| done >= n) {
            paused.call_once(|| eprintln!("paused after {n} rows until interrupted"));
            crate::checkpointed::wait_for_interrupt(stop);
        }
    };
    let (film, stats) = pool
        .install(|| {
            rayforge::raster::render_film_observed(
                camera,
                &scene.world,
                options,
                Some(stop),
                &on_band,
            )
        })
        .map_err(raster_failure)?;
    let (canvas, non_finite) = develop_with_overlay(scene, camera, &film);
    let elapsed = started.elapsed();
    if let Some(mut display) = display_for(settings, output, (canvas.width(), canvas.height()), &[])
    {
        display.image(&canvas);
    }
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

/// A raster frame that did not finish as a failure: stopped by Ctrl-C or a termination signal
/// (exit 130, nothing written), or refused (exit 2).
pub(crate) fn raster_failure(error: RasterError) -> Failure {
    match error {
        RasterError::Cancelled { .. } => {
            Failure::Interrupted(format!("{error}; nothing was written"))
        }
        _ => Failure::usage(error.to_string()),
    }
}

/// The ray tracer's options that change pixels: depth, bailout, sampling, subsampling (the
/// same for `--trace-pixel` and the render, so the traced pixel is the rendered one).
pub(crate) fn ray_options<'p>(settings: &RenderSettings, scene: &Scene) -> RenderOptions<'p> {
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

/// Where in each pixel the camera rays go: `--adaptive-aa`, `--spp` (that many rays), or the
/// scene camera's own grid (`anti-alias`) or sample count (`samples`, as `--spp`).
fn sampling(settings: &RenderSettings, scene: &Scene) -> Sampling {
    match settings.adaptive_aa {
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
    if let Some(budget) = settings.path.time {
        return ray_passes(settings, scene, camera, pool, options, output, budget);
    }
    let (width, height) = (camera.hsize(), camera.vsize());
    // Everything besides the scene and the size that changes a pixel; the thread count does
    // not.
    let described = format!(
        "{:?}; max depth {:?}; subsample {:?}; bailout {}; frame {frame}; rayforge {}",
        options.sampling,
        settings.max_depth,
        settings.subsample,
        settings.bailout,
        env!("CARGO_PKG_VERSION")
    );
    let (finished, log) = checkpointed::open(settings, output, width, height, &described)?;
    let display = display_for(settings, output, (width, height), &[]);
    let started = Instant::now();
    let (image, stats, logged, display) = render_logged(
        settings,
        camera,
        scene,
        pool,
        RenderOptions {
            finished: finished.as_ref(),
            ..options
        },
        log,
        display,
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
        return Err(too_many_rays(settings, (x, y), &saved));
    }
    if !image.is_complete() {
        return Err(checkpointed::interrupted(
            image.height(),
            &logged,
            &checkpoint,
            &format!("{} rays", stats.rays),
        ));
    }
    let (canvas, non_finite) =
        show_and_write(settings, scene, camera, image.film(), display, output)?;
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

/// The ray tracer's finished film developed (with the scene's canvas items), shown last in the
/// tev viewer when there is one, and written to `output`: the image, and how many of its
/// pixels were not finite.
fn show_and_write(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    film: &Film,
    display: Option<Display>,
    output: &Path,
) -> Result<(Canvas, usize), Failure> {
    let (canvas, non_finite) = develop_with_overlay(scene, camera, film);
    if let Some(mut display) = display {
        display.image(&canvas);
    }
    write_image(settings, &canvas, output)?;
    Ok((canvas, non_finite))
}

/// The failure of a render stopped at pixel (`x`, `y`) by `--max-rays-per-sample`, and what
/// became of its rows (`saved`).
fn too_many_rays(settings: &RenderSettings, (x, y): (usize, usize), saved: &str) -> Failure {
    Failure::usage(format!(
        "pixel ({x}, {y}): a camera ray there leads to more than {} rays (reflections, \
         refractions and shadow rays), the limit set by --max-rays-per-sample (lower \
         --max-depth or raise --bailout); {saved}",
        settings.max_rays_per_sample,
    ))
}

/// The most camera rays per pixel a ray-traced `--time` render refines to when nothing sets
/// its sampling: `--spp`'s limit, a 64 × 64 grid.
const MOST_TIMED_PER_SIDE: u32 = 64;

/// The ray tracer's render on a time budget (`--time`): passes of 1, 4, 16, … camera rays per
/// pixel ([`Sampling::refining_passes`]), each a whole render of its own, up to the sampling
/// asked for (`--spp`, `--adaptive-aa` or the camera's own), or with none up to
/// [`MOST_TIMED_PER_SIDE`] a side. A pass that would end past the budget (its time foreseen
/// from the last pass's per camera ray) is not started, and the last whole pass is written: the
/// very image a render at its sampling makes in one pass, however it was watched. Each pass's
/// rows go to the tev viewer as they finish. No checkpoint: an interrupted render in passes
/// writes nothing, as the path tracer's.
fn ray_passes(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    pool: &ThreadPool,
    options: RenderOptions<'_>,
    output: &Path,
    budget: std::time::Duration,
) -> Result<(), Failure> {
    if settings.resume {
        return Err(Failure::usage(
            "--resume continues a render made in one pass: not with --time",
        ));
    }
    let most = if options.sampling == Sampling::Centre && settings.spp.is_none() {
        Sampling::Stratified {
            per_side: MOST_TIMED_PER_SIDE,
        }
    } else {
        options.sampling
    };
    let display = display_for(settings, output, (camera.hsize(), camera.vsize()), &[]);
    let started = Instant::now();
    let (rendered, _, display) =
        checkpointed::render(settings, camera.vsize(), 0, None, display, |hooks| {
            let mut last: Option<(Sampling, PartialImage)> = None;
            let mut rays = 0;
            let mut last_pass = (std::time::Duration::ZERO, 1);
            for (i, sampling) in most.refining_passes().into_iter().enumerate() {
                if i > 0 {
                    let (took, rays_per_pixel) = last_pass;
                    let ahead = took.mul_f64(sampling.camera_rays() as f64 / rays_per_pixel as f64);
                    if started.elapsed() + ahead > budget {
                        break;
                    }
                    (hooks.restart_progress)();
                }
                let pass_started = Instant::now();
                let pass = RenderOptions {
                    sampling,
                    progress: Some(hooks.progress),
                    cancel: Some(hooks.stop),
                    on_row: Some(hooks.on_row),
                    ..options
                };
                let (image, stats) = pool.install(|| render_rows(camera, &scene.world, &pass));
                rays += stats.rays;
                if let Some(pixel) = stats.over_budget {
                    return (Err(pixel), false);
                }
                if !image.is_complete() {
                    return (Ok((None, last, rays)), false);
                }
                last_pass = (pass_started.elapsed(), sampling.camera_rays());
                last = Some((sampling, image));
            }
            (Ok((last, None, rays)), true)
        });
    let elapsed = started.elapsed();
    // The last whole pass, or when interrupted the one before the interrupted pass.
    let (whole, before, rays) =
        rendered.map_err(|pixel| too_many_rays(settings, pixel, "nothing was written"))?;
    let Some((sampling, image)) = whole else {
        let reached = before.map_or(0, |(sampling, _)| sampling.camera_rays());
        return Err(Failure::Interrupted(format!(
            "interrupted after passes up to {reached} camera rays per pixel; a render in \
             passes keeps no checkpoint, so nothing was written"
        )));
    };
    let (canvas, non_finite) =
        show_and_write(settings, scene, camera, image.film(), display, output)?;
    if !settings.quiet {
        eprintln!(
            "{}",
            summary_line(canvas.width(), canvas.height(), elapsed, rays, output)
        );
        eprintln!(
            "refined within {:.2} s to {} camera rays per pixel ({sampling:?})",
            budget.as_secs_f64(),
            sampling.camera_rays()
        );
        if let Some(warning) = non_finite_warning(non_finite, output) {
            eprintln!("{warning}");
        }
    }
    Ok(())
}

/// Renders on `pool` with the rows saved to `log` as they finish and shown in `display`
/// (see [`checkpointed`]).
fn render_logged(
    settings: &RenderSettings,
    camera: &Camera,
    scene: &Scene,
    pool: &ThreadPool,
    options: RenderOptions<'_>,
    log: Log,
    display: Option<Display>,
) -> (PartialImage, RenderStats, Logged, Option<Display>) {
    let already = options.finished.map_or(0, PartialImage::finished_rows);
    let ((image, stats), logged, display) = checkpointed::render(
        settings,
        camera.vsize(),
        already,
        Some(log),
        display,
        |hooks| {
            let options = RenderOptions {
                progress: Some(hooks.progress),
                cancel: Some(hooks.stop),
                on_row: Some(hooks.on_row),
                ..options
            };
            let rendered = pool.install(|| render_rows(camera, &scene.world, &options));
            let complete = rendered.0.is_complete();
            (rendered, complete)
        },
    );
    (image, stats, logged, display)
}

/// The tev display of the render to `output`, when `--display-server` asks for one: the
/// image named after the output, with `layers` beside its colour.
pub fn display_for(
    settings: &RenderSettings,
    output: &Path,
    size: (usize, usize),
    layers: &[&str],
) -> Option<Display> {
    let mut rows = vec![""];
    rows.extend_from_slice(layers);
    let layout = Layout {
        whole: &[],
        rows: &rows,
    };
    display_with(settings, output, size, &layout)
}

/// [`display_for`] with the layers `layout` names (the path tracer's denoised layer).
pub fn display_with(
    settings: &RenderSettings,
    output: &Path,
    size: (usize, usize),
    layout: &Layout<'_>,
) -> Option<Display> {
    let address = settings.display_server.as_deref()?;
    let name = output.display().to_string();
    Some(Display::connect_with(
        address,
        &name,
        size,
        layout,
        settings.quiet,
        settings.display_timeout,
    ))
}

/// The film developed (the optics model's exposure when the scene asks for it), its pixels
/// that are not finite blackened (their count returned, see [`crate::finite`]), with the
/// scene's canvas items drawn over it: after the exposure, as their colours are the scene's
/// own.
pub(crate) fn develop_with_overlay(scene: &Scene, camera: &Camera, film: &Film) -> (Canvas, usize) {
    let exposure = rayforge::render::exposure(&scene.world);
    develop_book_image(film, exposure, Some((&scene.overlay, camera)))
}

/// [`develop_with_overlay`] from what it needs of the scene: how to expose, and the canvas
/// items with the camera they are drawn for (`rayforge merge` has no scene loaded unless it
/// has canvas items).
pub(crate) fn develop_book_image(
    film: &Film,
    exposure: Exposure,
    overlay: Option<(&Overlay, &Camera)>,
) -> (Canvas, usize) {
    finish_image(develop(film, exposure), overlay)
}

/// A developed image made ready to show or write: its non-finite pixels blackened (how many
/// is returned) and the canvas items drawn over it.
pub(crate) fn finish_image(
    mut canvas: Canvas,
    overlay: Option<(&Overlay, &Camera)>,
) -> (Canvas, usize) {
    let non_finite = crate::finite::blacken_non_finite(&mut canvas);
    if let Some((overlay, camera)) = overlay {
        overlay.draw(&mut canvas, camera);
    }
    (canvas, non_finite)
}

/// Encodes the image in the output's format and writes it atomically.
fn write_image(settings: &RenderSettings, canvas: &Canvas, output: &Path) -> Result<(), Failure> {
    write_image_as(settings.format, canvas, output)
}

/// Encodes the image in `format` and writes it atomically (`rayforge merge` too).
pub(crate) fn write_image_as(
    format: ImageFormat,
    canvas: &Canvas,
    output: &Path,
) -> Result<(), Failure> {
    let bytes = format.encode(canvas)?;
    write_atomically(output, &bytes)
}
