//! Materials (`material:` as a mapping or a defined name) and their patterns.

use crate::assets::Assets;
use crate::defines::{is_reference, merge, Defines, Trail};
use crate::error::SceneError;
use crate::source::{
    as_str, check_keys, describe, is_mapping, is_number, is_sequence, required, Entry, Node, Source,
};
use crate::transform::transform_list;
use rayforge::shading::bsdf::{metal, METAL_NAMES};
use rayforge::shading::{
    Alpha, Bump, BumpKind, EmissionSide, Filter, Physical, PhysicalPatterns, UvMapping, UvPattern,
};
use rayforge::{Color, Material, Pattern, PatternKind, Transform};

/// The keys a material may have.
const MATERIAL_KEYS: &[&str] = &[
    "color",
    "ambient",
    "diffuse",
    "specular",
    "shininess",
    "reflective",
    "transparency",
    "refractive-index",
    "pattern",
    "bump",
    "gloss",
    "opacity",
    "matte-gloss-balance",
    "emission",
    "emission-side",
    "two-sided",
    "type",
    "metal",
    "eta",
    "k",
    "alpha",
    "roughness",
];

/// The path tracer's material types (`type:`), as scene files name them.
const PHYSICAL_TYPES: &[&str] = &[
    "diffuse",
    "conductor",
    "dielectric",
    "thin-dielectric",
    "plastic",
    "mirror",
];

/// The keys that only a physical material (`type:`) reads; which apply depends on the type.
const PHYSICAL_KEYS: &[&str] = &["metal", "eta", "k", "alpha", "roughness"];

/// The metal a conductor is when it names neither `metal` nor `eta` and `k`.
const DEFAULT_METAL: &str = "aluminium";

/// The refractive index of a dielectric, thin dielectric or plastic without `refractive-index`.
const DEFAULT_PHYSICAL_INDEX: f64 = 1.5;

/// The pattern types, as scene files name them.
const PATTERN_TYPES: &[&str] = &[
    "stripes",
    "gradient",
    "rings",
    "ring",
    "checkers",
    "radial-gradient",
    "blended",
    "perturbed",
    "map",
];

/// The faces of a cube map, in the order `PatternKind::CubeMap` stores them.
const CUBE_FACES: [&str; 6] = ["left", "front", "right", "back", "up", "down"];

/// Reads the entries of a `material:` value: a mapping, or the name of a defined one.
pub fn material_entries<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    node: &'n Node<'s>,
) -> Result<Vec<Entry<'n, 's>>, SceneError> {
    if is_reference(node) {
        defines.mapping_entries(source, node, "material", &mut Vec::new())
    } else {
        source.entries(node, "material")
    }
}

/// Builds a material from entries layered over `base` (the inherited or default material).
pub fn material<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    node: &'n Node<'s>,
    base: &Material,
) -> Result<Material, SceneError> {
    let entries = material_entries(source, defines, node)?;
    check_keys(source, &entries, "a material", MATERIAL_KEYS)?;
    let mut m = base.clone();
    for &Entry { name, value, .. } in &entries {
        let number = || source.number(value, name);
        match name {
            "color" => m.color = color(source, value, name)?,
            "ambient" => m.ambient = number()?,
            "diffuse" => m.diffuse = number()?,
            "specular" => m.specular = number()?,
            "shininess" => m.shininess = number()?,
            "reflective" => m.reflective = fraction(source, value, name)?,
            "transparency" => m.transparency = fraction(source, value, name)?,
            // A pattern here grades a physical material's index: read below.
            "refractive-index" if is_mapping(value) => {}
            "refractive-index" => m.refractive_index = number()?,
            "bump" => m.bump = Some(Box::new(bump(source, defines, assets, value)?)),
            "gloss" => m.gloss = fractions(source, value, name)?,
            "opacity" => m.opacity = fraction(source, value, name)?,
            "matte-gloss-balance" => {
                let (matte, gloss) = matte_gloss_balance(source, value)?;
                m.color = matte;
                m.gloss = gloss;
            }
            "emission" => m.emission = emission(source, value)?,
            "two-sided" => m.two_sided = source.boolean(value, name)?,
            "emission-side" => {
                m.emission_side = match source.string(value, name)? {
                    "front" => EmissionSide::Front,
                    "back" => EmissionSide::Back,
                    "both" => EmissionSide::Both,
                    other => {
                        return Err(source.error(
                            value,
                            name,
                            format!(
                                "unknown emission side `{other}`; expected front (where the \
                                 normal points), back or both"
                            ),
                        ))
                    }
                }
            }
            // The path tracer's material, read below from all its keys together.
            "type" | "metal" | "eta" | "k" | "alpha" | "roughness" => {}
            _ => m.pattern = Some(Box::new(pattern(source, defines, assets, value)?)),
        }
    }
    if let Some(physical) = physical(source, &entries)? {
        m.physical = Some(physical);
        m.physical_patterns = physical_patterns(source, defines, assets, &entries)?;
    } else if let Some(e) = entries
        .iter()
        .find(|e| e.name == "refractive-index" && is_mapping(e.value))
    {
        return Err(source.error(
            e.value,
            e.name,
            "a pattern of refractive indices needs a path tracer's material: add `type: \
             dielectric`, `thin-dielectric` or `plastic`",
        ));
    }
    Ok(m)
}

