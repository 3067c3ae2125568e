//! `medium:` items: named participating media (fog, smoke, coloured liquids, wax), which
//! objects bound with `interior:` and `exterior:` and the camera and world sit in
//! (`medium:`). Only the path tracer renders them (the command warns under the others).
//!
//! ```yaml
//! - medium: fog                # its name, for later items (defined before its use)
//!   type: homogeneous          # the default; or grid, or cloud
//!   sigma-a: 0.01              # absorption per unit length: a number or [r, g, b]
//!   sigma-s: [0.1, 0.1, 0.12]  # scattering per unit length
//!   # or instead: albedo: 0.9 (σs / σt) with density: 0.2 (σt; homogeneous only, default 1)
//!   scale: 1                   # multiplies σa and σs (default 1)
//!   g: 0.3                     # Henyey–Greenstein asymmetry, −0.99 to 0.99 (default 0)
//!   emission: [0, 0, 0]        # radiance given off per unit of absorption (default 0)
//! - medium: smoke
//!   type: grid                 # the coefficients where the density is 1
//!   sigma-s: 4
//!   size: [2, 2, 1]            # samples along x, y and z, then
//!   data: [0, 1, 0.5, 2]       # the densities, x fastest
//!   # or: file: smoke.vol      # Mitsuba's grid volume (float32, one channel)
//!   bounds: [[-1, 0, -1], [1, 2, 1]]  # the grid's box (default the .vol's, else the unit cube)
//!   transform: [[rotate-y, 0.5]]      # places the box (a transform list)
//! - medium: sky
//!   type: cloud                # pbrt-v4's procedural cloud; σa, σs (or albedo) where dense
//!   sigma-s: 4
//!   density: 1                 # how dense the noise's peaks are (default 1)
//!   wispiness: 1               # how far the noise draws itself out into wisps (default 1)
//!   frequency: 5               # noise features per unit of the box's space (default 5)
//!   bounds: [[-1, 0, -1], [1, 1, 1]]  # the cloud's box (default the unit cube), and
//!   transform: [[scale, 2, 1, 2]]     # its place, as a grid's
//! ```

use crate::assets::Assets;
use crate::defines::{Defines, Trail};
use crate::error::SceneError;
use crate::material::checked;
use crate::source::{check_keys, required, Entry, Node, Source};
use crate::transform::transform_list;
use rayforge::math::{point, Aabb, Transform};
use rayforge::media::{
    coefficient, CloudMedium, DensityGrid, GridMedium, HenyeyGreenstein, Homogeneous, Medium,
    MediumError, MediumId, MediumInterface, MAX_ASYMMETRY,
};
use rayforge::Color;

/// The keys of a medium item.
const KEYS: &[&str] = &[
    "medium",
    "type",
    "sigma-a",
    "sigma-s",
    "albedo",
    "density",
    "scale",
    "g",
    "emission",
    "size",
    "data",
    "file",
    "bounds",
    "transform",
    "wispiness",
    "frequency",
];

/// The keys only a grid reads.
const GRID_ONLY_KEYS: &[&str] = &["size", "data", "file"];

/// The keys a grid and a cloud read: the box and its place.
const BOX_KEYS: &[&str] = &["bounds", "transform"];

/// The keys only a cloud reads.
const CLOUD_ONLY_KEYS: &[&str] = &["wispiness", "frequency"];

/// A cloud's `density`, `wispiness` and `frequency` where not given: pbrt-v4's.
const CLOUD_DEFAULTS: [(&str, f64); 3] = [("density", 1.0), ("wispiness", 1.0), ("frequency", 5.0)];

/// What a `medium:` item's `type` says.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Homogeneous,
    Grid,
    Cloud,
}

