//! A glTF model as a whole scene (`rayforge render model.glb`): its objects, its lights or a
//! default one, a default sky, and one of its cameras or a default one that frames it.
//!
//! The defaults, for files that lack them:
//! - **camera**: looking along glTF's −Z (the front view of glTF viewers) at the centre of
//!   the model's box, with a 45° vertical field of view, from the distance at which the box's
//!   bounding sphere fills the view;
//! - **light** (when the file has no `KHR_lights_punctual` light): a white directional light
//!   of intensity 0.6 (`intensity` as in a scene file's `light`) from the viewer's upper left,
//!   along glTF's (−1, 2, 2) towards the model;
//! - **sky**: a uniform grey of 0.5 (the background of the ray tracer; light from every
//!   direction for the path tracer).

use super::model::GltfModel;
use super::nodes::{GltfCamera, GltfLight, LightKind, Projection};
use super::space::GLTF_TO_BOOK;
use crate::assets::Assets;
use crate::error::SceneError;
use crate::items::camera::LookAt;
use crate::scene::{CameraChoice, LoadOptions, Scene};
use glam::{DMat4, DVec3};
use rayforge::draw2d::Overlay;
use rayforge::shading::{DirectionalLight, Light, PointLight, SpotLight};
use rayforge::World;
use rayforge::{Camera, Color, Transform};
use std::f64::consts::PI;
use std::path::Path;

/// The default image width of a model rendered directly (the height follows the camera's
/// aspect ratio, 4:3 without one).
pub const DEFAULT_WIDTH: usize = 800;

/// The default camera's vertical field of view.
const DEFAULT_YFOV: f64 = PI / 4.0;

/// The sky of a model rendered directly.
pub const DEFAULT_SKY: f64 = 0.5;

/// The default light's intensity.
const DEFAULT_LIGHT: f64 = 0.6;

/// The model's lights in the book's world, placed by `placement` (after [`GLTF_TO_BOOK`]).
/// Intensities are divided by π: the book's lights are irradiance over π (a white Lambertian
/// surface facing a light of intensity 1 shows 1), glTF's are irradiance.
pub fn book_lights(lights: &[GltfLight], placement: &DMat4) -> Vec<Light> {
    lights
        .iter()
        .filter_map(|l| {
            let position = placement.transform_point3(l.position);
            let direction = placement.transform_vector3(l.direction).normalize_or_zero();
            let intensity = l.intensity * (1.0 / PI);
            Some(match l.kind {
                LightKind::Point => Light::Point(PointLight {
                    falloff: true,
                    ..PointLight::new(position, intensity)
                }),
                LightKind::Spot { inner, outer } => {
                    let spot = SpotLight::new(
                        position,
                        direction,
                        outer,
                        (outer - inner).max(0.0),
                        intensity,
                    )?;
                    Light::Spot(SpotLight {
                        falloff: true,
                        ..spot
                    })
                }
                LightKind::Directional => Light::Directional(DirectionalLight {
                    towards: -direction,
                    intensity,
                }),
            })
        })
        .collect()
}

/// The book's camera for a glTF camera placed by `placement`, `width × height` pixels.
pub fn book_camera(
    camera: &GltfCamera,
    placement: &DMat4,
    width: usize,
    height: usize,
) -> Result<Camera, String> {
    // World from camera in the book's world; the book's camera space has +x to the image's
    // left where glTF's has it to the right: mirror x.
    let world_from_camera =
        *placement * camera.world * DMat4::from_diagonal(glam::DVec4::new(-1.0, 1.0, 1.0, 1.0));
    let view = Transform::try_new(world_from_camera.inverse()).map_err(|_| {
        format!(
            "the camera `{}` is placed by a singular transform",
            camera.name
        )
    })?;
    let aspect = width as f64 / height as f64;
    let built = match camera.projection {
        Projection::Perspective { yfov, .. } => {
            let longer = longer_side((yfov / 2.0).tan(), aspect);
            Camera::new(width, height, 2.0 * longer.atan())
        }
        Projection::Orthographic { ymag, .. } => {
            Camera::orthographic(width, height, longer_side(ymag, aspect))
        }
    };
    Ok(built.with_transform_of(view))
}

/// The half extent across the image's longer side, from `vertical`'s across its height (the
/// book's cameras are sized by their longer side, glTF's by their height).
fn longer_side(vertical: f64, aspect: f64) -> f64 {
    if aspect >= 1.0 {
        vertical * aspect
    } else {
        vertical
    }
}