/// The patterns that vary a physical material's GGX width (`alpha` or `roughness` given as a
/// pattern mapping instead of a number) and refractive index (`refractive-index` likewise);
/// `None` when every parameter is a number. Which keys a type takes was checked by
/// [`physical`].
fn physical_patterns<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    entries: &[Entry<'n, 's>],
) -> Result<Option<Box<PhysicalPatterns>>, SceneError> {
    let mut patterns = PhysicalPatterns {
        alpha: None,
        eta: None,
    };
    for e in entries.iter().filter(|e| is_mapping(e.value)) {
        match e.name {
            "alpha" | "roughness" => {
                patterns.alpha = Some(Alpha {
                    pattern: pattern(source, defines, assets, e.value)?,
                    squared: e.name == "roughness",
                })
            }
            "refractive-index" => patterns.eta = Some(pattern(source, defines, assets, e.value)?),
            _ => {}
        }
    }
    Ok((patterns.alpha.is_some() || patterns.eta.is_some()).then(|| Box::new(patterns)))
}

/// `emission`: `[r, g, b]`, or one number meaning grey; no channel negative.
fn emission(source: &Source<'_>, node: &Node<'_>) -> Result<Color, SceneError> {
    let c = if is_sequence(node) {
        color(source, node, "emission")?
    } else if is_number(node) {
        let v = source.number(node, "emission")?;
        Color::new(v, v, v)
    } else {
        return Err(source.error(
            node,
            "emission",
            format!(
                "expected a colour [r, g, b] or one number, found {}",
                describe(node)
            ),
        ));
    };
    if c.red < 0.0 || c.green < 0.0 || c.blue < 0.0 {
        return Err(source.error(node, "emission", "emitted light cannot be negative"));
    }
    Ok(c)
}