impl Kind {
    /// Whether this kind reads `key` (of the keys not every medium has).
    fn reads(self, key: &str) -> bool {
        let in_any = |lists: &[&[&str]]| lists.iter().any(|l| l.contains(&key));
        match self {
            Kind::Homogeneous => !in_any(&[GRID_ONLY_KEYS, BOX_KEYS, CLOUD_ONLY_KEYS]),
            Kind::Grid => !in_any(&[CLOUD_ONLY_KEYS]),
            // pbrt-v4's cloud gives off no light.
            Kind::Cloud => !in_any(&[GRID_ONLY_KEYS, &["emission"]]),
        }
    }

    /// The `type: …` that reads `key`, for the error that names it.
    fn readers_of(key: &str) -> &'static str {
        if GRID_ONLY_KEYS.contains(&key) {
            "only a `type: grid` medium has this key"
        } else if CLOUD_ONLY_KEYS.contains(&key) {
            "only a `type: cloud` medium has this key"
        } else if BOX_KEYS.contains(&key) {
            "only a `type: grid` or `type: cloud` medium has this key"
        } else {
            "a `type: cloud` medium gives off no light (pbrt-v4's cloud has no emission)"
        }
    }
}

/// A `.vol` file's header: `VOL`, version 3, encoding, three sizes, channels, a box.
const VOL_HEADER_BYTES: usize = 48;

/// The material name of a surface that only separates media: rays cross it unbent, it
/// neither reflects nor blocks light (reserved: a define of that name is not reachable).
pub const INTERFACE: &str = "interface";

/// The name `interior:`, `exterior:` and `medium:` take for empty space.
pub const VACUUM: &str = "vacuum";

/// Stands for the world's medium in an object's interface until the whole file is read
/// (the `world:` item may come after the object): [`resolve_around`] replaces it.
const AROUND: MediumId = MediumId(u32::MAX);

/// What an object's (or its groups') `interior:`, `exterior:` and `material: interface` say.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MediaKeys {
    /// `interior:`, if given (`Some(None)`: vacuum).
    pub interior: Option<Option<MediumId>>,
    /// `exterior:`, if given.
    pub exterior: Option<Option<MediumId>>,
    /// `material: interface`: the surface only separates media.
    pub index_matched: bool,
}

impl MediaKeys {
    /// Nothing said.
    pub const NONE: Self = Self {
        interior: None,
        exterior: None,
        index_matched: false,
    };

    /// The interface they give an object: none where nothing is said (a ray crossing the
    /// surface stays in its medium); else the interior (vacuum unless given) and the exterior
    /// (the world's medium unless given).
    pub fn interface(&self) -> Option<MediumInterface> {
        if self.interior.is_none() && self.exterior.is_none() && !self.index_matched {
            return None;
        }
        Some(MediumInterface {
            inside: self.interior.flatten(),
            outside: self.exterior.unwrap_or(Some(AROUND)),
            index_matched: self.index_matched,
        })
    }
}

/// Gives the objects whose exterior was left to the world the world's medium `around`
/// (`None`: vacuum).
pub fn resolve_around(objects: &mut [rayforge::Object], around: Option<MediumId>) {
    for interface in objects.iter_mut().filter_map(|o| o.media.as_mut()) {
        if interface.outside == Some(AROUND) {
            interface.outside = around;
        }
    }
}

/// A medium named by the camera or the world, looked up once the whole file is read (they
/// may come before the `medium:` item): the name, and the error for a name never defined.
pub struct NamedLater {
    name: String,
    unknown: SceneError,
}

impl NamedLater {
    /// The name `node` gives under `key`.
    pub fn new(source: &Source<'_>, node: &Node<'_>, key: &str) -> Result<Self, SceneError> {
        let name = source.string(node, key)?.to_string();
        let unknown = source.error(
            node,
            key,
            format!("no medium is named `{name}` (`vacuum` is empty space)"),
        );
        Ok(Self { name, unknown })
    }

    /// The medium it names, among those read.
    pub fn resolve(self, defines: &Defines<'_, '_>) -> Result<Option<MediumId>, SceneError> {
        if self.name == VACUUM {
            return Ok(None);
        }
        defines.medium(&self.name).map(Some).ok_or(self.unknown)
    }
}

