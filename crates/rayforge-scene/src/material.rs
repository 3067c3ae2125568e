//! Materials (`material:` as a mapping or a defined name) and their patterns.

use crate::assets::Assets;
use crate::defines::{is_reference, merge, Defines, Trail};
use crate::error::SceneError;
use crate::source::{
    as_str, check_keys, describe, is_mapping, is_number, is_sequence, required, Entry, Node, Source,
};
use crate::transform::transform_list;
use rayforge::shading::bsdf::{metal, Coat, ConductorBase, Layers, METAL_NAMES};
use rayforge::shading::{
    Alpha, Bump, BumpKind, EmissionSide, Filter, Physical, PhysicalPatterns, UvMapping, UvPattern,
};
use rayforge::{Color, Material, Pattern, PatternKind, Transform};

/// The keys every material may have (the books' and the ones all renderers share); a physical
/// material (`type:`) may also have [`PHYSICAL_KEYS`].
const COMMON_KEYS: &[&str] = &[
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
];

/// The path tracer's material types (`type:`), as scene files name them.
const PHYSICAL_TYPES: &[&str] = &[
    "diffuse",
    "conductor",
    "dielectric",
    "thin-dielectric",
    "plastic",
    "mirror",
    "coated-diffuse",
    "coated-conductor",
    "diffuse-transmission",
];

/// The keys that only a physical material (`type:`) reads; which apply depends on the type.
const PHYSICAL_KEYS: &[&str] = &[
    "metal",
    "eta",
    "k",
    "alpha",
    "roughness",
    "alpha-u",
    "alpha-v",
    "roughness-u",
    "roughness-v",
    "base-alpha",
    "base-roughness",
    "base-alpha-u",
    "base-alpha-v",
    "base-roughness-u",
    "base-roughness-v",
    "thickness",
    "medium-albedo",
    "medium-g",
    "walk-depth",
    "walk-samples",
    "reflectance",
    "transmittance",
];

/// A metal's index keys.
const METAL_KEYS: &[&str] = &["metal", "eta", "k"];
/// The keys of a GGX width, isotropic or per tangent.
const WIDTH_KEYS: &[&str] = &[
    "alpha",
    "roughness",
    "alpha-u",
    "alpha-v",
    "roughness-u",
    "roughness-v",
];
/// The keys of a coated conductor's metal's GGX width.
const BASE_WIDTH_KEYS: &[&str] = &[
    "base-alpha",
    "base-roughness",
    "base-alpha-u",
    "base-alpha-v",
    "base-roughness-u",
    "base-roughness-v",
];
/// The keys of the medium between a coat and its base, and of the walk through it.
const LAYER_KEYS: &[&str] = &[
    "thickness",
    "medium-albedo",
    "medium-g",
    "walk-depth",
    "walk-samples",
];

/// The most events of one walk through a coated material's layers (`walk-depth`), and walks
/// per estimate (`walk-samples`): each costs time at every shading of the material.
const MAX_WALK_DEPTH: u64 = 100;
const MAX_WALK_SAMPLES: u64 = 64;
/// The thickest layer accepted (optical thickness; at 100 not a ray in 10⁴³ crosses it).
const MAX_THICKNESS: f64 = 100.0;

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
    check_keys(
        source,
        &entries,
        "a material",
        &[COMMON_KEYS, &["type"], PHYSICAL_KEYS].concat(),
    )?;
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
            _ if name == "type" || PHYSICAL_KEYS.contains(&name) => {}
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

