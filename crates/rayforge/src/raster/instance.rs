//! Instances (the book's "Describing and rendering a scene"): a model (a tessellation, shared
//! by every object of the same shape) placed by its object's 4×4 transform, composed with the
//! camera's into one model-view transform, and accepted, rejected or marked for clipping as a
//! whole by its bounding sphere.

use super::clip::{ClipPlane, SphereSide};
use super::tessellate::{face_count, refine_until, refined_face_count, tessellate_until};
use super::tessellate::{Tessellation, EXTENT};
use super::Projection;
use super::RasterError;
use crate::geometry::Winding;
use crate::math::{Point3, Transform};
use crate::scene::Csg;
use crate::scene::{Object, Shape, World};
use glam::{DAffine3, DMat3};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// A model with its bounding sphere in object space.
#[derive(Debug)]
pub(crate) struct Model<'w> {
    pub mesh: Tessellation<'w>,
    pub sphere: (Point3, f64),
}

/// One object (or one primitive of a CSG solid) ready to draw.
#[derive(Debug)]
pub(crate) struct Instance<'w> {
    /// The object whose material and patterns shade it (a CSG primitive for CSG solids).
    pub surface: &'w Object,
    /// `world_from_object`, the parents' transforms included.
    pub transform: Transform,
    /// The model.
    pub model: Arc<Model<'w>>,
    /// Object space to view space: the camera transform after the object's.
    pub to_view: DAffine3,
    /// Whether back faces may be skipped.
    pub cull: bool,
    /// +1 or -1: the sign of a front face's screen-space orientation (a mirroring transform
    /// turns it over, and so does a mesh of the other [`Winding`]).
    pub front_sign: i64,
    /// For a CSG primitive: the solid and which leaf this is; its faces are kept only where
    /// the solid keeps its surface.
    pub csg: Option<(&'w Csg, usize)>,
    /// The planes its bounding sphere crosses (triangles are clipped against these only).
    pub planes: ([ClipPlane; 5], usize),
    /// Where its vertices start in the frame's vertex array.
    pub vertex_base: usize,
    /// Where its normals start in the frame's normal array.
    pub normal_base: usize,
}

/// A surface to draw: the object that shades it, its full transform, and its CSG solid.
type Part<'w> = (&'w Object, Transform, Option<(&'w Csg, usize)>);

/// What identifies a shape's tessellation, so that equal shapes share one.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ModelKey {
    Sphere,
    Cube,
    Plane,
    Rectangle,
    Cylinder(u64, u64, bool),
    Cone(u64, u64, bool),
    Torus(u64, u64),
    Ring(u64, u64),
    Mesh(usize),
    Curves(usize),
}

fn model_key(shape: &Shape) -> Option<ModelKey> {
    Some(match shape {
        Shape::Sphere => ModelKey::Sphere,
        Shape::Cube => ModelKey::Cube,
        Shape::Plane => ModelKey::Plane,
        Shape::Rectangle => ModelKey::Rectangle,
        Shape::Cylinder {
            minimum,
            maximum,
            closed,
        } => ModelKey::Cylinder(minimum.to_bits(), maximum.to_bits(), *closed),
        Shape::Cone {
            minimum,
            maximum,
            closed,
        } => ModelKey::Cone(minimum.to_bits(), maximum.to_bits(), *closed),
        Shape::Torus { major, minor } => ModelKey::Torus(major.to_bits(), minor.to_bits()),
        Shape::Ring { inner, outer } => ModelKey::Ring(inner.to_bits(), outer.to_bits()),
        Shape::Mesh(mesh) => ModelKey::Mesh(Arc::as_ptr(mesh) as usize),
        Shape::Curves(curves) => ModelKey::Curves(Arc::as_ptr(curves) as usize),
        Shape::Triangle(_) | Shape::Csg(_) | Shape::Partial(_) => return None,
    })
}

/// Tessellations already made for this frame.
#[derive(Default)]
struct Models<'w> {
    shared: Vec<((ModelKey, u64), Arc<Model<'w>>)>,
}

impl<'w> Models<'w> {
    /// The model of a shape, its faces cut so that no edge is longer than `max_edge` (object
    /// units; 0 for no refinement: only CSG primitives are refined, see [`refine`]).
    /// Refused, before any of it is made, when the model alone would have more than `budget`
    /// triangles; [`RasterError::Cancelled`] (its counts of tiles 0, for the caller to fill
    /// in) once `cancel` is set while it is made.
    fn get(
        &mut self,
        shape: &'w Shape,
        divisions: u32,
        max_edge: f64,
        budget: u64,
        cancel: Option<&AtomicBool>,
    ) -> Result<Arc<Model<'w>>, RasterError> {
        let key = model_key(shape).map(|k| (k, max_edge.to_bits()));
        if let Some(key) = key {
            if let Some((_, model)) = self.shared.iter().find(|(k, _)| *k == key) {
                return Ok(Arc::clone(model));
            }
        }
        let too_many = || RasterError::TooManyTriangles { limit: budget };
        if face_count(shape, divisions) > budget {
            return Err(too_many());
        }
        let cancelled = RasterError::Cancelled {
            tiles_drawn: 0,
            tiles: 0,
        };
        let mut mesh = tessellate_until(shape, divisions, cancel).ok_or(cancelled)?;
        if max_edge > 0.0 {
            if refined_face_count(&mesh, max_edge) > budget {
                return Err(too_many());
            }
            mesh = refine_until(&mesh, max_edge, cancel).ok_or(cancelled)?;
        }
        let sphere = mesh.bounding_sphere();
        let model = Arc::new(Model { mesh, sphere });
        if let Some(key) = key {
            self.shared.push((key, Arc::clone(&model)));
        }
        Ok(model)
    }
}

