//! The rasterizer's entry point: a world through a camera into a film, and developed.

use super::bin::{bin_all, BinContext, Chunk, Tiles, TILE_HEIGHT};
use super::edge::subpixel_bits;
use super::instance::instances;
use super::lanes::PhongRuns;
use super::shade::{raster_lights, ShadeContext};
use super::surface::build_mips;
use super::tile::{draw_tile, draw_wireframe_tile, TileBuffers};
use super::vertex::{transform_vertices, ViewVertex};
use super::Projection;
use crate::camera::Camera;
use crate::canvas::Canvas;
use crate::color::Color;
use crate::film::{develop_in_place, Exposure, Film, PixelFilter, SharedFilm};
use crate::math::Vec3;
use crate::options::RasterOptions;
use crate::scene::{LightingModel, World};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

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
    /// The camera is spherical (a pbrt file's) or realistic (a lens system's, whose rays bend
    /// at every element), which no projection onto a plane draws, or its image is a screen window of its canvas (off the axis, or pixels not square),
    /// which the rasterizer's centred projection does not draw.
    #[error(
        "the camera is {0}, and the rasterizer draws through perspective cameras centred on \
         their axis only; render it with --renderer ray or --renderer path"
    )]
    Unprojected(&'static str),
    /// The render's stop flag was set (Ctrl-C, a termination signal, the page's cancel): it
    /// stopped before the next stage or tile, its image unfinished.
    #[error("the raster frame was interrupted after {tiles_drawn} of its {tiles} tiles")]
    Cancelled {
        /// Tiles drawn whole before the stop was seen.
        tiles_drawn: u64,
        /// Tiles in the frame.
        tiles: u64,
    },
    /// The film given to draw into ([`render_rows_into`]) is not the camera's size or not
    /// box-filtered: the rasterizer gives each pixel one sample of weight 1.
    #[error(
        "the rasterizer draws into a box-filtered film of the camera's size, and was given a \
         {width}×{height} film (box filter: {box_filter})"
    )]
    FilmMismatch {
        /// The film's width.
        width: usize,
        /// The film's height.
        height: usize,
        /// Whether its filter is the box.
        box_filter: bool,
    },
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
    let mut rasterizer = Rasterizer::new();
    let stats = rasterizer.render(camera, world, options, None)?.1;
    Ok((rasterizer.canvas, stats))
}

/// Rasterizes `world` through `camera` into a film, with counts of what was drawn. Every pixel
/// is one sample of weight 1 (the colour its nearest triangle shades it), under the box
/// filter: the tiles draw finished colours, which the film takes as they are. Once `cancel`
/// is set the frame stops before its next stage or tile ([`RasterError::Cancelled`]).
pub fn render_film(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
    cancel: Option<&AtomicBool>,
) -> Result<(Film, RasterStats), RasterError> {
    render_film_observed(camera, world, options, cancel, &|_| {})
}

/// [`render_film`], calling `on_band` with the number of rows of each band of tiles (32, the
/// last one fewer) once the band is drawn whole, from the thread that drew it: a caller that
/// follows the frame (the command's testing aid that waits inside a frame for an interrupt,
/// `--pause-after-rows`, so that a test stops a frame at a known point).
pub fn render_film_observed(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
    cancel: Option<&AtomicBool>,
    on_band: &(dyn Fn(usize) + Sync),
) -> Result<(Film, RasterStats), RasterError> {
    let mut rasterizer = Rasterizer::new();
    let stats = rasterizer.draw(camera, world, options, cancel, on_band)?;
    Ok((Film::from_canvas(rasterizer.canvas), stats))
}

/// A rasterizer that keeps its memory from frame to frame: the image, the projected vertices
/// and the tiles' lists of triangles. Drawing a scene again (an animation, an orbiting camera,
/// the live preview) then writes into memory it already has, where a fresh render of a
/// million triangles at 1920×1080 asks the system for and clears some 200 MB (the page
/// faults were 15 % of such a frame). It holds what its largest frame needed until dropped.
///
/// Every frame is the same image, to the bit, as [`render`] of it alone: every pixel and every
/// vertex is written anew, and the lists are emptied before they are filled.
#[derive(Default)]
pub struct Rasterizer {
    canvas: Canvas,
    scratch: Scratch,
}

