//! The path tracer against Mitsuba 3 on the five reference scenes of `scenes/pbr`.
//!
//! Two measurements per scene:
//!
//! 1. **Samples per second**: `rayforge render` at 1 and 2 threads, and Mitsuba 3's
//!    `scalar_rgb` and `llvm_ad_rgb` variants at 1 and 2 threads, the same scene, size and
//!    samples per pixel, each render a process of its own, the configurations taking turns
//!    (`--pbr-repeat` rounds: the median rate counts, and each ratio is the median of the
//!    rounds' ratios, see [`paired_ratio`]). rayforge's time is the render time of its
//!    summary line; Mitsuba's is one `mi.render` call timed inside
//!    `tools/fidelity/bench_mitsuba.py --one` (Python, scene loading and, for the JIT
//!    variant, a warm-up render that compiles the kernels are left out).
//! 2. **Equal-time error**: at 2 threads, rayforge's image at `--pbr-spp` (its median render
//!    time is the budget) against Mitsuba's faster variant at the samples per pixel that fit
//!    in the same time at its measured rate, with each of its samplers; the RMSE of each
//!    against a high-sample Mitsuba reference from `--pbr-reference`.
//!
//! Mitsuba is never a dependency: when Python cannot import it, the part is a table with a
//! note saying so.

use super::report::{seconds, times, Report, Table};
use super::scenes::rayforge_executable;
use super::Bench;
use rayforge_cli::failure::Failure;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The reference scenes, as named in `scenes/pbr` and in `tools/fidelity/mitsuba_scenes.py`.
pub const SCENES: [&str; 5] = [
    "furnace",
    "furnace-closed",
    "cornell",
    "spheres-materials",
    "envmap",
];

/// Mitsuba's variants timed: the plain one and the JIT-compiled one (its fastest on a CPU).
const VARIANTS: [&str; 2] = ["scalar_rgb", "llvm_ad_rgb"];

/// Mitsuba's samplers tried in the equal-time comparison (`independent` is its default).
const SAMPLERS: [&str; 3] = ["independent", "multijitter", "ldsampler"];

/// Thread counts of the samples-per-second table.
const THREADS: [usize; 2] = [1, 2];

/// Threads of the equal-time comparison.
const ERROR_THREADS: usize = 2;

/// The driver script, relative to the repository's root.
pub const DRIVER: &str = "tools/fidelity/bench_mitsuba.py";

/// The seed of Mitsuba's equal-time renders: far from the references' seeds (0–31 and
/// 100000 on), so no render shares random numbers with the image it is compared with.
const ERROR_SEED: u32 = 7_000_000;

/// The largest PFM read back: 64 MiB (a 2048×2048 colour image is 48 MiB).
const MAX_PFM_BYTES: u64 = 64 << 20;

/// How to get Mitsuba, quoted when it is missing.
const INSTALL: &str = "`pip install mitsuba numpy` (see tools/fidelity/README.md), or give \
                       --python FILE";

/// Python with Mitsuba 3, found.
struct Mitsuba {
    python: PathBuf,
    driver: PathBuf,
    version: String,
}

impl Mitsuba {
    /// Whether `python` imports Mitsuba 3 and the driver is there; `Err` says why not.
    fn find(python: &Path, driver: &Path) -> Result<Self, String> {
        if !driver.is_file() {
            return Err(format!(
                "the driver `{}` is not there (run from the repository's root)",
                driver.display()
            ));
        }
        let output = Command::new(python)
            .args(["-c", "import mitsuba, drjit; print(mitsuba.__version__)"])
            .output()
            .map_err(|e| format!("cannot run `{}` ({e}); {INSTALL}", python.display()))?;
        if !output.status.success() {
            return Err(format!(
                "`{}` cannot import mitsuba; {INSTALL}",
                python.display()
            ));
        }
        Ok(Self {
            python: python.to_path_buf(),
            driver: driver.to_path_buf(),
            version: String::from_utf8_lossy(&output.stdout).trim().to_string(),
        })
    }

