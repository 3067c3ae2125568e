//! pbrt-v4 scene files (`.pbrt`, `.pbrt.gz`), the format of *Physically Based Rendering*'s
//! renderer and of the scenes rendering papers test on, read into a [`Scene`] for the path
//! tracer.
//!
//! The format is read as pbrt-v4 defines it (<https://pbrt.org/fileformat-v4>): tokens
//! ([`lexer`]), typed parameter lists ([`params`]), the directives with the graphics state and
//! its stack ([`reader`]), then the build ([`build`]) of the camera and options ([`camera`]),
//! the film's sensor ([`sensor`]),
//! shapes ([`shapes`]), materials ([`materials`]), lights ([`lights`]), textures
//! ([`textures`]), spectra ([`spectra`]) and motion blur ([`motion`]). Every error names the file, line, column and directive or parameter; a
//! parameter nothing reads is a warning naming its line, as pbrt-v4 warns. What is read, what
//! is approximated and what is refused is listed in `docs/scene-format.md` ("pbrt-v4 scenes").
//!
//! The files are untrusted input as a YAML scene is: regular files only, each at most
//! [`PbrtLimits::file_bytes`] (gzip's output too, bounded as it inflates), all together at
//! most [`PbrtLimits::total_bytes`], names resolved in the top-level file's folder and kept
//! inside it unless [`LoadOptions::allow_outside`], `Include` nested at most
//! [`PbrtLimits::include_depth`] deep, the parameter values counted against
//! [`PbrtLimits::values`] as they are lexed, the meshes' triangles within
//! [`LoadOptions::max_triangles`] (the defaults: [`PbrtLimits::DEFAULT`]).

mod area_power;
mod bilinear;
mod build;
mod camera;
mod displace;
mod image_lights;
mod input;
mod lens_file;
mod lexer;
mod lights;
mod loop_subdiv;
mod materials;
mod measured_media;
mod media;
mod motion;
mod params;
mod reader;
pub(crate) mod sensor;
mod shapes;
mod spectra;
mod stream;
mod textures;

pub use crate::scene::PbrtLimits;
pub use input::{MAX_INCLUDE_DEPTH, MAX_SCENE_BYTES, MAX_TOTAL_BYTES, MAX_VALUES};

use crate::error::SceneError;
use crate::scene::{LoadOptions, Scene};
use std::path::{Path, PathBuf};

/// Whether `path` names a pbrt scene: `.pbrt`, or `.pbrt.gz` (any case).
pub fn is_scene_file(path: &Path) -> bool {
    let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
        return false;
    };
    let name = name.to_ascii_lowercase();
    name.ends_with(".pbrt") || name.ends_with(".pbrt.gz")
}

/// Reads and builds the pbrt scene whose top-level file is `path`.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let mut files = input::Files::new(path, options.allow_outside)
        .stopped_by(options.stop.clone())
        .limited_by(options.pbrt);
    let description = reader::read(&mut files)?;
    build::scene(description, &files, options)
}

/// The image the scene's `Film` names (`"string filename"`, pbrt-v4's default `pbrt.exr`), to
/// be written in the current folder when the command is given no output: a plain file name,
/// else an error at the film. Only the options block, before `WorldBegin`, is read, under the
/// same `options` as [`load`] (the folder rule and `allow_outside`, the pbrt limits, the stop
/// flag), so that a scene the load takes never fails here first.
///
/// The command needs the name before it reads the scene (the output's lock and checks come
/// first, so that a second render to the same image is refused before a long read): the
/// options block is read twice, once here and once by the load, and costs little beside it.
pub fn film_output(path: &Path, options: &LoadOptions) -> Result<PathBuf, SceneError> {
    let mut files = input::Files::new(path, options.allow_outside)
        .stopped_by(options.stop.clone())
        .limited_by(options.pbrt);
    let description = reader::read_options(&mut files)?;
    build::film_output(&description, path)
}
