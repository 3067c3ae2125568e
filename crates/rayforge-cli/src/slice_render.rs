//! `rayforge render --slice I/N`: one slice of a render (see [`crate::slice`]) rendered into
//! a film of its own rows, kept in a part file ([`crate::part_file`]) for `rayforge merge`.
//!
//! Each renderer renders its slice with the very code of a whole render, told which rows to
//! leave alone (the ray tracer and the path tracer take a row mask) or which samples to take
//! (the path tracer's sample range): a row or a sample is the same bits whichever process
//! renders it. The film holds only the slice's rows ([`SharedFilm::with_rows`]; every row for
//! a cut by samples), so a slice's memory is its share of the image's, not the whole image's:
//! a task of a poster cut into many slices fits where the poster's film would not. No rows
//! beyond the slice's are needed for a pixel filter wider than a pixel: the path tracer draws
//! each sample for one pixel and weighs it there rather than splatting it onto its neighbours,
//! and the other renderers give each pixel one estimate. The rasterizer bins the whole frame
//! (its triangles are not cut by rows) and draws the bands of tiles that hold its slice's rows,
//! each into a band of its own, keeping the slice's rows. A part already there and complete for
//! the same render and slice is kept, so a requeued task costs a scene load and a read of its
//! part. Slices are not checkpointed: an interrupted slice writes nothing and is rendered
//! again. With `--aovs` a path-traced slice renders the AOVs of its rows too (into films of
//! those rows, as the image's) and keeps them in its part, for the merge to write them and to
//! guide its denoiser (`merge --aovs`, `merge --denoise`); `--denoise` itself is the merge's,
//! as a denoiser must see the whole image.

use crate::atomic_write::{check_writable, write_atomically_with};
use crate::failure::Failure;
use crate::memory::reserve_for_slice;
use crate::output_lock::OutputLock;
use crate::part_file::{scene_fingerprint, Development, Part, PartHeader, PART_AOVS};
use crate::path_command::samples_per_pixel;
use crate::progress::row_bar;
use crate::render_command::{load_scene, output_not_an_input, ray_options, thread_pool};
use crate::settings::{Chosen, RenderSettings};
use crate::slice::{Cut, Slice};
use rayforge::camera::Camera;
use rayforge::film::{Film, PixelFilter, SharedFilm, MAX_FILM_PIXELS};
use rayforge::options::{PathOptions, SampleAllocation};
use rayforge::render::path::{learn_roulette, render_path, Aovs, LearnedRoulette, PathJob};
use rayforge::render::{exposure, render_rows_into, RenderOptions};
use rayforge_scene::Scene;
use rayon::ThreadPool;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Renders `slice` of the scene to the part file `settings.output`, unless a complete part of
/// the same render and slice is already there.
pub fn run(settings: &RenderSettings, slice: &Slice) -> Result<(), Failure> {
    let output = settings.output.as_path();
    check_writable(output)?;
    let _lock = OutputLock::acquire(output)?;
    let (scene, camera, chosen, header) = prepare(settings, slice)?;
    output_not_an_input(settings, &scene, output)?;
    if is_complete(output, &header, settings)? {
        if !settings.quiet {
            eprintln!(
                "slice {slice}: `{}` is already complete; nothing to render",
                output.display()
            );
        }
        return Ok(());
    }
    let (width, height) = (camera.hsize(), camera.vsize());
    let films = if header.aovs { 1 + PART_AOVS as u64 } else { 1 };
    reserve_for_slice(width, height, slice.row_count(height), films)?;
    let pool = thread_pool(settings)?;
    let started = Instant::now();
    let render = SliceRender {
        settings,
        slice,
        scene: &scene,
        camera: &camera,
        pool: &pool,
    };
    let (film, aovs) = match chosen {
        Chosen::Ray => (render.ray()?, None),
        Chosen::Raster(options) => (render.raster(&options)?, None),
        Chosen::Path(options) => render.path(options, header.samples(), header.aovs)?,
    };
    let elapsed = started.elapsed();
    let samples = header.samples();
    let part = Part::new(header, film, aovs)?;
    write_atomically_with(output, |out| part.write_to(out))?;
    if !settings.quiet {
        let covers = match slice.cut {
            Cut::Rows => format!(
                "{} of {height} rows (from row {} in steps of {})",
                slice.row_count(height),
                slice.index,
                slice.count
            ),
            Cut::Samples => format!("samples {samples:?} of every pixel"),
        };
        eprintln!(
            "slice {slice} of {width}×{height}, {covers}: rendered in {:.2} s, written to `{}`",
            elapsed.as_secs_f64(),
            output.display()
        );
    }
    Ok(())
}