    /// One timed render through the driver's `--one` mode.
    fn render(&self, job: &MitsubaJob, pfm: Option<&Path>) -> Result<MitsubaRun, String> {
        let mut c = Command::new(&self.python);
        c.arg(&self.driver)
            .args(["--one", job.scene, job.variant, &job.threads.to_string()])
            .args([
                "--spp",
                &job.spp.to_string(),
                "--seed",
                &job.seed.to_string(),
            ])
            .args(["--sampler", job.sampler]);
        if let Some(pfm) = pfm {
            c.arg("--pfm").arg(pfm);
        }
        let output = run_process(c)?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        let line = stdout.lines().rev().find(|l| l.starts_with('{'));
        line.and_then(parse_mitsuba_line)
            .ok_or_else(|| format!("the driver printed no result: {}", stdout.trim()))
    }
}

/// What the driver is asked to render.
struct MitsubaJob<'a> {
    scene: &'a str,
    variant: &'a str,
    threads: usize,
    sampler: &'a str,
    spp: u32,
    seed: u32,
}

/// What the driver reports of one render.
#[derive(Debug, Clone, PartialEq)]
struct MitsubaRun {
    /// Samples per pixel the sampler took (ldsampler rounds up to a power of 4).
    spp: u32,
    /// Pixels.
    pixels: u64,
    /// Seconds of the timed `mi.render` call.
    seconds: f64,
}

impl MitsubaRun {
    fn rate(&self) -> f64 {
        self.pixels as f64 * f64::from(self.spp) / self.seconds.max(1e-9)
    }
}

/// The driver's JSON line, read into a [`MitsubaRun`].
fn parse_mitsuba_line(line: &str) -> Option<MitsubaRun> {
    let v: serde_json::Value = serde_json::from_str(line).ok()?;
    let seconds = v.get("seconds")?.as_f64()?;
    let pixels = v.get("width")?.as_u64()? * v.get("height")?.as_u64()?;
    let spp = u32::try_from(v.get("spp")?.as_u64()?).ok()?;
    (seconds > 0.0).then_some(MitsubaRun {
        spp,
        pixels,
        seconds,
    })
}

/// What rayforge's summary line says of a path traced render.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RayforgeRun {
    width: u64,
    height: u64,
    spp: u64,
    /// The render time of the summary line (to the millisecond).
    seconds: f64,
}

impl RayforgeRun {
    fn pixels(&self) -> u64 {
        self.width * self.height
    }
    fn rate(&self) -> f64 {
        (self.pixels() * self.spp) as f64 / self.seconds.max(1e-9)
    }
}

/// Reads `path traced 256×256 at 64 spp in 3.104 s, …` (the last such line of `stderr`).
fn parse_path_summary(stderr: &str) -> Option<RayforgeRun> {
    let line = stderr
        .lines()
        .rev()
        .find(|l| l.starts_with("path traced "))?;
    let rest = line.strip_prefix("path traced ")?;
    let (size, rest) = rest.split_once(" at ")?;
    let (width, height) = size.split_once('×')?;
    let (spp, rest) = rest.split_once(" spp in ")?;
    let (secs, _) = rest.split_once(" s,")?;
    Some(RayforgeRun {
        width: width.parse().ok()?,
        height: height.parse().ok()?,
        spp: spp.parse().ok()?,
        seconds: secs.parse().ok()?,
    })
}

/// Runs a process to its end; a failure names the program and quotes its last lines.
fn run_process(mut command: Command) -> Result<Output, String> {
    let program = command.get_program().to_string_lossy().into_owned();
    let output = command
        .output()
        .map_err(|e| format!("cannot run `{program}`: {e}"))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let tail: Vec<&str> = stderr.lines().rev().take(3).collect();
        return Err(format!(
            "`{program}` failed ({}): {}",
            output.status,
            tail.into_iter().rev().collect::<Vec<_>>().join(" / ")
        ));
    }
    Ok(output)
}

/// The median (the mean of the middle two for an even count); `None` for no values.
fn median(values: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    })
}

/// The median over rounds of `ours ÷ theirs`, each round's two rates taken together (rounds
/// where either failed left out). The renders of one round run within seconds of each other,
/// so a slow spell of a shared machine that spans them slows both and cancels in their ratio,
/// where the ratio of the two medians can pair one side's quiet round with the other's slow
/// one.
fn paired_ratio(ours: &[Option<f64>], theirs: &[Option<f64>]) -> Option<f64> {
    let ratios: Vec<f64> = ours
        .iter()
        .zip(theirs)
        .filter_map(|(a, b)| Some(a.as_ref()? / b.as_ref()?))
        .collect();
    median(&ratios)
}

