//! pbrt-v4's media: `MakeNamedMedium` (`homogeneous`, `uniformgrid` and `rgbgrid`), the
//! `MediumInterface` of each shape, and the camera's medium (the outside medium in force at
//! `Camera`), into the world's media and each object's `MediumInterface`.
//!
//! Every type reads `sigma_a` and `sigma_s` (rgb or spectrum; 1 when absent, pbrt-v4's
//! defaults) and `g`, and all but `cloud` `scale`; `homogeneous` also `Le` with `Lescale`, and `preset`, one of
//! pbrt-v4's named measured media ([`measured_media`](super::measured_media)), in place of
//! `sigma_a` and `sigma_s`. `uniformgrid` reads `density` (`nx` × `ny` × `nz` values, x
//! fastest) over the box `p0`–`p1` in the medium's space, placed by the transform in force at
//! `MakeNamedMedium`, and gives off light as pbrt-v4's grid does: `Le` times the grid
//! `Lescale`, or a blackbody at the grid `temperature`. `rgbgrid` reads grids of colours for
//! `sigma_a`, `sigma_s` and `Le` over the same box. `cloud` is pbrt-v4's procedural cloud
//! ([`CloudMedium`]: `density`, `wispiness`, `frequency` over the box `p0`–`p1`). What
//! rayforge does not render is refused: the other types (`nanovdb`, whose files rayforge
//! does not read).

use super::measured_media;
use super::params::ParamType;
use super::reader::{Description, Entity, MaterialRef, MediaNames, ShapeEntity};
use super::spectra::{self, SpectrumUse};
use crate::error::SceneError;
use glam::{DMat4, DVec3};
use rayforge::math::{Aabb, Transform};
use rayforge::media::{
    BlackbodyTable, CloudMedium, ColorGrid, DensityGrid, Glow, GridMedium, HenyeyGreenstein,
    Homogeneous, Medium, MediumId, MediumInterface, MAX_ASYMMETRY, MAX_BLACKBODY_ENTRIES,
};
use rayforge::shading::spectrum::{planck, spectrum_to_xyz, xyz_to_linear_srgb};
use rayforge::{Color, World};
use std::collections::HashMap;

/// pbrt-v4's default σa and σs (`HomogeneousMedium::Create`, `GridMedium::Create`: 1).
const DEFAULT_SIGMA_A: Color = Color::WHITE;
const DEFAULT_SIGMA_S: Color = Color::WHITE;

/// The scene's media, built into `world`, by name; a grid holds at most `max_grid_samples`
/// samples (`LoadOptions::max_grid_samples`), one pass through a medium at most
/// `max_optical_depth` (`LoadOptions::max_optical_depth`).
pub fn build(
    desc: &Description,
    world: &mut World,
    max_grid_samples: usize,
    max_optical_depth: f64,
) -> Result<HashMap<String, MediumId>, SceneError> {
    let mut names: Vec<&String> = desc.media.keys().collect();
    // In a fixed order, so that ids do not depend on the hash.
    names.sort();
    let mut ids = HashMap::new();
    for name in names {
        let (entity, world_from_medium) = &desc.media[name];
        let medium = medium(entity, world_from_medium, max_grid_samples)?;
        let id = medium
            .within_optical_depth(max_optical_depth)
            .and_then(|medium| world.media.add(medium))
            .map_err(|e| entity.error(e.to_string()))?;
        ids.insert(name.clone(), id);
    }
    Ok(ids)
}

