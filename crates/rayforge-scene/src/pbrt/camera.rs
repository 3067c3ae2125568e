//! The options block as rayforge's camera and path-tracer options: `Camera`, `Film`,
//! `Sampler`, `Integrator`, `PixelFilter` and `Option`.
//!
//! **The camera's axes.** pbrt's camera looks down its +z with +y up and +x to the image's
//! right, in a left-handed space; rayforge's (the book's) looks down its −z with +y up and +x
//! to the image's left, in a left-handed space too. Both worlds are the same space, so a
//! file's coordinates are used as they are, and the camera's transform is pbrt's
//! camera-from-world followed by a half turn about y (x and z negated): a rotation, so
//! nothing is mirrored. `fov` spans the image's shorter side, as pbrt-v4 says; rayforge's
//! field of view spans the longer, and is worked out from it.
//!
//! **The screen.** pbrt-v4's perspective and orthographic cameras map the image onto a
//! screen window: by default −1 to 1 across the shorter side of the frame
//! (`frameaspectratio`, the image's own by default), or the file's `screenwindow`
//! (x_min, x_max, y_min, y_max). A perspective camera's screen is the canvas one unit ahead
//! over `tan(fov / 2)`, an orthographic one's is in world units. Where the file gives either
//! parameter, the window is rayforge's camera's [`ScreenWindow`] (the image off the axis, or
//! its pixels stretched); otherwise the camera is the centred one it always was.
//!
//! **The spherical camera** is rayforge's of the same layout ([`SphericalMapping`]):
//! `equalarea` (pbrt-v4's default) or `equirectangular`. pbrt-v4 reads its `lensradius`,
//! `focaldistance`, `screenwindow` and `frameaspectratio` and uses none of them; so does
//! rayforge, without a warning.
//!
//! **The realistic camera** is rayforge's [`LensSystem`] (pbrt-v4's `RealisticCamera`: the
//! lens file's interfaces traced from the film, see its module): `lensfile` (read by
//! [`super::lens_file`]), `aperturediameter` (1 mm), `focusdistance` (10), `aperture` (the
//! circular stop, or a built-in shape: `gaussian`, `square`, `pentagon`, `star`; an image
//! file is refused), and the `Film`'s `diagonal` (35 mm). Its image is what pbrt-v4's is: a
//! film of that diagonal, vignetted, each ray weighted by `cos⁴θ` over the exit pupil's
//! solid angle, so dimmer than a pinhole's.

use super::input::Files;
use super::params::{Param, ParamType};
use super::reader::{Entity, Options};
use crate::error::SceneError;
use crate::scene::Written;
use glam::{DMat4, DVec4};
use rayforge::camera::{ApertureShape, LensSettings, LensSystem, ScreenWindow, SphericalMapping};
use rayforge::film::PixelFilter;
use rayforge::options::{LightSamplerKind, PathOptions, SamplerKind};
use rayforge::{Camera, Transform};

/// The largest image side a pbrt film may ask for.
pub const MAX_RESOLUTION: u64 = 1 << 16;

/// What the options block sets up.
pub struct Setup {
    /// The camera, at the film's resolution.
    pub camera: Camera,
    /// Samples per pixel (`pixelsamples`, or pbrt-v4's default for the sampler).
    pub samples: u32,
    /// Where the file gives the samples, when it does.
    pub samples_at: Option<Written>,
    /// The path tracer's options (`maxdepth`, sampler, filter, seed, light sampler).
    pub path: PathOptions,
    /// The most bounces (`maxdepth`).
    pub max_depth: u32,
    /// Where the file gives `maxdepth`, when it does.
    pub max_depth_at: Option<Written>,
}

/// From pbrt's camera space to the book's: x and z negated.
pub(crate) const PBRT_TO_BOOK_CAMERA: DMat4 = DMat4::from_cols(
    DVec4::new(-1.0, 0.0, 0.0, 0.0),
    DVec4::new(0.0, 1.0, 0.0, 0.0),
    DVec4::new(0.0, 0.0, -1.0, 0.0),
    DVec4::new(0.0, 0.0, 0.0, 1.0),
);