/// The path tracer's material from `type` and the keys it takes (`metal`, `eta`, `k`,
/// `alpha`, `roughness`, `refractive-index`); `None` without `type`, when no key only a
/// physical material reads may be given.
fn physical(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
) -> Result<Option<Physical>, SceneError> {
    let find = |k: &str| entries.iter().find(|e| e.name == k);
    let Some(type_entry) = find("type") else {
        if let Some(e) = entries.iter().find(|e| PHYSICAL_KEYS.contains(&e.name)) {
            return Err(source.error(
                e.key,
                e.name,
                format!(
                    "`{}` applies to the path tracer's materials: add a `type:` that takes it \
                     ({})",
                    e.name,
                    types_taking(e.name)
                ),
            ));
        }
        return Ok(None);
    };
    let kind = source.string(type_entry.value, "type")?;
    let allowed: &[&str] = match kind {
        "conductor" => PHYSICAL_KEYS,
        "dielectric" | "plastic" => &["alpha", "roughness"],
        "diffuse" | "thin-dielectric" | "mirror" => &[],
        other => {
            return Err(source.error(
                type_entry.value,
                "type",
                format!(
                    "unknown material type `{other}`; expected one of: {}",
                    PHYSICAL_TYPES.join(", ")
                ),
            ))
        }
    };
    if let Some(e) = entries
        .iter()
        .find(|e| PHYSICAL_KEYS.contains(&e.name) && !allowed.contains(&e.name))
    {
        return Err(source.error(
            e.key,
            e.name,
            format!(
                "`{}` does not apply to `type: {kind}` (it applies to {})",
                e.name,
                types_taking(e.name)
            ),
        ));
    }
    let index = || -> Result<f64, SceneError> {
        match find("refractive-index") {
            // A pattern: its value at each hit replaces this (see `physical_patterns`).
            Some(e) if is_mapping(e.value) => Ok(DEFAULT_PHYSICAL_INDEX),
            Some(e) => {
                let index = source.number(e.value, "refractive-index")?;
                if !(1.0..=9.0).contains(&index) {
                    return Err(source.error(
                        e.value,
                        "refractive-index",
                        format!("a refractive index lies between 1 and 9 (for `type: {kind}`)"),
                    ));
                }
                Ok(index)
            }
            None => Ok(DEFAULT_PHYSICAL_INDEX),
        }
    };
    let physical = match kind {
        "diffuse" => Physical::Diffuse,
        "mirror" => Physical::Mirror,
        "thin-dielectric" => Physical::ThinDielectric { eta: index()? },
        "dielectric" => Physical::Dielectric {
            eta: index()?,
            alpha: alpha(source, entries)?,
        },
        "plastic" => Physical::Plastic {
            eta: index()?,
            alpha: alpha(source, entries)?,
        },
        _ => {
            let (eta, k) = conductor_index(source, entries)?;
            Physical::Conductor {
                eta,
                k,
                alpha: alpha(source, entries)?,
            }
        }
    };
    Ok(Some(physical))
}

/// The types that take the physical key `key`, for messages.
fn types_taking(key: &str) -> &'static str {
    match key {
        "alpha" | "roughness" => "`type: conductor`, `dielectric` and `plastic`",
        _ => "`type: conductor`",
    }
}

/// The GGX width from `alpha` (0 to 1) or `roughness` (0 to 1, alpha = roughness²); 0 (smooth)
/// without either.
fn alpha(source: &Source<'_>, entries: &[Entry<'_, '_>]) -> Result<f64, SceneError> {
    let find = |k: &str| entries.iter().find(|e| e.name == k);
    let (a, r) = (find("alpha"), find("roughness"));
    if let (Some(a), Some(r)) = (a, r) {
        let second = if a.key.span.start.index() > r.key.span.start.index() {
            a
        } else {
            r
        };
        return Err(source.error(
            second.key,
            second.name,
            "give `alpha` or `roughness` (alpha = roughness²), not both",
        ));
    }
    let Some(e) = a.or(r) else {
        return Ok(0.0);
    };
    if is_mapping(e.value) {
        // A pattern: its value at each hit replaces this (see `physical_patterns`).
        return Ok(0.0);
    }
    let v = source.number(e.value, e.name)?;
    if !(0.0..=1.0).contains(&v) {
        return Err(source.error(
            e.value,
            e.name,
            format!("`{}` lies between 0 (polished) and 1", e.name),
        ));
    }
    Ok(if e.name == "roughness" { v * v } else { v })
}