/// Whether a top-level item is a `medium:` (not an `add:` whose own key `medium` names one,
/// as a camera's does).
pub fn is_medium(entries: &[Entry<'_, '_>]) -> bool {
    entries.iter().any(|e| e.name == "medium") && !entries.iter().any(|e| e.name == "add")
}

/// Reads a `medium:` item: its name and the medium (a grid of at most `max_grid_samples`
/// samples, `LoadOptions::max_grid_samples`).
pub fn medium<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    item: &'n Node<'s>,
    entries: &[Entry<'n, 's>],
    max_grid_samples: usize,
) -> Result<(&'n str, Medium), SceneError> {
    check_keys(source, entries, "a medium", KEYS)?;
    let name_node = required(source, entries, item, "medium", "a medium")?;
    let name = source.string(name_node, "medium")?;
    if name == VACUUM {
        return Err(source.error(
            name_node,
            "medium",
            "`vacuum` names empty space; give the medium another name",
        ));
    }
    let get = |key: &str| entries.iter().find(|e| e.name == key);
    let kind = match get("type") {
        None => Kind::Homogeneous,
        Some(e) => match source.string(e.value, "type")? {
            "homogeneous" => Kind::Homogeneous,
            "grid" => Kind::Grid,
            "cloud" => Kind::Cloud,
            other => {
                return Err(source.error(
                    e.value,
                    "type",
                    format!("unknown medium type `{other}`; expected homogeneous, grid or cloud"),
                ))
            }
        },
    };
    if let Some(e) = entries.iter().find(|e| !kind.reads(e.name)) {
        return Err(source.error(e.key, e.name, Kind::readers_of(e.name)));
    }
    let spectrum = |key: &'static str, default: Color| -> Result<Color, SceneError> {
        match get(key) {
            None => Ok(default),
            Some(e) => {
                let c = match source.number(e.value, key) {
                    Ok(v) => Color::new(v, v, v),
                    Err(_) if crate::source::is_sequence(e.value) => {
                        crate::material::color(source, e.value, key)?
                    }
                    Err(err) => return Err(err),
                };
                coefficient(key, c).map_err(|m| source.error(e.value, key, m.to_string()))
            }
        }
    };
    let scalar = |key: &'static str, default: f64| -> Result<f64, SceneError> {
        get(key).map_or(Ok(default), |e| source.number(e.value, key))
    };
    let (mut sigma_a, mut sigma_s) = match get("albedo") {
        Some(e) => {
            if let Some(both) = get("sigma-a").or_else(|| get("sigma-s")) {
                return Err(source.error(
                    both.key,
                    both.name,
                    "a medium gives either `albedo` (with `density`) or `sigma-a` and `sigma-s`, not both",
                ));
            }
            let albedo = spectrum("albedo", Color::WHITE)?;
            if albedo.max_channel() > 1.0 {
                return Err(source.error(e.value, "albedo", "an albedo lies between 0 and 1"));
            }
            // A grid's densities are its data and a cloud's `density` is its noise's: the
            // albedo then stands for the coefficients where the density is 1.
            let density = match kind {
                Kind::Grid => {
                    if let Some(d) = get("density") {
                        return Err(source.error(
                            d.key,
                            "density",
                            "a grid's density is its data; scale it with `scale`",
                        ));
                    }
                    1.0
                }
                Kind::Cloud => 1.0,
                Kind::Homogeneous => scalar("density", 1.0)?,
            };
            if density < 0.0 {
                let d = get("density").expect("given");
                return Err(source.error(d.value, "density", "a density is at least 0"));
            }
            ((Color::WHITE - albedo) * density, albedo * density)
        }
        None => {
            if let Some(d) = get("density").filter(|_| kind != Kind::Cloud) {
                return Err(source.error(d.key, "density", "`density` goes with `albedo`"));
            }
            (
                spectrum("sigma-a", Color::BLACK)?,
                spectrum("sigma-s", Color::BLACK)?,
            )
        }
    };
    let scale = scalar("scale", 1.0)?;
    if scale < 0.0 {
        let e = get("scale").expect("given");
        return Err(source.error(e.value, "scale", "a medium's scale is at least 0"));
    }
    sigma_a = sigma_a * scale;
    sigma_s = sigma_s * scale;
    let g = scalar("g", 0.0)?;
    if g.abs() > MAX_ASYMMETRY {
        let e = get("g").expect("given");
        return Err(source.error(
            e.value,
            "g",
            format!("g lies between −{MAX_ASYMMETRY} and {MAX_ASYMMETRY} (±1 would be a delta), found {g}"),
        ));
    }
    let phase = HenyeyGreenstein::new(g);
    let emission = spectrum("emission", Color::BLACK)?;
    let unit_cube = Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0));
    let at = get("bounds").map_or(item, |e| e.value);
    match kind {
        Kind::Homogeneous => {
            let medium = Homogeneous {
                sigma_a,
                sigma_s,
                emission,
                phase,
            };
            Ok((name, Medium::Homogeneous(medium)))
        }
        Kind::Grid => {
            let (density, vol_bounds) =
                density_grid(source, assets, item, entries, max_grid_samples)?;
            let (bounds, transform) =
                placed_box(source, defines, entries, vol_bounds.unwrap_or(unit_cube))?;
            let medium = GridMedium::new(
                sigma_a, sigma_s, emission, phase, density, bounds, transform,
            )
            .map_err(|m| source.error(at, "bounds", m.to_string()))?;
            Ok((name, Medium::Grid(Box::new(medium))))
        }
        Kind::Cloud => {
            let [density, wispiness, frequency] =
                CLOUD_DEFAULTS.map(|(key, default)| scalar(key, default));
            let (density, wispiness, frequency) = (density?, wispiness?, frequency?);
            let (bounds, transform) = placed_box(source, defines, entries, unit_cube)?;
            let medium = CloudMedium::new(
                sigma_a, sigma_s, phase, density, wispiness, frequency, bounds, transform,
            )
            // A negative `density`, `wispiness` or `frequency` is refused at its value.
            .map_err(|m| match m {
                MediumError::Parameter { name: key, .. } => {
                    source.error(get(key).map_or(item, |e| e.value), key, m.to_string())
                }
                _ => source.error(at, "bounds", m.to_string()),
            })?;
            Ok((name, Medium::Cloud(Box::new(medium))))
        }
    }
}

