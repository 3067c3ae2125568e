//! The pixel stage, one screen tile at a time: hidden surface removal with a depth buffer on
//! 1/z (the book's "Hidden surface removal": 1/z is linear on the screen, z is not), then each
//! pixel shaded once for the triangle it sees. Tiles in a row of tiles share a band of the
//! canvas, and bands are drawn in parallel.

use super::bin::{Tiles, TILE_HEIGHT, TILE_WIDTH};
use super::edge::{Coverage, PixelRect};
use super::lanes::Run;
use super::line::line_pixels_in;
use super::shade::{Face, ShadeContext};
use crate::color::Color;
use glam::IVec2;

/// No triangle covers the pixel.
const NONE: u32 = u32::MAX;

/// What a pixel sees: a chunk and an entry of that chunk's bin for this tile.
#[derive(Debug, Clone, Copy)]
struct Seen {
    chunk: u32,
    entry: u32,
}

/// Scratch buffers of one worker, reused from tile to tile.
pub(crate) struct TileBuffers {
    depth: Vec<f64>,
    seen: Vec<Seen>,
    cache: Vec<(u32, u32, Face)>,
    run: Run,
}

/// Faces remembered per tile: a pixel's neighbours mostly show the same triangle.
const CACHE: usize = 64;
// A run of pixels marks the slots it reads in a 64-bit mask (`Run::uses_slot`).
const _: () = assert!(CACHE <= 64);

impl TileBuffers {
    pub fn new() -> Self {
        Self {
            depth: vec![0.0; TILE_WIDTH * TILE_HEIGHT],
            seen: vec![
                Seen {
                    chunk: NONE,
                    entry: NONE
                };
                TILE_WIDTH * TILE_HEIGHT
            ],
            cache: vec![(NONE, NONE, Face::default()); CACHE],
            run: Run::new(),
        }
    }
}

/// Draws tile (`column`, `row`) into `band`, the canvas rows of its row of tiles.
pub(crate) fn draw_tile(
    ctx: &ShadeContext<'_, '_>,
    tiles: &Tiles,
    column: usize,
    row: usize,
    band: &mut [Color],
    background: Color,
    buffers: &mut TileBuffers,
) {
    let rect = tiles.rect(column, row);
    let tile = row * tiles.columns + column;
    let (x0, y0) = (rect.x0, rect.y0);
    let local = |x: i64, y: i64| (y - y0) as usize * TILE_WIDTH + (x - x0) as usize;
    buffers.depth.fill(0.0);
    buffers.seen.fill(Seen {
        chunk: NONE,
        entry: NONE,
    });
    for (chunk_index, chunk) in ctx.chunks.iter().enumerate() {
        for (entry_index, entry) in chunk.bins[tile].iter().enumerate() {
            let (screen, inv_z) = ctx.screen_triangle(chunk, entry.instance, entry.prim);
            let Some(coverage) = Coverage::new(screen, ctx.bits) else {
                continue;
            };
            let area = coverage.area2() as f64;
            let (depth, seen) = (&mut buffers.depth, &mut buffers.seen);
            coverage.for_each_pixel(rect, |x, y, w| {
                let z = (w[0] as f64 * inv_z[0] + w[1] as f64 * inv_z[1] + w[2] as f64 * inv_z[2])
                    / area;
                let i = local(x, y);
                // Nearer is larger 1/z; on a tie the triangle drawn first stays.
                if z > depth[i] {
                    depth[i] = z;
                    seen[i] = Seen {
                        chunk: chunk_index as u32,
                        entry: entry_index as u32,
                    };
                }
            });
        }
    }
    for entry in &mut buffers.cache {
        entry.0 = NONE;
    }
    let width = tiles.width;
    let eye = ctx.projection.eye();
    let run = &mut buffers.run;
    // Half-open ranges, as in `Coverage::for_each_pixel`.
    for y in rect.y0..rect.y1 + 1 {
        for x in rect.x0..rect.x1 + 1 {
            let seen = buffers.seen[local(x, y)];
            let output = (y - y0) as usize * width + x as usize;
            if seen.chunk == NONE {
                band[output] = background;
                continue;
            }
            let slot = (seen.entry as usize ^ (seen.chunk as usize).wrapping_mul(7)) % CACHE;
            let cache = &mut buffers.cache;
            if (cache[slot].0, cache[slot].1) != (seen.chunk, seen.entry) {
                if run.uses_slot(slot) {
                    run.flush(&ctx.runs, eye, cache, band);
                }
                let chunk = &ctx.chunks[seen.chunk as usize];
                let entry = chunk.bins[tile][seen.entry as usize];
                let cached = &mut cache[slot];
                ctx.fill_face(&mut cached.2, chunk, entry.instance, entry.prim);
                (cached.0, cached.1) = (seen.chunk, seen.entry);
            }
            let face = &cache[slot].2;
            // Pixels whose lighting can go into runs are shaded a run at a time.
            if ctx.runs.material(face.instance).is_some() {
                if !run.accepts(face.instance) {
                    run.flush(&ctx.runs, eye, cache, band);
                }
                run.push(face, slot, x, y, output);
            } else {
                band[output] = ctx.shade(face, x, y);
            }
        }
    }
    run.flush(&ctx.runs, eye, &buffers.cache, band);
}

/// Draws the edges of every triangle binned to tile (`column`, `row`), in its material's
/// colour, over the background: the book's wireframe, hidden edges included. Each tile draws
/// the part of each line inside it, pixel for pixel what the whole line would set there.
pub(crate) fn draw_wireframe_tile(
    ctx: &ShadeContext<'_, '_>,
    tiles: &Tiles,
    column: usize,
    row: usize,
    band: &mut [Color],
    background: Color,
) {
    let rect: PixelRect = tiles.rect(column, row);
    let tile = row * tiles.columns + column;
    let width = tiles.width;
    for y in rect.y0..=rect.y1 {
        let start = (y - rect.y0) as usize * width;
        band[start + rect.x0 as usize..=start + rect.x1 as usize].fill(background);
    }
    let shift = ctx.bits;
    for chunk in ctx.chunks {
        for entry in &chunk.bins[tile] {
            let (screen, _) = ctx.screen_triangle(chunk, entry.instance, entry.prim);
            let colour = ctx.instances[entry.instance as usize]
                .surface
                .material
                .color;
            // The pixel each corner falls in.
            let p = screen.map(|s| IVec2::new((s.x >> shift) as i32, (s.y >> shift) as i32));
            for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
                line_pixels_in(a, b, Some((rect.x0, rect.y0, rect.x1, rect.y1)), |x, y| {
                    if (rect.x0..=rect.x1).contains(&x) && (rect.y0..=rect.y1).contains(&y) {
                        band[(y - rect.y0) as usize * width + x as usize] = colour;
                    }
                });
            }
        }
    }
}