/// The path tracer's material from `type` and the keys it takes (`metal`, `eta`, `k`, the
/// GGX widths, the coated types' layer keys, diffuse transmission's shares,
/// `refractive-index`); `None` without `type`, when no key only a physical material reads may
/// be given.
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
    let allowed: Vec<&str> = match kind {
        "conductor" => [METAL_KEYS, WIDTH_KEYS].concat(),
        "dielectric" => WIDTH_KEYS.to_vec(),
        "coated-diffuse" => [WIDTH_KEYS, LAYER_KEYS].concat(),
        "coated-conductor" => [METAL_KEYS, WIDTH_KEYS, BASE_WIDTH_KEYS, LAYER_KEYS].concat(),
        "plastic" => vec!["alpha", "roughness"],
        "diffuse-transmission" => vec!["reflectance", "transmittance"],
        "diffuse" | "thin-dielectric" | "mirror" => Vec::new(),
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
    let coat = || -> Result<Coat, SceneError> {
        let (alpha_u, alpha_v) = widths(source, entries, "")?;
        Ok(Coat {
            eta: index()?,
            alpha_u,
            alpha_v,
        })
    };
    let physical = match kind {
        "diffuse" => Physical::Diffuse,
        "mirror" => Physical::Mirror,
        "thin-dielectric" => Physical::ThinDielectric { eta: index()? },
        "dielectric" => {
            let (alpha_u, alpha_v) = widths(source, entries, "")?;
            Physical::Dielectric {
                eta: index()?,
                alpha_u,
                alpha_v,
            }
        }
        "plastic" => Physical::Plastic {
            eta: index()?,
            alpha: widths(source, entries, "")?.0,
        },
        "coated-diffuse" => Physical::CoatedDiffuse {
            coat: coat()?,
            layers: layers(source, entries)?,
        },
        "coated-conductor" => {
            let (eta, k) = conductor_index(source, entries)?;
            let (alpha_u, alpha_v) = widths(source, entries, "base-")?;
            Physical::CoatedConductor {
                coat: coat()?,
                base: ConductorBase {
                    eta,
                    k,
                    alpha_u,
                    alpha_v,
                },
                layers: layers(source, entries)?,
            }
        }
        "diffuse-transmission" => {
            let share = |key: &str| match find(key) {
                Some(e) => shares(source, e.value, key),
                None => Ok(Color::new(0.25, 0.25, 0.25)),
            };
            Physical::DiffuseTransmission {
                reflectance: share("reflectance")?,
                transmittance: share("transmittance")?,
            }
        }
        _ => {
            let (eta, k) = conductor_index(source, entries)?;
            let (alpha_u, alpha_v) = widths(source, entries, "")?;
            Physical::Conductor {
                eta,
                k,
                alpha_u,
                alpha_v,
            }
        }
    };
    Ok(Some(physical))
}

/// The types that take the physical key `key`, for messages.
fn types_taking(key: &str) -> &'static str {
    match key {
        "alpha" | "roughness" => {
            "`type: conductor`, `dielectric`, `plastic`, `coated-diffuse` and `coated-conductor`"
        }
        "alpha-u" | "alpha-v" | "roughness-u" | "roughness-v" => {
            "`type: conductor`, `dielectric`, `coated-diffuse` and `coated-conductor`"
        }
        "thickness" | "medium-albedo" | "medium-g" | "walk-depth" | "walk-samples" => {
            "`type: coated-diffuse` and `coated-conductor`"
        }
        "reflectance" | "transmittance" => "`type: diffuse-transmission`",
        _ if key.starts_with("base-") => "`type: coated-conductor`",
        _ => "`type: conductor` and `coated-conductor`",
    }
}

/// The GGX widths `(alpha_u, alpha_v)` from the keys `{prefix}alpha` or `{prefix}roughness`
/// (one width, 0 to 1, alpha = roughness²), or the pairs `{prefix}alpha-u` and
/// `{prefix}alpha-v` (or `roughness-u` and `roughness-v`) for an anisotropic surface, `u`
/// along the surface's tangent; (0, 0) (smooth) without any.
fn widths(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    prefix: &str,
) -> Result<(f64, f64), SceneError> {
    let named = |suffix: &str| {
        let key = format!("{prefix}{suffix}");
        entries.iter().find(move |e| e.name == key)
    };
    let given: Vec<&Entry<'_, '_>> = [
        "alpha",
        "roughness",
        "alpha-u",
        "alpha-v",
        "roughness-u",
        "roughness-v",
    ]
    .iter()
    .filter_map(|suffix| named(suffix))
    .collect();
    let Some(first) = given.iter().min_by_key(|e| e.key.span.start.index()) else {
        return Ok((0.0, 0.0));
    };
    let (a, r) = (named("alpha"), named("roughness"));
    if let (Some(a), Some(r)) = (a, r) {
        let second = later(a, r);
        return Err(source.error(
            second.key,
            second.name,
            format!("give `{prefix}alpha` or `{prefix}roughness` (alpha = roughness²), not both"),
        ));
    }
    if let Some(iso) = a.or(r) {
        if let Some(other) = given.iter().find(|e| e.name != iso.name) {
            let second = later(iso, other);
            return Err(source.error(
                second.key,
                second.name,
                format!(
                    "give one width (`{}`) or one per tangent (`{}-u` and `{}-v`), not both",
                    iso.name, iso.name, iso.name
                ),
            ));
        }
        if is_mapping(iso.value) {
            // A pattern: its value at each hit replaces this (see `physical_patterns`).
            return Ok((0.0, 0.0));
        }
        let v = width(source, iso)?;
        return Ok((v, v));
    }
    // Per tangent: a pair of one kind.
    let root = first.name.trim_end_matches("-u").trim_end_matches("-v");
    if let Some(other) = given.iter().find(|e| !e.name.starts_with(root)) {
        return Err(source.error(
            other.key,
            other.name,
            format!("give both widths as `{root}-u` and `{root}-v`, not one of each kind"),
        ));
    }
    let kind = &root[prefix.len()..];
    let (u, v) = (named(&format!("{kind}-u")), named(&format!("{kind}-v")));
    match (u, v) {
        (Some(u), Some(v)) => Ok((width(source, u)?, width(source, v)?)),
        _ => Err(source.error(
            first.key,
            first.name,
            format!(
                "`{}` needs `{root}-u` and `{root}-v` both: one width per tangent",
                first.name
            ),
        )),
    }
}

