//! An object: a shape placed in the world by a transform, with a material (chapters 5–9).

use crate::color::Color;
use crate::geometry::LocalHit;
use crate::geometry::Mesh;
use crate::geometry::Triangle;
use crate::math::random::SplitMix64;
use crate::math::{Aabb, Motion, Point3, Ray, SingularTransform, Transform, Vec3};
use crate::media::MediumInterface;
use crate::scene::{Intersection, Shape};
use crate::shading::texture_graph::TextureContext;
use crate::shading::{Material, MetalRough, SurfacePoint};
use std::borrow::Cow;

/// A shape with its transform and material.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// What it is, in object space.
    pub shape: Shape,
    /// `world_from_object` (and its cached inverse).
    pub transform: Transform,
    /// How it looks.
    pub material: Material,
    /// Whether it blocks light from reaching other surfaces (`shadow: false` in scene files).
    pub casts_shadow: bool,
    /// Where it moves while the shutter is open (motion blur); `transform` is then where it
    /// is when the shutter opens. Boxed: most objects stand still.
    pub motion: Option<Box<Motion>>,
    /// The media inside and outside it, where it bounds one (see [`MediumInterface`]); `None`:
    /// a ray crossing it stays in the medium it was in.
    pub media: Option<MediumInterface>,
}

impl Object {
    /// An object with the identity transform and the default material.
    pub fn new(shape: Shape) -> Self {
        Self {
            shape,
            transform: Transform::IDENTITY,
            material: Material::DEFAULT,
            casts_shadow: true,
            motion: None,
            media: None,
        }
    }

    /// The book's `sphere()`.
    pub fn sphere() -> Self {
        Self::new(Shape::Sphere)
    }

    /// The book's `plane()`.
    pub fn plane() -> Self {
        Self::new(Shape::Plane)
    }

    /// The book's `cube()`.
    pub fn cube() -> Self {
        Self::new(Shape::Cube)
    }

    /// The book's `cylinder()`: infinite and open.
    pub fn cylinder() -> Self {
        Self::new(Shape::CYLINDER)
    }

    /// The book's `cone()`: infinite and open.
    pub fn cone() -> Self {
        Self::new(Shape::CONE)
    }

    /// The book's `triangle(p1, p2, p3)`.
    pub fn triangle(p1: Point3, p2: Point3, p3: Point3) -> Self {
        Self::new(Shape::Triangle(Box::new(Triangle::new(p1, p2, p3))))
    }

    /// The book's `smooth_triangle(p1, p2, p3, n1, n2, n3)`.
    pub fn smooth_triangle(
        p1: Point3,
        p2: Point3,
        p3: Point3,
        n1: Vec3,
        n2: Vec3,
        n3: Vec3,
    ) -> Self {
        Self::new(Shape::Triangle(Box::new(Triangle::smooth(
            p1, p2, p3, n1, n2, n3,
        ))))
    }

    /// A mesh object (an OBJ model), sharing the mesh with any other instances.
    pub fn mesh(mesh: std::sync::Arc<crate::geometry::Mesh>) -> Self {
        Self::new(Shape::Mesh(mesh))
    }

    /// The book's `glass_sphere()`.
    pub fn glass_sphere() -> Self {
        Self::sphere().with_material(Material::glass())
    }

    /// The same object with a transform given as a matrix.
    ///
    /// # Panics
    /// When the matrix is singular; scene loaders use [`Transform::try_new`] and
    /// [`Object::with_transform_of`] instead.
    pub fn with_transform(self, matrix: glam::DMat4) -> Self {
        self.with_transform_of(Transform::new(matrix))
    }

    /// The same object with a prepared transform. A CSG solid's primitives are moved instead
    /// (see [`Object::placed_by`]).
    pub fn with_transform_of(mut self, transform: Transform) -> Self {
        if let Shape::Csg(_) = self.shape {
            // A product of two invertible transforms is invertible; should rounding say
            // otherwise, keep the transform on the solid itself (its geometry stays right).
            if let Ok(placed) = self.placed_by(&transform) {
                return placed;
            }
        }
        self.transform = transform;
        self
    }