/// A conductor's complex index: `metal: NAME`, or `eta` and `k` given together; aluminium
/// without either.
fn conductor_index(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
) -> Result<(Color, Color), SceneError> {
    let find = |k: &str| entries.iter().find(|e| e.name == k);
    let (eta, k) = (find("eta"), find("k"));
    if let Some(m) = find("metal") {
        if let Some(e) = eta.or(k) {
            return Err(source.error(e.key, e.name, "give `metal` or `eta` and `k`, not both"));
        }
        let name = source.string(m.value, "metal")?;
        return metal(name).ok_or_else(|| {
            source.error(
                m.value,
                "metal",
                format!(
                    "unknown metal `{name}`; expected one of: {}",
                    METAL_NAMES.join(", ")
                ),
            )
        });
    }
    match (eta, k) {
        (None, None) => Ok(metal(DEFAULT_METAL).expect("the default metal is in the table")),
        (Some(e), None) | (None, Some(e)) => {
            let other = if e.name == "eta" { "k" } else { "eta" };
            Err(source.error(
                e.key,
                e.name,
                format!(
                    "`{}` needs `{other}` too: a metal's index is eta + i·k, per channel",
                    e.name
                ),
            ))
        }
        (Some(eta), Some(k)) => {
            let eta_c = color(source, eta.value, "eta")?;
            if eta_c.red <= 0.0 || eta_c.green <= 0.0 || eta_c.blue <= 0.0 {
                return Err(source.error(eta.value, "eta", "`eta` must be positive"));
            }
            let k_c = color(source, k.value, "k")?;
            if k_c.red < 0.0 || k_c.green < 0.0 || k_c.blue < 0.0 {
                return Err(source.error(k.value, "k", "`k` cannot be negative"));
            }
            Ok((eta_c, k_c))
        }
    }
}

/// Bumps on the normal: `type: waves` (`amplitude`, `wavelength`), `type: noise`
/// (`strength`) or `type: normal-map` (`file`, `mapping`, optional `strength`), each with an
/// optional `transform`.
fn bump<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    node: &'n Node<'s>,
) -> Result<Bump, SceneError> {
    let entries = source.entries(node, "bump")?;
    let get = |k: &str| entries.iter().find(|e| e.name == k).map(|e| e.value);
    let required =
        |k: &str| get(k).ok_or_else(|| source.error(node, k, format!("this bump needs `{k}:`")));
    let type_node = required("type")?;
    let kind = match source.string(type_node, "type")? {
        "waves" => {
            check_keys(
                source,
                &entries,
                "waves",
                &["type", "amplitude", "wavelength", "transform"],
            )?;
            let wavelength_node = required("wavelength")?;
            let wavelength = source.number(wavelength_node, "wavelength")?;
            if wavelength <= 0.0 {
                return Err(source.error(
                    wavelength_node,
                    "wavelength",
                    "the wavelength must be positive",
                ));
            }
            BumpKind::Waves {
                amplitude: source.number(required("amplitude")?, "amplitude")?,
                wavelength,
            }
        }
        "noise" => {
            check_keys(
                source,
                &entries,
                "noise bumps",
                &["type", "strength", "transform"],
            )?;
            BumpKind::Noise {
                strength: source.number(required("strength")?, "strength")?,
            }
        }
        "normal-map" => {
            check_keys(
                source,
                &entries,
                "a normal map",
                &[
                    "type",
                    "file",
                    "mapping",
                    "major-radius",
                    "strength",
                    "transform",
                ],
            )?;
            let file = required("file")?;
            let path = assets.resolve(source.string(file, "file")?);
            let map = assets
                .texture(&path)
                .map_err(|e| source.error(file, "file", e.message))?;
            let mapping_node = required("mapping")?;
            let mapping = match source.string(mapping_node, "mapping")? {
                "spherical" => UvMapping::Spherical,
                "planar" => UvMapping::Planar,
                "cylindrical" => UvMapping::Cylindrical,
                "toroidal" => UvMapping::Toroidal {
                    major: match get("major-radius") {
                        Some(n) => source.number(n, "major-radius")?,
                        None => 1.0,
                    },
                },
                other => {
                    return Err(source.error(
                        mapping_node,
                        "mapping",
                        format!(
                            "unknown mapping `{other}` for a normal map; expected one of: \
                             spherical, planar, cylindrical, toroidal"
                        ),
                    ))
                }
            };
            let strength = match get("strength") {
                Some(n) => source.number(n, "strength")?,
                None => 1.0,
            };
            BumpKind::NormalMap {
                map,
                mapping,
                strength,
            }
        }
        other => {
            return Err(source.error(
                type_node,
                "type",
                format!("unknown bump type `{other}`; expected waves, noise or normal-map"),
            ))
        }
    };
    let mut b = Bump::new(kind);
    if let Some(t) = get("transform") {
        b.transform = checked(
            source,
            t,
            transform_list(source, defines, t, &mut Trail::new())?,
        )?;
    }
    Ok(b)
}