/// The film's resolution.
pub fn resolution(film: Option<&Entity>) -> Result<(usize, usize), SceneError> {
    let Some(film) = film else {
        return Ok((1280, 720));
    };
    let side = |name: &str, default: i64| -> Result<usize, SceneError> {
        match film.params.integer(name)? {
            None => Ok(default as usize),
            Some((v, p)) if v < 1 || v as u64 > MAX_RESOLUTION => Err(p.error(format!(
                "an image side is from 1 to {MAX_RESOLUTION} pixels, found {v}"
            ))),
            Some((v, _)) => Ok(v as usize),
        }
    };
    Ok((side("xresolution", 1280)?, side("yresolution", 720)?))
}

/// The film's `filename` (pbrt-v4's default `pbrt.exr`), and where it is written.
pub fn film_filename(options: &Options) -> Result<(String, Option<&Entity>), SceneError> {
    let film = options.film.as_ref();
    let name = match film {
        Some(f) => f.params.string("filename")?.map(|(n, _)| n.to_string()),
        None => None,
    };
    Ok((name.unwrap_or_else(|| "pbrt.exr".into()), film))
}

/// The camera and path-tracer options of `options` (a lens file read from `files`),
/// warnings added to `warnings`.
pub fn setup(
    options: &Options,
    files: &Files,
    warnings: &mut Vec<SceneError>,
) -> Result<Setup, SceneError> {
    let film = options.film.as_ref();
    if let Some(film) = film {
        match film.name.as_str() {
            "rgb" => {}
            "gbuffer" | "spectral" => warnings
                .push(film.error(format!("a \"{}\" film is written as an rgb one", film.name))),
            other => {
                return Err(film.error(format!(
                    "the film \"{}\" is not one pbrt-v4 has (rgb, gbuffer, spectral)",
                    crate::error::clip_to(other, 60)
                )))
            }
        }
        // The output's name is the command's business (its default output).
        film.params.string("filename")?;
    }
    let (width, height) = resolution(film)?;
    let placed = Placed {
        film,
        files,
        width,
        height,
    };
    let camera = camera(options.camera.as_ref(), &placed, warnings)?.with_sensor(
        super::sensor::sensor(film, options.camera.as_ref().map(|(e, _)| e), warnings)?,
    );
    let sampling = sampler(options.sampler.as_ref(), warnings)?;
    let mut path = PathOptions {
        sampler: sampling.kind,
        ..PathOptions::default()
    };
    path.filter = filter(options.filter.as_ref(), warnings)?;
    let (max_depth, max_depth_at) = integrator(options.integrator.as_ref(), &mut path, warnings)?;
    for (name, value, loc) in &options.options {
        match name.as_str() {
            "seed" => {
                path.seed = value.parse().map_err(|_| {
                    loc.error(
                        Some("Option"),
                        format!("the option \"seed\" takes a whole number, found `{value}`"),
                    )
                })?;
            }
            // Read with the shapes (`displace::edge_scale`).
            "displacementedgescale" => {}
            _ => warnings.push(loc.error(
                Some("Option"),
                format!(
                    "the option \"{}\" is not used",
                    crate::error::clip_to(name, 60)
                ),
            )),
        }
    }
    if let Some(seed) = sampling.seed {
        path.seed = seed;
    }
    Ok(Setup {
        camera,
        samples: sampling.samples,
        samples_at: sampling.samples_at,
        path,
        max_depth,
        max_depth_at,
    })
}

/// What a camera is built for besides its directive: the film (its resolution, and the
/// `diagonal` a realistic camera's film has), and the scene's files (a lens file's).
struct Placed<'a> {
    film: Option<&'a Entity>,
    files: &'a Files,
    width: usize,
    height: usize,
}

