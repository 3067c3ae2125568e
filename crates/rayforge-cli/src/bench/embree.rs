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

    #[test]
    fn a_line_without_a_field_is_an_error() {
        assert!(parse(r#"{"hits":3}"#)
            .unwrap_err()
            .contains("build_seconds"));
        assert!(parse("Segmentation fault").is_err());
    }
}
