//! The fuzzing loop: every seed as it is, then mutated inputs, each run under `catch_unwind`.
//! A panic is minimised and written out; a watchdog writes out an input that runs past the
//! time limit and stops the process (a hang cannot be unwound).

use crate::corpus::seeds;
use crate::mutate::Mutator;
use crate::targets::Target;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

/// How long to fuzz, and where crashes go.
#[derive(Debug, Clone)]
pub struct Options {
    /// Seeds the mutations: the same seed tries the same inputs.
    pub seed: u64,
    /// Stop after this many mutated inputs (the seeds run first, uncounted).
    pub iterations: Option<u64>,
    /// Stop after this long.
    pub duration: Option<Duration>,
    /// An input running longer than this is a hang: written out, and the process aborted.
    pub timeout: Duration,
    /// Where crashing and hanging inputs are written.
    pub crash_dir: PathBuf,
    /// Called now and then with the number of inputs run so far.
    pub report_every: Option<Duration>,
    /// Write the slowest input to the crash directory at the end.
    pub keep_slowest: bool,
}

impl Options {
    /// `iterations` inputs from `seed`, crashes under the build directory.
    pub fn quick(seed: u64, iterations: u64) -> Self {
        Self {
            seed,
            iterations: Some(iterations),
            duration: None,
            timeout: Duration::from_secs(60),
            crash_dir: default_crash_dir(),
            report_every: None,
            keep_slowest: false,
        }
    }
}

/// `target/fuzz-crashes` in the workspace (or under `CARGO_TARGET_DIR`).
pub fn default_crash_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| crate::targets::repo_root().join("target"));
    target.join("fuzz-crashes")
}

/// What a run that found nothing did.
#[derive(Debug, Clone, Copy)]
pub struct Report {
    /// Inputs run, seeds included.
    pub executed: u64,
    /// How long it took.
    pub elapsed: Duration,
    /// The slowest single input.
    pub slowest: Duration,
    /// Inputs the reader accepted (the rest it refused with an error).
    pub accepted: u64,
    /// Inputs during which something panicked and the reader caught it (a bug in a library
    /// the reader guards against); the first few are written to the crash directory.
    pub caught_panics: u64,
}

/// An input that panicked.
#[derive(Debug, Clone)]
pub struct Crash {
    /// Which target.
    pub target: Target,
    /// The panic's message and location.
    pub message: String,
    /// The input as generated.
    pub input: Vec<u8>,
    /// The smallest input found that still panics.
    pub minimized: Vec<u8>,
    /// Where the minimised input was written (the original beside it, `.orig`).
    pub saved_to: Option<PathBuf>,
}

impl std::fmt::Display for Crash {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "the {} target panicked: {}",
            self.target.name(),
            self.message
        )?;
        if let Some(p) = &self.saved_to {
            writeln!(f, "input written to {}", p.display())?;
        }
        write!(
            f,
            "minimal input ({} bytes, from {}):\n{}",
            self.minimized.len(),
            self.input.len(),
            String::from_utf8_lossy(&self.minimized).escape_debug()
        )
    }
}

/// The last panic's message and place, recorded by the hook this module installs.
static LAST_PANIC: Mutex<String> = Mutex::new(String::new());
/// Whether panics are printed (a minimiser causes hundreds).
static QUIET: AtomicBool = AtomicBool::new(false);
/// Panics so far, caught or not: a reader that catches a panic in a library it calls (the
/// image decoders) survives it, and the fuzzer still counts it as a finding.
static PANICS: AtomicU64 = AtomicU64::new(0);

fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            PANICS.fetch_add(1, Ordering::Relaxed);
            let message = match info.payload().downcast_ref::<&str>() {
                Some(s) => (*s).to_string(),
                None => info
                    .payload()
                    .downcast_ref::<String>()
                    .cloned()
                    .unwrap_or_else(|| "a panic".into()),
            };
            let place = info
                .location()
                .map(|l| format!(" at {}:{}", l.file(), l.line()))
                .unwrap_or_default();
            if let Ok(mut last) = LAST_PANIC.lock() {
                *last = format!("{message}{place}");
            }
            if !QUIET.load(Ordering::Relaxed) {
                previous(info);
            }
        }));
    });
}