/// The camera of `camera` (pbrt's default, a perspective camera of 90° at the origin, when
/// absent) for `placed`.
fn camera(
    camera: Option<&(Entity, DMat4)>,
    placed: &Placed<'_>,
    warnings: &mut Vec<SceneError>,
) -> Result<Camera, SceneError> {
    let (width, height) = (placed.width, placed.height);
    let (entity, camera_from_world) = match camera {
        Some((e, m)) => (Some(e), *m),
        None => (None, DMat4::IDENTITY),
    };
    let view = Transform::try_new(PBRT_TO_BOOK_CAMERA * camera_from_world).map_err(|_| {
        let message = "the camera's transform is singular";
        match entity {
            Some(e) => e.error(message),
            None => SceneError::new(std::path::Path::new(""), message),
        }
    })?;
    let (longer, shorter) = (width.max(height) as f64, width.min(height) as f64);
    let Some(entity) = entity else {
        let fov = 2.0 * ((45.0f64).to_radians().tan() * longer / shorter).atan();
        return Ok(Camera::new(width, height, fov).with_transform_of(view));
    };
    let params = &entity.params;
    let built = match entity.name.as_str() {
        "perspective" => {
            let fov = params.float_or("fov", 90.0)?;
            if !(fov > 0.0 && fov < 180.0) {
                return Err(entity.error(format!(
                    "a perspective camera's fov is between 0 and 180 degrees, found {fov}"
                )));
            }
            let tan_half = (fov.to_radians() / 2.0).tan();
            let half_longer = tan_half * longer / shorter;
            let lens = params.float_or("lensradius", 0.0)?;
            let focus = params.float_or("focaldistance", 1e6)?;
            if lens < 0.0 || focus <= 0.0 {
                return Err(
                    entity.error("a lens radius is not negative and a focal distance above 0")
                );
            }
            let camera =
                Camera::new(width, height, 2.0 * half_longer.atan()).with_lens(2.0 * lens, focus);
            windowed(camera, entity, width, height, tan_half)?
        }
        "orthographic" => {
            // pbrt's screen window spans −1 to 1 across the shorter side.
            let camera = Camera::orthographic(width, height, longer / shorter);
            windowed(camera, entity, width, height, 1.0)?
        }
        "spherical" => {
            let mapping = match params.string("mapping")? {
                None | Some(("equalarea", _)) => SphericalMapping::EqualArea,
                Some(("equirectangular", _)) => SphericalMapping::Equirectangular,
                Some((other, p)) => {
                    return Err(p.error(format!(
                        "the spherical camera's mapping \"{}\" is not one pbrt-v4 has \
                         (equalarea, equirectangular)",
                        crate::error::clip_to(other, 60)
                    )))
                }
            };
            // Read and unused by pbrt-v4's spherical camera too: no warning.
            params.float("lensradius")?;
            params.float("focaldistance")?;
            params.float("frameaspectratio")?;
            params.numbers("screenwindow", ParamType::Float)?;
            Camera::spherical(width, height, mapping)
        }
        "realistic" => realistic(entity, placed, warnings)?,
        other => {
            return Err(entity.error(format!(
                "the camera \"{}\" is not one pbrt-v4 has (orthographic, perspective, \
                 realistic, spherical)",
                crate::error::clip_to(other, 60)
            )))
        }
    };
    Ok(built.with_transform_of(view))
}