/// The header of `slice`'s part, from the scene read and checked as the slice's task reads
/// it, without rendering: `rayforge slurm` refuses before submitting what every task of its
/// job array would refuse (a cut by samples of the ray tracer, more slices than samples, a
/// scene that does not load), and learns the image's size.
pub fn plan(settings: &RenderSettings, slice: &Slice) -> Result<PartHeader, Failure> {
    prepare(settings, slice).map(|(_, _, _, header)| header)
}

/// The scene, its camera, the renderer chosen and the part's header for `slice`.
fn prepare(
    settings: &RenderSettings,
    slice: &Slice,
) -> Result<(Scene, Camera, Chosen, PartHeader), Failure> {
    let (scene, camera) = load_scene(settings, 0)?;
    let chosen = match settings.choose(&scene)? {
        // A slice shares samples evenly: an adaptive plan would cost every slice a pilot of
        // the whole image, an eighth of the render, however small its own share.
        Chosen::Path(options) => Chosen::Path(PathOptions {
            allocation: SampleAllocation::Uniform,
            ..options
        }),
        other => other,
    };
    let header = header(settings, slice, &scene, &camera, &chosen)?;
    Ok((scene, camera, chosen, header))
}

/// The part's header for `slice` of this render: the scene's fingerprint and every setting
/// that changes a pixel. Refuses a cut by samples for the renderers whose samples are not an
/// index sequence, and more sample slices than samples.
fn header(
    settings: &RenderSettings,
    slice: &Slice,
    scene: &Scene,
    camera: &Camera,
    chosen: &Chosen,
) -> Result<PartHeader, Failure> {
    let version = env!("CARGO_PKG_VERSION");
    let lighting = scene.world.lighting;
    // Only the path tracer renders AOVs (`--aovs` is refused for the others).
    let aovs = settings.path.aovs && matches!(chosen, Chosen::Path(_));
    let (described, development, spp) = match chosen {
        Chosen::Ray => {
            let o = ray_options(settings, scene);
            let described = format!(
                "ray; lighting {lighting:?}; {:?}; max depth {}; subsample {:?}; bailout {}; \
                 rayforge {version}",
                o.sampling, o.max_depth, o.subsample, o.bailout
            );
            (described, Development::Book(exposure(&scene.world)), 0)
        }
        Chosen::Raster(o) => (
            format!("raster; lighting {lighting:?}; {o:?}; rayforge {version}"),
            Development::Book(exposure(&scene.world)),
            0,
        ),
        Chosen::Path(o) => {
            let spp = samples_per_pixel(settings, scene);
            let described = format!("path; {o:?}; spp {spp}; rayforge {version}");
            (described, Development::Path, spp)
        }
    };
    let (width, height) = (camera.hsize(), camera.vsize());
    if (width as u64).saturating_mul(height as u64) > MAX_FILM_PIXELS {
        return Err(Failure::usage(format!(
            "a {width}×{height} image has more than {MAX_FILM_PIXELS} pixels, the most `rayforge \
             merge` joins (it holds the whole image's film, 32 bytes a pixel, and develops the \
             image): its slices could be rendered but never merged; render it at most \
             {MAX_FILM_PIXELS} pixels"
        )));
    }
    if slice.cut == Cut::Samples {
        if !matches!(chosen, Chosen::Path(_)) {
            return Err(Failure::usage(
                "--slice-by samples cuts the path tracer's sample sequence; the ray tracer's \
                 samples are a stratified grid of each pixel and the rasterizer takes one, so \
                 neither can be cut into ranges: use --slice-by rows",
            ));
        }
        if slice.count > spp {
            return Err(Failure::usage(format!(
                "--slice-by samples cannot cut {spp} samples per pixel into {} slices: give at \
                 most {spp} slices, more samples (--spp) or --slice-by rows",
                slice.count
            )));
        }
    }
    let bytes = rayforge_scene::read_scene_file(&settings.scene)
        .map_err(|e| Failure::usage(format!("cannot read `{}`: {e}", settings.scene.display())))?;
    let scene_path = std::fs::canonicalize(&settings.scene).unwrap_or(settings.scene.clone());
    let fingerprint = scene_fingerprint(&bytes, &scene.files).map_err(Failure::usage)?;
    Ok(PartHeader {
        fingerprint,
        width,
        height,
        slice: *slice,
        spp,
        development,
        overlay: !scene.overlay.is_empty(),
        aovs,
        scene: scene_path.to_string_lossy().into_owned(),
        settings: described,
    })
}

