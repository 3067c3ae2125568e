//! Computer Graphics from Scratch's lights, `type: ambient` and `type: directional`, and the
//! intensities every light accepts (a colour, or one number for white light of that strength,
//! as that book writes its intensities).

use crate::material::color;
use crate::source::{check_keys, Entry, Node, Source};
use crate::SceneError;
use rayforge::shading::DirectionalLight;
use rayforge::{vector, Color, Light};

/// A light's `intensity`: `[r, g, b]`, or one number `i` meaning `[i, i, i]`.
pub fn intensity(source: &Source<'_>, node: &Node<'_>) -> Result<Color, SceneError> {
    if source.sequence(node, "intensity").is_ok() {
        return color(source, node, "intensity");
    }
    let i = source.number(node, "intensity")?;
    Ok(Color::new(i, i, i))
}

/// `type: ambient` (`intensity`) or `type: directional` (`intensity` and either `towards`, the
/// direction from the scene to the light as the book gives it, or `direction`, the way the
/// light travels, as a spotlight's).
pub fn cgfs_light(
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
