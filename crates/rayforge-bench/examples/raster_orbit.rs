//! Frames per second of the rasterizer while the camera orbits a scene, the figure the live
//! preview (`rayforge serve`) depends on when a user drags the view:
//!
//! ```sh
//! cargo run --release -p rayforge-bench --example raster_orbit -- \
//!     [SCENE] [WIDTH] [HEIGHT] [FRAMES]
//! ```
//!
//! Defaults: the book's cover (`scenes/trtc/cover.yml`) at 640×360, 360 frames, one degree of
//! yaw about the point the camera looks at per frame (a full turn). Each frame is drawn by one
//! [`Rasterizer`] that keeps its buffers, as the preview does, developed, and turned into the
//! 8-bit RGB any display takes. Prints the mean and the slowest frame; the scene's own raster
//! options (`world: raster:`) are used when it gives them.

use rayforge::raster::Rasterizer;
use std::path::PathBuf;
use std::time::{Duration, Instant};

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(
        args.next()
            .unwrap_or_else(|| "scenes/trtc/cover.yml".into()),
    );
    let mut number = |default: usize| {
        args.next()
            .and_then(|v| v.parse::<usize>().ok())
            .unwrap_or(default)
    };
    let (width, height, frames) = (number(640), number(360), number(360).max(1));
    let scene = match rayforge_scene::load_file(&path) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let Some(look_at) = scene.look_at else {
        eprintln!(
            "{}: the camera is not placed by from, to and up; nothing to orbit",
            path.display()
        );
        std::process::exit(2);
    };
    let camera = scene.camera.resized(width, height);
    let options = scene.raster.unwrap_or_default();
    let up = look_at.up.normalize();
    let mut rasterizer = Rasterizer::new();
    let mut slowest = Duration::ZERO;
    let mut bytes = 0usize;
    let started = Instant::now();
    for frame in 0..frames {
        let turn = glam::DQuat::from_axis_angle(up, (frame as f64).to_radians());
        let Some(view) = camera.turned_about(look_at.to, turn) else {
            eprintln!("frame {frame}: the turned camera cannot be inverted");
            std::process::exit(2);
        };
        let begun = Instant::now();
        match rasterizer.render(&view, &scene.world, &options) {
            Ok((image, _)) => bytes += image.to_rgb8().len(),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        }
        slowest = slowest.max(begun.elapsed());
    }
    let mean = started.elapsed() / frames as u32;
    println!(
        "{}: {width}×{height}, {frames} frames orbiting: {:.1} frames per second \
         (mean {:.2} ms, slowest {:.2} ms; {} MB of pixels shown)",
        path.display(),
        1.0 / mean.as_secs_f64(),
        mean.as_secs_f64() * 1e3,
        slowest.as_secs_f64() * 1e3,
        bytes / 1_000_000
    );
}
