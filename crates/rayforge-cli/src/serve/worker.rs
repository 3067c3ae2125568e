//! One page's renders: the newest request, rendered in passes with the render command's own
//! functions on one of the server's render threads (see [`super::session`]), each pass's image
//! sent to the page; with `denoise`, the passes denoised beside the render as well (see
//! [`crate::live_denoise`]), and the last one denoised in its place.
//!
//! A request is translated into `rayforge render`'s arguments and checked by the same code
//! ([`RenderSettings::from_args`]), so the page's final image is the one `rayforge render`
//! writes with those flags, and a size over `--max-pixels` is refused in the same words.

use super::budget::{MemoryBudget, Refusal};
use super::orbit::{implied_look_at, orbit};
use super::protocol::{self, Frame, Request, Started};
use super::Config;
use crate::args::{Cli, Command, Renderer};
use crate::denoise::Guides;
use crate::failure::Failure;
use crate::finite::blacken_non_finite;
use crate::format::ImageFormat;
use crate::live_denoise::{self, resolved, LiveDenoiser, Oidn};
use crate::path_command::{doubling_passes, samples_per_pixel};
use crate::path_output::{encode_for, AOV_NAMES};
use crate::render_command::{
    develop_with_overlay, finish_image, has_media, load_options, ray_options, sized_camera,
    strip_media, MEDIA_IGNORED,
};
use crate::settings::{Chosen, RenderSettings};
use clap::Parser;
use rayforge::camera::Camera;
use rayforge::canvas::Canvas;
use rayforge::film::{Film, SharedFilm};
use rayforge::options::{PathOptions, RasterOptions};
use rayforge::raster::Rasterizer;
use rayforge::render::path::{learn_roulette, render_path, Aovs, PathJob};
use rayforge::render::{render_rows, RenderOptions, Sampling};
use rayforge::LightingModel;
use rayforge_denoise::Session;
use rayforge_scene::{LoadOptions, Scene, StopFlag};
use rayon::ThreadPool;
use std::ffi::OsString;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::sync::mpsc::Sender;

/// A request to render, as the page's session hands it over.
#[derive(Clone)]
pub struct Job {
    /// Its number in the session, which the messages about it carry.
    pub id: u64,
    /// What to render.
    pub request: Request,
    /// How many times the scene's files had changed when it was asked for: the scene is read
    /// again when this differs from the one read last.
    pub generation: u64,
    /// Set when a newer request (or the page leaving) makes this one stale.
    pub cancel: Arc<AtomicBool>,
}

/// A message for the page.
pub enum Outgoing {
    /// JSON text (see [`protocol`]).
    Text(String),
    /// A PNG image.
    Binary(Vec<u8>),
}

/// The page is gone: its session dropped the receiving end.
pub struct Gone;

/// Shortest time between two progress messages: the page's progress line need not move more
/// often than the eye follows, and the messages would crowd out the images.
const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

/// Images narrower or lower than this many pixels get no quarter-size first pass.
const MIN_PREVIEW_SIDE: usize = 8;

/// The scene as last read, and its own lighting model (which requests override).
struct Loaded {
    generation: u64,
    scene: Scene,
    lighting: LightingModel,
}

/// The renders of one page.
pub struct Worker {
    config: Arc<Config>,
    pool: Arc<ThreadPool>,
    /// The memory every page's renders in flight share.
    budget: Arc<MemoryBudget>,
    out: Sender<Outgoing>,
    loaded: Option<Loaded>,
    /// The page's rasterizer, which keeps its memory from frame to frame.
    rasterizer: Rasterizer,
    /// OIDN, loaded when a request first asks to denoise, in one session for the page's
    /// renders: its device, and its filters while the size stays, serve every frame (a
    /// preview would otherwise spend most of its time making them).
    denoiser: Option<Session>,
}

impl Worker {
    /// A worker rendering on `pool` within `budget` and sending to `out`.
    pub fn new(
        config: Arc<Config>,
        pool: Arc<ThreadPool>,
        budget: Arc<MemoryBudget>,
        out: Sender<Outgoing>,
    ) -> Self {
        Self {
            config,
            pool,
            budget,
            out,
            loaded: None,
            rasterizer: Rasterizer::new(),
            denoiser: None,
        }
    }