    /// The same object with a material.
    pub fn with_material(mut self, material: Material) -> Self {
        self.material = material;
        self
    }

    /// The book's `set_transform(shape, m)`.
    ///
    /// # Panics
    /// When the matrix is singular.
    pub fn set_transform(&mut self, matrix: glam::DMat4) {
        self.transform = Transform::new(matrix);
    }

    /// The book's `parent_space_bounds_of(shape)`: the shape's box in world space (around
    /// every place it passes through, for a moving object).
    pub fn bounds(&self) -> Aabb {
        match &self.motion {
            None => self.shape.bounds().transform(&self.transform),
            Some(motion) => motion.bounds(&self.shape.bounds()),
        }
    }

    /// The transform at `time` (a fraction of the shutter interval): `transform` itself for an
    /// object that stands still.
    #[inline]
    pub fn transform_at(&self, time: f64) -> Cow<'_, Transform> {
        match &self.motion {
            None => Cow::Borrowed(&self.transform),
            Some(motion) => Cow::Owned(motion.at(time)),
        }
    }

    /// The book's `world_to_object(shape, point)` (for a moving object, where it is when the
    /// shutter opens).
    #[inline]
    pub fn world_to_object(&self, point: Point3) -> Point3 {
        self.transform.inverse_point(point)
    }

    /// `world_to_object` at an instant of the shutter interval.
    #[inline]
    pub fn world_to_object_at(&self, point: Point3, time: f64) -> Point3 {
        self.transform_at(time).inverse_point(point)
    }

    /// The surface colour of this object's material at a world-space point (on the object as it
    /// was at `time`), read at the surface's texture coordinates and vertex colour `at` (see
    /// [`Material::surface_color`]).
    #[inline]
    pub fn surface_color(&self, point: Point3, at: &SurfacePoint, time: f64) -> Color {
        self.material
            .surface_color(at, || self.world_to_object_at(point, time))
    }

    /// The ray in object space (where the object is at the ray's time): what the book's
    /// `test_shape` records as `saved_ray`.
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        ray.to_object(&self.transform_at(ray.time))
    }

    /// The book's `intersect(shape, ray)`: appends every intersection (any sign of `t`) to `out`.
    #[inline]
    pub fn intersect<'a>(&'a self, ray: &Ray, out: &mut Vec<Intersection<'a>>) {
        let local = self.ray_to_object(ray);
        self.shape
            .intersect_hits(&local, |h| out.push(Intersection::from_local(self, h)));
    }

    /// The nearest hit of the object-space ray `local` in `[t_min, t_max)`, on the surface as
    /// the material leaves it: a glTF material's alpha mask and single-sided back cut holes
    /// that rays pass through (see [`MetalRough`](crate::shading::MetalRough)).
    #[inline]
    pub fn closest_local_hit(&self, local: &Ray, t_min: f64, t_max: f64) -> Option<LocalHit> {
        match (&self.shape, self.material.metal_rough.as_deref()) {
            (Shape::Mesh(mesh), Some(m)) if m.has_holes() || m.culls_back() => {
                mesh.closest_hit_where(local, t_min, t_max, |h| surface_is_there(mesh, m, local, h))
            }
            (shape, None) if self.has_alpha() => {
                shape.closest_hit_where(local, t_min, t_max, |h| self.alpha_keeps(local, h))
            }
            _ => self.shape.closest_hit(local, t_min, t_max),
        }
    }

    /// Whether the object-space ray `local` meets the surface in `[t_min, t_max)`, with the
    /// holes of [`Object::closest_local_hit`].
    #[inline]
    pub fn any_local_hit(&self, local: &Ray, t_min: f64, t_max: f64) -> bool {
        match (&self.shape, self.material.metal_rough.as_deref()) {
            (Shape::Mesh(mesh), Some(m)) if m.has_holes() || m.culls_back() => {
                mesh.any_hit_where(local, t_min, t_max, |h| surface_is_there(mesh, m, local, h))
            }
            (shape, None) if self.has_alpha() => {
                shape.any_hit_where(local, t_min, t_max, |h| self.alpha_keeps(local, h))
            }
            _ => self.shape.any_hit(local, t_min, t_max),
        }
    }

    /// Whether the material cuts the surface by an alpha texture (pbrt-v4's `alpha`; not on
    /// CSG solids, whose primitives' hits the solid filters itself).
    #[inline]
    pub(crate) fn has_alpha(&self) -> bool {
        !matches!(self.shape, Shape::Csg(_))
            && self
                .material
                .textures
                .as_ref()
                .is_some_and(|t| t.alpha.is_some())
    }

    /// Where the material's textures are read at a hit on this object: the world-space
    /// `point`, the surface's `at` coordinates, or where it has none pbrt-v4's: a triangle's
    /// (0, 0), (1, 0), (1, 1) at its corners, a quadric's parametric ones
    /// ([`Shape::quadric_uv`]); and the world-space geometric `normal`.
    #[inline]
    pub fn texture_context(
        &self,
        point: Point3,
        at: &SurfacePoint,
        hit: &LocalHit,
        normal: Vec3,
    ) -> TextureContext {
        let uv = match (at.uv, &self.shape) {
            (Some(uv), _) => uv,
            (None, Shape::Mesh(_)) => (hit.u + hit.v, hit.v),
            (None, shape) => shape.quadric_uv(self.transform_at(hit.time).inverse_point(point)),
        };
        TextureContext { uv, point, normal }
    }

    /// Whether a hit on this object survives its alpha texture: pbrt-v4's stochastic test,
    /// the coin a hash of the ray and the hit (as for glTF's blended surfaces), so the same ray
    /// always gets the same answer and shadow rays see the same holes as camera rays.
    fn alpha_keeps(&self, local: &Ray, hit: &LocalHit) -> bool {
        let Some(textures) = self.material.textures.as_deref() else {
            return true;
        };
        let transform = self.transform_at(local.time);
        let at = self.shape.surface_point(hit);
        let local_point = local.position(hit.t);
        let point = transform.point(local_point);
        let normal = match &self.shape {
            Shape::Mesh(mesh) => mesh.face_normal(hit.face),
            shape => shape.normal_at_hit(local_point, hit),
        };
        let ctx = self.texture_context(point, &at, hit, transform.normal(normal));
        textures.is_there(&ctx, hit_coin(local, hit))
    }

    /// The world-space tangent at a hit on a mesh with tangents, with the sign that turns
    /// `normal × tangent` into the bitangent (flipped where the transform mirrors).
    #[inline]
    pub fn tangent_at(&self, hit: &LocalHit) -> Option<(Vec3, f64)> {
        let Shape::Mesh(mesh) = &self.shape else {
            return None;
        };
        let (tangent, sign) = mesh.tangent_at(hit)?;
        let transform = self.transform_at(hit.time);
        let sign = if transform.mirrors() { -sign } else { sign };
        Some((transform.vector(tangent), sign))
    }

    /// The book's `intersect(shape, ray)` returning a fresh list (for tests and one-off queries).
    pub fn intersections<'a>(&'a self, ray: &Ray) -> Vec<Intersection<'a>> {
        let mut out = Vec::new();
        self.intersect(ray, &mut out);
        out
    }

    /// The book's `normal_to_world(shape, normal)`: an object-space normal in world space, unit
    /// length.
    #[inline]
    pub fn normal_to_world(&self, normal: Vec3) -> Vec3 {
        self.transform.normal(normal)
    }

    /// The book's `normal_at(shape, world_point)`: the unit world-space normal.
    #[inline]
    pub fn normal_at(&self, world_point: Point3) -> Vec3 {
        let local = self.shape.normal_at(self.world_to_object(world_point));
        self.transform.normal(local)
    }

    /// The book's `normal_at(shape, world_point, hit)`: the normal at an intersection, using its
    /// `u`, `v` where the shape interpolates normals (smooth triangles).
    #[inline]
    pub fn normal_at_hit(&self, world_point: Point3, hit: &Intersection<'_>) -> Vec3 {
        self.normal_at_local_hit(world_point, &hit.local())
    }

    /// The unit world-space normal at a hit given in the shape's own terms (at the hit's time).
    #[inline]
    pub fn normal_at_local_hit(&self, world_point: Point3, hit: &LocalHit) -> Vec3 {
        let transform = self.transform_at(hit.time);
        let local = self
            .shape
            .normal_at_hit(transform.inverse_point(world_point), hit);
        transform.normal(local)
    }

    /// The object whose surface a hit is on: the hit primitive of a CSG solid, or itself.
    #[inline]
    pub fn surface(&self, leaf: u32) -> &Object {
        match &self.shape {
            Shape::Csg(csg) => csg.leaves().get(leaf as usize).unwrap_or(self),
            _ => self,
        }
    }

    /// The same object placed by `parent` (applied after its own transform). A CSG solid keeps
    /// the identity and moves its primitives instead, so each primitive always knows its full
    /// world transform (which its normals and patterns need).
    pub fn placed_by(&self, parent: &Transform) -> Result<Object, SingularTransform> {
        self.placed_by_moving(parent, parent)
    }

    /// The same object placed by a parent that moves from `start` (when the shutter opens) to
    /// `end` (when it closes), each applied after the object's own transform at that time.
    /// Passing the same transform twice is [`Object::placed_by`]; a parent that moves makes the
    /// object move (a CSG solid passes the motion on to its primitives).
    pub fn placed_by_moving(
        &self,
        start: &Transform,
        end: &Transform,
    ) -> Result<Object, SingularTransform> {
        let own_end = self.motion.as_ref().map_or(&self.transform, |m| m.end());
        let placed_start = start.then_after(&self.transform)?;
        let placed_end = end.then_after(own_end)?;
        let mut placed = self.clone();
        match &self.shape {
            Shape::Csg(csg) => {
                let leaves = csg.placed_by_moving(&placed_start, &placed_end)?;
                placed.shape = Shape::Csg(std::sync::Arc::new(leaves));
                placed.transform = Transform::IDENTITY;
                placed.motion = None;
            }
            _ => {
                placed.transform = placed_start;
                placed.motion = (placed_end != placed_start)
                    .then(|| Box::new(Motion::new(placed_start, placed_end)));
            }
        }
        Ok(placed)
    }
}

