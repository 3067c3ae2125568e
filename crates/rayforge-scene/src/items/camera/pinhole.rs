//! The Ray Tracer Challenge's camera: `add: camera` with `field-of-view` (radians, or
//! `field-of-view-degrees`), `from`, `to` and `up`, optionally the thin lens of depth of field
//! (`aperture`, `focal-distance`), and `handedness`; or, with `projection`, a spherical
//! camera (pbrt-v4's, equirectangular or equal-area) at the same place; and the film's
//! sensor (`iso`, `exposure-time`, `white-balance`, `max-component`) as pbrt-v4's RGB film
//! has it, so that a scene written in YAML records light as the same scene in pbrt-v4's format
//! (the viewport and zoom cameras read the same film keys through `film`).
//!
//! The book's world is left-handed: the image's right is `up × forward`. Scenes written for
//! right-handed renderers (pbrt, Mitsuba, the path tracer's reference scenes) put the image's
//! right along `forward × up`; `handedness: right` places the camera as those renderers do
//! ([`look_at`]) so that they render as their authors saw them, not mirrored (nor widened: see
//! [`look_at`] for the book view's other difference).
//!
//! Separate from the other books' cameras: it is the one placed by a view transform, and the
//! one with a lens.

use crate::error::SceneError;
use crate::source::{check_keys, required, Entry, Node, Source};
use rayforge::camera::SphericalMapping;
use rayforge::math::{look_at, point, vector, view_transform};
use rayforge::{Camera, Transform};

/// The keys the book's camera accepts.
const KEYS: &[&str] = &[
    "add",
    "width",
    "height",
    "field-of-view",
    "field-of-view-degrees",
    "handedness",
    "from",
    "to",
    "up",
    "samples",
    "aperture",
    "focal-distance",
    "shutter",
    "projection",
    "iso",
    "exposure-time",
    "white-balance",
    "max-component",
];

/// The keys a spherical camera has no use for: it sees every direction about it, through no
/// lens.
const NOT_SPHERICAL: &[&str] = &[
    "field-of-view",
    "field-of-view-degrees",
    "aperture",
    "focal-distance",
];

/// The book's camera placement, as the scene gives it: the eye at `from` looking at `to`, with
/// `up` the scene's upward direction (not necessarily square to the view). Checked: `to` is
/// away from `from` and `up` is not along the view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LookAt {
    /// The eye.
    pub from: rayforge::math::Point3,
    /// The point looked at.
    pub to: rayforge::math::Point3,
    /// The scene's up.
    pub up: rayforge::math::Vec3,
}

/// The book's camera of an `add: camera` item with neither `zoom:` nor `viewport:`, and where
/// it looks from and at.
pub fn camera(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
) -> Result<(Camera, LookAt), SceneError> {
    check_keys(source, entries, "a camera", KEYS)?;
    let get = |k: &str| required(source, entries, item, k, "the camera");
    let width = source.integer(get("width")?, "width", 1)? as usize;
    let height = source.integer(get("height")?, "height", 1)? as usize;
    let right_handed = handedness(source, entries)?;
    if let Some(mapping) = projection(source, entries)? {
        if let Some(e) = entries.iter().find(|e| NOT_SPHERICAL.contains(&e.name)) {
            return Err(source.error(
                e.key,
                e.name,
                format!(
                    "a spherical camera sees every direction about it, through no lens: \
                     `{}` has no meaning for it",
                    e.name
                ),
            ));
        }
        let (view, look_at) = view(source, entries, item, right_handed)?;
        let camera = Camera::spherical(width, height, mapping).with_transform_of(view);
        return Ok((film(source, entries, camera)?, look_at));
    }
    let fov = match entries.iter().find(|e| e.name == "field-of-view-degrees") {
        Some(e) if entries.iter().any(|e| e.name == "field-of-view") => {
            return Err(source.error(
                e.key,
                "field-of-view-degrees",
                "give `field-of-view` (radians) or `field-of-view-degrees`, not both",
            ))
        }
        Some(e) => {
            let degrees = source.number(e.value, "field-of-view-degrees")?;
            if !(degrees > 0.0 && degrees < 180.0) {
                return Err(source.error(
                    e.value,
                    "field-of-view-degrees",
                    format!(
                        "the field of view must lie between 0 and 180 degrees, found {degrees}"
                    ),
                ));
            }
            degrees.to_radians()
        }
        None => field_of_view(source, get("field-of-view")?)?,
    };
    let (view, look_at) = view(source, entries, item, right_handed)?;
    let camera = Camera::new(width, height, fov).with_transform_of(view);
    let camera = lens(source, entries, item, camera)?;
    Ok((film(source, entries, camera)?, look_at))
}

