//! An object: a shape placed in the world by a transform, with a material (chapters 5–9).

use crate::math::{Point3, Ray, Transform, Vec3};
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

    /// The same object with a prepared transform.
    pub fn with_transform_of(mut self, transform: Transform) -> Self {
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
            .intersect(&local, |t| out.push(Intersection::new(t, self)));
    }

    /// The book's `intersect(shape, ray)` returning a fresh list (for tests and one-off queries).
    pub fn intersections<'a>(&'a self, ray: &Ray) -> Vec<Intersection<'a>> {
        let mut out = Vec::new();
        self.intersect(ray, &mut out);
        out
    }

    /// The book's `normal_at(shape, world_point)`: the unit world-space normal.
    #[inline]
    pub fn normal_at(&self, world_point: Point3) -> Vec3 {
        let local = self.shape.normal_at(self.world_to_object(world_point));
        self.transform.normal(local)
    }
}
