//! Points drawn on shapes, for the path tracer's light sampling (pbrt-v4's `Shape::Sample`):
//! by area on the shape's own surface ([`ShapeSampler::sample_area`], `Shape::Sample(u)`), and
//! on the shape placed by a transform as seen from a point, with the density per solid angle
//! there ([`ShapeSampler::sample_solid_angle`], `Shape::Sample(ctx, u)`) and the same density
//! for a point a path reached by itself ([`ShapeSampler::pdf_solid_angle`], `Shape::PDF(ctx,
//! wi)`), which multiple importance sampling weighs against the BSDF's.
//!
//! Sampling belongs to the shapes, not to the lights: how to draw a point uniformly on a
//! spindle torus or a cone is the shape's geometry, so each shape's file holds its own area and
//! draw (`sphere::sample_area`, `torus::sample_area`, ...), and this module gathers them into
//! one enum and turns their densities into the ones light sampling needs. What a point gives
//! off, and which side of the surface glows, is the lights' business.
//!
//! By solid angle, a sphere seen from outside draws a direction in the cone it subtends
//! ([`sphere::SubtendedCone`]), where every sample meets the visible cap; from inside, and
//! every other shape, a point is drawn by area and its density turned into one per solid
//! angle (`density per area × distance² / |cos θ|`). A sphere stretched unevenly (an
//! ellipsoid) is not a sphere in the world, and is drawn by area too.

use super::{cone, cube, cylinder, rectangle, ring, sphere, torus, triangle, LocalHit, Mesh};
use super::{sphere::SubtendedCone, PartialQuadric, Triangle};
use crate::math::{Distribution1D, Point3, Transform, Vec3};
use std::sync::Arc;

/// A shape that can be sampled by area, in its own object space (the unit sphere, the cube
/// from −1 to 1, ...): the shapes of [`crate::scene::Shape`] with a finite surface.
#[derive(Debug, Clone)]
pub enum ShapeSampler {
    /// The unit sphere.
    Sphere,
    /// The cube from −1 to 1.
    Cube,
    /// The square from −1 to 1 of the xz plane.
    Rectangle,
    /// The ring (a disc when `inner` is 0) of the xz plane.
    Ring {
        /// Radius of the hole.
        inner: f64,
        /// Outer radius.
        outer: f64,
    },
    /// One triangle (its face normal is the side an emitting face lights).
    Triangle(Box<Triangle>),
    /// A triangle mesh: a face picked by its area, a point on it uniformly.
    Mesh {
        /// The mesh.
        mesh: Arc<Mesh>,
        /// Its faces, in proportion to their areas.
        faces: Distribution1D,
    },
    /// The cylinder of radius 1 between two finite heights, with its end discs when closed.
    Cylinder(Heights),
    /// The double cone x² + z² = y² between two finite heights, with its end discs when
    /// closed.
    Cone(Heights),
    /// One of pbrt-v4's cut quadrics, uniformly over what its cut keeps.
    Partial(PartialQuadric),
    /// A ring or spindle torus about the y axis (see [`torus::is_sampled`]).
    Torus {
        /// Radius of the tube's centre circle.
        major: f64,
        /// Radius of the tube.
        minor: f64,
    },
}

/// Where a finite cylinder or cone of [`ShapeSampler`] runs along y, and whether its end
/// discs are part of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Heights {
    /// The lower end.
    pub minimum: f64,
    /// The upper end.
    pub maximum: f64,
    /// Whether the end discs are part of the surface.
    pub closed: bool,
}

impl Heights {
    /// The heights from `minimum` to `maximum`, if both are finite and the span is not empty
    /// (an infinite cylinder or cone has no area to sample).
    pub fn finite(minimum: f64, maximum: f64, closed: bool) -> Option<Self> {
        (minimum.is_finite() && maximum.is_finite() && maximum > minimum).then_some(Self {
            minimum,
            maximum,
            closed,
        })
    }
}

