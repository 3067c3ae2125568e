//! `rayforge render --renderer path`: the path tracer's render, in one pass or in passes (for
//! a time budget or a viewer), checkpointed and resumed, to its films; they are written by
//! [`crate::path_output`] (the image, with `--aovs` the AOVs, with `--denoise` denoised).

use crate::checkpoint;
use crate::checkpointed;
use crate::failure::Failure;
use crate::live_denoise::{resolved, Frame, LiveDenoiser, Oidn, Summary};
use crate::path_output::{PathOutputs, AOV_NAMES};
use crate::render_command::display_with;
use crate::settings::RenderSettings;
use crate::settings::MAX_PATH_SPP;
use crate::summary::{non_finite_warning, path_summary_line};
use crate::tev::Layout;
use rayforge::camera::Camera;
use rayforge::canvas::Canvas;
use rayforge::film::{Film, SharedFilm};
use rayforge::options::PathOptions;
use rayforge::render::path::{
    learn_roulette, plans_samples, prepare_render, render_path, Aovs, PathJob, PathStats,
};
use rayforge::render::PartialImage;
use rayforge_denoise::SessionStats;
use rayforge_scene::Scene;
use rayon::ThreadPool;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

/// Samples per pixel when neither `--spp` nor the scene gives a count (a YAML camera without
/// `samples`): a path-traced image of one sample is mostly noise.
pub const DEFAULT_PATH_SPP: u32 = 64;

/// The samples per pixel: `--spp`, else the count the scene's file gives (the camera's
/// `samples`, a pbrt `Sampler`'s `pixelsamples`, 1 included: the file is followed), else the
/// scene's own default when above 1 (a pbrt file without `pixelsamples` takes pbrt-v4's
/// default for its sampler; a zoom camera its anti-aliasing grid), else [`DEFAULT_PATH_SPP`].
pub(crate) fn samples_per_pixel(settings: &RenderSettings, scene: &Scene) -> u64 {
    let from_scene = scene.samples_at.is_some() || scene.samples > 1;
    let spp = settings.spp.unwrap_or(if from_scene {
        scene.samples
    } else {
        DEFAULT_PATH_SPP
    });
    u64::from(spp.max(1))
}

/// The passes of samples the render takes: with `--time` or `--display-server` doubling passes
/// (1, 1, 2, 4, …; with `--time` and no sample count, up to the most samples a path render
/// takes), else one pass of `spp`.
fn passes(settings: &RenderSettings, spp: u64) -> Vec<Range<u64>> {
    let time = settings.path.time.is_some();
    if !time && settings.display_server.is_none() {
        return std::iter::once(0..spp).collect();
    }
    let most = if time && settings.spp.is_none() {
        u64::from(MAX_PATH_SPP)
    } else {
        spp
    };
    doubling_passes(most)
}

/// Passes of 1, 1, 2, 4, … samples up to `most` in all, each doubling the samples so far (so
/// the time to the next image grows with the time spent); `rayforge serve` refines so too.
pub(crate) fn doubling_passes(most: u64) -> Vec<Range<u64>> {
    let mut passes: Vec<Range<u64>> = std::iter::once(0..1.min(most)).collect();
    let mut start = 1;
    while start < most {
        let end = (start * 2).min(most);
        passes.push(start..end);
        start = end;
    }
    passes
}

/// Adds the rows saved in a checkpoint to the films, each pixel as one sample of weight 1 of
/// its resolved colour (which resolves to the same bits), and marks them done. `saved` holds
/// `width` × the layers per row: the image's row, then each AOV's ([`Aovs::films`]).
fn restore_rows(
    saved: &PartialImage,
    width: usize,
    film: &SharedFilm,
    aovs: Option<&Aovs>,
    done: &mut [bool],
) -> Result<(), Failure> {
    let refused = |e| Failure::internal(format!("the checkpoint's rows do not fit the film: {e}"));
    let saved_film = saved.film();
    for (y, done) in done.iter_mut().enumerate() {
        if !saved.is_done(y) {
            continue;
        }
        let row = saved_film.row_sums(y);
        let mut layers = row.chunks_exact(width);
        let mut add = |target: &SharedFilm| -> Result<(), Failure> {
            let colours = layers.next().unwrap_or_default();
            let mut part = Film::with_filter(width, 1, target.filter()).map_err(refused)?;
            for (x, &colour) in colours.iter().enumerate() {
                part.add_pixel_sum(x, 0, colour, 1.0);
            }
            target.add(y, &part).map_err(refused)
        };
        add(film)?;
        for target in aovs.iter().flat_map(|a| a.films()) {
            add(target)?;
        }
        *done = true;
    }
    Ok(())
}

