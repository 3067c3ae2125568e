//! An object: a shape placed in the world by a transform, with a material (chapters 5–9).

use crate::geometry::LocalHit;
use crate::geometry::Triangle;
use crate::math::{Aabb, Point3, Ray, SingularTransform, Transform, Vec3};
use crate::{Intersection, Material, Shape};

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
}

impl Object {
    /// An object with the identity transform and the default material.
    pub fn new(shape: Shape) -> Self {
        Self {
            shape,
            transform: Transform::IDENTITY,
            material: Material::DEFAULT,
            casts_shadow: true,
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

    /// The book's `parent_space_bounds_of(shape)`: the shape's box in world space.
    pub fn bounds(&self) -> Aabb {
        self.shape.bounds().transform(&self.transform)
    }

    /// The book's `world_to_object(shape, point)`.
    #[inline]
    pub fn world_to_object(&self, point: Point3) -> Point3 {
        self.transform.inverse_point(point)
    }

    /// The ray in object space: what the book's `test_shape` records as `saved_ray`.
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        ray.to_object(&self.transform)
    }

    /// The book's `intersect(shape, ray)`: appends every intersection (any sign of `t`) to `out`.
    #[inline]
    pub fn intersect<'a>(&'a self, ray: &Ray, out: &mut Vec<Intersection<'a>>) {
        let local = self.ray_to_object(ray);
        self.shape
            .intersect_hits(&local, |h| out.push(Intersection::from_local(self, h)));
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

    /// The unit world-space normal at a hit given in the shape's own terms.
    #[inline]
    pub fn normal_at_local_hit(&self, world_point: Point3, hit: &LocalHit) -> Vec3 {
        let local = self
            .shape
            .normal_at_hit(self.world_to_object(world_point), hit);
        self.transform.normal(local)
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
        let placement = parent.then_after(&self.transform)?;
        let mut placed = self.clone();
        match &self.shape {
            Shape::Csg(csg) => {
                placed.shape = Shape::Csg(std::sync::Arc::new(csg.placed_by(&placement)?));
                placed.transform = Transform::IDENTITY;
            }
            _ => placed.transform = placement,
        }
        Ok(placed)
    }
}
