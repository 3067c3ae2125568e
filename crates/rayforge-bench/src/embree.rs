//! Running the Embree harness (`bench/peers/embree/primary.c`) and reading the one JSON line it
//! prints.

use std::path::Path;
use std::process::Command;

/// What the harness reports.
#[derive(Debug, Clone, PartialEq)]
pub struct EmbreeRun {
    /// Embree's version, as its device reports it.
    pub version: String,
    /// Seconds `rtcCommitScene` took (the BVH build).
    pub build_seconds: f64,
    /// Seconds of the fastest trace of all rays.
    pub trace_seconds: f64,
    /// Rays that hit.
    pub hits: u64,
    /// The sum of hit distances.
    pub t_sum: f64,
}

/// Runs the harness on a mesh file and a rays file; an error says what went wrong in one line.
pub fn run(
    harness: &Path,
    mesh: &Path,
    rays: &Path,
    threads: usize,
    repeat: u32,
) -> Result<EmbreeRun, String> {
    let output = Command::new(harness)
        .arg(mesh)
        .arg(rays)
        .args(["--threads", &threads.to_string()])
        .args(["--repeat", &repeat.max(1).to_string()])
        .output()
        .map_err(|e| format!("cannot run `{}`: {e}", harness.display()))?;
    if !output.status.success() {
        return Err(format!(
            "`{}` failed ({}): {}",
            harness.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout.lines().last().unwrap_or_default();
    parse(line).map_err(|e| format!("the Embree harness printed `{line}`: {e}"))
}

/// Runs the harness `rounds` times (at least once), one build and one trace each, calling
/// `between` before each run (rayforge's own pass: the two sides take turns on the machine);
/// the fastest build and the fastest trace count.
pub fn run_in_turns(
    harness: &Path,
    mesh: &Path,
    rays: &Path,
    threads: usize,
    rounds: u32,
    mut between: impl FnMut(),
) -> Result<EmbreeRun, String> {
    let mut best: Option<EmbreeRun> = None;
    for _ in 0..rounds.max(1) {
        between();
        let run = run(harness, mesh, rays, threads, 1)?;
        best = Some(match best {
            None => run,
            Some(b) => fastest(b, run),
        });
    }
    Ok(best.expect("at least one round"))
}

/// Two runs as one: the faster trace (with what it found) and the faster build.
fn fastest(a: EmbreeRun, b: EmbreeRun) -> EmbreeRun {
    let build_seconds = a.build_seconds.min(b.build_seconds);
    let faster = if b.trace_seconds < a.trace_seconds {
        b
    } else {
        a
    };
    EmbreeRun {
        build_seconds,
        ..faster
    }
}

/// Reads the harness's JSON line.
fn parse(line: &str) -> Result<EmbreeRun, String> {
    let value: serde_json::Value = serde_json::from_str(line).map_err(|e| e.to_string())?;
    let number = |key: &str| {
        value
            .get(key)
            .and_then(serde_json::Value::as_f64)
            .ok_or_else(|| format!("no number `{key}`"))
    };
    Ok(EmbreeRun {
        version: value
            .get("embree_version")
            .and_then(serde_json::Value::as_str)
            .unwrap_or("?")
            .to_string(),
        build_seconds: number("build_seconds")?,
        trace_seconds: number("trace_seconds")?,
        hits: value
            .get("hits")
            .and_then(serde_json::Value::as_u64)
            .ok_or("no count `hits`")?,
        t_sum: number("t_sum")?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_harness_line() {
        let run = parse(
            r#"{"peer":"embree","embree_version":"3.13.5","triangles":12,"rays":4,"threads":2,"build_seconds":0.5,"trace_seconds":0.25,"hits":3,"t_sum":7.5}"#,
        )
        .unwrap();
        assert_eq!(run.version, "3.13.5");
        assert_eq!((run.hits, run.t_sum, run.trace_seconds), (3, 7.5, 0.25));
    }

    fn sample(build_seconds: f64, trace_seconds: f64, hits: u64) -> EmbreeRun {
        EmbreeRun {
            version: "3.13.5".into(),
            build_seconds,
            trace_seconds,
            hits,
            t_sum: 1.0,
        }
    }

    #[test]
    fn runs_combine_into_the_fastest_build_and_trace() {
        let best = fastest(sample(0.5, 0.2, 7), sample(0.4, 0.3, 8));
        assert_eq!(
            (best.build_seconds, best.trace_seconds, best.hits),
            (0.4, 0.2, 7)
        );
        let best = fastest(sample(0.4, 0.3, 8), sample(0.5, 0.2, 7));
        assert_eq!(
            (best.build_seconds, best.trace_seconds, best.hits),
            (0.4, 0.2, 7)
        );
    }

    #[cfg(unix)]
    #[test]
    fn runs_in_turns_call_back_before_every_run() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let harness = dir.path().join("harness");
        std::fs::write(
            &harness,
            "#!/bin/sh\necho '{\"embree_version\":\"3.13.5\",\"build_seconds\":0.5,\
             \"trace_seconds\":0.25,\"hits\":3,\"t_sum\":7.5}'\n",
        )
        .unwrap();
        std::fs::set_permissions(&harness, std::fs::Permissions::from_mode(0o755)).unwrap();
        let mut turns = 0;
        let run = run_in_turns(&harness, dir.path(), dir.path(), 2, 3, || turns += 1).unwrap();
        assert_eq!(turns, 3);
        assert_eq!((run.hits, run.trace_seconds), (3, 0.25));
        let missing = dir.path().join("missing");
        assert!(run_in_turns(&missing, dir.path(), dir.path(), 2, 3, || {}).is_err());
    }

    #[test]
    fn a_line_without_a_field_is_an_error() {
        assert!(parse(r#"{"hits":3}"#)
            .unwrap_err()
            .contains("build_seconds"));
        assert!(parse("Segmentation fault").is_err());
    }
}