/// How many films' worth of memory a path traced render holds at its peak: the image's and,
/// with --aovs or --denoise, the four AOVs' (`AOV_NAMES`); with an adaptive plan, as many
/// again for the pilot's sums the plan keeps, and one for the pilot's record of each pixel.
pub fn films_held(settings: &RenderSettings, scene: &Scene, options: &PathOptions) -> u64 {
    let films = if settings.path.aovs || settings.path.denoise {
        5
    } else {
        1
    };
    let spp = samples_per_pixel(settings, scene);
    let planned = plans_samples(options, spp) && passes(settings, spp).len() == 1;
    if planned {
        2 * films + 1
    } else {
        films
    }
}

/// Path traces the scene and writes the image (and the AOVs); a summary line after. Finished
/// rows are saved to the output's checkpoint as they come, and `--resume` continues from them.
pub fn path_render(
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    pool: &ThreadPool,
    options: PathOptions,
    output: &Path,
) -> Result<(), Failure> {
    let (width, height) = (camera.hsize(), camera.vsize());
    // Loaded first: without the library, the render is refused before it is spent.
    let denoiser = settings
        .path
        .denoise
        .then(|| crate::denoise::load("--denoise"))
        .transpose()?;
    let spp = samples_per_pixel(settings, scene);
    let film = Film::with_filter(width, height, options.filter)
        .map_err(|e| Failure::usage(format!("{e}")))?;
    let film = SharedFilm::from(film);
    // The denoiser's guides are the albedo and normal AOVs, written only with --aovs.
    let aovs = (settings.path.aovs || denoiser.is_some()).then(|| Aovs::new(width, height));
    // One OIDN device and its filters for every denoise of the render: the passes a viewer
    // watches and the final image.
    let session = denoiser
        .as_ref()
        .map(|d| d.session(pool.current_num_threads()));
    let outputs = PathOutputs {
        output,
        format: settings.format,
        aovs: settings.path.aovs,
        denoiser: session.as_ref(),
        overlay: Some((&scene.overlay, camera)),
    };
    outputs.check_writable()?;
    // A saved row holds the image's row, then each AOV's with --aovs.
    let layers = if aovs.is_some() {
        1 + AOV_NAMES.len()
    } else {
        1
    };
    let passes = passes(settings, spp);
    // Watched or on a time budget, the image is refined in passes; otherwise it is rendered
    // in one, each row saved to the checkpoint once it has all its samples (in passes, rows
    // would have them only in the last pass, so there is no checkpoint then).
    let progressive = passes.len() > 1 || settings.path.time.is_some();
    if progressive && settings.resume {
        return Err(Failure::usage(
            "--resume continues a render made in one pass: not with --time or --display-server",
        ));
    }
    let (finished, log) = if progressive {
        (None, None)
    } else {
        // Everything besides the scene and the size that changes a pixel; the thread count
        // does not.
        let described = format!(
            "path; {options:?}; spp {spp}; layers {layers}; rayforge {}",
            env!("CARGO_PKG_VERSION")
        );
        let (finished, log) =
            checkpointed::open(settings, output, width * layers, height, &described)?;
        (finished, Some(log))
    };
    let mut done = vec![false; height];
    if let Some(saved) = &finished {
        restore_rows(saved, width, &film, aovs.as_ref(), &mut done)?;
    }
    let already = done.iter().filter(|&&d| d).count();
    // With --denoise, the viewer's image is the denoised one (each pass's beside the render,
    // then the final), and the rows fill its `noisy` layer.
    let mut rows = vec![if denoiser.is_some() { "noisy" } else { "" }];
    if aovs.is_some() {
        rows.extend(AOV_NAMES);
    }
    let whole: &[&str] = if denoiser.is_some() {
        &["denoised"]
    } else {
        &[]
    };
    let layout = Layout { whole, rows: &rows };
    let display = display_with(settings, output, (width, height), &layout);
    // The passes a viewer watches are denoised beside the render (see `live_denoise`).
    let live = session
        .as_ref()
        .zip(aovs.as_ref())
        .filter(|_| display.is_some() && passes.len() > 1);
    let started = Instant::now();
    let mut live_summary = None;
    let (rendered, logged, display) =
        checkpointed::render(settings, height, already, log, display, |hooks| {
            std::thread::scope(|scope| {
                let show_layer = hooks.show_layer;
                let live = live.map(|(session, aovs)| {
                    let oidn = Oidn { session };
                    let deliver = move |_: &Frame, image| show_layer("denoised", image);
                    (LiveDenoiser::start(scope, oidn, deliver), aovs)
                });
                let offer = |pass: usize, samples: u64| {
                    if let Some((live, aovs)) = &live {
                        live.offer(|| Frame {
                            image: resolved(&film),
                            albedo: resolved(&aovs.albedo),
                            normal: resolved(&aovs.normal),
                            pass,
                            samples,
                        });
                    }
                };
                let rendered = 'passes: {
                    let mut total = PathStats::default();
                    let mut reached = 0;
                    let (roulette, plan) = if passes.len() > 1 {
                        // In passes, samples are shared evenly, and the roulette is learned
                        // once, not again in each pass. The pilot heeds a stop, and then
                        // nothing is rendered.
                        let stop = Some(hooks.stop);
                        let learned = pool
                            .install(|| learn_roulette(camera, &scene.world, &options, spp, stop));
                        let Some(roulette) = learned else {
                            break 'passes (Ok((total, reached)), false);
                        };
                        (roulette, None)
                    } else {
                        // The pilot heeds a stop; the render after it then stops at once.
                        let aovs = aovs.is_some();
                        pool.install(|| {
                            prepare_render(
                                camera,
                                &scene.world,
                                &options,
                                spp,
                                aovs,
                                Some(hooks.stop),
                            )
                        })
                    };
                    for (i, pass) in passes.iter().enumerate() {
                        if i > 0 {
                            // A pass takes about its share of samples of the time so far.
                            let spent = started.elapsed();
                            let next =
                                spent.mul_f64((pass.end - pass.start) as f64 / reached as f64);
                            if settings
                                .path
                                .time
                                .is_some_and(|budget| spent + next > budget)
                            {
                                break;
                            }
                            done.fill(false);
                            (hooks.restart_progress)();
                        }
                        let job = PathJob {
                            options,
                            samples: pass.clone(),
                            plan: plan.as_ref(),
                            progress: Some(hooks.progress),
                            cancel: Some(hooks.stop),
                            on_row: Some(hooks.on_row),
                            roulette: Some(&roulette),
                        };
                        let stats = pool.install(|| {
                            render_path(camera, &scene.world, &job, &film, aovs.as_ref(), &mut done)
                        });
                        match stats {
                            Ok(stats) => {
                                total.rays += stats.rays;
                                total.samples += stats.samples;
                                total.discarded += stats.discarded;
                            }
                            Err(e) => break 'passes (Err(e), false),
                        }
                        if !done.iter().all(|&d| d) {
                            break 'passes (Ok((total, reached)), false);
                        }
                        reached = pass.end;
                        if i + 1 < passes.len() {
                            offer(i + 1, reached);
                        }
                    }
                    (Ok((total, reached)), true)
                };
                if let Some((live, _)) = live {
                    live_summary = Some(live.finish());
                }
                rendered
            })
        });
    let (stats, spp) = rendered
        .map_err(|e| Failure::internal(format!("the path tracer refused its film: {e}")))?;
    let elapsed = started.elapsed();
    let checkpoint = checkpoint::path_for(output);
    if done.iter().any(|&d| !d) {
        if progressive {
            return Err(Failure::Interrupted(format!(
                "interrupted after {spp} samples per pixel in passes; a render in passes keeps \
                 no checkpoint, so nothing was written"
            )));
        }
        let work = format!("{} samples, {} rays", stats.samples, stats.rays);
        return Err(checkpointed::interrupted(
            height,
            &logged,
            &checkpoint,
            &work,
        ));
    }
    let image = film.into_film().resolve();
    let aovs = aovs.map(|aovs| {
        [aovs.albedo, aovs.normal, aovs.depth, aovs.samples].map(|f| f.into_film().resolve())
    });
    let shown_layer = whole.first().copied().unwrap_or("");
    let show = |image: &Canvas| {
        if let Some(mut display) = display {
            display.layer(shown_layer, image);
        }
    };
    let non_finite = outputs.write(image, aovs, show)?;
    // The image is complete: its checkpoint has done its job.
    let _ = std::fs::remove_file(&checkpoint);
    if !settings.quiet {
        eprintln!(
            "{}",
            path_summary_line(
                width,
                height,
                spp,
                elapsed,
                stats.samples,
                stats.rays,
                output
            )
        );
        if let (Some(live), Some(session)) = (&live_summary, &session) {
            eprintln!("{}", live_summary_line(live, session.stats()));
        }
        if stats.discarded > 0 {
            eprintln!(
                "{} samples whose radiance was not a finite number were left out",
                stats.discarded
            );
        }
        for (pixels, path) in non_finite {
            if let Some(warning) = non_finite_warning(pixels, &path) {
                eprintln!("{warning}");
            }
        }
    }
    Ok(())
}

/// The line after the summary that says how the passes denoised beside the render went, and
/// what OIDN made for them and the final image (one device, its filters once per size).
fn live_summary_line(live: &Summary, made: SessionStats) -> String {
    let each = live.time.as_secs_f64() * 1000.0 / live.denoised.max(1) as f64;
    let mut line = format!(
        "denoised beside the render: {} pass{} ({each:.0} ms each), {} skipped while the \
         denoiser was busy",
        live.denoised,
        if live.denoised == 1 { "" } else { "es" },
        live.skipped
    );
    if let Some(failure) = &live.failure {
        line.push_str(&format!(" (it stopped: {failure})"));
    }
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    line.push_str(&format!(
        "; with the final image, {} on {} (its filters made {})",
        plural(made.denoised, "image", "images"),
        plural(made.devices, "OIDN device", "OIDN devices"),
        plural(made.setups, "time", "times"),
    ));
    line
}