/// A point drawn uniformly by area on a shape's own surface, in object space: its density is
/// one over the shape's [`area`](ShapeSampler::area).
#[derive(Debug, Clone, Copy)]
pub struct AreaSample {
    /// The point.
    pub point: Point3,
    /// The unit normal of the surface there, as a ray's hit there sees it (its outward normal,
    /// or a flat shape's front), which the stretch of its area by a transform needs.
    pub normal: Vec3,
    /// Where a ray's hit there would be: the face and barycentric `u`, `v` on a mesh (which
    /// its texture coordinates need); nothing elsewhere.
    pub hit: LocalHit,
}

/// A point drawn on a placed shape as seen from a point, in world space.
#[derive(Debug, Clone, Copy)]
pub struct SolidAngleSample {
    /// The point.
    pub point: Point3,
    /// The unit normal of the surface there, oriented as [`AreaSample::normal`].
    pub normal: Vec3,
    /// The unit direction from the viewer to the point.
    pub direction: Vec3,
    /// The distance from the viewer to the point.
    pub distance: f64,
    /// The density of `direction` per unit of solid angle at the viewer.
    pub pdf: f64,
    /// Where a ray's hit there would be (see [`AreaSample::hit`]).
    pub hit: LocalHit,
}

impl ShapeSampler {
    /// The sampler of a triangle mesh, its faces picked by their areas; `None` when no face
    /// has any area.
    pub fn mesh(mesh: &Arc<Mesh>) -> Option<Self> {
        let areas: Vec<f64> = mesh
            .faces()
            .map(|f| {
                let [a, b, c] = mesh.corners(&f);
                (b - a).cross(c - a).length() / 2.0
            })
            .collect();
        Some(ShapeSampler::Mesh {
            mesh: Arc::clone(mesh),
            faces: Distribution1D::new(&areas).ok()?,
        })
    }

    /// The object-space area.
    pub fn area(&self) -> f64 {
        match self {
            ShapeSampler::Sphere => sphere::AREA,
            ShapeSampler::Cube => cube::AREA,
            ShapeSampler::Rectangle => rectangle::AREA,
            ShapeSampler::Ring { inner, outer } => ring::area(*inner, *outer),
            ShapeSampler::Triangle(t) => t.e1.cross(t.e2).length() / 2.0,
            ShapeSampler::Mesh { faces, .. } => faces.integral() * faces.len() as f64,
            ShapeSampler::Cylinder(h) => cylinder::area(h.minimum, h.maximum, h.closed),
            ShapeSampler::Cone(h) => cone::area(h.minimum, h.maximum, h.closed),
            ShapeSampler::Torus { major, minor } => torus::area(*major, *minor),
            ShapeSampler::Partial(q) => q.area(),
        }
    }

    /// A point uniformly by area, from `pick` (which part of the surface: a mesh's face, a
    /// cube's, a cylinder's side or caps) and `u`, all in [0, 1).
    pub fn sample_area(&self, pick: f64, u: [f64; 2]) -> AreaSample {
        let (point, normal) = match self {
            ShapeSampler::Sphere => sphere::sample_area(u),
            ShapeSampler::Cube => cube::sample_area(pick, u),
            ShapeSampler::Rectangle => (rectangle::point_at(u[0], u[1]), Vec3::Y),
            ShapeSampler::Ring { inner, outer } => (ring::sample_area(*inner, *outer, u), Vec3::Y),
            ShapeSampler::Triangle(t) => {
                let (b1, b2) = triangle::uniform_weights(u[0], u[1]);
                (t.p1 + t.e1 * b1 + t.e2 * b2, t.normal)
            }
            ShapeSampler::Mesh { mesh, faces } => {
                let (face, _) = faces.sample_discrete(pick);
                let [a, b, c] = mesh.corners(&mesh.face(face));
                let (b1, b2) = triangle::uniform_weights(u[0], u[1]);
                return AreaSample {
                    point: a + (b - a) * b1 + (c - a) * b2,
                    normal: mesh.face_normal(face as u32).normalize_or_zero(),
                    hit: LocalHit {
                        u: b1,
                        v: b2,
                        face: face as u32,
                        ..LocalHit::default()
                    },
                };
            }
            ShapeSampler::Cylinder(h) => {
                cylinder::sample_area(h.minimum, h.maximum, h.closed, pick, u)
            }
            ShapeSampler::Cone(h) => cone::sample_area(h.minimum, h.maximum, h.closed, pick, u),
            ShapeSampler::Torus { major, minor } => torus::sample_area(*major, *minor, u),
            ShapeSampler::Partial(q) => q.sample_area(u),
        };
        AreaSample {
            point,
            normal,
            hit: LocalHit::default(),
        }
    }

