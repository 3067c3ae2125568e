//! `rayforge render`: load the scene, render it on a thread pool, write the image, summarise.

use crate::diagnostics::{scene_report, scene_warning};
use crate::failure::Failure;
use crate::output::write_atomically;
use crate::progress::row_bar;
use crate::settings::RenderSettings;
use rayforge::render::{render, RenderOptions, Sampling};
use rayforge::Camera;
use std::time::Instant;

/// Runs the render command.
pub fn run(settings: &RenderSettings) -> Result<(), Failure> {
    let scene =
        rayforge_scene::load_file(&settings.scene).map_err(|e| Failure::Input(scene_report(e)))?;
    if !settings.quiet {
        for warning in &scene.warnings {
            eprintln!("{:?}", scene_warning(warning.clone()));
        }
    }
    let camera = sized_camera(&scene.camera, settings)?;
    let pool = {
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(n) = settings.threads {
            builder = builder.num_threads(n);
        }
        builder
            .build()
            .map_err(|e| Failure::Internal(miette::miette!("cannot start worker threads: {e}")))?
    };
    let bar = row_bar(camera.vsize(), settings.quiet);
    let started = Instant::now();
    let progress = |rows: usize| bar.inc(rows as u64);
    let sampling = match settings.adaptive {
        // Three levels of splitting: at most 64 sub-squares, about 4 rays each, per pixel.
        Some(threshold) => Sampling::Adaptive {
            threshold,
            depth: 3,
        },
        None => Sampling::with_samples(settings.spp.unwrap_or(scene.samples)),
    };
    let options = RenderOptions {
        max_depth: settings.max_depth,
        sampling,
        progress: Some(&progress),
    };
    let (canvas, stats) = pool.install(|| render(&camera, &scene.world, &options));
    bar.finish_and_clear();
    let elapsed = started.elapsed().as_secs_f64();
    let bytes = settings.format.encode(&canvas)?;
    write_atomically(&settings.output, &bytes)?;
    if !settings.quiet {
        let rate = stats.rays as f64 / elapsed.max(1e-9);
        eprintln!(
            "rendered {}×{} in {elapsed:.2} s, {} rays/s ({} rays) → {}",
            canvas.width(),
            canvas.height(),
            si(rate),
            si(stats.rays as f64),
            settings.output.display()
        );
    }
    Ok(())
}

/// The scene's camera at the size the flags ask for, within the pixel limit.
fn sized_camera(camera: &Camera, settings: &RenderSettings) -> Result<Camera, Failure> {
    let (w0, h0) = (camera.hsize() as f64, camera.vsize() as f64);
    let (w, h) = match (settings.width, settings.height) {
        (None, None) => (camera.hsize(), camera.vsize()),
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, ((w as f64 * h0 / w0).round() as usize).max(1)),
        (None, Some(h)) => (((h as f64 * w0 / h0).round() as usize).max(1), h),
    };
    let pixels = w as u64 * h as u64;
    if pixels > settings.max_pixels {
        return Err(Failure::usage(format!(
            "{w}×{h} is {pixels} pixels, more than the limit {} (raise it with --max-pixels)",
            settings.max_pixels
        )));
    }
    Ok(if (w, h) == (camera.hsize(), camera.vsize()) {
        camera.clone()
    } else {
        camera.resized(w, h)
    })
}

/// A count with an SI prefix: 4.1 M, 950 k.
fn si(v: f64) -> String {
    match v {
        v if v >= 1e9 => format!("{:.2} G", v / 1e9),
        v if v >= 1e6 => format!("{:.2} M", v / 1e6),
        v if v >= 1e3 => format!("{:.1} k", v / 1e3),
        v => format!("{v:.0}"),
    }
}