/// The per-frame arrays a [`Rasterizer`] keeps.
#[derive(Default)]
struct Scratch {
    vertices: Vec<ViewVertex>,
    /// Each vertex's outcode against its instance's clipping planes (see `vertex.rs`).
    outside: Vec<u8>,
    normals: Vec<Vec3>,
    chunks: Vec<Chunk>,
}

impl Rasterizer {
    /// A rasterizer that has drawn nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Rasterizes `world` through `camera` on the current rayon thread pool and develops it
    /// (the optics model's automatic exposure, as the ray tracer's film gets it): the image,
    /// lent until the next frame, and counts of what was drawn. Once `cancel` is set the
    /// frame stops before its next stage or tile ([`RasterError::Cancelled`]).
    pub fn render(
        &mut self,
        camera: &Camera,
        world: &World,
        options: &RasterOptions,
        cancel: Option<&AtomicBool>,
    ) -> Result<(&Canvas, RasterStats), RasterError> {
        let stats = self.draw(camera, world, options, cancel, &|_| {})?;
        let exposure = match world.lighting {
            LightingModel::Optics => Exposure::Automatic,
            _ => Exposure::Fixed,
        };
        develop_in_place(&mut self.canvas, exposure);
        Ok((&self.canvas, stats))
    }

    /// The last frame's image, developed (empty before the first frame).
    pub fn canvas(&self) -> &Canvas {
        &self.canvas
    }

    /// Draws the frame into the rasterizer's canvas, every pixel one sample of weight 1, not
    /// yet developed; `on_band` told the rows of each band drawn whole.
    fn draw(
        &mut self,
        camera: &Camera,
        world: &World,
        options: &RasterOptions,
        cancel: Option<&AtomicBool>,
        on_band: &(dyn Fn(usize) + Sync),
    ) -> Result<RasterStats, RasterError> {
        check_camera(camera)?;
        let (width, height) = (camera.hsize(), camera.vsize());
        if (self.canvas.width(), self.canvas.height()) != (width, height) {
            // Every pixel is drawn below, so a canvas of the same size is not cleared.
            self.canvas = Canvas::new(width, height);
        }
        if width == 0 || height == 0 {
            return Ok(RasterStats::default());
        }
        let canvas = &mut self.canvas;
        with_frame(camera, world, options, cancel, &mut self.scratch, |frame| {
            canvas
                .pixels_mut()
                .par_chunks_mut(width * TILE_HEIGHT)
                .enumerate()
                .for_each_init(TileBuffers::new, |buffers, (row, band)| {
                    if frame.draw_band(row, band, buffers) {
                        on_band(band.len() / width);
                    }
                });
        })
    }
}