/// A grid's or a cloud's box (`bounds`, else `default`) in its own space, and the transform
/// that places it in the world (`transform`, else none).
fn placed_box(
    source: &Source<'_>,
    defines: &Defines<'_, '_>,
    entries: &[Entry<'_, '_>],
    default: Aabb,
) -> Result<(Aabb, Transform), SceneError> {
    let get = |key: &str| entries.iter().find(|e| e.name == key);
    let bounds = match get("bounds") {
        Some(e) => {
            let corners = source.sequence(e.value, "bounds")?;
            let [lo, hi] = corners else {
                return Err(source.error(
                    e.value,
                    "bounds",
                    "expected two corners, [[x, y, z], [x, y, z]]",
                ));
            };
            let (lo, hi) = (source.triple(lo, "bounds")?, source.triple(hi, "bounds")?);
            Aabb::new(point(lo[0], lo[1], lo[2]), point(hi[0], hi[1], hi[2]))
        }
        None => default,
    };
    let transform = match get("transform") {
        Some(e) => {
            let m = transform_list(source, defines, e.value, &mut Trail::new())?;
            checked(source, e.value, m)?
        }
        None => Transform::IDENTITY,
    };
    Ok((bounds, transform))
}

/// A grid medium's densities: `size` with `data`, or a `.vol` `file` (and its box); at most
/// `max_grid_samples` samples, checked from the size (the `.vol` file's size and header)
/// before they are read.
fn density_grid(
    source: &Source<'_>,
    assets: &mut Assets,
    item: &Node<'_>,
    entries: &[Entry<'_, '_>],
    max_grid_samples: usize,
) -> Result<(DensityGrid, Option<Aabb>), SceneError> {
    let get = |key: &str| entries.iter().find(|e| e.name == key);
    match (get("file"), get("data")) {
        (Some(file), None) => {
            if let Some(size) = get("size") {
                return Err(source.error(size.key, "size", "a `.vol` file gives its own size"));
            }
            let name = source.string(file.value, "file")?;
            let path = assets.resolve(name);
            let most = VOL_HEADER_BYTES as u64 + 4 * max_grid_samples as u64;
            let bytes = assets
                .volume_bytes(&path, most)
                .map_err(|e| source.error(file.value, "file", format!("`{name}`: {e}")))?;
            read_vol(&bytes, max_grid_samples)
                .map_err(|e| source.error(file.value, "file", format!("`{name}`: {e}")))
        }
        (None, Some(data)) => {
            let size_node = required(source, entries, item, "size", "a grid given by `data`")?;
            let [x, y, z] = source.triple(size_node, "size")?;
            let size = [x, y, z].map(|v| {
                if v >= 1.0 && v.fract() == 0.0 {
                    v as usize
                } else {
                    0
                }
            });
            if let Some(count) = size.iter().try_fold(1usize, |n, &s| n.checked_mul(s)) {
                if count > max_grid_samples {
                    return Err(source.error(
                        size_node,
                        "size",
                        format!(
                            "a grid of {x} × {y} × {z} samples is past the limit of \
                             {max_grid_samples} (--max-grid-samples)"
                        ),
                    ));
                }
            }
            let values = source
                .sequence(data.value, "data")?
                .iter()
                .map(|v| source.number(v, "data").map(|v| v as f32))
                .collect::<Result<Vec<_>, _>>()?;
            let grid = DensityGrid::new(size, values)
                .map_err(|e| source.error(data.value, "data", e.to_string()))?;
            Ok((grid, None))
        }
        (Some(_), Some(data)) => Err(source.error(
            data.key,
            "data",
            "a grid gives its densities by `data` or by `file`, not both",
        )),
        (None, None) => Err(source.error(
            item,
            "data",
            "a grid medium needs `data:` (with `size:`) or `file:`",
        )),
    }
}

