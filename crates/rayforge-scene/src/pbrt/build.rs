//! A read [`Description`] built into rayforge's [`Scene`]: the world's objects (each shape
//! with its material, its area light's emission, and its transform; named objects placed at
//! each `ObjectInstance`, sharing their meshes; moving shapes, instances and camera as
//! [`motion`] places them), its lights and sky, the camera and the path tracer's options.

use super::area_power;
use super::camera;
use super::displace::Displacing;
use super::input::Files;
use super::lights::{self, Lit};
use super::materials;
use super::media;
use super::motion;
use super::reader::{Description, Entity, MaterialRef, ShapeEntity};
use super::shapes::{self, Built};
use super::textures::{self, SceneTextures};
use crate::budget::Budget;
use crate::error::SceneError;
use crate::scene::{LoadOptions, Scene};
use rayforge::draw2d::Overlay;
use rayforge::shading::texture_graph::{FloatInput, SurfaceTextures};
use rayforge::shading::EmissionSide;
use rayforge::{Color, Material, Object, Shape, Transform, World};
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;
use std::sync::Arc;

/// The materials built so far, each once.
struct MaterialCache<'d> {
    desc: &'d Description,
    textures: &'d SceneTextures,
    by_index: HashMap<usize, Material>,
    by_name: HashMap<String, Material>,
    /// `Option "displacementedgescale"`, for the displaced meshes.
    edge_scale: f64,
}

impl MaterialCache<'_> {
    fn get(
        &mut self,
        reference: &MaterialRef,
        warnings: &mut Vec<SceneError>,
    ) -> Result<Material, SceneError> {
        let desc = self.desc;
        match reference {
            MaterialRef::Index(i) => {
                if let Some(m) = self.by_index.get(i) {
                    return Ok(m.clone());
                }
                let built = match &desc.materials[*i] {
                    // pbrt's default material: diffuse, reflectance 0.5.
                    None => Material {
                        color: Color::WHITE * 0.5,
                        physical: Some(rayforge::shading::Physical::Diffuse),
                        ..Material::DEFAULT
                    },
                    Some(entity) => materials::material(entity, self.textures, desc, warnings)?,
                };
                self.by_index.insert(*i, built.clone());
                Ok(built)
            }
            MaterialRef::Named(name, loc) => {
                if let Some(m) = self.by_name.get(name) {
                    return Ok(m.clone());
                }
                let entity = desc.named_materials.get(name).ok_or_else(|| {
                    loc.error(
                        Some("NamedMaterial"),
                        format!(
                            "no material is named \"{}\" (`MakeNamedMaterial` makes one)",
                            crate::error::clip_to(name, 60)
                        ),
                    )
                })?;
                let built = materials::material(entity, self.textures, desc, warnings)?;
                self.by_name.insert(name.clone(), built.clone());
                Ok(built)
            }
        }
    }
}

