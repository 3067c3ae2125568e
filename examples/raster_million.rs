//! Times the rasterizer on the benchmark's million-triangle height field at 1920×1080 and
//! writes the last frame as `raster_million.ppm`:
//!
//! ```sh
//! cargo run --release -p rayforge --example raster_million -- [flat|gouraud|phong] [FRAMES]
//! ```
//!
//! With `FRAMES` 0 it only builds the scene, so `/usr/bin/time` of a run with N frames less
//! one with 0 is the CPU time of N frames (docs/performance.md).

#[path = "../crates/rayforge/benches/support/height_field.rs"]
mod height_field;

use rayforge::raster::{self, RasterOptions, Shading};

fn main() {
    let (camera, world) = height_field::scene();
    let mode = std::env::args().nth(1).unwrap_or_else(|| "phong".into());
    let frames: u32 = std::env::args()
        .nth(2)
        .and_then(|v| v.parse().ok())
        .unwrap_or(10);
    let shading = match mode.as_str() {
        "flat" => Shading::Flat,
        "gouraud" => Shading::Gouraud,
        _ => Shading::Phong,
    };
    let options = RasterOptions {
        shading,
        ..RasterOptions::default()
    };
    // One rasterizer for every frame, as an animation or the live preview keeps one: its
    // image, vertices and tile lists are reused, not allocated again per frame.
    let mut rasterizer = raster::Rasterizer::new();
    let started = std::time::Instant::now();
    let mut stats = None;
    for _ in 0..frames {
        match rasterizer.render(&camera, &world, &options, None) {
            Ok((_, counts)) => stats = Some(counts),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        }
    }
    if let Some(stats) = stats {
        let canvas = rasterizer.canvas();
        eprintln!(
            "{mode}: {:?} per frame, {stats:?}",
            started.elapsed() / frames
        );
        if let Err(e) = std::fs::write("raster_million.ppm", canvas.to_ppm()) {
            eprintln!("cannot write raster_million.ppm: {e}");
        }
    }
}
