//! `rayforge render --renderer path`: the path tracer's render, from the film to the files: the
//! image (linear in PFM and OpenEXR, sRGB-encoded in PNG and PPM, which are for looking at), and
//! with `--aovs` the albedo and normal images beside it for denoisers; with `--denoise` the
//! image denoised by Intel Open Image Denoise, guided by those two (see [`crate::denoise`]),
//! and with both the raw image beside it. Pixels that are not finite are written black in
//! every file and counted in a warning (see [`crate::finite`]).

use crate::atomic_write::write_atomically;
use crate::checkpoint;
use crate::checkpointed;
use crate::failure::Failure;
use crate::finite::blacken_non_finite;
use crate::format::{ImageFormat, Layer};
use crate::render_command::display_for;
use crate::settings::RenderSettings;
use crate::settings::MAX_PATH_SPP;
use crate::summary::{non_finite_warning, path_summary_line};
use rayforge::camera::Camera;
use rayforge::canvas::Canvas;
use rayforge::color::Color;
use rayforge::film::{Film, SharedFilm};
use rayforge::options::PathOptions;
use rayforge::render::path::{
    learn_roulette, plans_samples, prepare_render, render_path, Aovs, PathJob, PathStats,
};
use rayforge::render::PartialImage;
use rayforge_scene::Scene;
use rayon::ThreadPool;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Samples per pixel when neither `--spp` nor the camera's `samples` asks for more than one:
/// a path-traced image of one sample is mostly noise.
pub const DEFAULT_PATH_SPP: u32 = 64;