/// The realistic camera `entity` (see the module's documentation).
fn realistic(
    entity: &Entity,
    placed: &Placed<'_>,
    warnings: &mut Vec<SceneError>,
) -> Result<Camera, SceneError> {
    let params = &entity.params;
    let Some((name, at)) = params.string("lensfile")? else {
        return Err(entity.error(
            "a realistic camera needs its lens system: \"string lensfile\" naming a lens \
             description file",
        ));
    };
    let max_rows = placed.files.limits().lens_rows;
    let file = super::lens_file::read(name, at, placed.files, max_rows)?;
    let positive = |name: &str, default: f64| -> Result<f64, SceneError> {
        match params.float_at(name)? {
            None => Ok(default),
            Some((v, p)) if !(v.is_finite() && v > 0.0) => {
                Err(p.error(format!("{name} is above 0, found {v}")))
            }
            Some((v, _)) => Ok(v),
        }
    };
    let aperture_diameter = positive("aperturediameter", 1.0)?;
    let focus_distance = positive("focusdistance", 10.0)?;
    let aperture = match params.string("aperture")? {
        None => ApertureShape::Circular,
        Some((shape, p)) => ApertureShape::named(shape).ok_or_else(|| {
            p.error(format!(
                "the aperture \"{}\" would be an image file to pbrt-v4 (the diaphragm's \
                 transmission read from it), which rayforge does not read; it reads pbrt-v4's \
                 built-in shapes ({}) and, without `aperture`, the circular stop",
                crate::error::clip_to(shape, 60),
                ApertureShape::NAMES.join(", ")
            ))
        })?,
    };
    let film_diagonal = match placed.film {
        None => 35.0,
        Some(film) => match film.params.float_at("diagonal")? {
            None => 35.0,
            Some((v, p)) if !(v.is_finite() && v > 0.0) => {
                return Err(p.error(format!(
                    "a film's diagonal is above 0 millimetres, found {v}"
                )))
            }
            Some((v, _)) => v,
        },
    };
    let settings = LensSettings {
        aperture_diameter,
        focus_distance,
        film_diagonal,
        aperture,
        ..LensSettings::DEFAULT
    };
    let stop = placed.files.stop();
    let lens =
        LensSystem::new_until(&file.rows, &settings, stop.flag()).map_err(|e| match e.row {
            Some(row) => file.error_at_row(row, e.message),
            None => entity.error(e.message),
        })?;
    // Stopped while it traced the exit pupil: the camera's directive is where.
    let Some(lens) = lens else {
        entity.loc.stopped(stop, "Camera")?;
        return Err(entity.error("the lens system's build was stopped"));
    };
    if let Some((asked, most)) = lens.clamped_aperture() {
        warnings.push(entity.error(format!(
            "the aperture diameter {asked} mm is wider than the lens file's stop allows: \
             rendered at {most} mm, as pbrt-v4 clamps it"
        )));
    }
    Ok(Camera::realistic(
        placed.width,
        placed.height,
        std::sync::Arc::new(lens),
    ))
}

/// `camera` (of `width × height`) with pbrt-v4's screen window where the file gives
/// `frameaspectratio` or `screenwindow`: the frame's default, −1 to 1 across its shorter
/// side, or the file's four edges, times `scale` (a perspective camera's `tan(fov / 2)`, the
/// canvas one unit ahead; 1 for an orthographic camera's world units).
fn windowed(
    camera: Camera,
    entity: &Entity,
    width: usize,
    height: usize,
    scale: f64,
) -> Result<Camera, SceneError> {
    let params = &entity.params;
    let frame = match params.float_at("frameaspectratio")? {
        None => None,
        Some((v, p)) if !(v > 0.0 && v.is_finite()) => {
            return Err(p.error(format!("a frame aspect ratio is above 0, found {v}")))
        }
        Some((v, _)) => Some(v),
    };
    let given = match params.numbers("screenwindow", ParamType::Float)? {
        None => None,
        Some((&[x_min, x_max, y_min, y_max], p)) => Some((
            ScreenWindow {
                x_min,
                x_max,
                y_min,
                y_max,
            },
            p,
        )),
        Some((v, p)) => {
            return Err(p.error(format!(
                "a screen window has four values (x_min x_max y_min y_max), not {}",
                v.len()
            )))
        }
    };
    if frame.is_none() && given.is_none() {
        return Ok(camera);
    }
    let (window, at) = match given {
        Some((w, p)) => (w, Some(p)),
        None => {
            let frame = frame.unwrap_or(width as f64 / height as f64);
            let window = if frame > 1.0 {
                ScreenWindow::centred(frame, 1.0)
            } else {
                ScreenWindow::centred(1.0, 1.0 / frame)
            };
            (window, None)
        }
    };
    let window = ScreenWindow {
        x_min: window.x_min * scale,
        x_max: window.x_max * scale,
        y_min: window.y_min * scale,
        y_max: window.y_max * scale,
    };
    camera.with_screen_window(window).ok_or_else(|| {
        let message = format!(
            "a screen window has finite edges, x_min ≠ x_max and y_min ≠ y_max; found \
             {} {} {} {}",
            window.x_min, window.x_max, window.y_min, window.y_max
        );
        match at {
            Some(p) => p.error(message),
            None => entity.error(message),
        }
    })
}