/// `handedness`: whether the camera is placed as right-handed renderers place theirs.
fn handedness(source: &Source<'_>, entries: &[Entry<'_, '_>]) -> Result<bool, SceneError> {
    let Some(e) = entries.iter().find(|e| e.name == "handedness") else {
        return Ok(false);
    };
    match source.string(e.value, "handedness")? {
        "left" => Ok(false),
        "right" => Ok(true),
        other => Err(source.error(
            e.value,
            "handedness",
            format!(
                "unknown handedness `{}`; expected left (the book's) or right",
                crate::error::clip_to(other, 60)
            ),
        )),
    }
}

/// `projection`: `perspective` (the default, `None`), or a spherical camera's layout,
/// `equirectangular` or `equal-area` (pbrt-v4's `spherical` camera's two `mapping`s, laid
/// out as pbrt-v4 lays them: see [`SphericalMapping`]).
fn projection(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
) -> Result<Option<SphericalMapping>, SceneError> {
    let Some(e) = entries.iter().find(|e| e.name == "projection") else {
        return Ok(None);
    };
    match source.string(e.value, "projection")? {
        "perspective" => Ok(None),
        "equirectangular" => Ok(Some(SphericalMapping::Equirectangular)),
        "equal-area" => Ok(Some(SphericalMapping::EqualArea)),
        other => Err(source.error(
            e.value,
            "projection",
            format!(
                "unknown projection `{}`; expected perspective, equirectangular or equal-area",
                crate::error::clip_to(other, 60)
            ),
        )),
    }
}

/// The camera with the film's sensor, when a film key is given (none: the radiance as it
/// is, bit for bit): pbrt-v4's RGB film's, through the same library sensor its `Film`
/// directive makes (`film_sensor::cie1931`), so that `iso`, `exposure-time`,
/// `white-balance` and `max-component` mean here what `iso`, the shutter's open time,
/// `whitebalance` and `maxcomponentvalue` mean there. The exposure time is the film's own,
/// not `shutter`'s interval: that one is the time of object motions, in which a scene's
/// movements are written, and exposing the film longer must not move them.
pub(crate) fn film(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    camera: Camera,
) -> Result<Camera, SceneError> {
    let find = |k: &str| entries.iter().find(|e| e.name == k);
    // Where an error of the whole sensor is reported: the first of its keys given, the
    // white balance first (what can have no colour to balance from).
    let keys = ["white-balance", "iso", "exposure-time", "max-component"];
    let Some((key, at)) = keys.iter().find_map(|k| find(k).map(|e| (*k, e.value))) else {
        return Ok(camera);
    };
    let positive = |key: &str, default: f64| -> Result<f64, SceneError> {
        let Some(e) = find(key) else {
            return Ok(default);
        };
        let v = source.number(e.value, key)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(source.error(e.value, key, format!("`{key}` must be above 0, found {v}")))
        }
    };
    let iso = positive("iso", 100.0)?;
    let exposure = positive("exposure-time", 1.0)?;
    let max_component = positive("max-component", f64::INFINITY)?;
    let temperature = match find("white-balance") {
        None => 0.0,
        Some(e) => {
            let t = source.number(e.value, "white-balance")?;
            if t < 0.0 {
                return Err(source.error(
                    e.value,
                    "white-balance",
                    format!(
                        "a white balance is 0 (none) or a colour temperature above 0 kelvin, \
                         found {t}"
                    ),
                ));
            }
            t
        }
    };
    let ratio = exposure * iso / 100.0;
    if !ratio.is_finite() {
        return Err(source.error(
            at,
            key,
            format!(
                "the imaging ratio, `exposure-time` {exposure} × `iso` {iso} / 100, is past the \
                 largest number"
            ),
        ));
    }
    let sensor = crate::film_sensor::cie1931(ratio, temperature, max_component)
        .map_err(|message| source.error(at, key, message))?;
    Ok(camera.with_sensor(sensor))
}

