//! `rayforge render`: load the scene, render it on a thread pool, write the image, summarise.

use crate::atomic_write::{check_writable, write_atomically};
use crate::diagnostics::{print_warning, scene_failure};
use crate::failure::Failure;
use crate::progress::row_bar;
use crate::settings::RenderSettings;
use crate::summary::{raster_summary_line, summary_line};
use rayforge::render::{render, RenderOptions, Sampling};
use std::time::Instant;

/// Runs the render command.
pub fn run(settings: &RenderSettings) -> Result<(), Failure> {
    // Cheap checks first: a long render must not end in "cannot write".
    check_writable(&settings.output)?;
    let scene = rayforge_scene::load_file(&settings.scene).map_err(scene_failure)?;
    if !settings.quiet {
        scene.warnings.iter().for_each(print_warning);
    }
    let (width, height) = settings
        .size
        .resolve(scene.camera.hsize(), scene.camera.vsize())?;
    let camera = if (width, height) == (scene.camera.hsize(), scene.camera.vsize()) {
        scene.camera
    } else {
        scene.camera.resized(width, height)
    };
    let pool = {
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(n) = settings.threads {
            builder = builder.num_threads(n);
        }
        builder
            .build()
            .map_err(|e| Failure::internal(format!("cannot start worker threads: {e}")))?
    };
    if let Some(options) = &settings.raster {
        let started = Instant::now();
        let (canvas, stats) =
            pool.install(|| rayforge::raster::render_with_stats(&camera, &scene.world, options));
        let elapsed = started.elapsed();
        let bytes = settings.format.encode(&canvas)?;
        write_atomically(&settings.output, &bytes)?;
        if !settings.quiet {
            eprintln!(
                "{}",
                raster_summary_line(
                    canvas.width(),
                    canvas.height(),
                    elapsed,
                    stats.triangles,
                    stats.drawn,
                    &settings.output
                )
            );
        }
        return Ok(());
    }
    let sampling = match settings.adaptive {
        // Three levels of splitting: at most 64 sub-squares, about 4 rays each, per pixel.
        Some(threshold) => Sampling::Adaptive {
            threshold,
            depth: 3,
        },
        None => Sampling::with_samples(settings.spp.unwrap_or(scene.samples)),
    };
    let bar = row_bar(camera.vsize(), settings.quiet);
    let progress = |rows: usize| bar.inc(rows as u64);
    let options = RenderOptions {
        max_depth: settings.max_depth,
        sampling,
        progress: Some(&progress),
    };
    let started = Instant::now();
    let (canvas, stats) = pool.install(|| render(&camera, &scene.world, &options));
    let elapsed = started.elapsed();
    bar.finish_and_clear();
    let bytes = settings.format.encode(&canvas)?;
    write_atomically(&settings.output, &bytes)?;
    if !settings.quiet {
        eprintln!(
            "{}",
            summary_line(
                canvas.width(),
                canvas.height(),
                elapsed,
                stats.rays,
                &settings.output
            )
        );
    }
    Ok(())
}