/// What the `Sampler` says: samples per pixel and where the file gives them, the sampler's
/// kind, and its own `seed` (which wins over `Option "seed"`, as in pbrt-v4).
struct Sampling {
    samples: u32,
    samples_at: Option<Written>,
    kind: SamplerKind,
    seed: Option<u64>,
}

/// The place of parameter `p`, for an error the command line may raise at it later.
fn written(p: &Param) -> Written {
    Written {
        file: p.loc.file.to_path_buf(),
        span: p.loc.span,
        key: p.declaration(),
    }
}

/// The samples per pixel as pbrt-v4's samplers take them (`samplers.cpp`, each sampler's
/// `Create`): `pixelsamples`, whose default is 16 (`halton`, `sobol`, `zsobol`, the default
/// sampler, `paddedsobol`, `pmj02bn`) or 4 (`independent`); `stratified` takes
/// `xsamples` × `ysamples` (4 × 4). The independent sampler is rayforge's independent one,
/// the others its Owen-scrambled Sobol points: the same expectation, another sequence.
fn sampler(
    sampler: Option<&Entity>,
    warnings: &mut Vec<SceneError>,
) -> Result<Sampling, SceneError> {
    let max = crate::items::camera::MAX_PATH_SAMPLES;
    let mut sampling = Sampling {
        samples: 16,
        samples_at: None,
        kind: SamplerKind::Sobol,
        seed: None,
    };
    let Some(sampler) = sampler else {
        return Ok(sampling);
    };
    let params = &sampler.params;
    let count = |name: &str, default: i64| -> Result<(i64, Option<&Param>), SceneError> {
        match params.integer(name)? {
            None => Ok((default, None)),
            Some((n, p)) if n < 1 || n > i64::from(max) => {
                Err(p.error(format!("{name} is from 1 to {max}, found {n}")))
            }
            Some((n, p)) => Ok((n, Some(p))),
        }
    };
    let (samples, at) = match sampler.name.as_str() {
        "independent" => {
            sampling.kind = SamplerKind::Independent;
            count("pixelsamples", 4)?
        }
        "halton" | "sobol" | "zsobol" | "paddedsobol" | "pmj02bn" => count("pixelsamples", 16)?,
        "stratified" => {
            let (x, x_at) = count("xsamples", 4)?;
            let (y, y_at) = count("ysamples", 4)?;
            if !params.bool_or("jitter", true)? {
                warnings.push(sampler.error(
                    "an unjittered stratified sampler is rendered with jittered points (the \
                     same strata, each sample anywhere in its own)",
                ));
            }
            let n = x * y;
            if n > i64::from(max) {
                return Err(sampler.error(format!(
                    "xsamples × ysamples is {n} samples per pixel, more than {max}"
                )));
            }
            (n, y_at.or(x_at))
        }
        other => {
            return Err(sampler.error(format!(
                "the sampler \"{}\" is not one pbrt-v4 has (halton, independent, paddedsobol, \
                 pmj02bn, sobol, stratified, zsobol)",
                crate::error::clip_to(other, 60)
            )))
        }
    };
    if let Some((seed, _)) = params.integer("seed")? {
        // pbrt-v4 takes the seed as an int; any whole number seeds rayforge's sampler.
        sampling.seed = Some(seed as u64);
    }
    sampling.samples = samples as u32;
    sampling.samples_at = at.map(written);
    Ok(sampling)
}