/// The default camera (see the [module](self)) for a model placed by `placement`, and where
/// it looks from and at.
pub fn default_camera(model: &GltfModel, width: usize, height: usize) -> (Camera, LookAt) {
    let (lo, hi) = model
        .bounds(&DMat4::IDENTITY)
        .unwrap_or((DVec3::splat(-1.0), DVec3::ONE));
    let centre = (lo + hi) / 2.0;
    let radius = ((hi - lo).length() / 2.0).max(1e-6);
    let aspect = width as f64 / height as f64;
    // The narrower of the two fields of view must hold the sphere.
    let half_v = DEFAULT_YFOV / 2.0;
    let half_h = (half_v.tan() * aspect).atan();
    let distance = radius / half_v.min(half_h).sin();
    let from = GLTF_TO_BOOK.transform_point3(centre + DVec3::Z * distance);
    let to = GLTF_TO_BOOK.transform_point3(centre);
    let look = LookAt {
        from,
        to,
        up: DVec3::Y,
    };
    let longer = if aspect >= 1.0 { half_h } else { half_v };
    let camera = Camera::new(width, height, 2.0 * longer)
        .with_transform(rayforge::math::view_transform(from, to, DVec3::Y));
    (camera, look)
}

/// The default light (see the [module](self)), in the book's world.
pub fn default_light() -> Light {
    let towards = GLTF_TO_BOOK
        .transform_vector3(DVec3::new(-1.0, 2.0, 2.0))
        .normalize();
    Light::Directional(DirectionalLight {
        towards,
        intensity: Color::WHITE * DEFAULT_LIGHT,
    })
}

/// The image size for a model's camera when the user gives none: [`DEFAULT_WIDTH`] wide, as
/// tall as the camera's aspect ratio says.
pub fn default_size(camera: Option<&GltfCamera>) -> (usize, usize) {
    let aspect = match camera.map(|c| c.projection) {
        Some(Projection::Perspective {
            aspect: Some(a), ..
        }) if a.is_finite() && a > 0.0 => a,
        Some(Projection::Orthographic { xmag, ymag }) if xmag > 0.0 && ymag > 0.0 => xmag / ymag,
        _ => 4.0 / 3.0,
    };
    let height = (DEFAULT_WIDTH as f64 / aspect).round().clamp(1.0, 16_384.0) as usize;
    (DEFAULT_WIDTH, height)
}

/// The camera `choice` picks among `cameras`; `Ok(None)` for the first of none.
pub fn pick<'a>(
    path: &Path,
    cameras: &'a [GltfCamera],
    choice: &CameraChoice,
) -> Result<Option<&'a GltfCamera>, SceneError> {
    let names = || {
        if cameras.is_empty() {
            "it has none".to_string()
        } else {
            let list: Vec<String> = cameras
                .iter()
                .enumerate()
                .map(|(i, c)| format!("{i}: `{}`", c.name))
                .collect();
            format!("it has {}", list.join(", "))
        }
    };
    match choice {
        CameraChoice::First => Ok(cameras.first()),
        CameraChoice::Index(i) => cameras.get(*i).map(Some).ok_or_else(|| {
            SceneError::new(
                path,
                format!("the model has no camera {i} (`--camera`): {}", names()),
            )
            .with_key("cameras")
        }),
        CameraChoice::Named(name) => cameras
            .iter()
            .find(|c| &c.name == name)
            .map(Some)
            .ok_or_else(|| {
                SceneError::new(
                    path,
                    format!(
                        "the model has no camera named `{}` (`--camera`): {}",
                        crate::error::clip(name),
                        names()
                    ),
                )
                .with_key("cameras")
            }),
    }
}

/// Whether `path` names a glTF model (`.gltf` or `.glb`, in any case).
pub fn is_model_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// The scene of a model rendered directly (see the [module](self)).
pub fn model_scene(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let mut assets = Assets::new(
        path,
        options.allow_outside,
        options.max_triangles,
        options.max_image_memory,
        options.stop.clone(),
    );
    let model = assets.gltf(path)?;
    let chosen = pick(path, &model.cameras, &options.camera)?;
    let (width, height) = default_size(chosen);
    let (camera, look_at) = match chosen {
        Some(c) => (
            book_camera(c, &GLTF_TO_BOOK, width, height)
                .map_err(|e| SceneError::new(path, e).with_key("cameras"))?,
            None,
        ),
        None => {
            let (camera, look) = default_camera(&model, width, height);
            (camera, Some(look))
        }
    };
    let placement = Transform::new(GLTF_TO_BOOK);
    let mut world = World::new();
    world.objects = model
        .objects
        .iter()
        .filter_map(|o| o.placed_by(&placement).ok())
        .collect();
    world.lights = book_lights(&model.lights, &GLTF_TO_BOOK);
    if world.lights.is_empty() {
        world.lights.push(default_light());
    }
    world.background = Color::WHITE * DEFAULT_SKY;
    let warnings = model
        .notes
        .iter()
        .map(|note| SceneError::new(path, note.clone()))
        .collect();
    Ok(Scene {
        overlay: Overlay::new(Vec::new(), camera.hsize(), camera.vsize()),
        world,
        camera,
        samples: 1,
        samples_at: None,
        anti_alias: None,
        max_depth: None,
        max_depth_at: None,
        raster: None,
        path: None,
        warnings,
        look_at,
        files: assets.files(path),
    })
}
