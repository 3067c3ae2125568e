//! rayforge against Don Cross's program (Fundamentals of Ray Tracing, cosinekitty/raytrace):
//! a build of it the user made and named with `--peer cross-raytrace=FILE` (this repository
//! does not build it). His program has one thread and no options: each
//! command renders fixed scenes at their own size into the working directory. rayforge renders
//! the same scenes (`scenes/fundamentals/NAME.yml`, each at the program's own size, zoom and
//! anti-aliasing) one after the other with `--threads 1`, each render its own process as his
//! are. Both are timed on the wall clock, best of `--scene-repeat`.

use super::peers::Peer;
use super::report::{seconds, times, Check, Report, Table};
use super::scenes::{rayforge_executable, time_process};
use super::Bench;
use rayforge_cli::failure::Failure;
use std::process::Command;

/// How much faster than his program per thread the issue asks rayforge to be.
const TARGET: f64 = 1.5;

/// His `test` command's scenes, which it renders in this order.
const TEST_SUITE: [&str; 15] = [
    "chessboard",
    "overlap",
    "multisphere",
    "torus1",
    "torus2",
    "polyhedra",
    "donutbite",
    "saturn",
    "block",
    "cylinder",
    "spheroid",
    "cuboid",
    "difference",
    "intersection",
    "sphere",
];

/// His commands and the scenes each renders: the whole suite, then the scenes that have a
/// command of their own (the kaleidoscope is in no suite).
fn cases() -> Vec<(&'static str, Vec<&'static str>)> {
    vec![
        ("test", TEST_SUITE.to_vec()),
        ("spheroid", vec!["spheroid"]),
        ("block", vec!["block"]),
        ("chessboard", vec!["chessboard"]),
        ("kaleid", vec!["kaleid"]),
    ]
}

/// Runs every command of his program and the same scenes with rayforge.
pub fn run(bench: &Bench, report: &mut Report) -> Result<(), Failure> {
    let repeat = bench.settings.scene_repeat;
    let mut table = Table::new(
        format!(
            "Don Cross's program (one thread each, wall time of the processes, best of {repeat})"
        ),
        &[
            "command",
            "scenes",
            "Cross",
            "rayforge",
            "ratio (Cross / rayforge)",
            "target",
        ],
    );
    let target = format!("≥ {}", times(TARGET));
    let dir = bench.out("cross");
    std::fs::create_dir_all(&dir).map_err(|e| bench.write_error(&dir, e))?;
    let cross = bench.peers.cross.clone();
    let rayforge = rayforge_executable(bench.settings.rayforge.as_deref());
    let skipped = if bench.settings.quick {
        Some("--quick (his scenes have fixed sizes)".to_string())
    } else if cross.is_none() {
        Some(Peer::Cross.skipped_hint())
    } else if rayforge.is_none() {
        Some("no rayforge executable (see the whole renders)".to_string())
    } else {
        None
    };
    for (command, scenes) in cases() {
        let what = format!("Cross's `{command}`, one thread");
        let (Some(cross), Some(rayforge), None) = (&cross, &rayforge, &skipped) else {
            report.check(Check {
                what,
                measured: "not run".into(),
                target: target.clone(),
                met: None,
            });
            continue;
        };
        bench.progress(&format!(
            "Cross's `{command}` and the same scenes with rayforge"
        ));
        let theirs = time_process(
            || {
                let mut c = Command::new(cross);
                c.arg(command).current_dir(&dir);
                c
            },
            repeat,
        );
        let mut ours = Ok(0.0);
        for scene in &scenes {
            let path = format!("scenes/fundamentals/{scene}.yml");
            let timed = time_process(
                || {
                    let mut c = Command::new(rayforge);
                    c.arg("render").arg(&path).arg("-o");
                    c.arg(dir.join(format!("{scene}-rayforge.png")));
                    c.args(["--threads", "1"]);
                    c
                },
                repeat,
            );
            ours = match (ours, timed) {
                (Ok(sum), Ok(t)) => Ok(sum + t.seconds),
                (Err(e), _) | (_, Err(e)) => Err(e),
            };
        }
        let listed = match scenes.len() {
            1 => scenes[0].to_string(),
            n => format!("{n}: every scene but kaleid"),
        };
        let mut cells = vec![format!("`{command}`"), listed];
        match (theirs, ours) {
            (Ok(theirs), Ok(ours)) => {
                let ratio = theirs.seconds / ours;
                cells.extend([seconds(theirs.seconds), seconds(ours), times(ratio)]);
                report.check(Check {
                    what,
                    measured: format!("{} faster", times(ratio)),
                    target: target.clone(),
                    met: Some(ratio >= TARGET),
                });
            }
            (theirs, ours) => {
                for e in [theirs.err(), ours.err()].into_iter().flatten() {
                    table.note(format!("`{command}`: {e}"));
                }
                cells.extend(["failed".into(), "failed".into(), "—".into()]);
                report.check(Check {
                    what,
                    measured: "failed".into(),
                    target: target.clone(),
                    met: None,
                });
            }
        }
        cells.push(target.clone());
        table.row(cells);
    }
    match skipped {
        Some(why) => table.note(format!("Skipped: {why}.")),
        None => table.note(format!("Images: `{}`.", dir.display())),
    }
    report.table(&table);
    Ok(())
}