/// The samples per pixel: `--spp`, else the camera's `samples` when above 1, else
/// [`DEFAULT_PATH_SPP`].
pub(crate) fn samples_per_pixel(settings: &RenderSettings, scene: &Scene) -> u64 {
    let spp = settings.spp.unwrap_or(if scene.samples > 1 {
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
    // Beside the image, except in OpenEXR, which holds them as layers; with --denoise the raw
    // image too.
    let beside = settings.path.aovs && !settings.format.is_exr();
    let aov_paths = beside.then(|| aov_paths(output));
    let noisy_path = (beside && denoiser.is_some()).then(|| noisy_path(output));
    for path in aov_paths.iter().flatten().chain(&noisy_path) {
        crate::atomic_write::check_writable(path)?;
    }
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
    let layer_names: &[&str] = if aovs.is_some() { &AOV_NAMES } else { &[] };
    let display = display_for(settings, output, (width, height), layer_names);
    let started = Instant::now();
    let (rendered, logged, display) =
        checkpointed::render(settings, height, already, log, display, |hooks| {
            let mut total = PathStats::default();
            let mut reached = 0;
            let (roulette, plan) = if passes.len() > 1 {
                // In passes, samples are shared evenly, and the roulette is learned once, not
                // again in each pass.
                // The pilot heeds a stop, and then nothing is rendered.
                let stop = Some(hooks.stop);
                let learned =
                    pool.install(|| learn_roulette(camera, &scene.world, &options, spp, stop));
                let Some(roulette) = learned else {
                    return (Ok((total, reached)), false);
                };
                (roulette, None)
            } else {
                // The pilot heeds a stop; the render after it then stops at once.
                let aovs = aovs.is_some();
                pool.install(|| {
                    prepare_render(camera, &scene.world, &options, spp, aovs, Some(hooks.stop))
                })
            };
            for (i, pass) in passes.iter().enumerate() {
                if i > 0 {
                    // A pass takes about its share of samples of the time so far.
                    let spent = started.elapsed();
                    let next = spent.mul_f64((pass.end - pass.start) as f64 / reached as f64);
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
                    Err(e) => return (Err(e), false),
                }
                if !done.iter().all(|&d| d) {
                    return (Ok((total, reached)), false);
                }
                reached = pass.end;
            }
            (Ok((total, reached)), true)
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
        return Err(checkpointed::interrupted(height, &logged, &checkpoint));
    }
    // Each file's pixels that were not finite, to warn about after the summary.
    let mut non_finite = Vec::new();
    let mut canvas = film.into_film().resolve();
    non_finite.push((blacken_non_finite(&mut canvas), output.to_path_buf()));
    let aovs = aovs.map(|aovs| {
        let mut resolved =
            [aovs.albedo, aovs.normal, aovs.depth, aovs.samples].map(|f| f.into_film().resolve());
        let counts = resolved.each_mut().map(blacken_non_finite);
        (resolved, counts)
    });
    let overlay = Some((&scene.overlay, camera));
    // Denoised in linear radiance, before the image is encoded for its format; the raw image
    // kept, finished as it would be without --denoise, when --aovs writes it.
    let mut noisy = None;
    if let (Some(denoiser), Some(([albedo, normal, ..], _))) = (&denoiser, &aovs) {
        let guides = crate::denoise::Guides {
            albedo,
            normal: Some(normal),
        };
        let threads = pool.current_num_threads();
        let denoised =
            crate::denoise::denoise(denoiser, &canvas, Some(guides), threads, "the render")?;
        let mut raw = std::mem::replace(&mut canvas, denoised);
        if settings.path.aovs {
            finish_path_image(&mut raw, settings.format, overlay);
            noisy = Some(raw);
        }
    }
    if let Some(mut display) = display {
        display.image(&canvas);
    }
    finish_path_image(&mut canvas, settings.format, overlay);
    // The AOVs, resolved; the albedo encoded as the image is, the normal in a display format
    // as normal maps store it; depth and sample count as they are (linear files only).
    let aov_images = aovs.filter(|_| settings.path.aovs).map(|aovs| {
        let ([mut albedo, mut normal, depth, samples], counts) = aovs;
        encode_for(settings.format, &mut albedo);
        if !settings.format.is_linear() {
            // [-1, 1] into [0, 1].
            for c in normal.pixels_mut() {
                *c = (*c + Color::WHITE) * 0.5;
            }
        }
        ([albedo, normal, depth, samples], counts)
    });
    match (&aov_images, &aov_paths) {
        // OpenEXR holds them as layers of the one file, as compositors and denoisers read them:
        // albedo and normal as `NAME.R/G/B`, the depth as OpenEXR's standard `Z` channel and the
        // sample count as one channel `samples`.
        (Some(([albedo, normal, depth, samples], counts)), None) => {
            non_finite.push((counts.iter().sum(), output.to_path_buf()));
            let mut layers = vec![
                Layer::rgb("albedo", albedo),
                Layer::rgb("normal", normal),
                Layer::single("Z", depth),
                Layer::single("samples", samples),
            ];
            layers.extend(noisy.as_ref().map(|noisy| Layer::rgb("noisy", noisy)));
            write_atomically(
                output,
                &settings.format.encode_with_layers(&canvas, &layers)?,
            )?;
        }
        (Some((images, counts)), Some(paths)) => {
            write_atomically(output, &settings.format.encode(&canvas)?)?;
            for (i, (image, path)) in images.iter().zip(paths).enumerate() {
                non_finite.push((counts[i], path.clone()));
                // Depth and sample count are no colours: always linear PFM.
                let format = if i < 2 {
                    settings.format
                } else {
                    ImageFormat::Pfm
                };
                write_atomically(path, &format.encode(image)?)?;
            }
            if let (Some(noisy), Some(path)) = (&noisy, &noisy_path) {
                write_atomically(path, &settings.format.encode(noisy)?)?;
            }
        }
        _ => write_atomically(output, &settings.format.encode(&canvas)?)?,
    }
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

/// The path tracer's image of `film` for `format`: resolved, its pixels that are not finite
/// blackened (their count returned), encoded for the format (see [`encode_for`]), with the
/// canvas items drawn over it; `rayforge merge` develops merged films the same way.
pub(crate) fn develop_path_image(
    film: &Film,
    format: ImageFormat,
    overlay: Option<(&rayforge::draw2d::Overlay, &Camera)>,
) -> (Canvas, usize) {
    let mut canvas = film.resolve();
    let non_finite = blacken_non_finite(&mut canvas);
    finish_path_image(&mut canvas, format, overlay);
    (canvas, non_finite)
}

/// The last steps of a path-traced image, after it is resolved (and shown to a viewer, in
/// linear values): encoded for `format`, the canvas items drawn over it.
fn finish_path_image(
    canvas: &mut Canvas,
    format: ImageFormat,
    overlay: Option<(&rayforge::draw2d::Overlay, &Camera)>,
) {
    encode_for(format, canvas);
    if let Some((overlay, camera)) = overlay {
        overlay.draw(canvas, camera);
    }
}

/// The AOVs `--aovs` writes, in the order of [`Aovs::films`].
pub const AOV_NAMES: [&str; 4] = ["albedo", "normal", "depth", "samples"];

/// Where `--aovs` writes the AOVs when the image is not OpenEXR: beside the image,
/// `out.albedo.png` and `out.normal.png` for `out.png` (in the image's format), and
/// `out.depth.pfm` and `out.samples.pfm` (always linear PFM).
pub fn aov_paths(output: &Path) -> [PathBuf; 4] {
    let ext = output
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    [
        beside(output, "albedo", &ext),
        beside(output, "normal", &ext),
        beside(output, "depth", "pfm"),
        beside(output, "samples", "pfm"),
    ]
}

/// `out.NAME.EXT` beside `out.png`.
fn beside(output: &Path, name: &str, ext: &str) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    output.with_file_name(format!("{stem}.{name}.{ext}"))
}

/// Where `--denoise --aovs` writes the raw image when the image is not OpenEXR: beside it,
/// `out.noisy.png` for `out.png`, in the image's format.
pub fn noisy_path(output: &Path) -> PathBuf {
    let ext = output
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    beside(output, "noisy", &ext)
}

/// Radiance as the format wants it: linear for PFM and OpenEXR; for the 8-bit formats,
/// encoded with the sRGB transfer curve (a display shows code values, not radiance).
pub(crate) fn encode_for(format: ImageFormat, canvas: &mut Canvas) {
    if format.is_linear() {
        return;
    }
    for c in canvas.pixels_mut() {
        *c = Color::new(srgb(c.red), srgb(c.green), srgb(c.blue));
    }
}

/// The sRGB transfer curve (IEC 61966-2-1) of a linear value, clamped to [0, 1] first.
fn srgb(linear: f64) -> f64 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_aovs_go_beside_the_image() {
        let [a, n, d, s] = aov_paths(Path::new("out/cornell.png"));
        assert_eq!(d, Path::new("out/cornell.depth.pfm"));
        assert_eq!(s, Path::new("out/cornell.samples.pfm"));
        assert_eq!(a, Path::new("out/cornell.albedo.png"));
        assert_eq!(n, Path::new("out/cornell.normal.png"));
        assert_eq!(
            noisy_path(Path::new("out/cornell.png")),
            Path::new("out/cornell.noisy.png")
        );
    }

    #[test]
    fn the_srgb_curve_meets_its_fixed_points() {
        assert_eq!(srgb(0.0), 0.0);
        assert!((srgb(1.0) - 1.0).abs() < 1e-12);
        assert!((srgb(0.18) - 0.4614).abs() < 1e-3);
        assert_eq!(srgb(5.0), srgb(1.0));
        assert_eq!(srgb(f64::NAN), 0.0);
    }
}
