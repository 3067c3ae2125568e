//! The world (chapter 7): objects and lights, and how its hits are lit (its lighting model).
//! The book's one-call entry points that trace it live in the crate's `book` facade.

use super::intersection::{sort_intersections, Intersection};
use super::object::Object;
use crate::color::Color;
use crate::math::{point, scaling, Ray};
use crate::media::{Media, MediumId};
use crate::shading::{EnvironmentMap, Light, Material};
use std::sync::Arc;

/// Everything in the scene that rays can meet or be lit by.
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    /// The objects, in the order they were added.
    pub objects: Vec<Object>,
    /// The light sources; each contributes its own diffuse and specular terms.
    pub lights: Vec<Light>,
    /// The colour of rays that hit nothing (black in the book).
    pub background: Color,
    /// How hits are shaded.
    pub lighting: LightingModel,
    /// The refractive index of empty space (the optics model's ambient index; 1 by default).
    pub ambient_index: f64,
    /// Light arriving from every direction far away (an equirectangular sky), for the path
    /// tracer; without one, the path tracer takes the background as a constant sky.
    pub environment: Option<Arc<EnvironmentMap>>,
    /// Further environment maps whose light adds to `environment`'s (a pbrt-v4 scene's
    /// several image `infinite` lights), for the path tracer, which samples each by its power.
    pub more_environments: Vec<Arc<EnvironmentMap>>,
    /// The participating media that objects' interfaces name (none by default); only the path
    /// tracer renders them.
    pub media: Media,
    /// The medium the camera sits in (`None`: vacuum); where it is the medium all around
    /// (fog), objects' outsides name it too.
    pub camera_medium: Option<MediumId>,
}

/// How a world's hits are shaded: which book's lighting model (chosen per scene).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightingModel {
    /// The Ray Tracer Challenge: Phong with per-material ambient, diffuse and specular weights,
    /// Schlick's Fresnel term, over- and under-points against acne.
    #[default]
    Phong,
    /// Computer Graphics from Scratch's first stage: the nearest surface's colour, unlit.
    Flat,
    /// Computer Graphics from Scratch: ambient, point and directional lights, the book's
    /// diffuse and specular terms and reflection blend, reproduced bit for bit.
    Cgfs,
    /// Fundamentals of Ray Tracing: matte, gloss, opacity and refraction by Fresnel's
    /// equations, lights falling off with the square of the distance, automatic exposure.
    Optics,
}

impl Default for World {
    fn default() -> Self {
        Self {
            objects: Vec::new(),
            lights: Vec::new(),
            background: Color::BLACK,
            lighting: LightingModel::Phong,
            ambient_index: 1.0,
            environment: None,
            more_environments: Vec::new(),
            media: Media::NONE,
            camera_medium: None,
        }
    }
}

impl World {
    /// The book's `world()`: nothing in it.
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether any medium fills part of the world: the path tracer then tracks light through
    /// media (and crosses index-matched boundaries), which the other renderers ignore.
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
    }

    /// The book's `intersect_world(world, ray)`: every intersection, sorted by `t`.
    pub fn intersect(&self, ray: &Ray) -> Vec<Intersection<'_>> {
        let mut xs = Vec::new();
        self.intersect_into(ray, &mut xs);
        xs
    }

    /// `intersect_world` into a caller's buffer (cleared first), sorted by `t`.
    pub fn intersect_into<'a>(&'a self, ray: &Ray, xs: &mut Vec<Intersection<'a>>) {
        xs.clear();
        for object in &self.objects {
            object.intersect(ray, xs);
        }
        sort_intersections(xs);
    }
}

/// The book's `default_world()`: a light at (-10, 10, -10) and two concentric spheres.
pub fn default_world() -> World {
    let outer = Object::sphere().with_material(Material {
        color: Color::new(0.8, 1.0, 0.6),
        diffuse: 0.7,
        specular: 0.2,
        ..Material::DEFAULT
    });
    let inner = Object::sphere().with_transform(scaling(0.5, 0.5, 0.5));
    World {
        objects: vec![outer, inner],
        lights: vec![Light::point(point(-10.0, 10.0, -10.0), Color::WHITE)],
        ..World::default()
    }
}