/// A PFM image as stored: width, height and `width × height × 3` floats in file order
/// (rows bottom to top), grey images repeated into three channels.
#[derive(Debug, Clone, PartialEq)]
struct Pfm {
    width: usize,
    height: usize,
    data: Vec<f32>,
}

/// Reads a PFM file (`PF` colour or `Pf` grey, either byte order), at most
/// [`MAX_PFM_BYTES`], its size checked against the header before anything is allocated.
fn read_pfm(path: &Path) -> Result<Pfm, String> {
    let fail = |why: String| format!("cannot read `{}`: {why}", path.display());
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(MAX_PFM_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(e.to_string()))?;
    if bytes.len() as u64 > MAX_PFM_BYTES {
        return Err(fail(format!("larger than {} MiB", MAX_PFM_BYTES >> 20)));
    }
    parse_pfm(&bytes).map_err(fail)
}

/// The PFM format of [`read_pfm`], from bytes.
fn parse_pfm(bytes: &[u8]) -> Result<Pfm, String> {
    let channels = match bytes.get(..2) {
        Some(b"PF") => 3,
        Some(b"Pf") => 1,
        _ => return Err("not a PFM file".into()),
    };
    // Three tokens after the magic, each after whitespace; one whitespace byte ends the header.
    let mut at = 2;
    let mut tokens = Vec::new();
    for _ in 0..3 {
        let start_ws = at;
        while bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() && at - start < 64 {
            at += 1;
        }
        if at == start_ws || at == start {
            return Err("malformed PFM header".into());
        }
        tokens.push(std::str::from_utf8(&bytes[start..at]).map_err(|_| "malformed header")?);
    }
    if !bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
        return Err("malformed PFM header".into());
    }
    let width: usize = tokens[0].parse().map_err(|_| "bad width")?;
    let height: usize = tokens[1].parse().map_err(|_| "bad height")?;
    let scale: f64 = tokens[2].parse().map_err(|_| "bad scale")?;
    if scale == 0.0 || !scale.is_finite() {
        return Err("bad scale".into());
    }
    let data = &bytes[at + 1..];
    let needed = width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(channels * 4))
        .ok_or("size overflows")?;
    if data.len() < needed {
        return Err(format!(
            "truncated: {width}×{height} needs {needed} bytes, has {}",
            data.len()
        ));
    }
    let floats = data[..needed].chunks_exact(4).map(|b| {
        let four = [b[0], b[1], b[2], b[3]];
        if scale < 0.0 {
            f32::from_le_bytes(four)
        } else {
            f32::from_be_bytes(four)
        }
    });
    let data = if channels == 3 {
        floats.collect()
    } else {
        floats.flat_map(|v| [v, v, v]).collect()
    };
    Ok(Pfm {
        width,
        height,
        data,
    })
}

/// The root mean square difference over every pixel and channel, with the count of values
/// left out because either side is not finite; an error when the sizes differ.
fn rmse(image: &Pfm, reference: &Pfm) -> Result<(f64, usize), String> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(format!(
            "the sizes differ: {}×{} against the reference's {}×{}",
            image.width, image.height, reference.width, reference.height
        ));
    }
    let (mut sum, mut n, mut bad) = (0.0f64, 0usize, 0usize);
    for (a, b) in image.data.iter().zip(&reference.data) {
        if a.is_finite() && b.is_finite() {
            let d = f64::from(*a) - f64::from(*b);
            sum += d * d;
            n += 1;
        } else {
            bad += 1;
        }
    }
    if n == 0 {
        return Err("no finite values".into());
    }
    Ok(((sum / n as f64).sqrt(), bad))
}

/// The reference of a scene: the high-sample image (`mitsuba-hi`, 8192 or 16384 spp) where
/// there is one, else the 2048-spp mean.
fn reference_for(dir: &Path, scene: &str) -> Option<PathBuf> {
    [
        format!("{scene}.mitsuba-hi.b0.pfm"),
        format!("{scene}.mitsuba.mean.pfm"),
    ]
    .into_iter()
    .map(|name| dir.join(name))
    .find(|p| p.is_file())
}