/// Of two entries, the one written later (the one an error names).
fn later<'e, 'n, 's>(a: &'e Entry<'n, 's>, b: &'e Entry<'n, 's>) -> &'e Entry<'n, 's> {
    if a.key.span.start.index() > b.key.span.start.index() {
        a
    } else {
        b
    }
}

/// One GGX width from an `alpha…` or `roughness…` key: 0 (polished) to 1, squared for
/// `roughness…`.
fn width(source: &Source<'_>, e: &Entry<'_, '_>) -> Result<f64, SceneError> {
    let v = source.number(e.value, e.name)?;
    if !(0.0..=1.0).contains(&v) {
        return Err(source.error(
            e.value,
            e.name,
            format!("`{}` lies between 0 (polished) and 1", e.name),
        ));
    }
    let roughness = e.name.trim_start_matches("base-").starts_with("roughness");
    Ok(if roughness { v * v } else { v })
}

/// A coated material's layers: `thickness` (optical, default 0.01), `medium-albedo` (0),
/// `medium-g` (0), `walk-depth` (10) and `walk-samples` (1), pbrt-v4's defaults.
fn layers(source: &Source<'_>, entries: &[Entry<'_, '_>]) -> Result<Layers, SceneError> {
    let find = |k: &str| entries.iter().find(|e| e.name == k);
    let mut layers = Layers::PBRT_DEFAULT;
    if let Some(e) = find("thickness") {
        let t = source.number(e.value, e.name)?;
        if !(t > 0.0 && t <= MAX_THICKNESS) {
            return Err(source.error(
                e.value,
                e.name,
                format!("a layer's thickness lies above 0 and at most {MAX_THICKNESS}"),
            ));
        }
        layers.thickness = t;
    }
    if let Some(e) = find("medium-albedo") {
        layers.albedo = shares(source, e.value, e.name)?;
    }
    if let Some(e) = find("medium-g") {
        let g = source.number(e.value, e.name)?;
        if !(g > -1.0 && g < 1.0) {
            return Err(source.error(
                e.value,
                e.name,
                "the medium's asymmetry `medium-g` lies strictly between -1 and 1",
            ));
        }
        layers.g = g;
    }
    let count = |key: &str, max: u64| -> Result<Option<u32>, SceneError> {
        let Some(e) = find(key) else {
            return Ok(None);
        };
        let n = source.integer(e.value, e.name, 1)?;
        if n > max {
            return Err(source.error(e.value, e.name, format!("`{key}` is at most {max}")));
        }
        Ok(Some(n as u32))
    };
    if let Some(n) = count("walk-depth", MAX_WALK_DEPTH)? {
        layers.max_depth = n;
    }
    if let Some(n) = count("walk-samples", MAX_WALK_SAMPLES)? {
        layers.samples = n;
    }
    Ok(layers)
}

/// Shares of light from 0 to 1: a colour `[r, g, b]` or one number meaning grey.
fn shares(source: &Source<'_>, node: &Node<'_>, key: &str) -> Result<Color, SceneError> {
    if is_number(node) {
        let v = fraction(source, node, key)?;
        Ok(Color::new(v, v, v))
    } else {
        fractions(source, node, key)
    }
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