/// Mitsuba's grid volume: `VOL`, version 3, encoding 1 (32-bit floats), the sizes along x,
/// y and z, one channel, the box (six floats), then the values, x fastest, little-endian; at
/// most `max_grid_samples` of them, their count multiplied without overflow.
fn read_vol(bytes: &[u8], max_grid_samples: usize) -> Result<(DensityGrid, Option<Aabb>), String> {
    if bytes.len() < VOL_HEADER_BYTES || &bytes[0..3] != b"VOL" {
        return Err("not a Mitsuba grid volume (it does not begin with `VOL`)".into());
    }
    if bytes[3] != 3 {
        return Err(format!(
            "version {} of the .vol format; only version 3 is read",
            bytes[3]
        ));
    }
    let int = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    if int(4) != 1 {
        return Err(format!(
            "encoding {}; only 1 (32-bit floats) is read",
            int(4)
        ));
    }
    let size = [int(8), int(12), int(16)];
    if int(20) != 1 {
        return Err(format!("{} channels; a density grid has one", int(20)));
    }
    if size.iter().any(|&s| s < 1) {
        return Err(format!("size {size:?}: each must be at least 1"));
    }
    let size = size.map(|s| s as usize);
    let Some(count) = size
        .iter()
        .try_fold(1usize, |n, &s| n.checked_mul(s))
        .filter(|&n| n <= max_grid_samples)
    else {
        return Err(format!(
            "{} × {} × {} samples; the limit is {max_grid_samples} (--max-grid-samples)",
            size[0], size[1], size[2]
        ));
    };
    let expected = VOL_HEADER_BYTES + 4 * count;
    if bytes.len() != expected {
        return Err(format!(
            "{} bytes where its header says {expected}",
            bytes.len()
        ));
    }
    let lo = point(
        f64::from(float(24)),
        f64::from(float(28)),
        f64::from(float(32)),
    );
    let hi = point(
        f64::from(float(36)),
        f64::from(float(40)),
        f64::from(float(44)),
    );
    let values = bytes[VOL_HEADER_BYTES..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect();
    let grid = DensityGrid::new(size, values).map_err(|e| e.to_string())?;
    Ok((grid, Some(Aabb::new(lo, hi))))
}

/// The medium `node` names under `key` (`vacuum`: none), which must be defined already.
pub fn medium_named(
    source: &Source<'_>,
    defines: &Defines<'_, '_>,
    node: &Node<'_>,
    key: &str,
) -> Result<Option<MediumId>, SceneError> {
    let name = source.string(node, key)?;
    if name == VACUUM {
        return Ok(None);
    }
    defines.medium(name).map(Some).ok_or_else(|| {
        source.error(
            node,
            key,
            format!("no medium is named `{name}` (a `medium:` item must come before its use; `vacuum` is empty space)"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayforge::media::MAX_GRID_SAMPLES;

    fn vol(size: [i32; 3], values: &[f32]) -> Vec<u8> {
        let mut b = b"VOL\x03".to_vec();
        for i in [1, size[0], size[1], size[2], 1] {
            b.extend(i.to_le_bytes());
        }
        for f in [-1.0f32, 0.0, -1.0, 1.0, 2.0, 1.0] {
            b.extend(f.to_le_bytes());
        }
        for v in values {
            b.extend(v.to_le_bytes());
        }
        b
    }

    #[test]
    fn a_vol_file_gives_its_grid_and_box() {
        let (grid, bounds) =
            read_vol(&vol([2, 1, 1], &[0.5, 1.5]), MAX_GRID_SAMPLES).expect("read");
        assert_eq!(grid.size(), [2, 1, 1]);
        assert_eq!(grid.lookup(point(0.75, 0.5, 0.5)), 1.5);
        assert_eq!(
            bounds,
            Some(Aabb::new(point(-1.0, 0.0, -1.0), point(1.0, 2.0, 1.0)))
        );
    }

    #[test]
    fn broken_vol_files_are_refused() {
        let good = vol([2, 1, 1], &[0.5, 1.5]);
        assert!(read_vol(&good[..50], MAX_GRID_SAMPLES).is_err());
        assert!(read_vol(b"VOX\x03", MAX_GRID_SAMPLES).is_err());
        let mut huge = vol([1 << 12, 1 << 12, 1 << 12], &[]);
        huge.truncate(VOL_HEADER_BYTES);
        assert!(read_vol(&huge, MAX_GRID_SAMPLES)
            .unwrap_err()
            .contains("limit"));
        let mut v2 = good.clone();
        v2[3] = 2;
        assert!(read_vol(&v2, MAX_GRID_SAMPLES).is_err());
        assert!(read_vol(&vol([0, 1, 1], &[]), MAX_GRID_SAMPLES).is_err());
        assert!(read_vol(&vol([1, 1, 1], &[-1.0]), MAX_GRID_SAMPLES).is_err());
    }

    /// The media fuzz target's finding: sizes whose product overflows 64 bits (three of
    /// 2³¹ − 1) panicked in the multiplication (debug builds) before the limit was asked.
    #[test]
    fn a_vol_header_whose_sample_count_overflows_is_refused() {
        let e = read_vol(&vol([i32::MAX; 3], &[1.0; 4]), MAX_GRID_SAMPLES).unwrap_err();
        assert!(
            e.contains("2147483647 × 2147483647 × 2147483647 samples"),
            "{e}"
        );
        assert!(e.contains("--max-grid-samples"), "{e}");
    }

    #[test]
    fn a_vol_file_past_a_lower_limit_is_refused_before_its_grid_is_made() {
        let e = read_vol(&vol([2, 2, 1], &[0.0; 4]), 3).unwrap_err();
        assert!(e.contains("the limit is 3 (--max-grid-samples)"), "{e}");
        assert!(read_vol(&vol([2, 2, 1], &[0.0; 4]), 4).is_ok());
    }
}