/// Fundamentals of Ray Tracing's `SetMatteGlossBalance(g, matte, gloss)`:
/// `{balance: g, matte: [r, g, b], gloss: [r, g, b]}` makes the matte colour `(1 - g)·matte` and
/// the gloss colour `g·gloss`, splitting the light a surface returns between the two.
fn matte_gloss_balance(source: &Source<'_>, node: &Node<'_>) -> Result<(Color, Color), SceneError> {
    let entries = source.entries(node, "matte-gloss-balance")?;
    check_keys(
        source,
        &entries,
        "`matte-gloss-balance`",
        &["balance", "matte", "gloss"],
    )?;
    let get = |k: &str| required(source, &entries, node, k, "`matte-gloss-balance`");
    let balance_node = get("balance")?;
    let balance = source.number(balance_node, "balance")?;
    if !(0.0..=1.0).contains(&balance) {
        return Err(source.error(balance_node, "balance", "the balance lies between 0 and 1"));
    }
    let matte = color(source, get("matte")?, "matte")?;
    let gloss = fractions(source, get("gloss")?, "gloss")?;
    Ok((matte * (1.0 - balance), gloss * balance))
}

/// A share of light from 0 to 1: `reflective`, `transparency`, `opacity`. More than 1 (or
/// less than 0) would make a secondary ray carry more light than the ray that spawned it, so
/// weights would grow with every bounce and no bailout could ever prune the ray tree.
fn fraction(source: &Source<'_>, node: &Node<'_>, key: &str) -> Result<f64, SceneError> {
    let value = source.number(node, key)?;
    if !(0.0..=1.0).contains(&value) {
        return Err(source.error(
            node,
            key,
            format!("expected a share of light from 0 to 1, found {value}"),
        ));
    }
    Ok(value)
}

/// A colour of shares from 0 to 1 (`gloss`), for the same reason as [`fraction`].
fn fractions(source: &Source<'_>, node: &Node<'_>, key: &str) -> Result<Color, SceneError> {
    let [r, g, b] = source.triple(node, key)?;
    if [r, g, b].iter().any(|c| !(0.0..=1.0).contains(c)) {
        return Err(source.error(
            node,
            key,
            format!("expected a share of light from 0 to 1 in each channel, found [{r}, {g}, {b}]"),
        ));
    }
    Ok(Color::new(r, g, b))
}

/// `[r, g, b]`.
pub fn color(source: &Source<'_>, node: &Node<'_>, key: &str) -> Result<Color, SceneError> {
    let [r, g, b] = source.triple(node, key)?;
    Ok(Color::new(r, g, b))
}

/// A pattern mapping: `type`, `colors` (colours or nested patterns), `transform`, and the
/// extras' keys (`patterns` for blends, `pattern` and `scale` for perturbation); or the name
/// of a defined one.
pub fn pattern<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    node: &'n Node<'s>,
) -> Result<Pattern, SceneError> {
    let mut nesting = Nesting {
        trail: Trail::new(),
        depth: 0,
    };
    nested_pattern(source, defines, assets, node, &mut nesting)
}

/// Patterns may nest this deep (inline or through defines). Reading and shading both recurse
/// once a level; no real pattern needs more than a handful.
const MAX_PATTERN_DEPTH: usize = 64;

/// Where a pattern being read sits: the defined patterns it is inside (a pattern that contains
/// itself is a cycle) and how deep it is.
struct Nesting<'n> {
    trail: Trail<'n>,
    depth: usize,
}