    /// The unit object-space geometric normal at `point` of the surface (of face `face`, for
    /// meshes), oriented as [`AreaSample::normal`].
    pub fn normal_at(&self, point: Point3, face: u32) -> Vec3 {
        let n = match self {
            ShapeSampler::Sphere => sphere::normal_at(point),
            ShapeSampler::Cube => cube::normal_at(point),
            ShapeSampler::Rectangle => rectangle::normal_at(point),
            ShapeSampler::Ring { .. } => ring::normal_at(point),
            ShapeSampler::Triangle(t) => t.normal,
            ShapeSampler::Mesh { mesh, .. } => mesh.face_normal(face),
            ShapeSampler::Cylinder(h) => cylinder::normal_at(point, h.minimum, h.maximum),
            ShapeSampler::Cone(h) => cone::normal_at(point, h.minimum, h.maximum),
            ShapeSampler::Torus { major, minor } => torus::normal_at(point, *major, *minor),
            ShapeSampler::Partial(q) => q.normal_at(point),
        };
        n.normalize_or_zero()
    }

    /// A point of the shape placed by `placed`, as seen from `from`, drawn the best way the
    /// shape has (see the [module](self)); `None` where it cannot be seen along the draw
    /// (`from` on the point itself, the surface edge-on).
    #[inline]
    pub fn sample_solid_angle(
        &self,
        placed: &Transform,
        from: Point3,
        pick: f64,
        u: [f64; 2],
    ) -> Option<SolidAngleSample> {
        if let Some(cone) = self.subtended_cone(placed, from) {
            let (point, normal) = cone.sample(u);
            let to_point = point - from;
            let distance = to_point.length();
            return (distance > 0.0).then(|| SolidAngleSample {
                point,
                normal,
                direction: to_point / distance,
                distance,
                pdf: cone.pdf(),
                hit: LocalHit::default(),
            });
        }
        self.sample_area_seen_from(placed, from, pick, u)
    }

    /// The density per solid angle at `from` with which
    /// [`sample_solid_angle`](Self::sample_solid_angle) draws `point` of the shape placed by
    /// `placed` (on face `face`, for meshes), seen along unit `direction`.
    #[inline]
    pub fn pdf_solid_angle(
        &self,
        placed: &Transform,
        from: Point3,
        point: Point3,
        direction: Vec3,
        face: u32,
    ) -> f64 {
        match self.subtended_cone(placed, from) {
            Some(cone) if cone.sees(point) => cone.pdf(),
            Some(_) => 0.0,
            None => self.pdf_area_seen_from(placed, from, point, direction, face),
        }
    }

    /// A point of the shape placed by `placed`, drawn uniformly by area whatever the shape
    /// (points facing away or hidden behind another part of the surface included), and its
    /// density per solid angle at `from`: what a surface only some of whose points give light
    /// needs (a CSG solid's primitive, of which the solid may cut away the side facing `from`).
    #[inline]
    pub fn sample_area_seen_from(
        &self,
        placed: &Transform,
        from: Point3,
        pick: f64,
        u: [f64; 2],
    ) -> Option<SolidAngleSample> {
        let sample = self.sample_area(pick, u);
        let point = placed.point(sample.point);
        let (area_pdf, normal) = self.area_density(placed, sample.normal);
        let to_point = point - from;
        let distance_squared = to_point.length_squared();
        let distance = distance_squared.sqrt();
        if distance <= 0.0 || area_pdf <= 0.0 {
            return None;
        }
        let direction = to_point / distance;
        let cos = normal.dot(direction);
        (cos != 0.0).then(|| SolidAngleSample {
            point,
            normal,
            direction,
            distance,
            pdf: area_pdf * distance_squared / cos.abs(),
            hit: sample.hit,
        })
    }

