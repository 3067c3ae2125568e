//! Whole renders against POV-Ray and raytracer_rs, each renderer run as a process and timed on
//! the wall clock from start to exit (parsing and loading included), at the same resolution,
//! samples per pixel and reflection depth, on the same number of threads: rayforge with
//! `--threads`, POV-Ray with `+WT`, raytracer_rs (a binary named with `--peer`) with
//! `RAYON_NUM_THREADS`. The images land in
//! `--out`/scenes to check that both drew the same scene.

use super::peers;
use super::report::{seconds, si, times, Check, Report, Table};
use super::{pov_mesh, Bench};
use rayforge_cli::failure::Failure;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// rayforge's reflection depth against POV-Ray (its default, the book's 5); the POV-Ray files
/// set `max_trace_level 6`, which is the same depth counted from the camera ray.
const MAX_DEPTH: u32 = 5;
/// raytracer_rs's `recursion_depth` of 5 counts the camera ray as the first level (its
/// `colour_at` returns black once the count reaches 0), so it follows 4 bounces: rayforge's
/// depth 4 traces the same.
const RAYTRACER_RS_DEPTH: u32 = 4;

/// How much faster than POV-Ray the second performance issue asks rayforge to be on the
/// book's cover, and on its other scenes.
const POVRAY_COVER_TARGET: f64 = 4.0;
const POVRAY_TARGET: f64 = 3.0;
/// How much faster than raytracer_rs the first performance issue asked rayforge to be.
const RAYTRACER_RS_TARGET: f64 = 5.0;