    /// Renders `job` (unless a newer one has made it stale) and says how it ended; `Gone`
    /// when the page is.
    pub fn run(&mut self, job: &Job) -> Result<(), Gone> {
        if job.cancel.load(Ordering::Relaxed) {
            return Ok(());
        }
        let started = Instant::now();
        match self.render(job, started) {
            Ok(()) => self.send_text(job, protocol::done(job.id, elapsed(started))),
            Err(Stop::Failed(message)) => {
                self.send_text(job, protocol::error(Some(job.id), &message))
            }
            Err(Stop::Scene(error)) => self.send_text(job, protocol::scene_error(job.id, &error)),
            Err(Stop::Cancelled) => Ok(()),
            Err(Stop::Gone) => Err(Gone),
        }
    }

    /// Reads the scene when its files changed, and renders the job's passes.
    fn render(&mut self, job: &Job, started: Instant) -> Result<(), Stop> {
        let settings = settings_for(&self.config, &job.request)?;
        let loaded = load(&mut self.loaded, &settings, job)?;
        self.config.files.set(&loaded.scene.files);
        let lighting = job.request.lighting.unwrap_or(loaded.lighting);
        loaded.scene.world.lighting = lighting;
        let scene = &loaded.scene;
        let mut camera = sized_camera(&settings, scene)?;
        // The book's camera turns about what it looks at; another, about what its image's
        // centre sees.
        let look_at = scene
            .look_at
            .or_else(|| implied_look_at(&camera, &scene.world));
        if job.request.yaw != 0.0 || job.request.pitch != 0.0 {
            let look_at =
                look_at.ok_or_else(|| Stop::Failed("the camera cannot be turned so".into()))?;
            camera = orbit(&camera, &look_at, job.request.yaw, job.request.pitch)
                .ok_or_else(|| Stop::Failed("the camera cannot be turned so".into()))?;
        }
        let chosen = settings.choose(scene)?;
        // The page's denoise box is the path tracer's --denoise; the other renderers' images
        // have no noise to take out, and ignore it.
        let denoise = job.request.denoise && matches!(chosen, Chosen::Path(_));
        if denoise && self.denoiser.is_none() {
            // Its absence says how to install it, as `rayforge render --denoise` does.
            let threads = self.pool.current_num_threads();
            self.denoiser = Some(crate::denoise::load("denoise")?.session(threads));
        }
        // As `rayforge render` does: the ray tracer and the rasterizer draw the scene in
        // vacuum, and the page is told so (the scene read is kept whole for the path tracer).
        let in_vacuum;
        let media_ignored = !matches!(chosen, Chosen::Path(_)) && has_media(scene);
        let scene = if media_ignored {
            let mut copy = scene.clone();
            strip_media(&mut copy);
            in_vacuum = copy;
            &in_vacuum
        } else {
            scene
        };
        let size = (camera.hsize(), camera.vsize());
        // The image's film, and with denoising the AOVs' beside it.
        let films = if denoise {
            1 + AOV_NAMES.len() as u64
        } else {
            1
        };
        // As `rayforge render` does: a size the machine cannot hold is an error, not an abort.
        crate::memory::reserve_for_render(size.0, size.1, films)?;
        // And beside the other pages' renders: held until this one ends.
        let bytes = crate::memory::render_bytes(size.0, size.1, films).unwrap_or(u64::MAX);
        let what = format!("a {}×{} render", size.0, size.1);
        let _memory = self
            .budget
            .reserve(bytes, &what, &job.cancel)
            .map_err(|refusal| match refusal {
                Refusal::TooLarge(message) => Stop::Failed(message),
                Refusal::Cancelled => Stop::Cancelled,
            })?;
        let (renderer, samples) = match chosen {
            Chosen::Ray => (
                Renderer::Ray,
                ray_options(&settings, scene).sampling.camera_rays(),
            ),
            Chosen::Raster(_) => (Renderer::Raster, 1),
            Chosen::Path(_) => (Renderer::Path, samples_per_pixel(&settings, scene)),
        };
        let about = Started {
            renderer,
            lighting,
            size,
            samples,
            orbits: look_at.is_some(),
            denoise,
            warnings: {
                let mut lines = protocol::warning_lines(&scene.warnings);
                if media_ignored {
                    lines.push(MEDIA_IGNORED.into());
                }
                lines
            },
        };
        let pass = Pass {
            job,
            out: &self.out,
            started,
            sending: Mutex::new(()),
        };
        pass.text(protocol::started(job.id, &about))?;
        let preview = job.request.preview;
        match chosen {
            Chosen::Ray => ray_passes(&pass, &self.pool, &settings, scene, &camera, preview),
            Chosen::Raster(options) => raster_pass(
                &pass,
                &self.pool,
                &mut self.rasterizer,
                scene,
                &camera,
                &options,
            ),
            Chosen::Path(options) => {
                let spp = if preview { 1 } else { samples };
                let camera = if preview { quarter(&camera) } else { camera };
                let denoiser = self.denoiser.as_ref().filter(|_| denoise);
                path_passes(&pass, &self.pool, scene, &camera, options, spp, denoiser)
            }
        }
    }