/// A pattern at any depth (see [`pattern`]).
fn nested_pattern<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    node: &'n Node<'s>,
    nesting: &mut Nesting<'n>,
) -> Result<Pattern, SceneError> {
    if nesting.depth >= MAX_PATTERN_DEPTH {
        return Err(source.error(
            node,
            "pattern",
            format!("patterns nest deeper than {MAX_PATTERN_DEPTH} levels"),
        ));
    }
    source.spend(node, "pattern")?;
    let mark = nesting.trail.len();
    nesting.depth += 1;
    let pattern = pattern_here(source, defines, assets, node, nesting);
    nesting.depth -= 1;
    nesting.trail.truncate(mark);
    pattern
}

/// The pattern at `node`, its parts read through [`nested_pattern`].
fn pattern_here<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    node: &'n Node<'s>,
    nesting: &mut Nesting<'n>,
) -> Result<Pattern, SceneError> {
    let mut entries = Vec::new();
    if let Some(name) = as_str(node) {
        entries = defines.mapping_entries(source, node, "pattern", &mut nesting.trail)?;
        // On the trail while its parts are read: a part that names it again is a cycle.
        nesting.trail.push(name);
    } else {
        for e in source.entries(node, "pattern")? {
            merge(&mut entries, e);
        }
    }
    let get = |k: &str| entries.iter().find(|e| e.name == k).map(|e| e.value);
    let type_node =
        get("type").ok_or_else(|| source.error(node, "type", "a pattern needs a `type:`"))?;
    let kind_name = source.string(type_node, "type")?;
    let allowed: &[&str] = match kind_name {
        "map" => &[
            "type",
            "mapping",
            "uv_pattern",
            "major-radius",
            "transform",
            "left",
            "front",
            "right",
            "back",
            "up",
            "down",
        ],
        "blended" => &["type", "patterns", "transform"],
        "perturbed" => &["type", "pattern", "scale", "transform"],
        _ => &["type", "colors", "transform"],
    };
    if !PATTERN_TYPES.contains(&kind_name) {
        let hint = if kind_name == "nested" {
            " (a pattern nests by standing in place of a colour in `colors:`)"
        } else {
            ""
        };
        return Err(source.error(
            type_node,
            "type",
            format!(
                "unknown pattern type `{kind_name}`; expected one of: {}{hint}",
                PATTERN_TYPES.join(", ")
            ),
        ));
    }
    check_keys(source, &entries, &format!("a {kind_name} pattern"), allowed)?;
    let required = |k: &str| {
        get(k).ok_or_else(|| {
            source.error(type_node, k, format!("a {kind_name} pattern needs `{k}:`"))
        })
    };
    let kind = match kind_name {
        "map" => {
            let mapping_node = required("mapping")?;
            match source.string(mapping_node, "mapping")? {
                "cube" => {
                    let mut faces = Vec::with_capacity(6);
                    for face in CUBE_FACES {
                        faces.push(uv_pattern(source, assets, required(face)?, face)?);
                    }
                    let faces: [UvPattern; 6] = faces
                        .try_into()
                        .map_err(|_| source.error(node, "mapping", "a cube map needs six faces"))?;
                    PatternKind::CubeMap(Box::new(faces))
                }
                name => {
                    let mapping = match name {
                        "spherical" => UvMapping::Spherical,
                        "planar" => UvMapping::Planar,
                        "cylindrical" => UvMapping::Cylindrical,
                        "toroidal" => {
                            let major = match get("major-radius") {
                                Some(n) => source.number(n, "major-radius")?,
                                None => 1.0,
                            };
                            UvMapping::Toroidal { major }
                        }
                        other => {
                            return Err(source.error(
                                mapping_node,
                                "mapping",
                                format!(
                                    "unknown mapping `{other}`; expected one of: spherical, planar, cylindrical, toroidal, cube"
                                ),
                            ))
                        }
                    };
                    PatternKind::Map {
                        mapping,
                        uv: uv_pattern(source, assets, required("uv_pattern")?, "uv_pattern")?,
                    }
                }
            }
        }
        "blended" => {
            let list = required("patterns")?;
            let mut parts = Vec::new();
            for p in source.sequence(list, "patterns")? {
                parts.push(nested_pattern(source, defines, assets, p, nesting)?);
            }
            if parts.is_empty() {
                return Err(source.error(list, "patterns", "a blend needs at least one pattern"));
            }
            PatternKind::Blended(parts)
        }
        "perturbed" => PatternKind::Perturbed {
            pattern: Box::new(nested_pattern(
                source,
                defines,
                assets,
                required("pattern")?,
                nesting,
            )?),
            scale: match get("scale") {
                Some(s) => source.number(s, "scale")?,
                None => DEFAULT_PERTURBATION,
            },
        },
        _ => {
            let list = required("colors")?;
            let mut parts = Vec::new();
            for c in source.sequence(list, "colors")? {
                parts.push(color_or_pattern(source, defines, assets, c, nesting)?);
            }
            let two =
                |parts: &mut Vec<Pattern>| -> Result<(Box<Pattern>, Box<Pattern>), SceneError> {
                    if parts.len() != 2 {
                        return Err(source.error(
                            list,
                            "colors",
                            format!(
                                "a {kind_name} pattern takes exactly 2 colors, found {}",
                                parts.len()
                            ),
                        ));
                    }
                    let b = parts.pop().expect("two parts");
                    let a = parts.pop().expect("two parts");
                    Ok((Box::new(a), Box::new(b)))
                };
            if parts.len() < 2 && kind_name != "gradient" && kind_name != "radial-gradient" {
                return Err(source.error(
                    list,
                    "colors",
                    format!(
                        "a {kind_name} pattern needs at least 2 colors, found {}",
                        parts.len()
                    ),
                ));
            }
            match kind_name {
                "stripes" => PatternKind::Stripes(parts),
                "rings" | "ring" => PatternKind::Rings(parts),
                "checkers" => PatternKind::Checkers(parts),
                "gradient" => {
                    let (a, b) = two(&mut parts)?;
                    PatternKind::Gradient(a, b)
                }
                _ => {
                    let (a, b) = two(&mut parts)?;
                    PatternKind::RadialGradient(a, b)
                }
            }
        }
    };
    let transform = match get("transform") {
        Some(t) => checked(
            source,
            t,
            transform_list(source, defines, t, &mut Trail::new())?,
        )?,
        None => Transform::IDENTITY,
    };
    Ok(Pattern::new(kind).with_transform(transform))
}