/// A peer's side of one scene.
enum Peer {
    /// A POV-Ray file in `--povray-scenes`, and the OBJ model its include is made from.
    PovRay {
        file: &'static str,
        model: Option<&'static str>,
    },
    /// A raytracer_rs binary named with `--peer` (its scene, size and samples are built in).
    RaytracerRs { example: &'static str },
}

/// One comparison: the scene as rayforge reads it, its size and samples, and the peer.
struct Case {
    name: &'static str,
    /// The YAML scene; `models:` at the start means the models directory.
    scene: &'static str,
    size: (u32, u32),
    spp: u32,
    /// Reflection and refraction bounces, as the peer counts them.
    depth: u32,
    peer: Peer,
}

fn cases() -> Vec<Case> {
    use Peer::*;
    vec![
        Case {
            name: "cover",
            scene: "scenes/trtc/cover.yml",
            size: (1080, 1080),
            spp: 1,
            depth: MAX_DEPTH,
            peer: PovRay {
                file: "cover.pov",
                model: None,
            },
        },
        Case {
            name: "chess board",
            scene: "scenes/bench/chessboard.yml",
            size: (1920, 1080),
            spp: 1,
            depth: MAX_DEPTH,
            peer: PovRay {
                file: "chessboard.pov",
                model: None,
            },
        },
        Case {
            name: "1024 spheres",
            scene: "scenes/bench/spheres.yml",
            size: (1920, 1080),
            spp: 1,
            depth: MAX_DEPTH,
            peer: PovRay {
                file: "spheres.pov",
                model: None,
            },
        },
        Case {
            name: "dragons (bounding-boxes.yml)",
            scene: "models:bounding-boxes.yml",
            size: (1920, 1080),
            spp: 1,
            depth: MAX_DEPTH,
            peer: PovRay {
                file: "dragons.pov",
                model: Some("dragon.obj"),
            },
        },
        Case {
            name: "cover",
            scene: "scenes/trtc/cover.yml",
            size: (1080, 1080),
            spp: 1,
            depth: RAYTRACER_RS_DEPTH,
            peer: RaytracerRs { example: "cover" },
        },
        Case {
            name: "dragons (bounding-boxes.yml)",
            scene: "models:bounding-boxes.yml",
            size: (1920, 1080),
            spp: 16,
            depth: RAYTRACER_RS_DEPTH,
            peer: RaytracerRs { example: "dragons" },
        },
    ]
}

/// What makes two of rayforge's renders the same: scene file, size, samples per pixel, depth.
type RenderKey = (PathBuf, (u32, u32), u32, u32);

/// A timed process: its fastest wall time, and what it printed last time.
pub(crate) struct Timed {
    pub seconds: f64,
    stderr: String,
}

/// Runs `command` `repeat` times; the fastest successful run counts, any failure is reported.
pub(crate) fn time_process(
    mut make: impl FnMut() -> Command,
    repeat: u32,
) -> Result<Timed, String> {
    let mut best: Option<Timed> = None;
    for _ in 0..repeat.max(1) {
        let mut command = make();
        let start = Instant::now();
        let output = command.output().map_err(|e| {
            format!(
                "cannot run `{}`: {e}",
                command.get_program().to_string_lossy()
            )
        })?;
        let seconds = start.elapsed().as_secs_f64();
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        if !output.status.success() {
            let tail: Vec<&str> = stderr.lines().rev().take(3).collect();
            return Err(format!(
                "`{}` failed ({}): {}",
                command.get_program().to_string_lossy(),
                output.status,
                tail.into_iter().rev().collect::<Vec<_>>().join(" / ")
            ));
        }
        if best.as_ref().is_none_or(|b| seconds < b.seconds) {
            best = Some(Timed { seconds, stderr });
        }
    }
    best.ok_or_else(|| "no run".to_string())
}

/// The ray count from rayforge's summary line (`… rays/s (9.5 M rays) → …`).
fn rays_from_summary(stderr: &str) -> Option<f64> {
    let line = stderr.lines().rev().find(|l| l.starts_with("rendered "))?;
    let inside = line.rsplit_once('(')?.1.split_once(" rays)")?.0;
    let (number, scale) = match inside.rsplit_once(' ') {
        Some((n, "k")) => (n, 1e3),
        Some((n, "M")) => (n, 1e6),
        Some((n, "G")) => (n, 1e9),
        _ => (inside, 1.0),
    };
    number.trim().parse::<f64>().ok().map(|n| n * scale)
}

/// Runs every comparison whose files are there.
pub fn run(bench: &Bench, report: &mut Report) -> Result<(), Failure> {
    let threads = bench.settings.threads;
    let dir = bench.out("scenes");
    std::fs::create_dir_all(&dir).map_err(|e| bench.write_error(&dir, e))?;
    let mut table = Table::new(
        format!(
            "Whole renders ({threads} threads, wall time of each process, best of {})",
            bench.settings.scene_repeat
        ),
        &[
            "scene",
            "size",
            "spp",
            "depth",
            "rayforge",
            "peer",
            "peer time",
            "ratio (peer / rayforge)",
            "target",
            "rayforge rays/s",
        ],
    );
    let rayforge = rayforge_executable(bench.settings.rayforge.as_deref());
    if rayforge.is_none() {
        table.note(format!(
            "Every render was skipped: no `{RAYFORGE}` beside rayforge-bench nor on PATH (build \
             it with `cargo build --release -p rayforge-cli`, or give --rayforge FILE)."
        ));
    }
    // rayforge's render of a (scene, size, spp), kept for the next peer of the same one.
    let mut ours: Vec<(RenderKey, Result<Timed, String>)> = Vec::new();
    for case in cases() {
        let scene = match case.scene.strip_prefix("models:") {
            Some(name) => bench.settings.models.join(name),
            None => PathBuf::from(case.scene),
        };
        let size = if bench.settings.quick {
            (case.size.0 / 40, case.size.1 / 40)
        } else {
            case.size
        };
        let (peer_name, target) = match case.peer {
            Peer::PovRay { .. } if case.name == "cover" => ("POV-Ray 3.7", POVRAY_COVER_TARGET),
            Peer::PovRay { .. } => ("POV-Ray 3.7", POVRAY_TARGET),
            Peer::RaytracerRs { .. } => ("raytracer_rs", RAYTRACER_RS_TARGET),
        };
        let size_text = format!("{}×{}", size.0, size.1);
        let target_text = if target > 1.0 {
            format!("≥ {}", times(target))
        } else {
            "> 1× (faster)".to_string()
        };
        let mut cells = vec![
            case.name.to_string(),
            size_text.clone(),
            case.spp.to_string(),
            case.depth.to_string(),
        ];
        if !scene.is_file() {
            table.note(format!(
                "{} was skipped: `{}` is not there{}.",
                case.name,
                scene.display(),
                if case.scene.starts_with("models:") {
                    " (it lives beside the repository, in shared/models)"
                } else {
                    " (run from the repository's root)"
                }
            ));
            continue;
        }
        let Some(rayforge) = &rayforge else {
            report.check(Check {
                what: format!("{} {size_text} {} spp, vs {peer_name}", case.name, case.spp),
                measured: "not run".into(),
                target: target_text,
                met: None,
            });
            continue;
        };
        let key = (scene.clone(), size, case.spp, case.depth);
        if !ours.iter().any(|(k, _)| *k == key) {
            bench.progress(&format!(
                "{}: rendering with rayforge at {size_text}",
                case.name
            ));
            let image = dir.join(format!(
                "{}-rayforge-{}spp-depth{}.png",
                slug(case.name),
                case.spp,
                case.depth
            ));
            let result = time_process(
                || {
                    let mut c = Command::new(rayforge);
                    c.arg("render").arg(&scene).arg("-o").arg(&image);
                    c.args([
                        "--width",
                        &size.0.to_string(),
                        "--height",
                        &size.1.to_string(),
                    ]);
                    c.args([
                        "--spp",
                        &case.spp.to_string(),
                        "--threads",
                        &threads.to_string(),
                    ]);
                    c.args(["--max-depth", &case.depth.to_string()]);
                    c
                },
                bench.settings.scene_repeat,
            );
            ours.push((key.clone(), result));
        }
        let ours_result = &ours
            .iter()
            .find(|(k, _)| *k == key)
            .expect("just rendered")
            .1;
        let ours_timed = match ours_result {
            Ok(t) => t,
            Err(message) => {
                table.note(format!("{}: rayforge failed: {message}", case.name));
                continue;
            }
        };
        cells.push(seconds(ours_timed.seconds));
        cells.push(peer_name.to_string());
        let what = format!("{} {size_text} {} spp, vs {peer_name}", case.name, case.spp);
        let peer = match peer_run(bench, &case, size, &dir) {
            PeerRun::Done(result) => result,
            PeerRun::Skipped(why) => {
                cells.extend(["skipped".into(), "—".into(), target_text.clone()]);
                table.note(format!(
                    "{} against {peer_name} was skipped: {why}.",
                    case.name
                ));
                Err(String::new())
            }
        };
        match &peer {
            Ok(theirs) => {
                let ratio = theirs.seconds / ours_timed.seconds;
                cells.extend([seconds(theirs.seconds), times(ratio), target_text.clone()]);
                let met = if target > 1.0 {
                    ratio >= target
                } else {
                    ratio > target
                };
                report.check(Check {
                    what,
                    measured: format!("{} faster", times(ratio)),
                    target: target_text,
                    met: Some(met),
                });
            }
            Err(message) => {
                if !message.is_empty() {
                    cells.extend(["failed".into(), "—".into(), target_text.clone()]);
                    table.note(format!("{} against {peer_name}: {message}", case.name));
                }
                report.check(Check {
                    what,
                    measured: "not run".into(),
                    target: target_text,
                    met: None,
                });
            }
        }
        cells.push(
            rays_from_summary(&ours_timed.stderr)
                .map(|r| format!("{}/s", si(r / ours_timed.seconds)))
                .unwrap_or_else(|| "—".into()),
        );
        table.row(cells);
    }
    table.note(format!(
        "Images: `{}` (rayforge and POV-Ray; a raytracer_rs binary writes where it was built to).",
        dir.display()
    ));
    report.table(&table);
    Ok(())
}

/// What became of a peer's render.
enum PeerRun {
    Done(Result<Timed, String>),
    Skipped(String),
}

/// Renders one case with its peer, if the peer is installed and can render at this size.
fn peer_run(bench: &Bench, case: &Case, size: (u32, u32), dir: &Path) -> PeerRun {
    let threads = bench.settings.threads.to_string();
    match case.peer {
        Peer::PovRay { file, model } => {
            let Some(povray) = bench.peers.povray.clone() else {
                return PeerRun::Skipped(peers::Peer::PovRay.skipped_hint());
            };
            let pov = bench.settings.povray_scenes.join(file);
            let Ok(pov) = pov.canonicalize() else {
                return PeerRun::Skipped(format!("`{}` is not there", pov.display()));
            };
            if let Some(model) = model {
                let obj = bench.settings.models.join(model);
                let include = dir.join(Path::new(model).with_extension("inc"));
                bench.progress(&format!(
                    "{}: writing {} for POV-Ray",
                    case.name,
                    include.display()
                ));
                if let Err(e) = pov_mesh::write_include(&obj, "Dragon", &include) {
                    return PeerRun::Done(Err(e));
                }
            }
            bench.progress(&format!("{}: rendering with POV-Ray", case.name));
            let image = format!("{}-povray.png", slug(case.name));
            PeerRun::Done(time_process(
                || {
                    let mut c = Command::new(&povray);
                    // Run in the output directory: POV-Ray writes only below its working
                    // directory, and finds the generated include there.
                    c.current_dir(dir);
                    c.arg(format!("+I{}", pov.display()));
                    c.arg(format!("+O{image}"));
                    c.arg(format!("+W{}", size.0)).arg(format!("+H{}", size.1));
                    // One sample per pixel (no anti-aliasing), PNG, no display window, no
                    // pause, linear output like rayforge's.
                    c.args(["-A", "+FN", "-D", "-P", "File_Gamma=1.0"]);
                    c.arg(format!("+WT{threads}"));
                    c
                },
                bench.settings.scene_repeat,
            ))
        }
        Peer::RaytracerRs { example } => {
            let (binary, peer) = match example {
                "cover" => (
                    bench.peers.raytracer_rs_cover.clone(),
                    peers::Peer::RaytracerRsCover,
                ),
                _ => (
                    bench.peers.raytracer_rs_dragons.clone(),
                    peers::Peer::RaytracerRsDragons,
                ),
            };
            let Some(binary) = binary else {
                return PeerRun::Skipped(peer.skipped_hint());
            };
            if bench.settings.quick {
                return PeerRun::Skipped(
                    "its examples render at a fixed size, too large for --quick".into(),
                );
            }
            bench.progress(&format!("{}: rendering with raytracer_rs", case.name));
            PeerRun::Done(time_process(
                || {
                    let mut c = Command::new(&binary);
                    c.env("RAYON_NUM_THREADS", &threads);
                    c
                },
                bench.settings.scene_repeat,
            ))
        }
    }
}

/// The file name of the `rayforge` executable on this system.
const RAYFORGE: &str = if cfg!(windows) {
    "rayforge.exe"
} else {
    "rayforge"
};

/// The `rayforge` executable whose renders are timed: `--rayforge` (checked to be a file with
/// the other arguments), else the one beside this program (cargo builds both into the same
/// directory), else the first on PATH; `None` when there is none.
pub(crate) fn rayforge_executable(given: Option<&Path>) -> Option<PathBuf> {
    if let Some(path) = given {
        return Some(path.to_path_buf());
    }
    let beside = std::env::current_exe()
        .ok()
        .and_then(|exe| Some(exe.parent()?.join(RAYFORGE)));
    let on_path = std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).collect::<Vec<_>>())
        .unwrap_or_default()
        .into_iter()
        .map(|dir| dir.join(RAYFORGE));
    beside.into_iter().chain(on_path).find(|p| p.is_file())
}

/// A file-name form of a case's name: `dragons (bounding-boxes.yml)` → `dragons`.
fn slug(name: &str) -> String {
    name.split(" (").next().unwrap_or(name).replace(' ', "-")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ray_count_is_read_back_from_the_summary_line() {
        // The line as `rayforge render` prints it, from the command's own summary.
        let line = rayforge_cli::summary::summary_line(
            1080,
            1080,
            std::time::Duration::from_millis(900),
            9_500_000,
            Path::new("c.png"),
        );
        let stderr = format!("progress…\n{line}\n");
        assert_eq!(rays_from_summary(&stderr), Some(9.5e6));
        assert_eq!(rays_from_summary("nothing"), None);
    }

    #[test]
    fn names_become_file_names() {
        assert_eq!(slug("dragons (bounding-boxes.yml)"), "dragons");
        assert_eq!(slug("chess board"), "chess-board");
    }
}