/// Whether a hit on a glTF mesh is on the surface: not on a culled back face, and where the
/// alpha mode keeps it. A blended surface's coin is a hash of the ray and the hit, so the same
/// ray always gets the same answer (renders stay independent of threads and order).
#[inline]
fn surface_is_there(mesh: &Mesh, material: &MetalRough, local: &Ray, hit: &LocalHit) -> bool {
    if material.culls_back() && local.direction.dot(mesh.face_normal(hit.face)) > 0.0 {
        return false;
    }
    if !material.has_holes() {
        return true;
    }
    let at = SurfacePoint {
        uv: mesh.texcoord_at(hit),
        vertex_color: mesh.color_at(hit),
    };
    material.is_there(&at, hit_coin(local, hit))
}

/// A number in `[0, 1)` that is a hash of the object-space ray and its hit: the coin of a
/// stochastic alpha test, the same for the same ray however often it is traced.
#[inline]
fn hit_coin(local: &Ray, hit: &LocalHit) -> f64 {
    let seed = u64::from(hit.face)
        ^ hit.t.to_bits().rotate_left(17)
        ^ local.direction.x.to_bits().rotate_left(31)
        ^ local.direction.y.to_bits().rotate_left(47)
        ^ local.origin.z.to_bits();
    (SplitMix64::new(seed).next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}
