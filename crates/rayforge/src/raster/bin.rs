//! The triangle stage: each triangle is clipped against the planes its instance's bounding
//! sphere crosses, culled when it faces away, and recorded in every screen tile its bounding
//! box touches.
//!
//! Triangles are taken in chunks of a fixed size, in parallel; each chunk keeps its own bins,
//! and a tile reads the chunks in order. So a tile sees its triangles in scene order whatever
//! the number of threads, and ties in the depth buffer resolve the same way every time.

use super::clip::{clip_triangle, ClipVertex};
use super::edge::{orient, pixel_bounds, FixedPoint, PixelRect};
use super::instance::Instance;
use super::vertex::{to_screen, ViewVertex};
use super::Projection;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Tile width in pixels.
pub(crate) const TILE_WIDTH: usize = 64;
/// Tile height in pixels.
pub(crate) const TILE_HEIGHT: usize = 32;
/// Triangles per chunk (of one object or several).
const CHUNK: usize = 32 * 1024;
/// Marks a bin entry that names a clipped piece rather than a face.
pub(crate) const CLIPPED: u32 = 1 << 31;

/// The grid of tiles over the image.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tiles {
    pub columns: usize,
    pub rows: usize,
    pub width: usize,
    pub height: usize,
}

impl Tiles {
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            columns: width.div_ceil(TILE_WIDTH),
            rows: height.div_ceil(TILE_HEIGHT),
            width,
            height,
        }
    }

    pub fn count(&self) -> usize {
        self.columns * self.rows
    }

    /// The pixels of tile (`column`, `row`).
    pub fn rect(&self, column: usize, row: usize) -> PixelRect {
        let (x0, y0) = (column * TILE_WIDTH, row * TILE_HEIGHT);
        PixelRect {
            x0: x0 as i64,
            y0: y0 as i64,
            x1: ((x0 + TILE_WIDTH).min(self.width) - 1) as i64,
            y1: ((y0 + TILE_HEIGHT).min(self.height) - 1) as i64,
        }
    }
}

/// A triangle in a tile's list: an instance and one of its faces, or (with [`CLIPPED`] set) a
/// piece in the chunk's list of clipped triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct BinEntry {
    pub instance: u32,
    pub prim: u32,
}

/// A piece of a clipped face: its own screen corners and, for each corner, its barycentric
/// weights on the original face (how its attributes are found).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClippedPiece {
    pub face: u32,
    pub screen: [FixedPoint; 3],
    pub inv_z: [f64; 3],
    pub weights: [[f64; 3]; 3],
}

/// What a chunk of triangles produced.
#[derive(Debug, Default)]
pub(crate) struct Chunk {
    /// Per tile, the triangles touching it, in order.
    pub bins: Vec<Vec<BinEntry>>,
    /// The pieces of faces that crossed a clipping plane.
    pub clipped: Vec<ClippedPiece>,
    pub counts: Counts,
}

impl Chunk {
    /// Empties the chunk for a new frame of `tiles` tiles, keeping its lists' memory.
    fn clear(&mut self, tiles: usize) {
        self.bins.resize_with(tiles, Vec::new);
        for bin in &mut self.bins {
            bin.clear();
        }
        self.clipped.clear();
        self.counts = Counts::default();
    }
}

/// Triangle counts, summed over chunks for [`RasterStats`](super::RasterStats).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Counts {
    pub faces: u64,
    pub culled: u64,
    pub clipped: u64,
    pub binned: u64,
}

/// A vertex as the clipper sees it: view position and weights on the original face.
#[derive(Debug, Clone, Copy)]
struct PieceVertex {
    view: DVec3,
    weights: [f64; 3],
}

impl ClipVertex for PieceVertex {
    fn position(&self) -> DVec3 {
        self.view
    }
    fn lerp(&self, other: &Self, t: f64) -> Self {
        let w = |i: usize| self.weights[i] + (other.weights[i] - self.weights[i]) * t;
        Self {
            view: self.view + (other.view - self.view) * t,
            weights: [w(0), w(1), w(2)],
        }
    }
}

/// Shared, read-only state of the triangle stage.
pub(crate) struct BinContext<'a, 'w> {
    pub instances: &'a [Instance<'w>],
    pub vertices: &'a [ViewVertex],
    /// Per vertex, the planes of its instance's list that it lies outside of, one bit each.
    pub outside: &'a [u8],
    pub projection: &'a Projection,
    pub tiles: Tiles,
    pub bits: u32,
}