/// The pixel filter: box, triangle (a tent), gaussian; others as a Gaussian, with a warning.
fn filter(
    filter: Option<&Entity>,
    warnings: &mut Vec<SceneError>,
) -> Result<PixelFilter, SceneError> {
    let Some(filter) = filter else {
        return Ok(PixelFilter::Gaussian { radius: 1.5 });
    };
    let default = match filter.name.as_str() {
        "box" => 0.5,
        "gaussian" => 1.5,
        "mitchell" | "triangle" => 2.0,
        "sinc" => 4.0,
        other => {
            return Err(filter.error(format!(
                "the filter \"{}\" is not one pbrt-v4 has (box, gaussian, mitchell, sinc, \
                 triangle)",
                crate::error::clip_to(other, 60)
            )))
        }
    };
    let x = filter.params.float_or("xradius", default)?;
    let y = filter.params.float_or("yradius", default)?;
    if x != y {
        warnings.push(filter.error(format!(
            "a filter of radii {x} and {y} is rendered with the larger in both directions"
        )));
    }
    let radius = x.max(y);
    let built = match filter.name.as_str() {
        "box" => {
            if radius != 0.5 {
                warnings.push(filter.error(format!(
                    "a box of radius {radius} is rendered as the pixel's own box (0.5)"
                )));
            }
            PixelFilter::Box
        }
        "triangle" => PixelFilter::Tent { radius },
        "gaussian" => PixelFilter::Gaussian { radius },
        other => {
            warnings.push(filter.error(format!(
                "the \"{other}\" filter is rendered as a Gaussian of the same radius"
            )));
            PixelFilter::Gaussian { radius }
        }
    };
    built.checked().map_err(|e| filter.error(format!("{e}")))
}

/// `maxdepth` (pbrt's default 5) and where the file gives it, the light sampler, and the
/// integrator's kind.
fn integrator(
    integrator: Option<&Entity>,
    path: &mut PathOptions,
    warnings: &mut Vec<SceneError>,
) -> Result<(u32, Option<Written>), SceneError> {
    path.light_sampler = LightSamplerKind::Bvh;
    let Some(integrator) = integrator else {
        path.max_depth = 5;
        return Ok((5, None));
    };
    let params = &integrator.params;
    match integrator.name.as_str() {
        "path" | "volpath" => {}
        other => warnings.push(integrator.error(format!(
            "the \"{}\" integrator is rendered with rayforge's path tracer",
            crate::error::clip_to(other, 60)
        ))),
    }
    let (depth, depth_at) = match params.integer("maxdepth")? {
        None => (5, None),
        Some((d, p)) => {
            let max = i64::from(PathOptions::MAX_DEPTH);
            if d < 0 || d > max {
                return Err(p.error(format!("maxdepth is from 0 to {max}, found {d}")));
            }
            (d as u32, Some(written(p)))
        }
    };
    if let Some((sampler, p)) = params.string("lightsampler")? {
        path.light_sampler = match sampler {
            "bvh" => LightSamplerKind::Bvh,
            "uniform" => LightSamplerKind::Uniform,
            "power" => LightSamplerKind::Power,
            other => {
                return Err(p.error(format!(
                    "the light sampler \"{}\" is not one pbrt-v4 has (bvh, power, uniform)",
                    crate::error::clip_to(other, 60)
                )))
            }
        };
    }
    path.max_depth = depth;
    Ok((depth, depth_at))
}
