//! `add: light`: The Ray Tracer Challenge's point lights, area lights (the soft-shadows bonus
//! chapter) and spotlights, Computer Graphics from Scratch's `type: ambient` and
//! `type: directional` lights, and the intensities every light accepts (a colour, or one number
//! for white light of that strength, as that book writes its intensities).
//!
//! Separate from the other items because a light goes into the world's lights, not its
//! objects: it has no transform, material or group.

use crate::error::SceneError;
use crate::material::color;
use crate::source::{check_keys, required, Entry, Node, Source};
use rayforge::math::point;
use rayforge::shading::DirectionalLight;
use rayforge::{vector, AreaLight, Color, Light, SpotLight};

/// The most samples one area light may take: each is a shadow ray per shading point.
const MAX_LIGHT_SAMPLES: u64 = 4096;

/// A light from `add: light`: a point light (`at`), or an area light (`corner`, `uvec`,
/// `usteps`, `vvec`, `vsteps`, optionally `jitter`), as the soft-shadows bonus chapter writes it,
/// a spotlight (`angle`), or with `type:` Computer Graphics from Scratch's `ambient` and
/// `directional` lights.
pub fn light(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    if let Some(kind) = entries.iter().find(|e| e.name == "type") {
        match source.string(kind.value, "type")? {
            "point" => {}
            "ambient" | "directional" => return cgfs_light(source, entries, item),
            other => {
                return Err(source.error(
                    kind.value,
                    "type",
                    format!(
                        "unknown light type `{other}`; expected point, ambient or directional \
                         (area lights and spotlights are told by `corner` and `angle`)"
                    ),
                ))
            }
        }
    }
    if entries.iter().any(|e| e.name == "corner") {
        area_light(source, entries, item)
    } else if entries.iter().any(|e| e.name == "angle") {
        spotlight(source, entries, item)
    } else {
        point_light(source, entries, item)
    }
}

/// A point light: `at` and `intensity`.
fn point_light(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    let what = "a point light";
    check_keys(source, entries, what, &["add", "type", "at", "intensity"])?;
    let get = |k: &str| required(source, entries, item, k, what);
    let intensity = intensity(source, get("intensity")?)?;
    let [x, y, z] = source.triple(get("at")?, "at")?;
    Ok(Light::point(point(x, y, z), intensity))
}

/// A spotlight: `at`, `direction`, the cone's half-`angle` and its `fade` (default 0).
fn spotlight(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    let what = "a spotlight";
    check_keys(
        source,
        entries,
        what,
        &["add", "at", "intensity", "direction", "angle", "fade"],
    )?;
    let get = |k: &str| required(source, entries, item, k, what);
    let intensity = intensity(source, get("intensity")?)?;
    let [x, y, z] = source.triple(get("at")?, "at")?;
    let direction_node = get("direction")?;
    let [dx, dy, dz] = source.triple(direction_node, "direction")?;
    let angle_node = get("angle")?;
    let angle = source.number(angle_node, "angle")?;
    if !(angle > 0.0 && angle < std::f64::consts::PI) {
        return Err(source.error(
            angle_node,
            "angle",
            format!("the cone's half-angle is in radians, between 0 and π; found {angle}"),
        ));
    }
    let fade = match entries.iter().find(|e| e.name == "fade") {
        Some(e) => source.number(e.value, "fade")?,
        None => 0.0,
    };
    let light = SpotLight::new(point(x, y, z), vector(dx, dy, dz), angle, fade, intensity)
        .ok_or_else(|| source.error(direction_node, "direction", "the direction is zero"))?;
    Ok(Light::Spot(light))
}

/// An area light: a grid of `usteps` × `vsteps` cells on the rectangle from `corner` along
/// `uvec` and `vvec`, sampled at their centres or, with `jitter: true`, at random in each.
fn area_light(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    let what = "an area light";
    check_keys(
        source,
        entries,
        what,
        &[
            "add",
            "intensity",
            "corner",
            "uvec",
            "usteps",
            "vvec",
            "vsteps",
            "jitter",
        ],
    )?;
    let get = |k: &str| required(source, entries, item, k, what);
    let intensity = intensity(source, get("intensity")?)?;
    let [cx, cy, cz] = source.triple(get("corner")?, "corner")?;
    let [ux, uy, uz] = source.triple(get("uvec")?, "uvec")?;
    let [vx, vy, vz] = source.triple(get("vvec")?, "vvec")?;
    let usteps = source.integer(get("usteps")?, "usteps", 1)?;
    let vsteps = source.integer(get("vsteps")?, "vsteps", 1)?;
    if usteps * vsteps > MAX_LIGHT_SAMPLES {
        return Err(source.error(
            get("usteps")?,
            "usteps",
            format!("{usteps}×{vsteps} samples is more than the limit {MAX_LIGHT_SAMPLES}"),
        ));
    }
    let mut light = AreaLight::new(
        point(cx, cy, cz),
        vector(ux, uy, uz),
        usteps as u32,
        vector(vx, vy, vz),
        vsteps as u32,
        intensity,
    );
    if let Some(j) = entries.iter().find(|e| e.name == "jitter") {
        light.jitter = source.boolean(j.value, "jitter")?;
    }
    Ok(Light::Area(light))
}

/// A light's `intensity`: `[r, g, b]`, or one number `i` meaning `[i, i, i]`.
fn intensity(source: &Source<'_>, node: &Node<'_>) -> Result<Color, SceneError> {
    if source.sequence(node, "intensity").is_ok() {
        return color(source, node, "intensity");
    }
    let i = source.number(node, "intensity")?;
    Ok(Color::new(i, i, i))
}

/// `type: ambient` (`intensity`) or `type: directional` (`intensity` and either `towards`, the
/// direction from the scene to the light as the book gives it, or `direction`, the way the
/// light travels, as a spotlight's).
fn cgfs_light(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<Light, SceneError> {
    let get = |k: &str| entries.iter().find(|e| e.name == k).map(|e| e.value);
    let kind = source.string(get("type").expect("the caller found `type`"), "type")?;
    let what = format!("an {kind} light").replace("an directional", "a directional");
    let allowed: &[&str] = if kind == "ambient" {
        &["add", "type", "intensity"]
    } else {
        &["add", "type", "intensity", "towards", "direction"]
    };
    check_keys(source, entries, &what, allowed)?;
    let intensity_node = get("intensity")
        .ok_or_else(|| source.error(item, "intensity", format!("{what} needs `intensity:`")))?;
    let intensity = intensity(source, intensity_node)?;
    if kind == "ambient" {
        return Ok(Light::Ambient(intensity));
    }
    let (key, node, sign) = match (get("towards"), get("direction")) {
        (Some(t), None) => ("towards", t, 1.0),
        (None, Some(d)) => ("direction", d, -1.0),
        (Some(_), Some(d)) => return Err(source.error(
            d,
            "direction",
            "give either `towards` (to the light) or `direction` (the light's travel), not both",
        )),
        (None, None) => {
            return Err(source.error(
                item,
                "towards",
                "a directional light needs `towards:` (the direction to the light)",
            ))
        }
    };
    let [x, y, z] = source.triple(node, key)?;
    let towards = vector(x, y, z) * sign;
    if towards.length_squared() == 0.0 {
        return Err(source.error(node, key, "the direction is zero"));
    }
    Ok(Light::Directional(DirectionalLight { towards, intensity }))
}