    /// Sends a text message about `job` unless a newer request made it stale.
    fn send_text(&self, job: &Job, text: String) -> Result<(), Gone> {
        if job.cancel.load(Ordering::Relaxed) {
            return Ok(());
        }
        self.out
            .blocking_send(Outgoing::Text(text))
            .map_err(|_| Gone)
    }
}

/// The scene for the job's generation of the files: the one read last, or read again (a
/// reading the job's cancel stops part-way, as a newer request or the page's going does).
fn load<'a>(
    loaded: &'a mut Option<Loaded>,
    settings: &RenderSettings,
    job: &Job,
) -> Result<&'a mut Loaded, Stop> {
    let generation = job.generation;
    if loaded.as_ref().map(|l| l.generation) != Some(generation) {
        // A scene that no longer reads is not kept: the page keeps its last good image.
        *loaded = None;
        let options = LoadOptions {
            stop: StopFlag::new(job.cancel.clone()),
            ..load_options(settings, 0)
        };
        let scene = rayforge_scene::load_file_with(&settings.scene, &options).map_err(|e| {
            if e.interrupted {
                Stop::Cancelled
            } else {
                Stop::Scene(e)
            }
        })?;
        let lighting = scene.world.lighting;
        *loaded = Some(Loaded {
            generation,
            scene,
            lighting,
        });
    }
    loaded
        .as_mut()
        .ok_or_else(|| Stop::Failed("the scene was not read".into()))
}

/// Why a job stopped before its last pass.
enum Stop {
    /// A newer request came: nothing to say.
    Cancelled,
    /// The page is gone.
    Gone,
    /// The request cannot be rendered; the message says why.
    Failed(String),
    /// The scene (or a file it names) does not read.
    Scene(rayforge_scene::SceneError),
}

impl From<Failure> for Stop {
    fn from(failure: Failure) -> Self {
        Stop::Failed(match failure {
            Failure::Input(m) | Failure::Internal(m) | Failure::Interrupted(m) => m,
            Failure::Scene(report) => report.to_string(),
        })
    }
}