    /// The density per solid angle at `from` with which
    /// [`sample_area_seen_from`](Self::sample_area_seen_from) draws `point` (see
    /// [`pdf_solid_angle`](Self::pdf_solid_angle)).
    #[inline]
    pub fn pdf_area_seen_from(
        &self,
        placed: &Transform,
        from: Point3,
        point: Point3,
        direction: Vec3,
        face: u32,
    ) -> f64 {
        let local = placed.inverse_point(point);
        let (area_pdf, normal) = self.area_density(placed, self.normal_at(local, face));
        let cos = normal.dot(direction).abs();
        if cos <= 0.0 {
            return 0.0;
        }
        area_pdf * (point - from).length_squared() / cos
    }

    /// The world-space density per area of a point drawn uniformly by area on the shape placed
    /// by `placed`, where its unit object-space normal is `n_local`, and the unit world normal
    /// there: the transform stretches a patch of surface by the length of its normal mapped by
    /// the inverse transpose times the volume scale.
    #[inline]
    pub fn area_density(&self, placed: &Transform, n_local: Vec3) -> (f64, Vec3) {
        let scaled_area = self.area() * placed.volume_scale();
        let normal = placed.normal_unnormalised(n_local);
        let length = normal.length();
        let scale = length * scaled_area;
        if scale > 0.0 && scale.is_finite() {
            // One division for both: `1 / length` is the density times the scaled area.
            let density = 1.0 / scale;
            (density, normal * (density * scaled_area))
        } else {
            (0.0, Vec3::ZERO)
        }
    }