/// How far a perturbed pattern moves points when the file does not say (the book suggests
/// 20 % or less of a pattern cell).
const DEFAULT_PERTURBATION: f64 = 0.2;

/// A `colors:` entry: `[r, g, b]` for a solid colour, or a nested pattern mapping.
fn color_or_pattern<'n, 's>(
    source: &Source<'s>,
    defines: &Defines<'n, 's>,
    assets: &mut Assets,
    node: &'n Node<'s>,
    nesting: &mut Nesting<'n>,
) -> Result<Pattern, SceneError> {
    if is_sequence(node) {
        source.spend(node, "colors")?;
        return Ok(Pattern::solid(color(source, node, "colors")?));
    }
    if as_str(node).is_some() || is_mapping(node) {
        return nested_pattern(source, defines, assets, node, nesting);
    }
    Err(source.error(
        node,
        "colors",
        format!(
            "expected a colour [r, g, b] or a pattern, found {}",
            describe(node)
        ),
    ))
}

/// A transform checked for invertibility, located at the list that produced it.
pub fn checked(
    source: &Source<'_>,
    node: &Node<'_>,
    matrix: glam::DMat4,
) -> Result<Transform, SceneError> {
    Transform::try_new(matrix).map_err(|e| source.error(node, "transform", e.to_string()))
}