/// Rasterizes `world` through `camera` into the rows `film` holds (a slice's, see
/// [`SharedFilm::with_rows`]), each pixel one sample of weight 1 as in [`render_film`], to the
/// bit. The triangles are binned into the tiles of the whole frame, as for a whole render, but
/// only the bands of tiles that hold one of the film's rows are drawn, each into a band of
/// pixels of its thread's own (`width` × 32 colours) from which the film's rows are kept: no
/// canvas of the whole image is made. Refused when `film` is not the camera's size or not
/// box-filtered. Once `cancel` is set the frame stops before its next stage or tile
/// ([`RasterError::Cancelled`]; the film then holds some of the rows).
pub fn render_rows_into(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
    film: &SharedFilm,
    cancel: Option<&AtomicBool>,
) -> Result<RasterStats, RasterError> {
    check_camera(camera)?;
    let (width, height) = (camera.hsize(), camera.vsize());
    if (film.width(), film.height()) != (width, height) || film.filter() != PixelFilter::Box {
        return Err(RasterError::FilmMismatch {
            width: film.width(),
            height: film.height(),
            box_filter: film.filter() == PixelFilter::Box,
        });
    }
    if width == 0 || height == 0 {
        return Ok(RasterStats::default());
    }
    let rows_of = |band: usize| band * TILE_HEIGHT..((band + 1) * TILE_HEIGHT).min(height);
    let bands: Vec<usize> = (0..height.div_ceil(TILE_HEIGHT))
        .filter(|&band| rows_of(band).any(|y| film.holds_row(y)))
        .collect();
    with_frame(
        camera,
        world,
        options,
        cancel,
        &mut Scratch::default(),
        |frame| {
            bands.into_par_iter().for_each_init(
                || (TileBuffers::new(), vec![Color::BLACK; width * TILE_HEIGHT]),
                |(buffers, pixels), band| {
                    if !frame.draw_band(band, pixels, buffers) {
                        // Stopped inside the band: its rows are not all drawn, and none is kept.
                        return;
                    }
                    for (y, row) in rows_of(band).zip(pixels.chunks_exact(width)) {
                        if !film.holds_row(y) {
                            continue;
                        }
                        let mut part = Film::new(width, 1);
                        for (x, &pixel) in row.iter().enumerate() {
                            part.add_pixel(x, 0, pixel, 1.0);
                        }
                        // A held row, the film's width, the box filter: checked above.
                        let added = film.add(y, &part);
                        debug_assert!(added.is_ok(), "{added:?}");
                    }
                },
            );
        },
    )
}

/// Whether the rasterizer can draw through `camera`: a pinhole centred on its axis.
fn check_camera(camera: &Camera) -> Result<(), RasterError> {
    if camera.is_orthographic() {
        return Err(RasterError::Orthographic);
    }
    if camera.spherical_mapping().is_some() {
        return Err(RasterError::Unprojected("spherical"));
    }
    if camera.lens_system().is_some() {
        return Err(RasterError::Unprojected(
            "realistic (a lens system traced element by element)",
        ));
    }
    if camera.screen_window().is_some() {
        return Err(RasterError::Unprojected("given a screen window"));
    }
    Ok(())
}

/// A frame ready to draw: the world's triangles projected and binned into the tiles of the
/// camera's whole image, with what shading them needs.
struct Frame<'a> {
    ctx: &'a ShadeContext<'a, 'a>,
    tiles: Tiles,
    background: Color,
    wireframe: bool,
    /// The stop flag, looked at before each tile: a tile of a frame of millions of triangles
    /// may take a while, a load of a flag next to nothing.
    cancel: Option<&'a AtomicBool>,
    /// Tiles drawn whole so far, all threads together (what a stopped frame reports).
    drawn: AtomicU64,
    /// The camera, whose sensor records each drawn colour.
    camera: &'a Camera,
}

impl Frame<'_> {
    /// Whether the stop flag is set.
    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// Draws every tile of band `row` (the image's rows `row · 32` on) into `band`, rows of the
    /// image's width: every pixel of the band's rows is written. `false` when the stop flag
    /// cut it short (some of its tiles are then not drawn).
    fn draw_band(&self, row: usize, band: &mut [Color], buffers: &mut TileBuffers) -> bool {
        for column in 0..self.tiles.columns {
            if self.cancelled() {
                return false;
            }
            if self.wireframe {
                draw_wireframe_tile(self.ctx, &self.tiles, column, row, band, self.background);
            } else {
                draw_tile(
                    self.ctx,
                    &self.tiles,
                    column,
                    row,
                    band,
                    self.background,
                    buffers,
                );
            }
            self.drawn.fetch_add(1, Ordering::Relaxed);
        }
        if !self.camera.sensor().is_identity() {
            for pixel in band.iter_mut() {
                *pixel = self.camera.record(*pixel);
            }
        }
        true
    }
}

