//! What reading a scene gives ([`Scene`]), and what bounds the reading ([`LoadOptions`]).
//!
//! Apart from the crate root so that the readers that build a scene (the YAML reader, a glTF
//! model rendered directly) can name them without importing the root that imports them.

use crate::error::SceneError;
use crate::images::DEFAULT_MAX_IMAGE_MEMORY;
use crate::items::camera::LookAt;
use crate::obj::DEFAULT_MAX_TRIANGLES;
use crate::stop::StopFlag;

/// A scene ready to render: the world and the camera that looks at it.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Objects, lights and background.
    pub world: rayforge::World,
    /// The camera from `add: camera`.
    pub camera: rayforge::Camera,
    /// Camera rays per pixel asked for by the camera's `samples` (1: one through the centre).
    pub samples: u32,
    /// Where the file gives `samples` (the camera's `samples`; a pbrt file's `pixelsamples`),
    /// when it does: the count is then the file's own, 1 included (the path tracer takes
    /// it as `--spp`); the renderer that draws the scene holds it to its own limit (at most
    /// [`crate::items::camera::MAX_RAY_SAMPLES`] for the ray tracer,
    /// [`crate::items::camera::MAX_PATH_SAMPLES`] for the path tracer, which the reader
    /// checks), and the error points here.
    pub samples_at: Option<Written>,
    /// Fundamentals of Ray Tracing's anti-aliasing, when the camera gives `anti-alias: N`: an
    /// N × N grid of rays from each pixel's corner, unjittered (`samples` is then N²).
    pub anti_alias: Option<u32>,
    /// Reflection and refraction bounces, when the scene's `world:` item sets `max-depth`.
    pub max_depth: Option<u32>,
    /// Where `max-depth` is written (a pbrt file's `maxdepth`), when it is: the reader holds
    /// it to the limit of the scene's own renderer, and the renderer the command line picks
    /// holds it to its own, the error pointing here.
    pub max_depth_at: Option<Written>,
    /// The rasterizer's options, when the scene's `world:` item says `renderer: raster`.
    pub raster: Option<rayforge::options::RasterOptions>,
    /// The path tracer's options, when the scene's `world:` item says `renderer: path`
    /// (`max-depth` included, as `max_depth`).
    pub path: Option<rayforge::options::PathOptions>,
    /// The canvas items (`add: canvas-line`, `add: canvas-triangle`), drawn over the image by
    /// either renderer.
    pub overlay: rayforge::draw2d::Overlay,
    /// Problems in the file that the reader worked around (each located like an error).
    pub warnings: Vec<SceneError>,
    /// Where the book's camera (`from`, `to`, `up`) stands and looks, for a viewer that
    /// orbits it (`rayforge serve`); `None` for the other books' cameras, placed otherwise.
    pub look_at: Option<LookAt>,
    /// Every file the scene read besides its own (OBJ models and material libraries, images,
    /// environment maps, glTF models with their buffers and images), each once, in the order
    /// first read: what a render's fingerprint covers and what the live page watches.
    pub files: Vec<std::path::PathBuf>,
}

/// Where a setting is written in a scene's files: the file (a pbrt scene's may be one it
/// includes), the place in it and the key as the format names it, for an error located there
/// by whoever holds the setting to a limit the reader could not know (the command line's
/// renderer).
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The file.
    pub file: std::path::PathBuf,
    /// The place in it.
    pub span: crate::error::Span,
    /// The key (`samples`, `max-depth`; `Sampler`, `Integrator` for a pbrt directive).
    pub key: String,
}

impl Written {
    /// An error with `message` at the setting.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::new(&self.file, message)
            .at(self.span)
            .with_key(self.key.clone())
    }
}