/// `rayforge render`'s settings for the request: its arguments, parsed and checked as the
/// command line's are (the output's name only picks the PNG format; nothing is written).
pub(super) fn settings_for(config: &Config, request: &Request) -> Result<RenderSettings, Failure> {
    let mut args: Vec<OsString> = ["rayforge", "render"].map(OsString::from).into();
    args.push(config.scene.clone().into_os_string());
    let mut flag = |name: &str, value: String| {
        args.push(name.into());
        args.push(value.into());
    };
    flag("--output", "live.png".into());
    flag("--max-pixels", config.max_pixels.to_string());
    if let Some(threads) = config.threads {
        flag("--threads", threads.to_string());
    }
    if let Some(renderer) = request.renderer {
        flag("--renderer", protocol::renderer_name(renderer).into());
    }
    if let Some(spp) = request.samples {
        flag("--spp", spp.to_string());
    }
    if let Some(width) = request.width {
        flag("--width", width.to_string());
    }
    if let Some(height) = request.height {
        flag("--height", height.to_string());
    }
    args.push("--quiet".into());
    if config.allow_outside {
        args.push("--allow-outside".into());
    }
    match Cli::try_parse_from(args) {
        Ok(Cli {
            command: Command::Render(render),
        }) => RenderSettings::from_args(render),
        Ok(_) => Err(Failure::internal(
            "the request did not make a render command",
        )),
        // clap's first line says what is wrong; its usage lines are about the command line.
        Err(e) => Err(Failure::usage(
            e.to_string()
                .lines()
                .next()
                .unwrap_or_default()
                .trim_start_matches("error: "),
        )),
    }
}

/// Milliseconds since `started`.
fn elapsed(started: Instant) -> u128 {
    started.elapsed().as_millis()
}

/// The camera at a quarter of the size (each side at least 1).
fn quarter(camera: &Camera) -> Camera {
    camera.resized((camera.hsize() / 4).max(1), (camera.vsize() / 4).max(1))
}

/// The job being rendered and where its images go.
struct Pass<'a> {
    job: &'a Job,
    out: &'a Sender<Outgoing>,
    started: Instant,
    /// Held while a frame's two messages go out: the denoiser's thread sends frames too.
    sending: Mutex<()>,
}

impl Pass<'_> {
    /// Whether a newer request made this job stale.
    fn cancelled(&self) -> bool {
        self.job.cancel.load(Ordering::Relaxed)
    }

    /// Sends a text message, unless the job is stale.
    fn text(&self, text: String) -> Result<(), Stop> {
        if self.cancelled() {
            return Err(Stop::Cancelled);
        }
        self.out
            .blocking_send(Outgoing::Text(text))
            .map_err(|_| Stop::Gone)
    }

    /// Sends pass `pass` of `passes`: the `frame` message, then the image as a PNG.
    fn frame(&self, canvas: &Canvas, pass: usize, passes: usize, samples: u64) -> Result<(), Stop> {
        self.send_frame(canvas, pass, passes, samples, false)
    }

    /// [`Pass::frame`], saying whether the image is `denoised`.
    fn send_frame(
        &self,
        canvas: &Canvas,
        pass: usize,
        passes: usize,
        samples: u64,
        denoised: bool,
    ) -> Result<(), Stop> {
        // A stale image is not encoded: a large PNG takes a second.
        if self.cancelled() {
            return Err(Stop::Cancelled);
        }
        let png = ImageFormat::Png.encode(canvas)?;
        let frame = Frame {
            pass,
            passes,
            size: (canvas.width(), canvas.height()),
            samples,
            millis: elapsed(self.started),
            denoised,
        };
        // A poisoned lock only means another frame's sender panicked: the messages still pair.
        let _sending = self.sending.lock().unwrap_or_else(|e| e.into_inner());
        self.text(protocol::frame(self.job.id, &frame))?;
        self.out
            .blocking_send(Outgoing::Binary(png))
            .map_err(|_| Stop::Gone)
    }

    /// A progress counter for pass `pass` of `passes` over `height` rows, for the renderers'
    /// `progress` hook: it sends a `progress` message at most every [`PROGRESS_INTERVAL`],
    /// dropping it when the page is behind (the next one says more).
    fn progress(&self, pass: usize, passes: usize, height: usize) -> Progress<'_> {
        Progress {
            pass: self,
            number: pass,
            passes,
            height,
            rows: AtomicUsize::new(0),
            last: Mutex::new(Instant::now()),
        }
    }
}

/// See [`Pass::progress`].
struct Progress<'a> {
    pass: &'a Pass<'a>,
    number: usize,
    passes: usize,
    height: usize,
    rows: AtomicUsize,
    last: Mutex<Instant>,
}