/// Builds the scene of `desc`, read from `files`, within `options`' limits.
pub fn scene(
    mut desc: Description,
    files: &Files,
    options: &LoadOptions,
) -> Result<Scene, SceneError> {
    let mut warnings = std::mem::take(&mut desc.warnings);
    let setup = camera::setup(&desc.options, files, &mut warnings)?;
    let mut world = World::new();
    let media_ids = media::build(
        &desc,
        &mut world,
        options.max_grid_samples,
        options.max_optical_depth,
    )?;
    world.camera_medium = media::camera_medium(&media_ids, desc.options.camera_medium.as_ref())?;
    let budget = Budget::default();
    let mut triangles = 0usize;
    let scene_textures = textures::build(&desc, files, options.max_image_memory)?;
    let mut cache = MaterialCache {
        desc: &desc,
        textures: &scene_textures,
        by_index: HashMap::new(),
        by_name: HashMap::new(),
        edge_scale: super::displace::edge_scale(&desc.options)?,
    };
    let mut noted = Notes::default();
    for shape in &desc.shapes {
        shape.entity.loc.stopped(files.stop(), "Shape")?;
        let boundary = media::is_boundary(&desc, &shape.material);
        let interface = media::interface(&media_ids, shape.media.as_ref(), boundary)?;
        if boundary {
            media::note_boundary_light(shape, &mut warnings);
            if interface.is_none() {
                // Nothing to cross: rays pass it as if it were not there (pbrt-v4).
                continue;
            }
        }
        let placed = place(
            shape,
            files,
            !boundary,
            &mut cache,
            &mut triangles,
            options,
            &mut warnings,
            &mut noted,
        )?;
        for mut object in placed {
            budget.spend().map_err(|e| shape.entity.error(e))?;
            object.media = interface;
            world.objects.push(object);
        }
    }
    // Named objects: each built once, its meshes shared by every use.
    let mut defined: HashMap<&str, Vec<Object>> = HashMap::new();
    let render_origin = motion::render_origin(&desc);
    for used in &desc.instances {
        let Some((shapes, _)) = desc.objects.get(&used.name) else {
            return Err(used.loc.error(
                Some("ObjectInstance"),
                format!(
                    "no object is named \"{}\" (`ObjectBegin` defines one)",
                    crate::error::clip_to(&used.name, 60)
                ),
            ));
        };
        if !defined.contains_key(used.name.as_str()) {
            let mut objects = Vec::new();
            for shape in shapes {
                shape.entity.loc.stopped(files.stop(), "Shape")?;
                let boundary = media::is_boundary(&desc, &shape.material);
                let interface = media::interface(&media_ids, shape.media.as_ref(), boundary)?;
                if boundary {
                    media::note_boundary_light(shape, &mut warnings);
                    if interface.is_none() {
                        continue;
                    }
                }
                let start = objects.len();
                objects.extend(place(
                    shape,
                    files,
                    false,
                    &mut cache,
                    &mut triangles,
                    options,
                    &mut warnings,
                    &mut noted,
                )?);
                for object in &mut objects[start..] {
                    object.media = interface;
                }
            }
            defined.insert(used.name.as_str(), objects);
        }
        let singular = || {
            used.loc.error(
                Some("ObjectInstance"),
                "the object is placed by a singular transform",
            )
        };
        let parent = Transform::try_new(used.world_from_instance).map_err(|_| singular())?;
        let parent_end = used
            .world_from_instance_end
            .map(Transform::try_new)
            .transpose()
            .map_err(|_| singular())?;
        for object in &defined[used.name.as_str()] {
            used.loc.stopped(files.stop(), "ObjectInstance")?;
            budget
                .spend()
                .map_err(|e| used.loc.error(Some("ObjectInstance"), e))?;
            let (placed, approximate) =
                motion::instance(object, &parent, parent_end.as_ref(), render_origin)
                    .map_err(|_| singular())?;
            if approximate && !noted.nested_motion {
                noted.nested_motion = true;
                warnings.push(used.loc.error(
                    Some("ObjectInstance"),
                    "a moving shape in an instance that moves otherwise than by a \
                     translation: rayforge interpolates the product of the two motions, \
                     pbrt-v4 each one apart, and the paths between the ends differ",
                ));
            }
            world.objects.push(placed);
        }
    }
    let mut memory = scene_textures.memory;
    let mut sky_images: Vec<lights::SkyImage> = Vec::new();
    for light in &desc.lights {
        match lights::light(light, files, &mut memory, &mut warnings)? {
            Lit::Light(l) => world.lights.push(l),
            Lit::Sky(c) => world.background += c,
            Lit::Map(image) => sky_images.push(image),
        }
    }
    // Several image skies are summed (the path tracer samples each by its power); uniform
    // skies beside them are added to the first, and the background is then the maps.
    let mut uniform = Color::BLACK;
    if !sky_images.is_empty() {
        uniform = std::mem::replace(&mut world.background, Color::BLACK);
    }
    for (i, image) in sky_images.into_iter().enumerate() {
        let map = Arc::new(image.into_map(if i == 0 { uniform } else { Color::BLACK })?);
        if i == 0 {
            world.environment = Some(map);
        } else {
            world.more_environments.push(map);
        }
    }
    // Every parameter nothing read, once each (an area light is shared by its shapes).
    let mut area_lights: Vec<&Rc<Entity>> = Vec::new();
    let unused = |entity: &Entity, warnings: &mut Vec<SceneError>| {
        warnings.extend(entity.params.unused(&entity.what()));
    };
    let options = &desc.options;
    for entity in [
        &options.film,
        &options.sampler,
        &options.integrator,
        &options.filter,
    ]
    .into_iter()
    .flatten()
    .chain(options.camera.as_ref().map(|(e, _)| e))
    {
        unused(entity, &mut warnings);
    }
    for shape in desc
        .shapes
        .iter()
        .chain(desc.objects.values().flat_map(|(s, _)| s))
    {
        unused(&shape.entity, &mut warnings);
        if let Some(a) = &shape.area_light {
            if !area_lights.iter().any(|b| Rc::ptr_eq(a, b)) {
                area_lights.push(a);
            }
        }
    }
    for a in area_lights {
        unused(a, &mut warnings);
    }
    for light in &desc.lights {
        unused(&light.entity, &mut warnings);
    }
    for texture in &desc.textures {
        unused(&texture.entity, &mut warnings);
    }
    for (medium, _) in desc.media.values() {
        unused(medium, &mut warnings);
    }
    for entity in desc
        .materials
        .iter()
        .flatten()
        .chain(desc.named_materials.values())
    {
        if entity.params.was_read() {
            unused(entity, &mut warnings);
        }
    }
    let max = crate::source::MAX_WARNINGS;
    if warnings.len() > max {
        warnings.truncate(max);
        warnings.push(SceneError::new(
            files.main_path(),
            format!("more than {max} warnings; the rest are not shown"),
        ));
    }
    let Setup {
        camera,
        samples,
        samples_at,
        path,
        max_depth,
        max_depth_at,
    } = setup;
    let camera = motion::camera(camera, &desc)?;
    Ok(Scene {
        overlay: Overlay::new(Vec::new(), camera.hsize(), camera.vsize()),
        world,
        camera,
        samples,
        samples_at,
        anti_alias: None,
        max_depth: Some(max_depth),
        max_depth_at,
        raster: None,
        path: Some(path),
        warnings,
        look_at: None,
        files: files.read_besides_main(),
    })
}