/// Bins every triangle of every instance into `chunks`, one per chunk of faces. The chunks'
/// lists keep their memory from the last frame (a rasterizer keeps them), so a frame of the
/// same scene does not grow thousands of lists again. `cancel` is looked at before each chunk
/// of [`CHUNK`] faces: once it is set no chunk is begun (a frame of millions of triangles
/// stops within one chunk), and the chunks not begun are left empty or as the last frame
/// left them, for the caller to refuse the frame.
pub(crate) fn bin_all(
    ctx: &BinContext<'_, '_>,
    chunks: &mut Vec<Chunk>,
    cancel: Option<&AtomicBool>,
) {
    // Chunks of CHUNK faces in scene order; a chunk may hold the faces of many small objects
    // (a chunk's bins cost memory per tile, so there must not be one per object).
    let mut jobs: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new()];
    let mut filled = 0;
    for (index, instance) in ctx.instances.iter().enumerate() {
        let faces = instance.model.mesh.faces.len();
        let mut start = 0;
        while start < faces {
            if filled == CHUNK {
                jobs.push(Vec::new());
                filled = 0;
            }
            let end = faces.min(start + CHUNK - filled);
            if let Some(job) = jobs.last_mut() {
                job.push((index, start, end));
            }
            filled += end - start;
            start = end;
        }
    }
    chunks.resize_with(jobs.len(), Chunk::default);
    chunks
        .par_iter_mut()
        .zip(jobs)
        .for_each(|(chunk, segments)| {
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return;
            }
            chunk.clear(ctx.tiles.count());
            for (index, start, end) in segments {
                bin_faces(ctx, chunk, index, start, end);
            }
        });
}

/// Bins faces `start..end` of instance `index` into `chunk`.
fn bin_faces(ctx: &BinContext<'_, '_>, chunk: &mut Chunk, index: usize, start: usize, end: usize) {
    let instance = &ctx.instances[index];
    let mesh = &instance.model.mesh;
    let vertices = &ctx.vertices[instance.vertex_base..][..mesh.positions.len()];
    let outside = &ctx.outside[instance.vertex_base..][..mesh.positions.len()];
    let planes = &instance.planes.0[..instance.planes.1];
    let image = PixelRect::image(ctx.tiles.width, ctx.tiles.height);
    for face_index in start..end {
        let face = mesh.faces.get(face_index);
        let face_index = face_index as u32;
        chunk.counts.faces += 1;
        if let Some((csg, leaf)) = instance.csg {
            let [a, b, c] = mesh.corners(&face).map(|p| instance.transform.point(p));
            if !csg.keeps_surface_point(leaf, (a + b + c) / 3.0) {
                continue;
            }
        }
        // Indexed and written out corner by corner, not with `array::map`: the binning pass
        // runs once per triangle, and `map` over the vertices compiled to a generic drain that
        // copied each vertex (a tenth of a million-triangle frame in `perf`).
        let [i0, i1, i2] = face.vertices;
        let corners = [
            &vertices[i0 as usize],
            &vertices[i1 as usize],
            &vertices[i2 as usize],
        ];
        // A triangle with every corner outside one plane is dropped; one with a corner outside
        // any plane is split (the planes' tests were made once per vertex, `vertex.rs`).
        let codes = [
            outside[i0 as usize],
            outside[i1 as usize],
            outside[i2 as usize],
        ];
        if codes[0] & codes[1] & codes[2] != 0 {
            continue;
        }
        if codes[0] | codes[1] | codes[2] != 0 {
            chunk.counts.clipped += 1;
            let tri = [0, 1, 2].map(|k| {
                let mut weights = [0.0; 3];
                weights[k] = 1.0;
                PieceVertex {
                    view: corners[k].view,
                    weights,
                }
            });
            for piece in clip_triangle(planes, tri).triangles() {
                let screen = piece.map(|v| to_screen(ctx.projection, v.view, ctx.bits));
                let entry = BinEntry {
                    instance: index as u32,
                    prim: CLIPPED | chunk.clipped.len() as u32,
                };
                if place(chunk, ctx, instance, image, screen, entry) {
                    chunk.clipped.push(ClippedPiece {
                        face: face_index,
                        screen,
                        inv_z: piece.map(|v| 1.0 / v.view.z),
                        weights: piece.map(|v| v.weights),
                    });
                }
            }
            continue;
        }
        let entry = BinEntry {
            instance: index as u32,
            prim: face_index,
        };
        place(
            chunk,
            ctx,
            instance,
            image,
            [corners[0].screen, corners[1].screen, corners[2].screen],
            entry,
        );
    }
}

/// Culls a screen triangle or records it in the tiles it touches; whether it was recorded.
#[inline]
fn place(
    chunk: &mut Chunk,
    ctx: &BinContext<'_, '_>,
    instance: &Instance<'_>,
    image: PixelRect,
    s: [FixedPoint; 3],
    entry: BinEntry,
) -> bool {
    let area = orient(s[0], s[1], s[2]);
    if area == 0 {
        return false;
    }
    if instance.cull && area.signum() != instance.front_sign {
        chunk.counts.culled += 1;
        return false;
    }
    let min = FixedPoint {
        x: s[0].x.min(s[1].x).min(s[2].x),
        y: s[0].y.min(s[1].y).min(s[2].y),
    };
    let max = FixedPoint {
        x: s[0].x.max(s[1].x).max(s[2].x),
        y: s[0].y.max(s[1].y).max(s[2].y),
    };
    let r = pixel_bounds(min, max, ctx.bits).intersect(&image);
    if r.is_empty() {
        return false;
    }
    chunk.counts.binned += 1;
    let (c0, c1) = (r.x0 as usize / TILE_WIDTH, r.x1 as usize / TILE_WIDTH);
    let (r0, r1) = (r.y0 as usize / TILE_HEIGHT, r.y1 as usize / TILE_HEIGHT);
    for row in r0..=r1 {
        for column in c0..=c1 {
            chunk.bins[row * ctx.tiles.columns + column].push(entry);
        }
    }
    true
}