impl Progress<'_> {
    /// `rows` more rows are finished.
    fn add(&self, rows: usize) {
        let done = self.rows.fetch_add(rows, Ordering::Relaxed) + rows;
        let Ok(mut last) = self.last.try_lock() else {
            return;
        };
        if last.elapsed() < PROGRESS_INTERVAL || self.pass.cancelled() {
            return;
        }
        *last = Instant::now();
        let message = protocol::progress(
            self.pass.job.id,
            self.number,
            self.passes,
            done,
            self.height,
        );
        // Full or closed: this one is dropped, and a closed page ends the job at its frame.
        let _ = self.pass.out.try_send(Outgoing::Text(message));
    }
}

/// The ray tracer's passes: a quarter-size image of one ray per pixel, then (unless only a
/// preview is asked for) the full size with one ray, then with the samples asked for. Each
/// pass is a fresh render; the last is `rayforge render`'s image.
fn ray_passes(
    pass: &Pass<'_>,
    pool: &ThreadPool,
    settings: &RenderSettings,
    scene: &Scene,
    camera: &Camera,
    preview: bool,
) -> Result<(), Stop> {
    let options = ray_options(settings, scene);
    let mut passes = Vec::new();
    if camera.hsize().min(camera.vsize()) >= MIN_PREVIEW_SIDE {
        passes.push((quarter(camera), Sampling::Centre));
    }
    if !preview || passes.is_empty() {
        passes.push((camera.clone(), Sampling::Centre));
        if options.sampling != Sampling::Centre {
            passes.push((camera.clone(), options.sampling));
        }
    }
    let count = passes.len();
    for (i, (camera, sampling)) in passes.into_iter().enumerate() {
        let progress = pass.progress(i + 1, count, camera.vsize());
        let add = |rows: usize| progress.add(rows);
        let options = RenderOptions {
            sampling,
            progress: Some(&add),
            cancel: Some(&pass.job.cancel),
            ..ray_options(settings, scene)
        };
        let (image, stats) = pool.install(|| render_rows(&camera, &scene.world, &options));
        if let Some((x, y)) = stats.over_budget {
            return Err(Stop::Failed(format!(
                "pixel ({x}, {y}): a camera ray there leads to more than {} rays, the limit \
                 of --max-rays-per-sample (lower the scene's max-depth)",
                settings.max_rays_per_sample
            )));
        }
        if !image.is_complete() {
            return Err(Stop::Cancelled);
        }
        let (canvas, _) = develop_with_overlay(scene, &camera, image.film());
        pass.frame(&canvas, i + 1, count, sampling.camera_rays())?;
    }
    Ok(())
}

/// The rasterizer's one pass: it is quick enough to need no preview. The page's rasterizer
/// keeps its buffers from the last frame (a user dragging the view asks for one frame after
/// another of the same scene); the image is the one `rayforge render --renderer raster`
/// writes, canvas items drawn over it.
fn raster_pass(
    pass: &Pass<'_>,
    pool: &ThreadPool,
    rasterizer: &mut Rasterizer,
    scene: &Scene,
    camera: &Camera,
    options: &RasterOptions,
) -> Result<(), Stop> {
    let (image, _) = pool
        .install(|| rasterizer.render(camera, &scene.world, options, Some(&pass.job.cancel)))
        .map_err(|e| match e {
            // A newer request, or the page gone: the frame is dropped, as a ray pass's is.
            rayforge::raster::RasterError::Cancelled { .. } => Stop::Cancelled,
            _ => Stop::Failed(e.to_string()),
        })?;
    let (canvas, _) = finish_image(image.clone(), Some((&scene.overlay, camera)));
    pass.frame(&canvas, 1, 1, 1)
}