/// A 2D pattern on (u, v): `checkers` (`width`, `height`, two `colors`), `align_check`
/// (`colors` with `main`, `ul`, `ur`, `bl`, `br`) or `image` (`file`, optional `filter`:
/// `bilinear`, the default, or `nearest`).
fn uv_pattern(
    source: &Source<'_>,
    assets: &mut Assets,
    node: &Node<'_>,
    key: &str,
) -> Result<UvPattern, SceneError> {
    let entries = source.entries(node, key)?;
    let get = |k: &str| entries.iter().find(|e| e.name == k).map(|e| e.value);
    let required =
        |k: &str| get(k).ok_or_else(|| source.error(node, k, format!("a UV pattern needs `{k}:`")));
    let type_node = required("type")?;
    match source.string(type_node, "type")? {
        "checkers" => {
            check_keys(
                source,
                &entries,
                "a UV checkers pattern",
                &["type", "width", "height", "colors"],
            )?;
            let width = source.number(required("width")?, "width")?;
            let height = source.number(required("height")?, "height")?;
            let colors_node = required("colors")?;
            let colors = source.sequence(colors_node, "colors")?;
            let [a, b] = colors else {
                return Err(source.error(
                    colors_node,
                    "colors",
                    format!("UV checkers take exactly 2 colors, found {}", colors.len()),
                ));
            };
            Ok(UvPattern::Checkers {
                width,
                height,
                a: color(source, a, "colors")?,
                b: color(source, b, "colors")?,
            })
        }
        "align_check" => {
            check_keys(
                source,
                &entries,
                "an align_check pattern",
                &["type", "colors"],
            )?;
            let colors = source.entries(required("colors")?, "colors")?;
            check_keys(
                source,
                &colors,
                "align_check colors",
                &["main", "ul", "ur", "bl", "br"],
            )?;
            let pick = |k: &str| -> Result<Color, SceneError> {
                let value = colors
                    .iter()
                    .find(|e| e.name == k)
                    .map(|e| e.value)
                    .ok_or_else(|| {
                        source.error(node, k, format!("align_check colors need `{k}:`"))
                    })?;
                color(source, value, k)
            };
            Ok(UvPattern::AlignCheck {
                main: pick("main")?,
                ul: pick("ul")?,
                ur: pick("ur")?,
                bl: pick("bl")?,
                br: pick("br")?,
            })
        }
        "image" => {
            check_keys(
                source,
                &entries,
                "an image pattern",
                &["type", "file", "filter"],
            )?;
            let file = required("file")?;
            let path = assets.resolve(source.string(file, "file")?);
            let texture = assets
                .texture(&path)
                .map_err(|e| source.error(file, "file", e.message))?;
            let filter = match get("filter") {
                None => Filter::Bilinear,
                Some(f) => match source.string(f, "filter")? {
                    "bilinear" => Filter::Bilinear,
                    "nearest" => Filter::Nearest,
                    other => {
                        return Err(source.error(
                            f,
                            "filter",
                            format!("unknown filter `{other}`; expected bilinear or nearest"),
                        ))
                    }
                },
            };
            let texture = if texture.filter == filter {
                texture
            } else {
                let mut t = (*texture).clone();
                t.filter = filter;
                std::sync::Arc::new(t)
            };
            Ok(UvPattern::Image(texture))
        }
        "board" => {
            check_keys(
                source,
                &entries,
                "a board pattern",
                &["type", "squares", "border", "colors"],
            )?;
            let squares = source.integer(required("squares")?, "squares", 1)?.min(1 << 16) as u32;
            let border_node = required("border")?;
            let border = source.number(border_node, "border")?;
            if !(0.0..0.5).contains(&border) {
                return Err(source.error(
                    border_node,
                    "border",
                    "the border is a fraction of the face on each side, from 0 to below 0.5",
                ));
            }
            let colors = source.entries(required("colors")?, "colors")?;
            check_keys(source, &colors, "board colors", &["light", "dark", "border"])?;
            let pick = |k: &str| -> Result<Color, SceneError> {
                let value = colors.iter().find(|e| e.name == k).map(|e| e.value).ok_or_else(
                    || source.error(node, k, format!("board colors need `{k}:`")),
                )?;
                color(source, value, k)
            };
            Ok(UvPattern::Board {
                squares,
                border,
                light: pick("light")?,
                dark: pick("dark")?,
                edge: pick("border")?,
            })
        }
        other => Err(source.error(
            type_node,
            "type",
            format!(
                "unknown UV pattern type `{other}`; expected one of: checkers, align_check, image, board"
            ),
        )),
    }
}