/// Whether `output` holds a whole, undamaged part with `header`. A part that is not (an
/// interrupted write cannot leave one, but a part of other settings or a damaged one can) is
/// noted and will be replaced; a file that is not a part at all (it does not begin as one, or
/// is not a regular file) is refused unless `--force`, so that a mistyped `-o` does not
/// destroy an image or a scene.
fn is_complete(
    output: &Path,
    header: &PartHeader,
    settings: &RenderSettings,
) -> Result<bool, Failure> {
    if output.symlink_metadata().is_err() {
        return Ok(false);
    }
    let why = match Part::read(output) {
        Ok(part) if part.header == *header => return Ok(true),
        Ok(_) => "it is a part of another render or slice".to_string(),
        Err(Failure::Input(why)) if Part::looks_like_one(output) => why,
        Err(_) if !settings.force => {
            return Err(Failure::usage(format!(
                "`{}` is there and is not a part file; --slice replaces only part files: give \
                 another --output, or --force to replace it",
                output.display()
            )))
        }
        Err(Failure::Input(why)) => why,
        Err(_) => "it cannot be read".to_string(),
    };
    if !settings.quiet {
        eprintln!("note: replacing `{}`: {why}", output.display());
    }
    Ok(false)
}

/// What rendering a slice needs, for the renderers that render only their rows.
struct SliceRender<'a> {
    settings: &'a RenderSettings,
    slice: &'a Slice,
    scene: &'a Scene,
    camera: &'a Camera,
    pool: &'a ThreadPool,
}