/// The medium `entity` describes, a grid of at most `max_grid_samples` samples.
fn medium(
    entity: &Entity,
    world_from_medium: &DMat4,
    max_grid_samples: usize,
) -> Result<Medium, SceneError> {
    let params = &entity.params;
    let spectrum = |name: &str, default: Color, usage: SpectrumUse| -> Result<Color, SceneError> {
        match params.find(
            name,
            &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
        ) {
            None => Ok(default),
            Some(p) => {
                let c = spectra::color(p, usage)?;
                rayforge::media::coefficient("a medium's coefficient", c)
                    .map_err(|e| p.error(e.to_string()))
            }
        }
    };
    let kind = match params.string("type")? {
        Some((t, _)) => t.to_string(),
        None => {
            return Err(entity.error(format!(
                "the medium \"{}\" has no \"string type\"",
                entity.name
            )))
        }
    };
    let g = params.float_or("g", 0.0)?;
    if g.abs() > MAX_ASYMMETRY {
        return Err(entity.error(format!(
            "`g` lies between −{MAX_ASYMMETRY} and {MAX_ASYMMETRY}, found {g}"
        )));
    }
    let phase = HenyeyGreenstein::new(g);
    if kind == "cloud" {
        return cloud(entity, world_from_medium, phase, &spectrum)
            .map(|m| Medium::Cloud(Box::new(m)));
    }
    let scale = params.float_or("scale", 1.0)?;
    if scale.is_nan() || scale < 0.0 {
        return Err(entity.error(format!("`scale` is at least 0, found {scale}")));
    }
    if kind == "rgbgrid" {
        return rgb_grid(entity, world_from_medium, scale, phase, max_grid_samples)
            .map(|m| Medium::Grid(Box::new(m)));
    }
    // A homogeneous medium's measured preset, as pbrt-v4 reads it: in place of `sigma_a` and
    // `sigma_s` (which are then not read), still multiplied by `scale`.
    let preset = if kind == "homogeneous" {
        match params.string("preset")? {
            Some((name, p)) => Some(measured_media::coefficients(name).ok_or_else(|| {
                p.error(format!(
                    "no measured medium is named \"{}\"; pbrt-v4's are: {}",
                    crate::error::clip_to(name, 60),
                    measured_media::names().collect::<Vec<_>>().join(", ")
                ))
            })?),
            None => None,
        }
    } else {
        None
    };
    let (sigma_a, sigma_s) = match preset {
        Some(coefficients) => coefficients,
        None => (
            spectrum("sigma_a", DEFAULT_SIGMA_A, SpectrumUse::Index)?,
            spectrum("sigma_s", DEFAULT_SIGMA_S, SpectrumUse::Index)?,
        ),
    };
    let (sigma_a, sigma_s) = (sigma_a * scale, sigma_s * scale);
    match kind.as_str() {
        "homogeneous" => {
            let emission = spectrum("Le", Color::BLACK, SpectrumUse::Illuminant)?
                * params.float_or("Lescale", 1.0)?;
            Ok(Medium::Homogeneous(Homogeneous {
                sigma_a,
                sigma_s,
                emission,
                phase,
            }))
        }
        "uniformgrid" => {
            let (size, _) = grid_size(entity, max_grid_samples)?;
            let Some((values, p)) = params.numbers("density", ParamType::Float)? else {
                return Err(entity.error("a `uniformgrid` medium needs `\"float density\"`"));
            };
            let values = values.iter().map(|&v| v as f32).collect();
            let density = DensityGrid::new(size, values).map_err(|e| p.error(e.to_string()))?;
            let (emission, glow) = grid_glow(entity, size, &spectrum)?;
            let p0 = params.point3_or("p0", DVec3::ZERO)?;
            let p1 = params.point3_or("p1", DVec3::ONE)?;
            let bounds = Aabb::new(p0.min(p1), p0.max(p1));
            let transform = Transform::try_new(*world_from_medium)
                .map_err(|_| entity.error("the medium is placed by a singular transform"))?;
            let mut grid = GridMedium::new(
                sigma_a, sigma_s, emission, phase, density, bounds, transform,
            )
            .map_err(|e| entity.error(e.to_string()))?;
            if let Some(glow) = glow {
                grid = grid.with_glow(glow);
            }
            Ok(Medium::Grid(Box::new(grid)))
        }
        "nanovdb" => Err(entity.error(
            "NanoVDB files (the medium type \"nanovdb\") are not read: no well-kept Rust reader \
             of the format exists; give the grid as a \"uniformgrid\" medium (its \"density\" \
             values) or, in a YAML scene, as a Mitsuba .vol file",
        )),
        other => Err(entity.error(format!(
            "the medium type \"{other}\" is not read; rayforge reads homogeneous, uniformgrid, \
             rgbgrid and cloud"
        ))),
    }
}

