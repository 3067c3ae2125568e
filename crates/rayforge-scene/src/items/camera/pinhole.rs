//! The Ray Tracer Challenge's camera: `add: camera` with `field-of-view` (radians, or
//! `field-of-view-degrees`), `from`, `to` and `up`, optionally the thin lens of depth of field
//! (`aperture`, `focal-distance`), and `handedness`.
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
    let right_handed = match entries.iter().find(|e| e.name == "handedness") {
        None => false,
        Some(e) => match source.string(e.value, "handedness")? {
            "left" => false,
            "right" => true,
            other => {
                return Err(source.error(
                    e.value,
                    "handedness",
                    format!("unknown handedness `{other}`; expected left (the book's) or right"),
                ))
            }
        },
    };
    let (view, look_at) = view(source, entries, item, right_handed)?;
    let camera = Camera::new(width, height, fov).with_transform_of(view);
    Ok((lens(source, entries, item, camera)?, look_at))
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