/// Prepares `world`'s frame through `camera` (of at least one pixel, perspective) in
/// `scratch`'s arrays and hands it to `draw`, with counts of what was binned; once `cancel` is
/// set, stops before the next stage (or, in `draw`, the next tile) with
/// [`RasterError::Cancelled`].
fn with_frame(
    camera: &Camera,
    world: &World,
    options: &RasterOptions,
    cancel: Option<&AtomicBool>,
    scratch: &mut Scratch,
    draw: impl FnOnce(&Frame<'_>),
) -> Result<RasterStats, RasterError> {
    let (width, height) = (camera.hsize(), camera.vsize());
    let tiles = Tiles::new(width, height);
    let tile_count = (tiles.columns * tiles.rows) as u64;
    let stopped = |tiles_drawn: u64| -> Result<(), RasterError> {
        match cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            true => Err(RasterError::Cancelled {
                tiles_drawn,
                tiles: tile_count,
            }),
            false => Ok(()),
        }
    };
    stopped(0)?;
    let projection = Projection::new(camera, options.near);
    let bits = subpixel_bits(width, height);
    let divisions = options.sphere_divisions.max(3);
    let instances = instances(
        world,
        &projection,
        divisions,
        options.backface_culling,
        options.max_triangles,
        cancel,
    )
    .map_err(|e| match e {
        // Stopped while a model was tessellated: no tile drawn.
        RasterError::Cancelled { .. } => RasterError::Cancelled {
            tiles_drawn: 0,
            tiles: tile_count,
        },
        e => e,
    })?;
    stopped(0)?;
    let Scratch {
        vertices,
        outside,
        normals,
        chunks,
    } = scratch;
    transform_vertices(
        &instances,
        &projection,
        bits,
        vertices,
        outside,
        normals,
        cancel,
    );
    stopped(0)?;
    bin_all(
        &BinContext {
            instances: &instances,
            vertices,
            outside,
            projection: &projection,
            tiles,
            bits,
        },
        chunks,
        cancel,
    );
    stopped(0)?;
    let mut stats = RasterStats {
        instances: instances.len() as u64,
        ..RasterStats::default()
    };
    for chunk in chunks.iter() {
        stats.triangles += chunk.counts.faces;
        stats.clipped += chunk.counts.clipped;
        stats.culled += chunk.counts.culled;
        stats.drawn += chunk.counts.binned;
    }
    let lights = raster_lights(&world.lights);
    let runs = PhongRuns::new(world.lighting, options.shading, &lights, &instances);
    let mut ctx = ShadeContext {
        instances: &instances,
        vertices,
        normals,
        chunks,
        projection: &projection,
        lights,
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
        runs,
    };
    if options.shading == crate::options::Shading::Gouraud && !options.wireframe {
        ctx.light_vertices();
    }
    let frame = Frame {
        ctx: &ctx,
        tiles,
        background: world.background,
        wireframe: options.wireframe,
        cancel,
        drawn: AtomicU64::new(0),
        camera,
    };
    draw(&frame);
    stopped(frame.drawn.load(Ordering::Relaxed))?;
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flag set while the objects are tessellated (before the frame's first tile): the
    /// instances give up within the model being made and the frame is refused with no tile
    /// drawn, its count of tiles filled in.
    #[test]
    fn a_stop_reaches_inside_the_tessellation() {
        let mut world = World::new();
        world
            .objects
            .push(crate::scene::Object::new(crate::scene::Shape::Sphere));
        let camera = Camera::new(64, 32, std::f64::consts::FRAC_PI_3);
        let projection = Projection::new(&camera, RasterOptions::default().near);
        let set = AtomicBool::new(true);
        let made = instances(&world, &projection, 512, true, u64::MAX, Some(&set));
        assert!(matches!(made, Err(RasterError::Cancelled { .. })));
        let made = instances(&world, &projection, 512, true, u64::MAX, None).unwrap();
        assert_eq!(made.len(), 1);
    }

    /// The projection and the binning look at the stop flag before each run of vertices and
    /// each chunk of faces (they were passes over arrays of up to `--max-raster-triangles`
    /// not looked into): with the flag set neither does any of its work, with it clear each
    /// does the same as with none. A sphere of 512 divisions is 524,288 faces: many runs of
    /// vertices and chunks of faces.
    #[test]
    fn a_stop_reaches_inside_the_projection_and_the_binning() {
        let mut world = World::new();
        world.objects.push(
            crate::scene::Object::new(crate::scene::Shape::Sphere)
                .with_transform(crate::math::translation(0.0, 0.0, -5.0)),
        );
        let camera = Camera::new(64, 32, std::f64::consts::FRAC_PI_3);
        let projection = Projection::new(&camera, RasterOptions::default().near);
        let made = instances(&world, &projection, 512, true, u64::MAX, None).unwrap();
        let bits = subpixel_bits(64, 32);
        let (set, clear) = (AtomicBool::new(true), AtomicBool::new(false));
        let project = |cancel| {
            let (mut vertices, mut outside, mut normals) = (Vec::new(), Vec::new(), Vec::new());
            transform_vertices(
                &made,
                &projection,
                bits,
                &mut vertices,
                &mut outside,
                &mut normals,
                cancel,
            );
            (vertices, outside, normals)
        };
        let (stopped, _, stopped_normals) = project(Some(&set));
        assert!(stopped.len() > 4 * 4096, "{} vertices", stopped.len());
        assert!(stopped
            .iter()
            .all(|v| v.inv_z == 0.0 && v.view == Vec3::ZERO));
        assert!(stopped_normals.iter().all(|n| *n == Vec3::ZERO));
        let (vertices, outside, _) = project(None);
        assert!(vertices.iter().all(|v| v.inv_z > 0.0));
        let (again, _, _) = project(Some(&clear));
        assert!(again
            .iter()
            .zip(&vertices)
            .all(|(a, b)| a.view == b.view && a.inv_z == b.inv_z));
        let context = BinContext {
            instances: &made,
            vertices: &vertices,
            outside: &outside,
            projection: &projection,
            tiles: Tiles::new(64, 32),
            bits,
        };
        let binned = |cancel| {
            let mut chunks = Vec::new();
            bin_all(&context, &mut chunks, cancel);
            (
                chunks.len(),
                chunks.iter().map(|c| c.counts.faces).sum::<u64>(),
            )
        };
        let (chunks, faces) = binned(Some(&set));
        assert!(chunks > 4, "{chunks} chunks");
        assert_eq!(faces, 0, "no face binned once stopped");
        assert_eq!(binned(None), (chunks, 524_288));
        assert_eq!(binned(Some(&clear)), binned(None));
    }

    /// The flag set at a known point, between two bands of one thread: the first band's tiles
    /// are drawn, none after it, and the frame is refused with that count.
    #[test]
    fn a_stop_set_between_bands_draws_no_tile_after_it() {
        let world = crate::scene::default_world();
        let camera = Camera::new(200, 100, std::f64::consts::FRAC_PI_3);
        let stop = AtomicBool::new(false);
        let (width, columns) = (200, 200usize.div_ceil(super::super::bin::TILE_WIDTH));
        let result = with_frame(
            &camera,
            &world,
            &RasterOptions::default(),
            Some(&stop),
            &mut Scratch::default(),
            |frame| {
                let mut band = vec![Color::BLACK; width * TILE_HEIGHT];
                let mut buffers = TileBuffers::new();
                assert!(frame.draw_band(0, &mut band, &mut buffers));
                stop.store(true, Ordering::Relaxed);
                assert!(!frame.draw_band(1, &mut band, &mut buffers));
            },
        );
        assert_eq!(
            result,
            Err(RasterError::Cancelled {
                tiles_drawn: columns as u64,
                tiles: (columns * 100usize.div_ceil(TILE_HEIGHT)) as u64,
            })
        );
    }
}