    /// The cone in which the sphere placed by `placed` is seen from `from`: for a sphere that
    /// stays a sphere (the transform's linear part a rotation times a uniform scale, within
    /// rounding) and a viewer outside it; `None` otherwise, where points are drawn by area.
    #[inline]
    fn subtended_cone(&self, placed: &Transform, from: Point3) -> Option<SubtendedCone> {
        let ShapeSampler::Sphere = self else {
            return None;
        };
        let (x, y, z) = (
            placed.vector(Vec3::X),
            placed.vector(Vec3::Y),
            placed.vector(Vec3::Z),
        );
        let (xx, yy, zz) = (x.length_squared(), y.length_squared(), z.length_squared());
        let scale2 = (xx + yy + zz) / 3.0;
        let tolerance = 1e-10 * scale2;
        let similar = [
            xx - scale2,
            yy - scale2,
            zz - scale2,
            x.dot(y),
            x.dot(z),
            y.dot(z),
        ]
        .iter()
        .all(|e| e.abs() <= tolerance);
        if !similar {
            return None;
        }
        SubtendedCone::seen_from(placed.point(Point3::ZERO), scale2.sqrt(), from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::stats::chi_square_p_value;
    use crate::math::{rotation_z, scaling, translation, Frame};
    use std::f64::consts::PI;

    fn numbers(random: &mut SplitMix64) -> [f64; 2] {
        [random.next_offset(), random.next_offset()]
    }

    /// A sphere of radius 0.3 at (1, 2, −1), turned (a similarity: sampled by its cone).
    fn placed_ball() -> Transform {
        Transform::new(translation(1.0, 2.0, -1.0) * rotation_z(0.7) * scaling(0.3, 0.3, 0.3))
    }

    #[test]
    fn a_sphere_seen_from_outside_is_sampled_uniformly_in_the_cone_it_subtends() {
        // Directions binned by cos θ about the axis (16 equal bins of [cos θₘ, 1]) and by the
        // angle about it (8 bins): uniform in the cone, every cell expects the same count.
        let placed = placed_ball();
        let centre = Point3::new(1.0, 2.0, -1.0);
        let from = Point3::new(2.5, 1.0, 0.4);
        let d = (centre - from).length();
        let cos_max = (1.0 - 0.09 / (d * d)).sqrt();
        let frame = Frame::from_normal((centre - from) / d);
        let mut random = SplitMix64::new(17);
        let (rows, columns) = (16, 8);
        let mut counts = vec![0_u64; rows * columns];
        let n = 160_000;
        for _ in 0..n {
            let pick = random.next_offset();
            let s = ShapeSampler::Sphere
                .sample_solid_angle(&placed, from, pick, numbers(&mut random))
                .expect("a sample");
            // On the sphere, on the cap facing the viewer, with the cone's density.
            assert!(((s.point - centre).length() - 0.3).abs() < 1e-12);
            assert!(s.normal.dot(s.direction) < 0.0);
            let expected_pdf = 1.0 / (2.0 * PI * (1.0 - cos_max));
            assert!((s.pdf - expected_pdf).abs() < 1e-9 * expected_pdf);
            let local = frame.to_local(s.direction);
            let row = ((1.0 - local.z) / (1.0 - cos_max) * rows as f64) as usize;
            let turn = local.y.atan2(local.x) / (2.0 * PI) + 0.5;
            let column = (turn * columns as f64) as usize;
            counts[row.min(rows - 1) * columns + column.min(columns - 1)] += 1;
        }
        let expected = vec![1.0 / (rows * columns) as f64; rows * columns];
        let p = chi_square_p_value(&counts, &expected);
        assert!(p > 1e-4, "p = {p}: {counts:?}");
    }

    #[test]
    fn from_inside_or_unevenly_stretched_a_sphere_is_sampled_by_area() {
        let from_inside = Point3::new(1.1, 2.05, -1.0);
        let ellipsoid = Transform::new(translation(1.0, 2.0, -1.0) * scaling(0.3, 0.5, 0.3));
        let from = Point3::new(3.0, 2.0, -1.0);
        let mut random = SplitMix64::new(8);
        for _ in 0..100 {
            let (pick, u) = (random.next_offset(), numbers(&mut random));
            let by_area =
                ShapeSampler::Sphere.sample_area_seen_from(&placed_ball(), from_inside, pick, u);
            let drawn =
                ShapeSampler::Sphere.sample_solid_angle(&placed_ball(), from_inside, pick, u);
            assert_eq!(by_area.map(|s| s.point), drawn.map(|s| s.point));
            let by_area = ShapeSampler::Sphere.sample_area_seen_from(&ellipsoid, from, pick, u);
            let drawn = ShapeSampler::Sphere.sample_solid_angle(&ellipsoid, from, pick, u);
            assert_eq!(by_area.map(|s| s.point), drawn.map(|s| s.point));
        }
        // A sphere seen from outside is not.
        let (pick, u) = (0.5, [0.3, 0.6]);
        let by_area = ShapeSampler::Sphere.sample_area_seen_from(&placed_ball(), from, pick, u);
        let drawn = ShapeSampler::Sphere.sample_solid_angle(&placed_ball(), from, pick, u);
        assert_ne!(by_area.map(|s| s.point), drawn.map(|s| s.point));
    }

    #[test]
    fn the_far_side_of_a_sphere_seen_from_outside_has_no_density() {
        // The cone's samples all lie on the cap facing the viewer: a point behind it, which
        // only a path through the sphere could reach, is never drawn.
        let placed = placed_ball();
        let centre = Point3::new(1.0, 2.0, -1.0);
        let from = Point3::new(3.0, 2.0, -1.0);
        let (near, far) = (centre + Vec3::X * 0.3, centre - Vec3::X * 0.3);
        let sampler = ShapeSampler::Sphere;
        assert!(sampler.pdf_solid_angle(&placed, from, near, -Vec3::X, 0) > 0.0);
        assert_eq!(
            sampler.pdf_solid_angle(&placed, from, far, -Vec3::X, 0),
            0.0
        );
    }
}