/// An upper bound on how much a linear map can stretch a length: `√(‖M‖₁·‖M‖∞)` bounds the
/// largest singular value.
fn stretch(m: &DMat3) -> f64 {
    let cols = [m.x_axis, m.y_axis, m.z_axis];
    let norm_1 = cols
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max);
    let rows = m.transpose();
    let norm_inf = [rows.x_axis, rows.y_axis, rows.z_axis]
        .iter()
        .map(|r| r.abs().element_sum())
        .fold(0.0, f64::max);
    (norm_1 * norm_inf).sqrt()
}

/// Every object of `world` as instances, without those wholly outside the view, with vertex
/// and normal offsets assigned in scene order. Refused when the instances together would have
/// more than `max_triangles` triangles: each instance's vertices are transformed into arrays of
/// the frame's own, so memory grows with the sum (64 spheres at 4096 divisions asked for 51 GB).
/// Once `cancel` is set, stops within the model being made ([`RasterError::Cancelled`], its
/// counts of tiles 0).
pub(crate) fn instances<'w>(
    world: &'w World,
    projection: &Projection,
    divisions: u32,
    culling: bool,
    max_triangles: u64,
    cancel: Option<&AtomicBool>,
) -> Result<Vec<Instance<'w>>, RasterError> {
    // Every object's triangles first, counted without making them (before culling and CSG
    // refinement, which only remove and add a few): a scene far over the limit is refused
    // before its first model is made.
    let estimate = world
        .objects
        .iter()
        .map(|object| face_count(&object.shape, divisions))
        .fold(0u64, u64::saturating_add);
    if estimate > max_triangles {
        return Err(RasterError::TooManyTriangles {
            limit: max_triangles,
        });
    }
    let mut models = Models::default();
    let mut triangles = 0u64;
    let mut out = Vec::new();
    let (mut vertex_base, mut normal_base) = (0, 0);
    for object in &world.objects {
        let parts: Vec<Part<'w>> = match &object.shape {
            Shape::Csg(csg) => csg
                .leaves()
                .iter()
                .enumerate()
                .map(|(i, leaf)| {
                    let placed = object
                        .transform
                        .then_after(&leaf.transform)
                        .unwrap_or(leaf.transform);
                    (leaf, placed, Some((&**csg, i)))
                })
                .collect(),
            _ => vec![(object, object.transform, None)],
        };
        for (surface, transform, csg) in parts {
            // A CSG primitive is refined to twice the resolution of a sphere as large as the whole
            // solid, so that small parts (a gear's teeth) stay small.
            let max_edge = match csg {
                Some((solid, _)) => {
                    let b = solid.bounds();
                    let world_edge = if b.is_empty() {
                        0.0
                    } else {
                        // Half a sphere's ring spacing: cut edges follow the other operands.
                        let radius = (b.max - b.min).length().min(2.0 * EXTENT) / 2.0;
                        radius * std::f64::consts::PI / (2 * divisions) as f64
                    };
                    let scale = stretch(&DAffine3::from_mat4(transform.matrix()).matrix3);
                    if scale > 0.0 && world_edge.is_finite() {
                        world_edge / scale
                    } else {
                        0.0
                    }
                }
                None => 0.0,
            };
            let model = models.get(
                &surface.shape,
                divisions,
                max_edge,
                max_triangles - triangles,
                cancel,
            )?;
            let to_view =
                *projection.world_to_view_affine() * DAffine3::from_mat4(transform.matrix());
            let (centre, radius) = model.sphere;
            let centre = to_view.transform_point3(centre);
            let radius = radius * stretch(&to_view.matrix3);
            let mut planes = (projection.planes().to_owned(), 0);
            let mut outside = false;
            for plane in projection.planes() {
                match plane.classify_sphere(centre, radius) {
                    SphereSide::Inside => {}
                    SphereSide::Outside => outside = true,
                    SphereSide::Crossing => {
                        planes.0[planes.1] = *plane;
                        planes.1 += 1;
                    }
                }
            }
            if outside || model.mesh.faces.is_empty() {
                continue;
            }
            // A mirroring transform turns the winding over, and so does a mesh whose faces
            // are counter-clockwise in right-handed axes (an OBJ model's).
            let mirrored = to_view.matrix3.determinant() < 0.0;
            let reversed = model.mesh.winding == Winding::RightHanded;
            let front_sign = if mirrored != reversed { 1 } else { -1 };
            triangles += model.mesh.faces.len() as u64;
            if triangles > max_triangles {
                return Err(RasterError::TooManyTriangles {
                    limit: max_triangles,
                });
            }
            let vertices = model.mesh.positions.len();
            let normals = model.mesh.normals.len();
            out.push(Instance {
                surface,
                transform,
                // From inside a closed shape (a room made of a cube) every face looks away. A
                // glTF material that is single-sided has no back to draw (as the ray tracers
                // pass through it), whatever the option.
                cull: (culling && csg.is_none() && model.mesh.closed && centre.length() > radius)
                    || surface
                        .material
                        .metal_rough
                        .as_ref()
                        .is_some_and(|m| m.culls_back()),
                model,
                to_view,
                front_sign,
                csg,
                planes,
                vertex_base,
                normal_base,
            });
            vertex_base += vertices;
            normal_base += normals;
        }
    }
    Ok(out)
}