/// Runs `input` on `target`: whether the reader accepted it, or the panic's message.
pub fn run_one(target: Target, input: &[u8]) -> Result<bool, String> {
    install_panic_hook();
    catch_unwind(AssertUnwindSafe(|| target.run(input))).map_err(|_| {
        LAST_PANIC
            .lock()
            .map(|m| m.clone())
            .unwrap_or_else(|_| "a panic".into())
    })
}

/// The input being run, for the watchdog.
struct Current {
    started: Option<Instant>,
    input: Vec<u8>,
}

/// Fuzzes `target` from its seeds.
pub fn fuzz(target: Target, options: &Options) -> Result<Report, Box<Crash>> {
    fuzz_from(target, &seeds(target), options)
}

/// Fuzzes `target` from the given seeds.
pub fn fuzz_from(
    target: Target,
    corpus: &[Vec<u8>],
    options: &Options,
) -> Result<Report, Box<Crash>> {
    install_panic_hook();
    let current = Arc::new(Mutex::new(Current {
        started: None,
        input: Vec::new(),
    }));
    let done = Arc::new(AtomicBool::new(false));
    let watchdog = {
        let (current, done) = (current.clone(), done.clone());
        let (timeout, dir) = (options.timeout, options.crash_dir.clone());
        std::thread::spawn(move || watch(target, &current, &done, timeout, &dir))
    };
    let result = fuzz_loop(target, corpus, options, &current);
    done.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    result
}

fn fuzz_loop(
    target: Target,
    corpus: &[Vec<u8>],
    options: &Options,
    current: &Mutex<Current>,
) -> Result<Report, Box<Crash>> {
    let start = Instant::now();
    let mut last_report = start;
    let mut mutator = Mutator::new(options.seed, target.flavour(), target.max_len());
    let mut report = Report {
        executed: 0,
        elapsed: Duration::ZERO,
        slowest: Duration::ZERO,
        accepted: 0,
        caught_panics: 0,
    };
    let mut mutated = 0u64;
    let mut slowest_input = Vec::new();
    let mut seeds = corpus.iter();
    loop {
        let input = match seeds.next() {
            Some(seed) => seed.clone(),
            None => {
                let out_of_time = options.duration.is_some_and(|d| start.elapsed() >= d);
                let out_of_inputs = options.iterations.is_some_and(|n| mutated >= n);
                if out_of_time || out_of_inputs {
                    break;
                }
                mutated += 1;
                mutator.next_input(corpus)
            }
        };
        let began = Instant::now();
        if let Ok(mut c) = current.lock() {
            c.started = Some(began);
            c.input.clone_from(&input);
        }
        let panics_before = PANICS.load(Ordering::Relaxed);
        let outcome = run_one(target, &input);
        if outcome.is_ok() && PANICS.load(Ordering::Relaxed) != panics_before {
            report.caught_panics += 1;
            if report.caught_panics <= 5 {
                save(&options.crash_dir, target, "caught", &input, None);
            }
        }
        if let Ok(mut c) = current.lock() {
            c.started = None;
        }
        let took = began.elapsed();
        if took > report.slowest {
            report.slowest = took;
            slowest_input.clone_from(&input);
        }
        report.executed += 1;
        match outcome {
            Ok(accepted) => report.accepted += u64::from(accepted),
            Err(message) => {
                return Err(Box::new(crashed(
                    target,
                    message,
                    input,
                    &options.crash_dir,
                )));
            }
        }
        if let Some(every) = options.report_every {
            if last_report.elapsed() >= every {
                last_report = Instant::now();
                let secs = start.elapsed().as_secs_f64();
                eprintln!(
                    "{}: {} inputs ({} accepted, {} caught panics) in {secs:.0} s ({:.0}/s), \
                     slowest {:.2} s",
                    target.name(),
                    report.executed,
                    report.accepted,
                    report.caught_panics,
                    report.executed as f64 / secs,
                    report.slowest.as_secs_f64()
                );
            }
        }
    }
    report.elapsed = start.elapsed();
    // Kept to look at: the slowest input shows where the readers spend their time.
    if options.keep_slowest {
        save(&options.crash_dir, target, "slowest", &slowest_input, None);
    }
    Ok(report)
}

