//! `rayforge-fuzz`: fuzz the readers for a while.
//!
//! ```text
//! cargo run --release -p rayforge-fuzz -- --target scene --seconds 3600
//! cargo run --release -p rayforge-fuzz -- --target all --seconds 1200 --seed 7
//! cargo run --release -p rayforge-fuzz -- --target obj --replay target/fuzz-crashes/obj-crash-….bin
//! cargo run --release -p rayforge-fuzz -- --target scene --write-seeds target/afl/seeds
//! ```

use rayforge_fuzz::corpus::write_seeds;
use rayforge_fuzz::runner::default_crash_dir;
use rayforge_fuzz::{fuzz, run_one, Options, Target};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

const USAGE: &str = "\
usage: rayforge-fuzz [--target scene|obj|image|gltf|ply|part|page|all] [--seconds N | --iterations N] [--seed N]
                     [--timeout SECONDS] [--crash-dir DIR] [--replay FILE] [--write-seeds DIR]

Fuzzes each target for --seconds (default 60) or --iterations mutated inputs, from --seed
(default: the time). A crash is minimised and written to --crash-dir (default
target/fuzz-crashes) and the exit status is 1; an input running past --timeout (default 10 s)
is written there as a hang and the process aborts; the slowest input of each target is kept
there too. --replay runs one file on the target (a crash or hang AFL++ found, too).
--write-seeds writes the target's seeds (those no longer than its longest input) into DIR as
<target>-<nnn>.bin and fuzzes nothing: the starting corpus of tools/fuzz/afl.sh.";

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}\n\n{USAGE}");
            ExitCode::from(2)
        }
    }
}

fn run() -> Result<ExitCode, String> {
    let mut targets = Target::ALL.to_vec();
    let mut seconds = None;
    let mut iterations = None;
    let mut seed = None;
    let mut timeout = 10.0;
    let mut crash_dir = default_crash_dir();
    let mut replay = None;
    let mut seeds_dir = None;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--target" => {
                let v = value()?;
                targets = if v == "all" {
                    Target::ALL.to_vec()
                } else {
                    vec![Target::from_name(&v).ok_or(format!("unknown target `{v}`"))?]
                };
            }
            "--seconds" => seconds = Some(number(&value()?)?),
            "--iterations" => iterations = Some(number(&value()?)? as u64),
            "--seed" => seed = Some(number(&value()?)? as u64),
            "--timeout" => timeout = number(&value()?)?,
            "--crash-dir" => crash_dir = PathBuf::from(value()?),
            "--replay" => replay = Some(PathBuf::from(value()?)),
            "--write-seeds" => seeds_dir = Some(PathBuf::from(value()?)),
            "-h" | "--help" => {
                println!("{USAGE}");
                return Ok(ExitCode::SUCCESS);
            }
            other => return Err(format!("unknown argument `{other}`")),
        }
    }
    if let Some(dir) = seeds_dir {
        for target in targets {
            let n = write_seeds(target, &dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            println!("{}: {n} seeds written to {}", target.name(), dir.display());
        }
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(file) = replay {
        let input = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        for target in targets {
            match run_one(target, &input) {
                Ok(accepted) => println!(
                    "{}: no panic ({})",
                    target.name(),
                    if accepted { "accepted" } else { "refused" }
                ),
                Err(m) => {
                    println!("{}: panicked: {m}", target.name());
                    return Ok(ExitCode::FAILURE);
                }
            }
        }
        return Ok(ExitCode::SUCCESS);
    }
    let seed = seed.unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(1, |d| d.as_secs())
    });
    let duration = match (seconds, iterations) {
        (None, None) => Some(Duration::from_secs(60)),
        (s, _) => s.map(Duration::from_secs_f64),
    };
    for target in targets {
        let options = Options {
            seed,
            iterations,
            duration,
            timeout: Duration::from_secs_f64(timeout),
            crash_dir: crash_dir.clone(),
            report_every: Some(Duration::from_secs(30)),
            keep_slowest: true,
        };
        eprintln!("{}: fuzzing from seed {seed}", target.name());
        match fuzz(target, &options) {
            Ok(r) => println!(
                "{}: {} inputs ({} accepted) in {:.1} s, no crash, {} caught panics \
                 (slowest input {:.3} s, seed {seed})",
                target.name(),
                r.executed,
                r.accepted,
                r.elapsed.as_secs_f64(),
                r.caught_panics,
                r.slowest.as_secs_f64()
            ),
            Err(crash) => {
                println!("{crash}");
                return Ok(ExitCode::FAILURE);
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn number(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v >= 0.0)
        .ok_or(format!("`{s}` is not a number of at least 0"))
}