/// Samples per pixel that fit in `budget` seconds at `rate` samples per second over `pixels`
/// (at least 1); ldsampler takes a power of 4, the largest not above that (at least 4).
fn equal_time_spp(rate: f64, budget: f64, pixels: u64, sampler: &str) -> u32 {
    let fit = (rate * budget / pixels.max(1) as f64).floor();
    let fit = if fit.is_finite() {
        fit.clamp(1.0, 1e6) as u32
    } else {
        1
    };
    if sampler == "ldsampler" {
        let mut p = 4;
        while p * 4 <= fit {
            p *= 4;
        }
        p
    } else {
        fit
    }
}

/// Samples per second with an SI prefix, in millions: `1.23 M`.
fn msps(rate: f64) -> String {
    format!("{:.3} M", rate / 1e6)
}

/// An RMSE to three significant figures.
fn error(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    }
}

/// One configuration of the samples-per-second table.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Config {
    /// rayforge as it renders by default (its roulette learned for the scene), at this many
    /// threads.
    Rayforge(usize),
    /// rayforge with the classic roulette (`--roulette-scale 1`, the rule of Mitsuba's `path`
    /// integrator), at this many threads: its paths are Mitsuba's length, so samples per
    /// second compare the work of a bounce alone. The learned roulette keeps paths longer
    /// where that buys more than it costs, which lowers the samples per second of a render
    /// and its error at equal time both, and ends them into a prediction of the light still
    /// to come where that is known (the closed furnace's paths: about a third of the rays).
    RayforgeClassic(usize),
    Mitsuba(&'static str, usize),
}

/// The configurations in the order each round runs them: rayforge (by default, then with
/// the classic roulette), then Mitsuba, per thread count, so the sides take turns.
fn configs() -> Vec<Config> {
    THREADS
        .iter()
        .flat_map(|&t| {
            [Config::Rayforge(t), Config::RayforgeClassic(t)]
                .into_iter()
                .chain(VARIANTS.iter().map(move |&v| Config::Mitsuba(v, t)))
        })
        .collect()
}