/// Minimises and writes out a crashing input.
fn crashed(target: Target, message: String, input: Vec<u8>, dir: &Path) -> Crash {
    QUIET.store(true, Ordering::Relaxed);
    let minimized = minimize(&input, |candidate| run_one(target, candidate).is_err());
    QUIET.store(false, Ordering::Relaxed);
    let saved_to = save(dir, target, "crash", &minimized, Some(&input));
    Crash {
        target,
        message,
        input,
        minimized,
        saved_to,
    }
}

/// Writes `input` to `dir` as `<target>-<kind>-<hash>.bin` (and the original beside it).
fn save(
    dir: &Path,
    target: Target,
    kind: &str,
    input: &[u8],
    original: Option<&[u8]>,
) -> Option<PathBuf> {
    std::fs::create_dir_all(dir).ok()?;
    let path = dir.join(format!(
        "{}-{kind}-{:016x}.bin",
        target.name(),
        fnv1a(input)
    ));
    std::fs::write(&path, input).ok()?;
    if let Some(original) = original {
        std::fs::write(path.with_extension("bin.orig"), original).ok()?;
    }
    Some(path)
}

/// Watches the input being run; past `timeout`, writes it out and aborts the process.
fn watch(
    target: Target,
    current: &Mutex<Current>,
    done: &AtomicBool,
    timeout: Duration,
    dir: &Path,
) {
    while !done.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(50));
        let Ok(c) = current.lock() else {
            return;
        };
        if c.started.is_some_and(|s| s.elapsed() > timeout) {
            let saved = save(dir, target, "hang", &c.input, None);
            eprintln!(
                "the {} target ran one input for more than {:.0} s (a hang); input written to {}",
                target.name(),
                timeout.as_secs_f64(),
                saved.map_or_else(|| "(could not write)".into(), |p| p.display().to_string())
            );
            std::process::abort();
        }
    }
}

/// Shrinks `input` while `fails` holds: whole lines first, then runs of bytes, halving the
/// size of what is removed down to single bytes (a simple delta debugging). Bounded to a few
/// thousand tries.
pub fn minimize(input: &[u8], mut fails: impl FnMut(&[u8]) -> bool) -> Vec<u8> {
    let mut best = input.to_vec();
    let mut tries = 0usize;
    const MAX_TRIES: usize = 4000;
    // Lines.
    let mut chunk = crate::mutate::lines(&best).len().div_ceil(2).max(1);
    loop {
        let lines: Vec<Vec<u8>> = crate::mutate::lines(&best)
            .into_iter()
            .map(<[u8]>::to_vec)
            .collect();
        let mut i = 0;
        let mut removed_any = false;
        let mut current = lines;
        while i < current.len() && tries < MAX_TRIES {
            let end = (i + chunk).min(current.len());
            let candidate: Vec<u8> = current[..i]
                .iter()
                .chain(&current[end..])
                .flatten()
                .copied()
                .collect();
            tries += 1;
            if fails(&candidate) {
                current.drain(i..end);
                best = candidate;
                removed_any = true;
            } else {
                i += chunk;
            }
        }
        if chunk == 1 && !removed_any || tries >= MAX_TRIES {
            break;
        }
        chunk = (chunk / 2).max(1);
    }
    // Bytes.
    let mut chunk = (best.len() / 2).max(1);
    while tries < MAX_TRIES {
        let mut i = 0;
        let mut removed_any = false;
        while i < best.len() && tries < MAX_TRIES {
            let end = (i + chunk).min(best.len());
            let mut candidate = best[..i].to_vec();
            candidate.extend_from_slice(&best[end..]);
            tries += 1;
            if fails(&candidate) {
                best = candidate;
                removed_any = true;
            } else {
                i += chunk;
            }
        }
        if chunk == 1 && !removed_any {
            break;
        }
        chunk = (chunk / 2).max(1);
    }
    best
}

/// FNV-1a, 64-bit: names crash files by their content.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimize_keeps_what_the_failure_needs() {
        let input = b"aaa\nbbb\nxyz\nccc\n";
        let min = minimize(input, |c| c.windows(2).any(|w| w == b"yz"));
        assert_eq!(min, b"yz");
    }
}