/// Limits on what loading a scene may take, beyond the fixed ones of the format.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadOptions {
    /// The most triangles the scene's OBJ models may hold together (a model used twice counts
    /// once), and the most vertices, normals or texture coordinates in any one model.
    pub max_triangles: usize,
    /// The animation frame to build: items with `per-frame` take that many steps (0, a still).
    pub frame: u64,
    /// The most memory, in bytes, the scene's images (textures and environment maps) may take
    /// together, an image used twice once: the colours each keeps, and while one is decoded
    /// its file and the decoder's buffers too. Each image is costed from its header and
    /// refused before it is decoded if it would go over.
    pub max_image_memory: u64,
    /// Whether the files the scene names (models, material libraries, images, environment
    /// maps) may be outside the scene file's folder. By default they may not: an absolute path,
    /// a `..` that climbs out or a symbolic link that leads out is an error at the `file:`
    /// that names it, so that a scene from elsewhere cannot read other files.
    pub allow_outside: bool,
    /// Which of a glTF model's cameras to look through when the model is rendered directly
    /// (`--camera`).
    pub camera: CameraChoice,
    /// The flag that stops the reading part-way (see [`StopFlag`]): none by default.
    pub stop: StopFlag,
    /// The limits of a pbrt-v4 scene's files (`--max-pbrt-*`).
    pub pbrt: PbrtLimits,
    /// The most samples one density or colour grid of a medium may hold (a YAML grid's
    /// `size`, a `.vol` file's header, a pbrt-v4 `uniformgrid` or `rgbgrid`'s `nx × ny × nz`),
    /// checked from the sizes before the grid (or a `.vol` file's body) is read into memory:
    /// `--max-grid-samples`, at most (and by default) `rayforge::media::MAX_GRID_SAMPLES`.
    pub max_grid_samples: usize,
    /// The most optical depth one straight pass through a grid or cloud medium may cross
    /// (its largest extinction times its box's world diagonal; about one tracking step a
    /// unit): `--max-optical-depth`, by default `rayforge::media::MAX_OPTICAL_DEPTH`.
    pub max_optical_depth: f64,
}

/// What a pbrt-v4 scene's files may hold (the triangles are [`LoadOptions::max_triangles`]).
/// Each default is far past a real scene (Bitterli's largest file is 9 MB; their meshes are
/// PLY files, read apart) and keeps a hostile or broken one within a few gigabytes and
/// seconds. Going over one is an error at the place it happened, naming its flag.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PbrtLimits {
    /// The most bytes one file may hold, a `.gz` before and after inflating
    /// (`--max-pbrt-file-bytes`).
    pub file_bytes: u64,
    /// The most bytes all files may hold together, after inflating; a file included again is
    /// counted again (`--max-pbrt-total-bytes`).
    pub total_bytes: u64,
    /// How deep `Include` and `Import` may nest (`--max-pbrt-include-depth`).
    pub include_depth: usize,
    /// The most parameter values (numbers, strings, booleans) all files may hold together,
    /// counted as they are lexed, before any is kept: what bounds the memory the parameter
    /// lists take, each value a few dozen bytes while it is read (`--max-pbrt-values`).
    pub values: u64,
    /// The most rows (interfaces) a realistic camera's lens file may hold: each costs the
    /// exit pupil's bounds a million intersections more (`--max-pbrt-lens-rows`).
    pub lens_rows: usize,
    /// The most radiances one emitting mesh with `power` is given (`--max-pbrt-radiances`):
    /// pbrt-v4 makes each triangle a light of its own power, and rayforge cuts the mesh into a
    /// piece per size of triangle, each a mesh of its own; past this many sizes, into this
    /// many bands of sizes, with a warning of the spread of areas in a band (see
    /// `pbrt/area_power.rs`). It bounds the pieces' cost, not what is read: nothing is refused.
    pub radiances: usize,
}

impl PbrtLimits {
    /// The defaults: 64 MiB a file (a YAML scene's limit), 1 GiB in all, 32 levels of
    /// includes, 2^26 (67,108,864) values (a mesh of 5 million triangles written inline),
    /// 64 lens rows (pbrt-v4's lens files have at most a few dozen),
    /// 1024 radiances an emitting mesh (enough for any mesh of a few sizes of triangle, a
    /// lamp of quads and fans, few enough that the pieces' meshes cost little beside the
    /// mesh's own).
    pub const DEFAULT: PbrtLimits = PbrtLimits {
        file_bytes: 64 * 1024 * 1024,
        total_bytes: 1 << 30,
        include_depth: 32,
        values: 1 << 26,
        lens_rows: 64,
        radiances: 1024,
    };
}

impl Default for PbrtLimits {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            max_triangles: DEFAULT_MAX_TRIANGLES,
            frame: 0,
            max_image_memory: DEFAULT_MAX_IMAGE_MEMORY,
            allow_outside: false,
            camera: CameraChoice::First,
            stop: StopFlag::default(),
            pbrt: PbrtLimits::DEFAULT,
            max_grid_samples: rayforge::media::MAX_GRID_SAMPLES,
            max_optical_depth: rayforge::media::MAX_OPTICAL_DEPTH,
        }
    }
}

/// Which of a model's cameras to look through.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CameraChoice {
    /// The file's first camera, else the default one.
    First,
    /// The camera at this index among the scene's cameras (node order).
    Index(usize),
    /// The camera of this name.
    Named(String),
}

impl CameraChoice {
    /// `--camera`'s value: a number is an index, anything else a name.
    pub fn parse(text: &str) -> Self {
        match text.parse() {
            Ok(i) => CameraChoice::Index(i),
            Err(_) => CameraChoice::Named(text.to_string()),
        }
    }
}