use camera::Setup;

/// Which once-per-scene warnings were given.
#[derive(Default)]
struct Notes {
    moving_light: bool,
    nested_motion: bool,
    instanced_light: bool,
}

/// The objects of `shape` placed by its transform (moving, where it moves), with its material
/// and, where `lit` (not in an object's definition) and it has one, its area light's emission.
#[allow(clippy::too_many_arguments)]
fn place(
    shape: &ShapeEntity,
    files: &Files,
    lit: bool,
    cache: &mut MaterialCache<'_>,
    triangles: &mut usize,
    options: &LoadOptions,
    warnings: &mut Vec<SceneError>,
    noted: &mut Notes,
) -> Result<Vec<Object>, SceneError> {
    let entity = &shape.entity;
    let (objects, area, patches) = match shapes::build(
        shape,
        files,
        &Displacing {
            textures: cache.textures,
            desc: cache.desc,
            edge_scale: cache.edge_scale,
        },
        triangles,
        options.max_triangles,
        warnings,
    )? {
        Built::Objects(objects, area) => (objects, area, None),
        Built::Patches(objects, area, patches) => (objects, area, Some(patches)),
    };
    if shape.world_from_object_end.is_some()
        && shape.area_light.is_some()
        && lit
        && !noted.moving_light
        && !media::is_boundary(cache.desc, &shape.material)
    {
        noted.moving_light = true;
        warnings.push(entity.error(
            "an area light on a moving shape, which pbrt-v4 refuses (\"Animated area lights \
             are not supported\"): rayforge renders it moving, its light where the shape is \
             at each ray's instant",
        ));
    }
    let mut material = cache.get(&shape.material, warnings)?;
    if let Some(alpha) = cache.textures.float(entity, "alpha", cache.desc)? {
        if !matches!(alpha, FloatInput::Fixed(a) if a >= 1.0) {
            let mut surface = material
                .textures
                .take()
                .map(|t| *t)
                .unwrap_or_else(|| SurfaceTextures::new(cache.textures.graph.clone()));
            surface.alpha = Some(alpha);
            material.textures = Some(Box::new(surface));
        }
    }
    let world_from_object = shape.world_from_object;
    let singular = || entity.error("the shape is placed by a singular transform");
    let transform = Transform::try_new(world_from_object).map_err(|_| singular())?;
    let end = shape
        .world_from_object_end
        .map(Transform::try_new)
        .transpose()
        .map_err(|_| singular())?;
    let place = |object: Object, material: Material| {
        motion::place(object.with_material(material), &transform, end.as_ref())
            .map_err(|_| singular())
    };
    let Some(area_light) = shape.area_light.as_ref().filter(|_| lit) else {
        // (A boundary's light is ignored with a warning of its own.)
        let boundary = media::is_boundary(cache.desc, &shape.material);
        if shape.area_light.is_some() && !noted.instanced_light && !boundary {
            noted.instanced_light = true;
            warnings.push(
                entity.error("area lights in object instances give no light (as in pbrt-v4)"),
            );
        }
        return objects
            .into_iter()
            .map(|o| place(o, material.clone()))
            .collect();
    };
    let side = |two_sided: bool| match (two_sided, shape.reverse, entity.name.as_str()) {
        (true, _, _) => EmissionSide::Both,
        // A mesh's faces were turned over already.
        (false, true, name)
            if !matches!(
                name,
                "trianglemesh" | "plymesh" | "bilinearmesh" | "loopsubdiv"
            ) =>
        {
            EmissionSide::Back
        }
        _ => EmissionSide::Front,
    };
    let emitting = |area: f64| -> Result<Material, SceneError> {
        let (radiance, two_sided) = lights::emission(area_light, area)?;
        Ok(Material {
            emission: radiance,
            emission_side: side(two_sided),
            ..material.clone()
        })
    };
    let mut placed = Vec::with_capacity(objects.len());
    for object in objects {
        match &object.shape {
            // pbrt-v4 makes an area light of each curve part, and then cannot sample it
            // (`Curve::Sample` is not written): a fatal error there.
            Shape::Curves(_) => {
                return Err(entity.error(
                    "a curve cannot be an area light (pbrt-v4 cannot sample one either); give \
                     it a material without `AreaLightSource`",
                ))
            }
            // `power` per triangle, or per bilinear patch, as pbrt-v4 gives it (see
            // `area_power`).
            Shape::Mesh(mesh) if area_power::has_power(area_light)? => {
                let world_from_mesh = world_from_object * object.transform.matrix();
                let cut = area_power::pieces(
                    mesh,
                    &world_from_mesh,
                    patches.as_deref(),
                    options.pbrt.radiances,
                )
                .map_err(|e| entity.error(e.to_string()))?;
                if let Some(spread) = cut.spread {
                    warnings.push(entity.error(format!(
                        "the area light's power is each triangle's, as in pbrt-v4, and this \
                         mesh's triangles have more than {} sizes (`--max-pbrt-radiances`): \
                         triangles whose areas differ by up to {:.2} % share one radiance \
                         (each band of sizes keeps its power)",
                        options.pbrt.radiances,
                        (spread - 1.0) * 100.0
                    )));
                }
                for (piece, area) in cut.pieces {
                    let mut lit = emitting(area)?;
                    if area <= 0.0 {
                        // Degenerate faces: no ray meets them, no light leaves them.
                        lit.emission = Color::BLACK;
                    }
                    let piece = Object::mesh(Arc::new(piece)).with_transform_of(object.transform);
                    placed.push(place(piece, lit)?);
                }
            }
            // pbrt-v4's spheres, disks and cylinders give their area in their own space
            // (`Sphere::Area` and the rest ignore the transform), and so does `power` here.
            _ => {
                let lit = emitting(area)?;
                placed.push(place(object, lit)?);
            }
        }
    }
    Ok(placed)
}

/// The path pbrt's `Film` names as the image, checked to be a plain file name (it comes from
/// a file that may not be the user's own; rayforge writes it in the current folder, as pbrt
/// does, and never elsewhere).
pub fn film_output(desc: &Description, scene: &Path) -> Result<std::path::PathBuf, SceneError> {
    let (name, film) = camera::film_filename(&desc.options)?;
    let plain = Path::new(&name);
    let ok = plain.components().count() == 1
        && matches!(
            plain.components().next(),
            Some(std::path::Component::Normal(_))
        );
    if !ok {
        let message = format!(
            "the film's filename \"{}\" is not a plain file name: rayforge writes a scene's \
             default output only into the current folder; give -o",
            crate::error::clip_to(&name, 80)
        );
        return Err(match film {
            Some(f) => f.error(message),
            None => SceneError::new(scene, message),
        });
    }
    Ok(plain.to_path_buf())
}