/// The path tracer's passes of 1, 1, 2, 4, … samples per pixel into one film, up to `spp`;
/// after each, the image resolved from the film so far, developed as `rayforge render`
/// develops a path-traced PNG (see `path_command::path_render`). With `denoiser`, the passes
/// are also denoised beside the render (skipped while it is busy) and sent flagged so, and the
/// last pass is sent only denoised with its AOVs: `rayforge render --denoise`'s image.
fn path_passes(
    pass: &Pass<'_>,
    pool: &ThreadPool,
    scene: &Scene,
    camera: &Camera,
    options: PathOptions,
    spp: u64,
    denoiser: Option<&Session>,
) -> Result<(), Stop> {
    let (width, height) = (camera.hsize(), camera.vsize());
    let film = Film::with_filter(width, height, options.filter)
        .map_err(|e| Stop::Failed(e.to_string()))?;
    let film = SharedFilm::from(film);
    let aovs = denoiser.map(|_| Aovs::new(width, height));
    let mut done = vec![false; height];
    // The roulette is learned once, not again in each pass, by a pilot sized for the passes'
    // samples (a sixteenth of them at most) that heeds the page's cancel. A preview (one
    // sample at a quarter size, sent again and again while the camera is dragged) is below
    // the pilot's least size and learns nothing: it plays the classic rule, unbiased, and a
    // roulette that trades noise against time over many samples has nothing to trade in one.
    // Before, its pilot of 41,000 paths cost about ten previews.
    let cancel = Some(&*pass.job.cancel);
    let learned = pool.install(|| learn_roulette(camera, &scene.world, &options, spp, cancel));
    let Some(roulette) = learned else {
        return Err(Stop::Cancelled);
    };
    let passes = doubling_passes(spp);
    let count = passes.len();
    let develop = |mut canvas: Canvas| {
        blacken_non_finite(&mut canvas);
        encode_for(ImageFormat::Png, &mut canvas);
        scene.overlay.draw(&mut canvas, camera);
        canvas
    };
    std::thread::scope(|scope| {
        let live = denoiser
            .zip(aovs.as_ref())
            .filter(|_| count > 1)
            .map(|(session, aovs)| {
                let oidn = Oidn { session };
                // A stale or closed page drops the frame; the render finds out at its own.
                let deliver = |frame: &live_denoise::Frame, image| {
                    let canvas = develop(image);
                    let _ = pass.send_frame(&canvas, frame.pass, count, frame.samples, true);
                };
                (LiveDenoiser::start(scope, oidn, deliver), aovs)
            });
        let rendered = (|| {
            for (i, samples) in passes.into_iter().enumerate() {
                let progress = pass.progress(i + 1, count, height);
                let add = |rows: usize| progress.add(rows);
                done.fill(false);
                let reached = samples.end;
                let job = PathJob {
                    options,
                    samples,
                    plan: None,
                    progress: Some(&add),
                    cancel: Some(&pass.job.cancel),
                    on_row: None,
                    roulette: Some(&roulette),
                };
                pool.install(|| {
                    render_path(camera, &scene.world, &job, &film, aovs.as_ref(), &mut done)
                })
                .map_err(|e| Stop::Failed(format!("the path tracer refused its film: {e}")))?;
                if !done.iter().all(|&d| d) {
                    return Err(Stop::Cancelled);
                }
                let last = i + 1 == count;
                if let Some((live, aovs)) = live.as_ref().filter(|_| !last) {
                    live.offer(|| live_denoise::Frame {
                        image: resolved(&film),
                        albedo: resolved(&aovs.albedo),
                        normal: resolved(&aovs.normal),
                        pass: i + 1,
                        samples: reached,
                    });
                }
                // Denoised, the last pass is sent once its denoise is done, below.
                if !(last && denoiser.is_some()) {
                    pass.frame(&develop(film.snapshot().resolve()), i + 1, count, reached)?;
                }
            }
            Ok(())
        })();
        // The pass in the denoiser's hands is sent before the last, denoised image.
        if let Some((live, _)) = live {
            live.finish();
        }
        rendered
    })?;
    if let (Some(denoiser), Some(aovs)) = (denoiser, &aovs) {
        let (albedo, normal) = (resolved(&aovs.albedo), resolved(&aovs.normal));
        let guides = Guides {
            albedo: &albedo,
            normal: Some(&normal),
        };
        let image = resolved(&film);
        let denoised = crate::denoise::denoise(denoiser, &image, Some(guides), "the image")?;
        pass.send_frame(&develop(denoised), count, count, spp, true)?;
    }
    Ok(())
}