/// Runs the part: the two tables, or one note saying why it was skipped.
pub fn run(bench: &Bench, report: &mut Report) -> Result<(), Failure> {
    let s = bench.settings;
    let spp = s.pbr_spp;
    let repeat = s.pbr_repeat;
    let mut rates = Table::new(
        format!(
            "The path tracer against Mitsuba 3: samples per second ({spp} spp, median of \
             {repeat}, each render a process)"
        ),
        &[
            "scene",
            "size",
            "threads",
            "rayforge",
            "Mitsuba scalar_rgb",
            "ratio",
            "Mitsuba llvm_ad_rgb",
            "ratio",
            "rayforge, classic roulette",
            "ratio to scalar_rgb",
        ],
    );
    let mitsuba = Mitsuba::find(&s.python, Path::new(DRIVER));
    let rayforge = rayforge_executable(s.rayforge.as_deref());
    let (mitsuba, rayforge) = match (mitsuba, rayforge) {
        (Ok(m), Some(r)) => (m, r),
        (Err(why), _) => {
            rates.note(format!("Skipped: Mitsuba 3 was not found: {why}."));
            report.table(&rates);
            return Ok(());
        }
        (_, None) => {
            rates.note(
                "Skipped: no `rayforge` beside rayforge-bench nor on PATH (build it with \
                 `cargo build --release -p rayforge-cli`, or give --rayforge FILE).",
            );
            report.table(&rates);
            return Ok(());
        }
    };
    let dir = bench.out("pbr");
    std::fs::create_dir_all(&dir).map_err(|e| bench.write_error(&dir, e))?;

    let mut errors = Table::new(
        format!(
            "The path tracer against Mitsuba 3: error at equal time ({ERROR_THREADS} threads; \
             the budget is rayforge's median time for {spp} spp)"
        ),
        &[
            "scene",
            "reference",
            "budget",
            "rayforge RMSE",
            "Mitsuba (best sampler)",
            "spp",
            "time",
            "RMSE",
            "RMSE at the budget",
            "Mitsuba ÷ rayforge",
        ],
    );
    let mut samplers = Table::new(
        format!(
            "Mitsuba's samplers at rayforge's budget ({ERROR_THREADS} threads; RMSE at the \
             budget = RMSE × √(time ÷ budget))"
        ),
        &[
            "scene",
            "variant",
            "sampler",
            "spp",
            "time",
            "RMSE",
            "RMSE at the budget",
        ],
    );
    let mut best_counts = [0usize; SAMPLERS.len()];

    // --quick: the first scene only, at 2 spp and one round: seconds, not minutes.
    let scenes: &[&str] = if s.quick { &SCENES[..1] } else { &SCENES };
    for &scene in scenes {
        let yml = PathBuf::from(format!("scenes/pbr/{scene}.yml"));
        if !yml.is_file() {
            rates.note(format!(
                "{scene} was skipped: `{}` is not there (run from the repository's root).",
                yml.display()
            ));
            continue;
        }
        // Samples per second: every configuration once per round, the rounds in turn.
        let configs = configs();
        // Each configuration's rate in each round (`None` where it failed or was skipped).
        let mut timings: Vec<Vec<Option<f64>>> = vec![Vec::new(); configs.len()];
        let mut failures: Vec<Option<String>> = vec![None; configs.len()];
        let mut size = None;
        let image = |t: usize| dir.join(format!("{scene}-rayforge-{spp}spp-t{t}.pfm"));
        for round in 0..repeat {
            for (k, config) in configs.iter().enumerate() {
                if failures[k].is_some() {
                    timings[k].push(None);
                    continue;
                }
                bench.progress(&format!(
                    "{scene}: {config:?}, round {} of {repeat}",
                    round + 1
                ));
                let result = match *config {
                    Config::Rayforge(t) | Config::RayforgeClassic(t) => {
                        let mut c = Command::new(&rayforge);
                        c.arg("render").arg(&yml).arg("-o");
                        if *config == Config::Rayforge(t) {
                            c.arg(image(t));
                        } else {
                            c.arg(dir.join(format!("{scene}-rayforge-classic-{spp}spp-t{t}.pfm")));
                            c.args(["--roulette-scale", "1"]);
                        }
                        c.args(["--spp", &spp.to_string(), "--threads", &t.to_string()]);
                        run_process(c).and_then(|out| {
                            let run = parse_path_summary(&String::from_utf8_lossy(&out.stderr))
                                .ok_or("rayforge printed no summary line")?;
                            size = Some((run.width, run.height));
                            Ok(run.rate())
                        })
                    }
                    Config::Mitsuba(variant, t) => mitsuba
                        .render(
                            &MitsubaJob {
                                scene,
                                variant,
                                threads: t,
                                sampler: "independent",
                                spp,
                                seed: 1000 + 2 * round,
                            },
                            None,
                        )
                        .map(|r| r.rate()),
                };
                match result {
                    Ok(rate) => timings[k].push(Some(rate)),
                    Err(why) => {
                        timings[k].push(None);
                        failures[k] = Some(why);
                    }
                }
            }
        }
        let rounds_of = |config: Config| -> &[Option<f64>] {
            configs
                .iter()
                .position(|c| *c == config)
                .map_or(&[], |k| &timings[k])
        };
        let rate_of = |config: Config| -> Option<f64> {
            median(
                &rounds_of(config)
                    .iter()
                    .flatten()
                    .copied()
                    .collect::<Vec<_>>(),
            )
        };
        let ratio = |a: Config, b: Config| -> String {
            paired_ratio(rounds_of(a), rounds_of(b)).map_or("—".into(), times)
        };
        for (k, why) in failures.iter().enumerate() {
            if let Some(why) = why {
                rates.note(format!("{scene}, {:?}: failed: {why}", configs[k]));
            }
        }
        let size_text = size.map_or("—".to_string(), |(w, h)| format!("{w}×{h}"));
        for t in THREADS {
            let ours = rate_of(Config::Rayforge(t));
            let mut cells = vec![
                scene.to_string(),
                size_text.clone(),
                t.to_string(),
                ours.map_or("failed".into(), msps),
            ];
            for variant in VARIANTS {
                let theirs = rate_of(Config::Mitsuba(variant, t));
                cells.push(theirs.map_or("failed".into(), msps));
                cells.push(ratio(Config::Rayforge(t), Config::Mitsuba(variant, t)));
            }
            let classic = rate_of(Config::RayforgeClassic(t));
            cells.push(classic.map_or("failed".into(), msps));
            cells.push(ratio(
                Config::RayforgeClassic(t),
                Config::Mitsuba(VARIANTS[0], t),
            ));
            rates.row(cells);
        }

        // Equal time, at 2 threads, against Mitsuba's faster variant there.
        let rayforge_timing = rate_of(Config::Rayforge(ERROR_THREADS));
        let Some(((width, height), our_rate)) = size.zip(rayforge_timing) else {
            continue;
        };
        let pixels = width * height;
        let budget = (pixels * u64::from(spp)) as f64 / our_rate;
        let fastest = VARIANTS
            .iter()
            .filter_map(|&v| Some((v, rate_of(Config::Mitsuba(v, ERROR_THREADS))?)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((variant, their_rate)) = fastest else {
            continue;
        };
        let Some(reference_path) = reference_for(&s.pbr_reference, scene) else {
            errors.note(format!(
                "{scene}: no reference `{scene}.mitsuba-hi.b0.pfm` or `{scene}.mitsuba.mean.pfm` \
                 in `{}` (--pbr-reference).",
                s.pbr_reference.display()
            ));
            continue;
        };
        let reference_name = reference_path
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        let compare = |path: &Path| -> Result<f64, String> {
            let (e, bad) = rmse(&read_pfm(path)?, &read_pfm(&reference_path)?)?;
            if bad > 0 {
                return Err(format!(
                    "`{}` has {bad} values that are not finite",
                    path.display()
                ));
            }
            Ok(e)
        };
        let ours = match compare(&image(ERROR_THREADS)) {
            Ok(e) => e,
            Err(why) => {
                errors.note(format!("{scene}: rayforge: {why}"));
                continue;
            }
        };
        // (sampler index, spp, seconds, RMSE, RMSE scaled to the budget)
        let mut theirs: Vec<(usize, u32, f64, f64, f64)> = Vec::new();
        for (k, sampler) in SAMPLERS.iter().enumerate() {
            let their_spp = equal_time_spp(their_rate, budget, pixels, sampler);
            bench.progress(&format!(
                "{scene}: Mitsuba {variant} {sampler} at {their_spp} spp (budget {})",
                seconds(budget)
            ));
            let pfm = dir.join(format!("{scene}-mitsuba-{sampler}-{their_spp}spp.pfm"));
            let job = MitsubaJob {
                scene,
                variant,
                threads: ERROR_THREADS,
                sampler,
                spp: their_spp,
                seed: ERROR_SEED,
            };
            let result = mitsuba
                .render(&job, Some(&pfm))
                .and_then(|run| Ok((run.clone(), compare(&pfm)?)));
            match result {
                Ok((run, e)) => {
                    let at_budget = e * (run.seconds / budget).sqrt();
                    samplers.row(vec![
                        scene.to_string(),
                        variant.to_string(),
                        sampler.to_string(),
                        run.spp.to_string(),
                        seconds(run.seconds),
                        error(e),
                        error(at_budget),
                    ]);
                    theirs.push((k, run.spp, run.seconds, e, at_budget));
                }
                Err(why) => samplers.note(format!("{scene}, {sampler}: failed: {why}")),
            }
        }
        let best = theirs.iter().min_by(|a, b| a.4.total_cmp(&b.4));
        let mut cells = vec![
            scene.to_string(),
            reference_name,
            format!("{} ({spp} spp)", seconds(budget)),
            error(ours),
        ];
        if let Some(&(k, their_spp, secs, e, at_budget)) = best {
            best_counts[k] += 1;
            cells.extend([
                format!("{variant}, {}", SAMPLERS[k]),
                their_spp.to_string(),
                seconds(secs),
                error(e),
                error(at_budget),
                times(at_budget / ours),
            ]);
        }
        errors.row(cells);
    }
    rates.note(format!(
        "Mitsuba {} through `{} {DRIVER} --one`: samples/s = pixels × spp ÷ the time of one \
         `mi.render` call (Python start-up, scene loading and, for llvm_ad_rgb, a warm-up render \
         that compiles its kernels left out); Mitsuba's threads set with \
         `drjit.set_thread_count`. rayforge: `rayforge render scenes/pbr/NAME.yml --spp {spp} \
         --threads T`, the render time of its summary line (scene loading left out; printed to \
         the millisecond). Ratios: rayforge's samples/s ÷ Mitsuba's (above 1, rayforge is faster), \
         the median over the rounds of each round's ratio (a round's renders run back to back, \
         so a slow spell of the machine that spans them cancels). \
         \"Classic roulette\": the same render with `--roulette-scale 1`, Mitsuba's rule, so that \
         paths are as long as Mitsuba's (by default rayforge learns the scale per scene, keeps \
         paths longer where that lowers the error reached in a given time, and ends them into a \
         prediction of the light still to come where its pilot could make one).",
        mitsuba.version,
        s.python.display()
    ));
    errors.note(format!(
        "RMSE over every pixel and channel against the reference in `{}` (`NAME.mitsuba-hi`, \
         8192 or 16384 spp, where there is one, else the 2048-spp mean; its own noise adds to \
         both sides alike). rayforge: its \
         default Sobol sampler, seed 0. Mitsuba: the variant faster at {ERROR_THREADS} threads \
         above, the spp that fit in the budget at its measured rate (ldsampler: the power of 4 \
         below), seed {ERROR_SEED}; its RMSE at the budget scales by √(time ÷ budget), as the \
         noise of an unbiased estimate does. Last column: Mitsuba's error at the budget with \
         its best sampler ÷ rayforge's (above 1, rayforge's image is closer). Images in `{}`.",
        s.pbr_reference.display(),
        dir.display()
    ));
    let best: Vec<String> = SAMPLERS
        .iter()
        .zip(best_counts)
        .filter(|(_, n)| *n > 0)
        .map(|(name, n)| format!("{name} on {n}"))
        .collect();
    if !best.is_empty() {
        samplers.note(format!(
            "Mitsuba's best sampler: {} of the scenes.",
            best.join(", ")
        ));
    }
    report.table(&rates);
    report.table(&errors);
    report.table(&samplers);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn the_summary_line_of_the_path_tracer_is_read_back() {
        let line = rayforge_cli::summary::path_summary_line(
            256,
            256,
            64,
            Duration::from_millis(3104),
            256 * 256 * 64,
            21_000_000,
            Path::new("out.pfm"),
        );
        let run = parse_path_summary(&format!("loading…\n{line}\n")).unwrap();
        assert_eq!((run.width, run.height, run.spp), (256, 256, 64));
        assert_eq!(run.seconds, 3.104, "the time to the millisecond");
        assert!((run.rate() - 256.0 * 256.0 * 64.0 / 3.104).abs() < 1e-6);
        assert_eq!(parse_path_summary("rendered 10×10 in 1.00 s"), None);
    }

    #[test]
    fn the_drivers_line_is_read_back() {
        let line = r#"{"scene": "cornell", "spp": 64, "width": 256, "height": 128, "seconds": 2.0, "warmup_seconds": null}"#;
        let run = parse_mitsuba_line(line).unwrap();
        assert_eq!((run.spp, run.pixels), (64, 256 * 128));
        assert_eq!(run.rate(), 256.0 * 128.0 * 32.0);
        assert_eq!(parse_mitsuba_line("{}"), None);
        assert_eq!(parse_mitsuba_line("not json"), None);
    }

    #[test]
    fn medians_and_equal_time_samples() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&[]), None);
        // 1 M samples/s for 2 s over 10 000 pixels: 200 spp; ldsampler takes 64.
        assert_eq!(equal_time_spp(1e6, 2.0, 10_000, "independent"), 200);
        assert_eq!(equal_time_spp(1e6, 2.0, 10_000, "ldsampler"), 64);
        assert_eq!(equal_time_spp(1e6, 2.56, 10_000, "ldsampler"), 256);
        assert_eq!(equal_time_spp(1.0, 1e-3, 10_000, "independent"), 1);
        assert_eq!(equal_time_spp(1.0, 1e-3, 10_000, "ldsampler"), 4);
    }

    #[test]
    fn ratios_pair_the_renders_of_each_round() {
        // The second round ran in a slow spell that halved both sides' rates: its ratio is
        // still 2, as the first round's, and their median is 2. The ratio of the two medians
        // pairs the third round's rates with each other only by chance: here 9 ÷ 4.
        let ours = [Some(10.0), Some(5.0), Some(9.0)];
        let theirs = [Some(5.0), Some(2.5), Some(4.0)];
        assert_eq!(paired_ratio(&ours, &theirs), Some(2.0));
        assert_eq!(median(&[10.0, 5.0, 9.0]), Some(9.0));
        assert_eq!(median(&[5.0, 2.5, 4.0]), Some(4.0));
        // Rounds where either side failed are left out.
        assert_eq!(
            paired_ratio(&[Some(3.0), None, Some(9.0)], &[Some(1.0), Some(1.0), None]),
            Some(3.0)
        );
        assert_eq!(paired_ratio(&[None], &[Some(1.0)]), None);
    }

    #[test]
    fn the_configurations_alternate_between_the_sides() {
        let c = configs();
        assert_eq!(c.len(), 8);
        assert_eq!(c[0], Config::Rayforge(1));
        assert_eq!(c[1], Config::RayforgeClassic(1));
        assert_eq!(c[2], Config::Mitsuba("scalar_rgb", 1));
        assert_eq!(c[4], Config::Rayforge(2));
    }

    fn pfm_bytes(header: &str, values: &[f32], little: bool) -> Vec<u8> {
        let mut b = header.as_bytes().to_vec();
        for v in values {
            b.extend(if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            });
        }
        b
    }

    #[test]
    fn pfm_files_are_read_in_both_byte_orders_and_checked() {
        let values = [0.5f32, 1.0, 2.0, 0.0, 0.25, 4.0];
        let le = parse_pfm(&pfm_bytes("PF\n2 1\n-1.0\n", &values, true)).unwrap();
        let be = parse_pfm(&pfm_bytes("PF\n2 1\n1.0\n", &values, false)).unwrap();
        assert_eq!(le, be);
        assert_eq!(
            (le.width, le.height, le.data.as_slice()),
            (2, 1, &values[..])
        );
        let grey = parse_pfm(&pfm_bytes("Pf 1 1 -1 ", &[3.0], true)).unwrap();
        assert_eq!(grey.data, vec![3.0; 3]);
        assert!(parse_pfm(&pfm_bytes("PF\n2 1\n-1.0\n", &values[..5], true)).is_err());
        assert!(parse_pfm(b"P6\n1 1\n255\n").is_err());
        assert!(parse_pfm(b"PF\n99999999999 99999999999\n-1\n").is_err());
    }

    #[test]
    fn the_rmse_is_over_every_value_and_skips_non_finite_ones() {
        let image = |data: Vec<f32>| Pfm {
            width: 2,
            height: 1,
            data,
        };
        let reference = image(vec![1.0; 6]);
        let (e, bad) = rmse(&image(vec![1.0, 1.0, 1.0, 1.0, 1.0, 3.0]), &reference).unwrap();
        // One value off by 2 among 6: √(4 / 6).
        assert!((e - (4.0f64 / 6.0).sqrt()).abs() < 1e-12 && bad == 0);
        let (e, bad) = rmse(&image(vec![f32::NAN, 2.0, 1.0, 1.0, 1.0, 1.0]), &reference).unwrap();
        assert!((e - (1.0f64 / 5.0).sqrt()).abs() < 1e-12 && bad == 1);
        let other = Pfm {
            width: 1,
            height: 2,
            data: vec![1.0; 6],
        };
        assert!(rmse(&other, &reference).is_err());
        assert_eq!(error(0.012345), "0.0123");
        assert_eq!(error(1.2345), "1.23");
    }

    #[test]
    fn the_high_sample_reference_is_preferred() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(reference_for(dir.path(), "cornell"), None);
        let mean = dir.path().join("cornell.mitsuba.mean.pfm");
        std::fs::write(&mean, b"").unwrap();
        assert_eq!(reference_for(dir.path(), "cornell"), Some(mean));
        let hi = dir.path().join("cornell.mitsuba-hi.b0.pfm");
        std::fs::write(&hi, b"").unwrap();
        assert_eq!(reference_for(dir.path(), "cornell"), Some(hi));
    }
}