impl SliceRender<'_> {
    /// A film with no samples that holds the slice's rows, and only those.
    fn film(&self, filter: PixelFilter) -> Result<SharedFilm, Failure> {
        let (width, height) = (self.camera.hsize(), self.camera.vsize());
        SharedFilm::with_rows(width, height, filter, self.slice.rows(height))
            .map_err(|e| Failure::usage(e.to_string()))
    }

    /// The rows the slice leaves alone, marked done, so that the renderers skip them.
    fn others_done(&self) -> Vec<bool> {
        (0..self.camera.vsize())
            .map(|y| !self.slice.has_row(y))
            .collect()
    }

    /// Runs `render` with a progress bar over the slice's rows and the stop flag of Ctrl-C.
    fn with_hooks<R>(&self, render: impl FnOnce(&(dyn Fn(usize) + Sync), &AtomicBool) -> R) -> R {
        let stop = crate::interrupt::stop_flag(self.settings.quiet);
        let rows = self.slice.row_count(self.camera.vsize());
        let bar = row_bar(rows, self.settings.quiet);
        let progress = |rows: usize| bar.inc(rows as u64);
        let rendered = render(&progress, stop);
        bar.finish_and_clear();
        rendered
    }

    /// The failure of a slice whose rows are not all `done` (interrupted): nothing is written.
    fn check_finished(&self, done: &[bool]) -> Result<(), Failure> {
        if done.iter().all(|&d| d) {
            return Ok(());
        }
        Err(Failure::Interrupted(format!(
            "slice {} was not finished and nothing was written; run the same command again",
            self.slice
        )))
    }

    /// The ray tracer's rows of the slice.
    fn ray(&self) -> Result<Film, Failure> {
        let film = self.film(PixelFilter::Box)?;
        let mut done = self.others_done();
        let stats = self.with_hooks(|progress, stop| {
            let options = RenderOptions {
                progress: Some(progress),
                cancel: Some(stop),
                ..ray_options(self.settings, self.scene)
            };
            self.pool.install(|| {
                render_rows_into(self.camera, &self.scene.world, &options, &film, &mut done)
            })
        });
        let stats = stats
            .map_err(|e| Failure::internal(format!("the ray tracer refused its film: {e}")))?;
        if let Some((x, y)) = stats.over_budget {
            return Err(Failure::usage(format!(
                "pixel ({x}, {y}): a camera ray there leads to more than {} rays, the limit set \
                 by --max-rays-per-sample (lower --max-depth or raise --bailout)",
                self.settings.max_rays_per_sample
            )));
        }
        self.check_finished(&done)?;
        Ok(film.into_film())
    }

    /// The rasterizer's rows of the slice: the bands of tiles that hold them drawn, in one go
    /// (it keeps no rows of a frame it did not finish: Ctrl-C stops it before its next tile,
    /// and no part is written).
    fn raster(&self, options: &rayforge::options::RasterOptions) -> Result<Film, Failure> {
        let film = self.film(PixelFilter::Box)?;
        let stop = crate::interrupt::stop_flag(self.settings.quiet);
        self.pool
            .install(|| {
                rayforge::raster::render_rows_into(
                    self.camera,
                    &self.scene.world,
                    options,
                    &film,
                    Some(stop),
                )
            })
            .map_err(crate::render_command::raster_failure)?;
        Ok(film.into_film())
    }

    /// The path tracer's rows of the slice, with its `samples`, and with `aovs` the AOVs'
    /// films of those rows.
    fn path(
        &self,
        options: PathOptions,
        samples: std::ops::Range<u64>,
        aovs: bool,
    ) -> Result<(Film, Option<[Film; PART_AOVS]>), Failure> {
        let film = self.film(options.filter)?;
        let height = self.camera.vsize();
        let aovs = aovs
            .then(|| Aovs::with_rows(self.camera.hsize(), height, self.slice.rows(height)))
            .transpose()
            .map_err(|e| Failure::usage(e.to_string()))?;
        let mut done = self.others_done();
        let stats = self.with_hooks(|progress, stop| {
            // Learned for the whole render's samples, as an unsliced render learns it, so
            // that the slices merge into its image.
            let spp = samples_per_pixel(self.settings, self.scene);
            let world = &self.scene.world;
            let learned = self
                .pool
                .install(|| learn_roulette(self.camera, world, &options, spp, Some(stop)));
            // Stopped, the render after it stops at once, its rows undone.
            let roulette = learned.unwrap_or(LearnedRoulette::fixed(1.0));
            let job = PathJob {
                options,
                samples,
                plan: None,
                progress: Some(progress),
                cancel: Some(stop),
                on_row: None,
                roulette: Some(&roulette),
            };
            self.pool.install(|| {
                let world = &self.scene.world;
                render_path(self.camera, world, &job, &film, aovs.as_ref(), &mut done)
            })
        });
        stats.map_err(|e| Failure::internal(format!("the path tracer refused its film: {e}")))?;
        self.check_finished(&done)?;
        let aovs = aovs.map(|a| [a.albedo, a.normal, a.depth, a.samples].map(|f| f.into_film()));
        Ok((film.into_film(), aovs))
    }
}