/// A `cloud`, as pbrt-v4's `CloudMedium::Create` reads it: `density` (1), `wispiness` (1),
/// `frequency` (5), `sigma_a` and `sigma_s` (1 when absent) and the box `p0`–`p1` (the unit
/// cube) in the medium's space, placed by `world_from_medium`. pbrt-v4 reads no `scale` for a
/// cloud, so rayforge does not either (one given is warned about as unused).
fn cloud(
    entity: &Entity,
    world_from_medium: &DMat4,
    phase: HenyeyGreenstein,
    spectrum: &impl Fn(&str, Color, SpectrumUse) -> Result<Color, SceneError>,
) -> Result<CloudMedium, SceneError> {
    let params = &entity.params;
    let sigma_a = spectrum("sigma_a", DEFAULT_SIGMA_A, SpectrumUse::Index)?;
    let sigma_s = spectrum("sigma_s", DEFAULT_SIGMA_S, SpectrumUse::Index)?;
    let scalar = |name: &str, default: f64| -> Result<f64, SceneError> {
        match params.float_at(name)? {
            None => Ok(default),
            Some((v, _)) if v.is_finite() && v >= 0.0 => Ok(v),
            Some((v, p)) => Err(p.error(format!(
                "a cloud's `{name}` is finite and at least 0, found {v}"
            ))),
        }
    };
    let density = scalar("density", 1.0)?;
    let wispiness = scalar("wispiness", 1.0)?;
    let frequency = scalar("frequency", 5.0)?;
    let p0 = params.point3_or("p0", DVec3::ZERO)?;
    let p1 = params.point3_or("p1", DVec3::ONE)?;
    let bounds = Aabb::new(p0.min(p1), p0.max(p1));
    let transform = Transform::try_new(*world_from_medium)
        .map_err(|_| entity.error("the medium is placed by a singular transform"))?;
    CloudMedium::new(
        sigma_a, sigma_s, phase, density, wispiness, frequency, bounds, transform,
    )
    .map_err(|e| entity.error(e.to_string()))
}

/// An `rgbgrid`, as pbrt-v4's `RGBGridMedium` reads it: `sigma_a` and `sigma_s` grids of
/// colours (`nx` × `ny` × `nz` rgb values, x fastest; either may be absent, then 1
/// throughout, not both) times `scale`, and light `Le` (a grid of colours, which needs
/// `sigma_a`) times `Lescale`, over the box `p0`–`p1` placed by `world_from_medium`; at most
/// `max_grid_samples` samples.
fn rgb_grid(
    entity: &Entity,
    world_from_medium: &DMat4,
    scale: f64,
    phase: HenyeyGreenstein,
    max_grid_samples: usize,
) -> Result<GridMedium, SceneError> {
    let params = &entity.params;
    let (size, count) = grid_size(entity, max_grid_samples)?;
    let colors = |name: &str| -> Result<Option<ColorGrid>, SceneError> {
        let Some((values, p)) = params.numbers(name, ParamType::Rgb)? else {
            return Ok(None);
        };
        if values.len() != 3 * count {
            return Err(p.error(format!(
                "a grid of nx × ny × nz = {count} samples takes {count} colours, found {}",
                values.len() / 3
            )));
        }
        let colors: Vec<Color> = values
            .chunks_exact(3)
            .map(|c| Color::new(c[0], c[1], c[2]))
            .collect();
        ColorGrid::new(size, &colors)
            .map(Some)
            .map_err(|e| p.error(e.to_string()))
    };
    let ones = || ColorGrid::new(size, &vec![Color::WHITE; count]);
    let (sigma_a, sigma_s, le) = (colors("sigma_a")?, colors("sigma_s")?, colors("Le")?);
    let (sigma_a, sigma_s) = match (sigma_a, sigma_s) {
        (None, None) => {
            return Err(entity
                .error("an `rgbgrid` medium needs `\"rgb sigma_a\"`, `\"rgb sigma_s\"` or both"))
        }
        (a, s) => {
            if le.is_some() && a.is_none() {
                return Err(entity.error("an `rgbgrid` giving `Le` needs `\"rgb sigma_a\"`"));
            }
            let fill = |g: Option<ColorGrid>| g.map_or_else(ones, Ok);
            (
                fill(a).map_err(|e| entity.error(e.to_string()))?,
                fill(s).map_err(|e| entity.error(e.to_string()))?,
            )
        }
    };
    let p0 = params.point3_or("p0", DVec3::ZERO)?;
    let p1 = params.point3_or("p1", DVec3::ONE)?;
    let bounds = Aabb::new(p0.min(p1), p0.max(p1));
    let transform = Transform::try_new(*world_from_medium)
        .map_err(|_| entity.error("the medium is placed by a singular transform"))?;
    let mut grid = GridMedium::of_colors(sigma_a, sigma_s, scale, phase, bounds, transform)
        .map_err(|e| entity.error(e.to_string()))?;
    if let Some(radiance) = le {
        let le_scale = params.float_or("Lescale", 1.0)?;
        if !(le_scale.is_finite() && le_scale >= 0.0) {
            return Err(entity.error(format!("`Lescale` is at least 0, found {le_scale}")));
        }
        grid = grid.with_glow(Glow::Colors {
            radiance,
            scale: le_scale,
        });
    }
    Ok(grid)
}

