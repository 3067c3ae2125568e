//! The rasterizer against Mesa's llvmpipe, the standard software OpenGL rasterizer, and the
//! rasterizer's frames per second while orbiting the cover (the live preview's figure).
//!
//! The frame is `crates/rayforge/benches/support/height_field.rs`'s: 1 002 528 triangles at
//! 1920×1080, a depth buffer, per-pixel Phong under two point lights, no culling. The peer is
//! `bench/peers/llvmpipe/frame.c` (built by `bench/peers/setup.sh` as `llvmpipe_frame` where
//! OSMesa is installed), which uploads the mesh once and times clear, draw and `glFinish` per
//! frame, printing the mean. rayforge draws the same frames in this process with one
//! [`Rasterizer`], as an animation keeps one, on the benchmark's threads. The two take turns,
//! `--repeat` rounds of [`FRAMES`] frames each; the best round's mean counts on each side.
//! Both means include the first frame (llvmpipe's compiles its shaders).

use super::peers::Peer;
use super::report::{Check, Report, Table};
use super::Bench;
use rayforge::raster::{RasterOptions, Rasterizer};
use rayforge_cli::failure::Failure;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

#[path = "../../rayforge/benches/support/height_field.rs"]
mod height_field;

/// Frames per round on each side.
const FRAMES: u32 = 10;

/// rayforge's frame rate as a share of llvmpipe's that the issue asks for: at least as fast.
const TARGET: f64 = 1.0;

/// The orbit: the cover at the live preview's size, one degree of yaw a frame, a full turn.
const ORBIT_SCENE: &str = "scenes/trtc/cover.yml";
const ORBIT_SIZE: (usize, usize) = (640, 360);
const ORBIT_FRAMES: u32 = 360;

/// Runs the llvmpipe comparison and the orbit.
pub fn run(bench: &Bench, report: &mut Report) -> Result<(), Failure> {
    let rounds = bench.settings.repeat;
    let mut table = Table::new(
        format!(
            "The rasterizer against llvmpipe (1 M triangles, 1920×1080, Phong, {} threads, \
             mean of {FRAMES} frames, best of {rounds} rounds in turn)",
            bench.settings.threads
        ),
        &[
            "frame",
            "rayforge",
            "llvmpipe",
            "ratio (llvmpipe / rayforge)",
            "pixels within 2/255",
            "target",
        ],
    );
    let target = format!("≥ {TARGET:.2}× (as fast)");
    let what = "rasterizer, 1 M triangles at 1920×1080, vs llvmpipe".to_string();
    let dir = bench.out("raster");
    std::fs::create_dir_all(&dir).map_err(|e| bench.write_error(&dir, e))?;
    let peer = bench.peers.llvmpipe.clone();
    let skipped = if bench.settings.quick {
        Some("--quick (the peer's frame has a fixed size)".to_string())
    } else {
        peer.is_none().then(|| Peer::Llvmpipe.skipped_hint())
    };
    match (&peer, skipped) {
        (Some(peer), None) => {
            bench.progress("the height field's frame with llvmpipe and rayforge, in turn");
            let (camera, world) = height_field::scene();
            let options = RasterOptions::default();
            let mut rasterizer = Rasterizer::new();
            let (mut ours, mut theirs) = (f64::INFINITY, f64::INFINITY);
            for _ in 0..rounds {
                theirs = theirs.min(llvmpipe_mean(peer, &dir, bench.settings.threads)?);
                let started = Instant::now();
                for _ in 0..FRAMES {
                    bench
                        .pool
                        .install(|| {
                            rasterizer
                                .render(&camera, &world, &options, None)
                                .map(|_| ())
                        })
                        .map_err(|e| Failure::internal(e.to_string()))?;
                }
                ours = ours.min(started.elapsed().as_secs_f64() * 1e3 / f64::from(FRAMES));
            }
            let agreement = agreement(&rasterizer.canvas().to_rgb8(), &dir)?;
            let ratio = theirs / ours;
            table.row(vec![
                "height field, Phong".into(),
                format!("{ours:.1} ms"),
                format!("{theirs:.1} ms"),
                format!("{ratio:.2}×"),
                format!(
                    "{:.4} % ({} of {} outside)",
                    100.0 * agreement.0 as f64 / agreement.1.max(1) as f64,
                    agreement.1 - agreement.0,
                    agreement.1
                ),
                target.clone(),
            ]);
            report.check(Check {
                what,
                measured: format!("{ratio:.2}× llvmpipe's speed"),
                target,
                met: Some(ratio >= TARGET),
            });
        }
        (_, skipped) => {
            let why = skipped.unwrap_or_default();
            table.note(format!("llvmpipe was skipped: {why}."));
            report.check(Check {
                what,
                measured: "not run".into(),
                target,
                met: None,
            });
        }
    }
    report.table(&table);
    orbit(bench, report)
}