/// `field-of-view`, in radians strictly between 0 and π.
fn field_of_view(source: &Source<'_>, node: &Node<'_>) -> Result<f64, SceneError> {
    let fov = source.number(node, "field-of-view")?;
    if !(fov > 0.0 && fov < std::f64::consts::PI) {
        return Err(source.error(
            node,
            "field-of-view",
            format!("the field of view is in radians and must lie between 0 and π, found {fov}"),
        ));
    }
    Ok(fov)
}

/// The view transform from `from`, `to` and `up`: the book's, or with `right_handed` that of
/// right-handed renderers ([`look_at`]); and the three, checked.
fn view(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
    right_handed: bool,
) -> Result<(Transform, LookAt), SceneError> {
    let get = |k: &str| required(source, entries, item, k, "the camera");
    let [fx, fy, fz] = source.triple(get("from")?, "from")?;
    let to_node = get("to")?;
    let [tx, ty, tz] = source.triple(to_node, "to")?;
    let up_node = get("up")?;
    let [ux, uy, uz] = source.triple(up_node, "up")?;
    let (from, to, up) = (point(fx, fy, fz), point(tx, ty, tz), vector(ux, uy, uz));
    // A view direction shorter than this share of the coordinates is lost in their rounding.
    let reach = from
        .abs()
        .max_element()
        .max(to.abs().max_element())
        .max(1.0);
    let sight = to - from;
    if sight.length() <= 1e-9 * reach {
        return Err(source.error(
            to_node,
            "to",
            format!(
                "the camera looks at its own position (`to` is {:e} from `from`)",
                sight.length()
            ),
        ));
    }
    if up.length_squared() == 0.0
        || sight.normalize().cross(up.normalize()).length_squared() < 1e-18
    {
        return Err(source.error(
            up_node,
            "up",
            "`up` is zero or parallel to the direction of view",
        ));
    }
    let matrix = if right_handed {
        look_at(from, to, up)
    } else {
        view_transform(from, to, up)
    };
    let transform = Transform::try_new(matrix)
        .map_err(|e| source.error(item, "up", format!("the view transform is singular: {e}")))?;
    Ok((transform, LookAt { from, to, up }))
}

/// The camera with a thin lens, when it has `aperture` (which then needs `focal-distance`).
fn lens(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    item: &Node<'_>,
    camera: Camera,
) -> Result<Camera, SceneError> {
    let Some(aperture_entry) = entries.iter().find(|e| e.name == "aperture") else {
        return Ok(camera);
    };
    let aperture = source.number(aperture_entry.value, "aperture")?;
    if aperture < 0.0 {
        return Err(source.error(
            aperture_entry.value,
            "aperture",
            "the aperture cannot be negative",
        ));
    }
    let focal_node = required(source, entries, item, "focal-distance", "the camera")?;
    let focal = source.number(focal_node, "focal-distance")?;
    if focal <= 0.0 {
        return Err(source.error(
            focal_node,
            "focal-distance",
            "the focal distance must be positive",
        ));
    }
    Ok(camera.with_lens(aperture, focal))
}