/// A grid's `nx`, `ny` and `nz` (1 where absent, as pbrt-v4), and the samples they make,
/// refused past `max_grid_samples` (before any grid is made of them; their product counted
/// without overflow, whatever the sizes).
fn grid_size(entity: &Entity, max_grid_samples: usize) -> Result<([usize; 3], usize), SceneError> {
    let size = |name: &str| -> Result<usize, SceneError> {
        match entity.params.integer(name)? {
            None => Ok(1),
            Some((n, p)) if n >= 1 => usize::try_from(n)
                .map_err(|_| p.error(format!("a grid's size {n} is past what memory can address"))),
            Some((n, p)) => Err(p.error(format!("a grid's size is at least 1, found {n}"))),
        }
    };
    let size = [size("nx")?, size("ny")?, size("nz")?];
    match size
        .iter()
        .try_fold(1usize, |n, &s| n.checked_mul(s))
        .filter(|&n| n <= max_grid_samples)
    {
        Some(count) => Ok((size, count)),
        None => Err(entity.error(format!(
            "a grid of nx × ny × nz = {} × {} × {} samples is past the limit of \
             {max_grid_samples} (--max-grid-samples)",
            size[0], size[1], size[2]
        ))),
    }
}

/// A `uniformgrid`'s light, as pbrt-v4's `GridMedium` reads it: `Le` (a spectrum) times the
/// grid `Lescale` (one value per sample, where given), or a blackbody at each sample's
/// `temperature` (less `temperatureoffset`, or its old name `temperaturecutoff`, times
/// `temperaturescale`), normalised to 1 at its peak, times `Lescale` where given; not both.
/// The uniform part (`Le` without `Lescale`), and the varying part where there is one.
fn grid_glow(
    entity: &Entity,
    size: [usize; 3],
    spectrum: &impl Fn(&str, Color, SpectrumUse) -> Result<Color, SceneError>,
) -> Result<(Color, Option<Glow>), SceneError> {
    let params = &entity.params;
    let le = spectrum("Le", Color::BLACK, SpectrumUse::Illuminant)?;
    let count = size[0] * size[1] * size[2];
    let samples = |name: &str| -> Result<Option<DensityGrid>, SceneError> {
        let Some((values, p)) = params.numbers(name, ParamType::Float)? else {
            return Ok(None);
        };
        if values.len() != count {
            return Err(p.error(format!(
                "a grid of nx × ny × nz = {count} samples takes {count} values, found {}",
                values.len()
            )));
        }
        if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(p.error(format!("values are finite and at least 0, found {v}")));
        }
        let values = values.iter().map(|&v| v as f32).collect();
        DensityGrid::new(size, values)
            .map(Some)
            .map_err(|e| p.error(e.to_string()))
    };
    let scale = samples("Lescale")?;
    let temperature = samples("temperature")?;
    match temperature {
        Some(temperature) => {
            if le.max_channel() > 0.0 {
                let p = params
                    .find(
                        "Le",
                        &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
                    )
                    .expect("read above");
                return Err(p.error("a grid gives `Le` or `temperature`, not both (as pbrt-v4)"));
            }
            let offset = match params.float("temperatureoffset")? {
                Some(v) => v,
                None => params.float_or("temperaturecutoff", 0.0)?,
            };
            let factor = params.float_or("temperaturescale", 1.0)?;
            if !(offset.is_finite() && factor.is_finite()) {
                return Err(entity.error("`temperatureoffset` and `temperaturescale` are finite"));
            }
            let hottest = (temperature.max_value() - offset) * factor;
            let table = BlackbodyTable::new(hottest, MAX_BLACKBODY_ENTRIES, blackbody_rgb);
            Ok((
                Color::BLACK,
                Some(Glow::Blackbody {
                    temperature,
                    offset,
                    factor,
                    scale,
                    table,
                }),
            ))
        }
        None => match scale {
            Some(scale) if le.max_channel() > 0.0 => Ok((
                Color::BLACK,
                Some(Glow::Scaled {
                    radiance: le,
                    scale,
                }),
            )),
            _ => Ok((le, None)),
        },
    }
}