/// One round of the peer: its mean frame in milliseconds, from the line it prints.
fn llvmpipe_mean(peer: &Path, dir: &Path, threads: usize) -> Result<f64, Failure> {
    let output = Command::new(peer)
        .arg(FRAMES.to_string())
        .env("LP_NUM_THREADS", threads.to_string())
        .current_dir(dir)
        .output()
        .map_err(|e| Failure::internal(format!("cannot run `{}`: {e}", peer.display())))?;
    let text = String::from_utf8_lossy(&output.stdout);
    let mean = text.lines().find_map(|line| {
        line.split_once(", mean ")?
            .1
            .split_once(" ms")?
            .0
            .parse()
            .ok()
    });
    match (output.status.success(), mean) {
        (true, Some(mean)) => Ok(mean),
        _ => Err(Failure::internal(format!(
            "`{}` printed no mean frame: {}{}",
            peer.display(),
            text.trim(),
            String::from_utf8_lossy(&output.stderr).trim()
        ))),
    }
}

/// How many pixels, of how many, have every channel within 2/255 of the peer's last frame
/// (`llvmpipe_frame.ppm`, binary P6 with a plain header, top row first).
fn agreement(ours: &[u8], dir: &Path) -> Result<(usize, usize), Failure> {
    let path = dir.join("llvmpipe_frame.ppm");
    let bytes = std::fs::read(&path)
        .map_err(|e| Failure::internal(format!("cannot read `{}`: {e}", path.display())))?;
    // The header is "P6\n1920 1080\n255\n": three lines before the pixels.
    let mut newlines = 0;
    let start = bytes
        .iter()
        .position(|&b| {
            newlines += usize::from(b == b'\n');
            newlines == 3
        })
        .map_or(bytes.len(), |i| i + 1);
    let theirs = &bytes[start..];
    if theirs.len() != ours.len() {
        return Err(Failure::internal(format!(
            "`{}` holds {} bytes of pixels, rayforge's frame {}",
            path.display(),
            theirs.len(),
            ours.len()
        )));
    }
    let close = ours
        .chunks_exact(3)
        .zip(theirs.chunks_exact(3))
        .filter(|(a, b)| a.iter().zip(*b).all(|(x, y)| x.abs_diff(*y) <= 2))
        .count();
    Ok((close, ours.len() / 3))
}

/// The cover orbiting at 640×360 with one rasterizer: frames per second, no peer.
fn orbit(bench: &Bench, report: &mut Report) -> Result<(), Failure> {
    let ((width, height), frames) = if bench.settings.quick {
        ((64, 36), 12)
    } else {
        (ORBIT_SIZE, ORBIT_FRAMES)
    };
    let mut table = Table::new(
        format!(
            "The rasterizer orbiting the cover ({width}×{height}, {frames} frames, {} threads)",
            bench.settings.threads
        ),
        &["scene", "frames per second", "mean frame", "slowest frame"],
    );
    let scene = rayforge_scene::load_file(Path::new(ORBIT_SCENE))
        .map_err(|e| Failure::usage(e.to_string()))?;
    let Some(look_at) = scene.look_at else {
        return Err(Failure::internal(format!(
            "{ORBIT_SCENE}: the camera is not placed by from, to and up"
        )));
    };
    bench.progress("the cover orbiting at 640×360");
    let camera = scene.camera.resized(width, height);
    let options = scene.raster.unwrap_or_default();
    let up = look_at.up.normalize();
    let mut rasterizer = Rasterizer::new();
    let mut slowest = 0.0f64;
    let started = Instant::now();
    for frame in 0..frames {
        let turn = glam::DQuat::from_axis_angle(up, f64::from(frame).to_radians());
        let view = camera
            .turned_about(look_at.to, turn)
            .ok_or_else(|| Failure::internal("the turned camera cannot be inverted"))?;
        let begun = Instant::now();
        bench
            .pool
            .install(|| {
                rasterizer
                    .render(&view, &scene.world, &options, None)
                    .map(|(image, _)| image.to_rgb8().len())
            })
            .map_err(|e| Failure::internal(e.to_string()))?;
        slowest = slowest.max(begun.elapsed().as_secs_f64());
    }
    let mean = started.elapsed().as_secs_f64() / f64::from(frames);
    table.row(vec![
        ORBIT_SCENE.into(),
        format!("{:.1}", 1.0 / mean),
        format!("{:.2} ms", mean * 1e3),
        format!("{:.2} ms", slowest * 1e3),
    ]);
    table.note(
        "Each frame is drawn by one Rasterizer that keeps its buffers (as `rayforge serve` \
         keeps one per page), developed and converted to 8-bit RGB; the camera turns one degree \
         a frame about the point it looks at.",
    );
    report.table(&table);
    Ok(())
}
