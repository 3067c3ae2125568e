//! The rasterizer's entry point: a world through a camera into a film, and developed.

use super::bin::{bin_all, BinContext, Tiles, TILE_HEIGHT};
use super::edge::subpixel_bits;
use super::instance::instances;
use super::shade::{raster_lights, ShadeContext};
use super::surface::build_mips;
use super::tile::{draw_tile, draw_wireframe_tile, TileBuffers};
use super::vertex::transform_vertices;
use super::Projection;
use crate::camera::Camera;
use crate::canvas::Canvas;
use crate::film::{develop, Exposure, Film};
use crate::options::RasterOptions;
use crate::scene::{LightingModel, World};
use rayon::prelude::*;

/// What a raster render did, for tests and summaries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RasterStats {
    /// Objects (CSG primitives counted one by one) drawn, after whole-object rejection.
    pub instances: u64,
    /// Triangles of those objects considered.
    pub triangles: u64,
    /// Triangles that crossed a clipping plane and were split.
    pub clipped: u64,
    /// Triangles (or pieces) skipped because they face away from the camera.
    pub culled: u64,
    /// Triangles (or pieces) handed to the tiles.
    pub drawn: u64,
}

/// Why a raster render was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RasterError {
    /// The scene's objects, tessellated, would have more triangles than
    /// [`RasterOptions::max_triangles`] (checked before they are made).
    #[error(
        "the scene's objects, tessellated at this sphere resolution, have more than {limit} \
         triangles; lower --sphere-divisions (or the scene's `sphere-divisions`) or raise \
         --max-raster-triangles"
    )]
    TooManyTriangles {
        /// The limit.
        limit: u64,
    },
    /// The camera is orthographic (a glTF file's); the rasterizer projects through a pinhole,
    /// its depth and interpolation by `1/z`.
    #[error(
        "the camera is orthographic, and the rasterizer draws through perspective cameras \
         only; render it with --renderer ray or --renderer path, or pick a perspective camera \
         with --camera"
    )]
    Orthographic,
}

/// Rasterizes `world` through `camera` on the current rayon thread pool, developed.
pub fn render(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
) -> Result<Canvas, RasterError> {
    Ok(render_with_stats(camera, world, options)?.0)
}

/// [`render`], with counts of what was drawn.
pub fn render_with_stats(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
) -> Result<(Canvas, RasterStats), RasterError> {
    let (film, stats) = render_film(camera, world, options)?;
    // The optics model's automatic exposure, as the ray tracer's film gets it: the image
    // divided by its brightest channel (one sample per pixel: the brightest pixel).
    let exposure = match world.lighting {
        LightingModel::Optics => Exposure::Automatic,
        _ => Exposure::Fixed,
    };
    Ok((develop(&film, exposure), stats))
}

/// Rasterizes `world` through `camera` into a film, with counts of what was drawn. Every pixel
/// is one sample of weight 1 (the colour its nearest triangle shades it), under the box
/// filter: the tiles draw finished colours, which the film takes as they are.
pub fn render_film(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
) -> Result<(Film, RasterStats), RasterError> {
    if camera.is_orthographic() {
        return Err(RasterError::Orthographic);
    }
    let (width, height) = (camera.hsize(), camera.vsize());
    let mut canvas = Canvas::new(width, height);
    if width == 0 || height == 0 {
        return Ok((Film::from_canvas(&canvas), RasterStats::default()));
    }
    let projection = Projection::new(camera, options.near);
    let bits = subpixel_bits(width, height);
    let divisions = options.sphere_divisions.max(3);
    let instances = instances(
        world,
        &projection,
        divisions,
        options.backface_culling,
        options.max_triangles,
    )?;
    let (vertices, normals) = transform_vertices(&instances, &projection, bits);
    let tiles = Tiles::new(width, height);
    let chunks = bin_all(&BinContext {
        instances: &instances,
        vertices: &vertices,
        projection: &projection,
        tiles,
        bits,
    });
    let mut stats = RasterStats {
        instances: instances.len() as u64,
        ..RasterStats::default()
    };
    for chunk in &chunks {
        stats.triangles += chunk.counts.faces;
        stats.clipped += chunk.counts.clipped;
        stats.culled += chunk.counts.culled;
        stats.drawn += chunk.counts.binned;
    }
    let mut ctx = ShadeContext {
        instances: &instances,
        vertices: &vertices,
        normals: &normals,
        chunks: &chunks,
        projection: &projection,
        lights: raster_lights(&world.lights),
        lighting: world.lighting,
        mips: if options.wireframe {
            Default::default()
        } else {
            build_mips(&instances)
        },
        shading: options.shading,
        filter: options.filter,
        bits,
        vertex_light: Vec::new(),
    };
    if options.shading == crate::options::Shading::Gouraud && !options.wireframe {
        ctx.light_vertices();
    }
    let background = world.background;
    canvas
        .pixels_mut()
        .par_chunks_mut(width * TILE_HEIGHT)
        .enumerate()
        .for_each_init(TileBuffers::new, |buffers, (row, band)| {
            for column in 0..tiles.columns {
                if options.wireframe {
                    draw_wireframe_tile(&ctx, &tiles, column, row, band, background);
                } else {
                    draw_tile(&ctx, &tiles, column, row, band, background, buffers);
                }
            }
        });
    Ok((Film::from_canvas(&canvas), stats))
}