/// The linear sRGB colour an RGB film sees of a blackbody at `kelvin` normalised to 1 at its
/// peak (pbrt-v4's `BlackbodySpectrum`).
fn blackbody_rgb(kelvin: f64) -> Color {
    // Wien's displacement law: the peak's wavelength, in nm.
    let peak = planck(2.897_771_955e6 / kelvin, kelvin);
    if peak.is_nan() || peak <= 0.0 {
        return Color::BLACK;
    }
    let c = xyz_to_linear_srgb(spectrum_to_xyz(|l| planck(l, kelvin) / peak));
    Color::new(c.red.max(0.0), c.green.max(0.0), c.blue.max(0.0))
}

/// The medium a name gives (empty: vacuum).
fn named(
    ids: &HashMap<String, MediumId>,
    name: &str,
    names: &MediaNames,
) -> Result<Option<MediumId>, SceneError> {
    if name.is_empty() {
        return Ok(None);
    }
    ids.get(name).copied().map(Some).ok_or_else(|| {
        names.loc.error(
            Some("MediumInterface"),
            format!(
                "no medium is named \"{}\" (`MakeNamedMedium` makes one)",
                crate::error::clip_to(name, 60)
            ),
        )
    })
}

/// A shape's interface: the media its `MediumInterface` names, and whether its material is
/// `interface` (a boundary only). pbrt-v4 leaves a ray crossing a surface whose two media
/// are the same in the medium it was in; so does `None`. An `interface` shape of `None`
/// changes nothing for any ray (pbrt-v4's rays skip it, its shadow rays in `volpath` too),
/// and is left out of the world.
pub fn interface(
    ids: &HashMap<String, MediumId>,
    names: Option<&MediaNames>,
    boundary_only: bool,
) -> Result<Option<MediumInterface>, SceneError> {
    let Some(names) = names else {
        return Ok(None);
    };
    let inside = named(ids, &names.inside, names)?;
    let outside = named(ids, &names.outside, names)?;
    if inside == outside {
        return Ok(None);
    }
    Ok(Some(MediumInterface {
        inside,
        outside,
        index_matched: boundary_only,
    }))
}

/// pbrt-v4's warning for an `AreaLightSource` on a shape of the `interface` material, whose
/// light it ignores (as rayforge does: a boundary has no surface to give off light).
pub fn note_boundary_light(shape: &ShapeEntity, warnings: &mut Vec<SceneError>) {
    if shape.area_light.is_some() {
        warnings.push(shape.entity.error(
            "the area light of a shape with the \"interface\" material gives no light (as \
             in pbrt-v4: the shape is only a boundary between media)",
        ));
    }
}

/// Whether the material `reference` names is pbrt-v4's `interface`.
pub fn is_boundary(desc: &Description, reference: &MaterialRef) -> bool {
    let entity = match reference {
        MaterialRef::Index(i) => desc.materials.get(*i).and_then(|m| m.as_ref()),
        MaterialRef::Named(name, _) => desc.named_materials.get(name),
    };
    entity.is_some_and(|e| {
        let kind = if e.directive == "MakeNamedMaterial" {
            e.params.string("type").ok().flatten().map(|(t, _)| t)
        } else {
            Some(e.name.as_str())
        };
        // pbrt-v4 reads `none` and an empty name as `interface`.
        matches!(kind, Some("interface" | "none" | ""))
    })
}

/// The camera's medium: the outside of the interface in force at `Camera`.
pub fn camera_medium(
    ids: &HashMap<String, MediumId>,
    names: Option<&MediaNames>,
) -> Result<Option<MediumId>, SceneError> {
    match names {
        Some(n) => named(ids, &n.outside, n),
        None => Ok(None),
    }
}
