//! pbrt-v4's quadrics as its scene files may cut them: a sphere kept between two heights and
//! up to an angle `φmax` about its axis, a disk with a hole swept to `φmax`, a cylinder swept
//! to `φmax`. They are in pbrt's own frame (the axis is z, φ measured from +x towards +y) and
//! carry their own sizes, so that the pbrt reader places them with the file's transform alone.
//!
//! **Intersection** is pbrt-v4's (`Sphere::BasicIntersect` and the others): both roots of the
//! quadric are found, and each is tested against the cut in turn, so a ray that enters
//! through the hole of a cut sphere still meets its inside. A hit point is pushed back onto
//! the surface before it is tested (as pbrt does), and a point on the axis is given the angle
//! of a point a hair off it.
//!
//! **Sampling by area** is uniform over what is left, which pbrt-v4 does not do: its
//! `Sphere::Sample` draws the whole sphere and divides by the cut area, so an area light on a
//! cut sphere is biased there. Here a cut sphere draws its height uniformly between the cuts
//! (the area of a sphere between two heights is proportional to their difference) and its
//! angle uniformly to `φmax`; a disk draws ρ² uniformly between the two radii' squares; a
//! cylinder draws its height and angle uniformly. Each draw's density is one over the cut area.
//!
//! Their fronts face as pbrt-v4's `∂p/∂u × ∂p/∂v` does: out of the sphere and the cylinder, to
//! +z for the disk. Their (u, v) are pbrt-v4's: `u = φ / φmax`, `v` from the lower cut's angle
//! to the upper's (sphere), from the outer edge in (disk), from `zmin` to `zmax` (cylinder).

use crate::math::{roots::solve_quadratic, sin_cos_turns, Aabb, Point3, Ray, Vec3};
use std::f64::consts::{PI, TAU};

/// A cut quadric of pbrt-v4 in its own frame (see the [module](self)). Build one with
/// [`PartialQuadric::sphere`], [`PartialQuadric::disk`] or [`PartialQuadric::cylinder`], which
/// clamp the cuts as pbrt-v4 does and refuse the ones that leave nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PartialQuadric {
    /// A sphere about the origin between two heights and up to an angle.
    Sphere {
        /// Its radius.
        radius: f64,
        /// The lower cut's height (−radius for none).
        z_min: f64,
        /// The upper cut's height (radius for none).
        z_max: f64,
        /// The angle from +z of the point at `z_min` (π for none): `acos(z_min / radius)`.
        theta_z_min: f64,
        /// The angle from +z of the point at `z_max` (0 for none).
        theta_z_max: f64,
        /// How far about z the surface is swept, in radians (2π for a whole turn).
        phi_max: f64,
    },
    /// A disk (an annulus where `inner_radius` is above 0) in the plane `z = height`.
    Disk {
        /// The plane's height.
        height: f64,
        /// The outer radius.
        radius: f64,
        /// The radius of the hole.
        inner_radius: f64,
        /// How far about z the surface is swept, in radians.
        phi_max: f64,
    },
    /// An open cylinder about z between two heights.
    Cylinder {
        /// Its radius.
        radius: f64,
        /// The lower end.
        z_min: f64,
        /// The upper end.
        z_max: f64,
        /// How far about z the surface is swept, in radians.
        phi_max: f64,
    },
}

/// Why a cut leaves no surface.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum CutError {
    /// The sweep is not above 0 (or not a number).
    #[error("the sweep φmax is above 0°, found {0}°")]
    Sweep(f64),
    /// The heights leave nothing between them.
    #[error("the cut keeps nothing between the heights {0} and {1}")]
    Heights(f64, f64),
    /// A radius is not a positive number, or the hole is as large as the disk.
    #[error("the radii {0} and {1} leave no surface")]
    Radii(f64, f64),
}

/// `φmax` in degrees as pbrt-v4 reads it: clamped to [0°, 360°], in radians; refused where
/// nothing is left (0° or less, or not a number).
fn sweep(phi_max_degrees: f64) -> Result<f64, CutError> {
    if phi_max_degrees.is_nan() || phi_max_degrees <= 0.0 {
        return Err(CutError::Sweep(phi_max_degrees));
    }
    Ok(phi_max_degrees.min(360.0).to_radians())
}

/// The angle of `(x, y)` about z from +x, in [0, 2π).
#[inline]
fn azimuth(x: f64, y: f64) -> f64 {
    let phi = y.atan2(x);
    if phi < 0.0 {
        phi + TAU
    } else {
        phi
    }
}

impl PartialQuadric {
    /// pbrt-v4's sphere of `radius` cut at `z_min`, `z_max` (each clamped to the sphere, in
    /// either order) and swept to `phi_max_degrees` (clamped to 360°).
    pub fn sphere(
        radius: f64,
        z_min: f64,
        z_max: f64,
        phi_max_degrees: f64,
    ) -> Result<Self, CutError> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(CutError::Radii(radius, 0.0));
        }
        let lo = z_min.min(z_max).clamp(-radius, radius);
        let hi = z_min.max(z_max).clamp(-radius, radius);
        if hi.is_nan() || lo.is_nan() || hi <= lo {
            return Err(CutError::Heights(z_min, z_max));
        }
        Ok(PartialQuadric::Sphere {
            radius,
            z_min: lo,
            z_max: hi,
            theta_z_min: (lo / radius).clamp(-1.0, 1.0).acos(),
            theta_z_max: (hi / radius).clamp(-1.0, 1.0).acos(),
            phi_max: sweep(phi_max_degrees)?,
        })
    }

    /// pbrt-v4's disk at `height` between `inner_radius` and `radius`, swept to
    /// `phi_max_degrees`.
    pub fn disk(
        height: f64,
        radius: f64,
        inner_radius: f64,
        phi_max_degrees: f64,
    ) -> Result<Self, CutError> {
        let ok = radius.is_finite() && inner_radius >= 0.0 && radius > inner_radius;
        if !ok || !height.is_finite() {
            return Err(CutError::Radii(inner_radius, radius));
        }
        Ok(PartialQuadric::Disk {
            height,
            radius,
            inner_radius,
            phi_max: sweep(phi_max_degrees)?,
        })
    }

    /// pbrt-v4's cylinder of `radius` between `z_min` and `z_max` (in either order), swept to
    /// `phi_max_degrees`.
    pub fn cylinder(
        radius: f64,
        z_min: f64,
        z_max: f64,
        phi_max_degrees: f64,
    ) -> Result<Self, CutError> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(CutError::Radii(radius, 0.0));
        }
        let (lo, hi) = (z_min.min(z_max), z_min.max(z_max));
        if !(hi > lo && lo.is_finite() && hi.is_finite()) {
            return Err(CutError::Heights(z_min, z_max));
        }
        Ok(PartialQuadric::Cylinder {
            radius,
            z_min: lo,
            z_max: hi,
            phi_max: sweep(phi_max_degrees)?,
        })
    }

    /// How far about z the surface is swept, in radians.
    pub fn phi_max(&self) -> f64 {
        match *self {
            PartialQuadric::Sphere { phi_max, .. }
            | PartialQuadric::Disk { phi_max, .. }
            | PartialQuadric::Cylinder { phi_max, .. } => phi_max,
        }
    }

    /// Calls `hit(t)` for each root of the ray with the whole quadric whose point the cut
    /// keeps (negative `t` included), nearer first.
    #[inline]
    pub fn intersect(&self, ray: &Ray, mut hit: impl FnMut(f64)) {
        let (o, d) = (ray.origin, ray.direction);
        match *self {
            PartialQuadric::Sphere {
                radius,
                z_min,
                z_max,
                phi_max,
                ..
            } => {
                let a = d.length_squared();
                let b = 2.0 * d.dot(o);
                let c = o.length_squared() - radius * radius;
                let Some((t0, t1)) = solve_quadratic(a, b, c) else {
                    return;
                };
                for t in [t0, t1] {
                    let mut p = o + d * t;
                    // Back onto the surface, as pbrt-v4 refines its hit.
                    p *= radius / p.length();
                    if p.x == 0.0 && p.y == 0.0 {
                        p.x = 1e-5 * radius;
                    }
                    let cut_below = z_min > -radius && p.z < z_min;
                    let cut_above = z_max < radius && p.z > z_max;
                    if !(cut_below || cut_above || azimuth(p.x, p.y) > phi_max) {
                        hit(t);
                    }
                }
            }
            PartialQuadric::Disk {
                height,
                radius,
                inner_radius,
                phi_max,
            } => {
                if d.z == 0.0 {
                    return;
                }
                let t = (height - o.z) / d.z;
                let (x, y) = (o.x + t * d.x, o.y + t * d.y);
                let r2 = x * x + y * y;
                if r2 > radius * radius || r2 < inner_radius * inner_radius {
                    return;
                }
                if azimuth(x, y) <= phi_max {
                    hit(t);
                }
            }
            PartialQuadric::Cylinder {
                radius,
                z_min,
                z_max,
                phi_max,
            } => {
                let a = d.x * d.x + d.y * d.y;
                let b = 2.0 * (d.x * o.x + d.y * o.y);
                let c = o.x * o.x + o.y * o.y - radius * radius;
                let Some((t0, t1)) = solve_quadratic(a, b, c) else {
                    return;
                };
                for t in [t0, t1] {
                    let p = o + d * t;
                    // Back onto the surface in x and y, as pbrt-v4 refines its hit.
                    let r = (p.x * p.x + p.y * p.y).sqrt();
                    let (x, y) = if r > 0.0 {
                        (p.x * radius / r, p.y * radius / r)
                    } else {
                        (p.x, p.y)
                    };
                    if p.z >= z_min && p.z <= z_max && azimuth(x, y) <= phi_max {
                        hit(t);
                    }
                }
            }
        }
    }

    /// The unit normal at a point of the surface, its front (see the [module](self)).
    #[inline]
    pub fn normal_at(&self, p: Point3) -> Vec3 {
        match *self {
            PartialQuadric::Sphere { .. } => p.normalize_or_zero(),
            PartialQuadric::Disk { .. } => Vec3::Z,
            PartialQuadric::Cylinder { .. } => Vec3::new(p.x, p.y, 0.0).normalize_or_zero(),
        }
    }

    /// pbrt-v4's (u, v) at a point of the surface (see the [module](self)).
    pub fn uv(&self, p: Point3) -> (f64, f64) {
        let phi = azimuth(p.x, p.y);
        let u = (phi / self.phi_max()).min(1.0);
        let v = match *self {
            PartialQuadric::Sphere {
                radius,
                theta_z_min,
                theta_z_max,
                ..
            } => {
                let theta = (p.z / radius).clamp(-1.0, 1.0).acos();
                (theta - theta_z_min) / (theta_z_max - theta_z_min)
            }
            PartialQuadric::Disk {
                radius,
                inner_radius,
                ..
            } => (radius - (p.x * p.x + p.y * p.y).sqrt()) / (radius - inner_radius),
            PartialQuadric::Cylinder { z_min, z_max, .. } => (p.z - z_min) / (z_max - z_min),
        };
        (u, v)
    }

    /// The point at pbrt-v4's (u, v) (what a tessellation of the surface walks).
    pub fn point_at(&self, u: f64, v: f64) -> Point3 {
        let phi = u * self.phi_max();
        let (sin, cos) = phi.sin_cos();
        match *self {
            PartialQuadric::Sphere {
                radius,
                theta_z_min,
                theta_z_max,
                ..
            } => {
                let theta = theta_z_min + v * (theta_z_max - theta_z_min);
                let (s, c) = theta.sin_cos();
                Point3::new(radius * s * cos, radius * s * sin, radius * c)
            }
            PartialQuadric::Disk {
                height,
                radius,
                inner_radius,
                ..
            } => {
                let r = radius - v * (radius - inner_radius);
                Point3::new(r * cos, r * sin, height)
            }
            PartialQuadric::Cylinder {
                radius,
                z_min,
                z_max,
                ..
            } => Point3::new(radius * cos, radius * sin, z_min + v * (z_max - z_min)),
        }
    }

    /// The area of what the cut keeps (pbrt-v4's `Area()`).
    pub fn area(&self) -> f64 {
        match *self {
            PartialQuadric::Sphere {
                radius,
                z_min,
                z_max,
                phi_max,
                ..
            } => phi_max * radius * (z_max - z_min),
            PartialQuadric::Disk {
                radius,
                inner_radius,
                phi_max,
                ..
            } => phi_max * 0.5 * (radius * radius - inner_radius * inner_radius),
            PartialQuadric::Cylinder {
                radius,
                z_min,
                z_max,
                phi_max,
            } => (z_max - z_min) * radius * phi_max,
        }
    }

    /// A point of what the cut keeps, uniformly by area, from `u` in [0, 1)², and its unit
    /// normal (see the [module](self) for each draw).
    pub fn sample_area(&self, [u, v]: [f64; 2]) -> (Point3, Vec3) {
        let (sin, cos) = sin_cos_turns(v * self.phi_max() / TAU);
        match *self {
            PartialQuadric::Sphere {
                radius,
                z_min,
                z_max,
                ..
            } => {
                let z = z_min + u * (z_max - z_min);
                let r = (radius * radius - z * z).max(0.0).sqrt();
                let p = Point3::new(r * cos, r * sin, z);
                (p, p / radius)
            }
            PartialQuadric::Disk {
                height,
                radius,
                inner_radius,
                ..
            } => {
                let ri2 = inner_radius * inner_radius;
                let r = (ri2 + u * (radius * radius - ri2)).sqrt();
                (Point3::new(r * cos, r * sin, height), Vec3::Z)
            }
            PartialQuadric::Cylinder {
                radius,
                z_min,
                z_max,
                ..
            } => {
                let z = z_min + u * (z_max - z_min);
                (
                    Point3::new(radius * cos, radius * sin, z),
                    Vec3::new(cos, sin, 0.0),
                )
            }
        }
    }

    /// The box around the surface: the whole quadric's between its heights, narrowed to the
    /// quarters of a turn the sweep reaches.
    pub fn bounds(&self) -> Aabb {
        let (r, z0, z1) = match *self {
            PartialQuadric::Sphere {
                radius,
                z_min,
                z_max,
                ..
            } => (radius, z_min, z_max),
            PartialQuadric::Disk { height, radius, .. } => (radius, height, height),
            PartialQuadric::Cylinder {
                radius,
                z_min,
                z_max,
                ..
            } => (radius, z_min, z_max),
        };
        // The sweep's extreme directions: its two ends and the axes it passes.
        let phi_max = self.phi_max();
        let mut lo = Vec3::new(1.0, 0.0, 0.0);
        let mut hi = lo;
        let end = Vec3::new(phi_max.cos(), phi_max.sin(), 0.0);
        let quarters = [Vec3::Y, Vec3::NEG_X, Vec3::NEG_Y];
        for (k, axis) in quarters.iter().enumerate() {
            if phi_max >= (k + 1) as f64 * PI / 2.0 {
                lo = lo.min(*axis);
                hi = hi.max(*axis);
            }
        }
        lo = lo.min(end);
        hi = hi.max(end);
        // A disk's hole, a cut sphere's narrower rings, only shrink the surface: the outer
        // radius in every swept direction bounds it; the origin's side stays in for holes.
        lo = lo.min(Vec3::ZERO);
        hi = hi.max(Vec3::ZERO);
        Aabb::new(
            Point3::new(r * lo.x, r * lo.y, z0),
            Point3::new(r * hi.x, r * hi.y, z1),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::stats::chi_square_p_value;

    fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
        Ray::new(Point3::from(o), Vec3::from(d))
    }

    fn hits(q: &PartialQuadric, r: &Ray) -> Vec<f64> {
        let mut out = Vec::new();
        q.intersect(r, |t| out.push(t));
        out
    }

    #[test]
    fn a_ray_through_the_hole_of_a_cut_sphere_meets_its_inside() {
        // The upper cap above z = 0.5 is cut away: a ray down the axis enters through the
        // hole and meets only the far (lower) side; pbrt-v4 tests both roots.
        let q = PartialQuadric::sphere(1.0, -1.0, 0.5, 360.0).unwrap();
        assert_eq!(hits(&q, &ray([0.0, 0.0, 3.0], [0.0, 0.0, -1.0])), vec![4.0]);
        // Sideways it meets both sides.
        assert_eq!(
            hits(&q, &ray([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0])),
            vec![2.0, 4.0]
        );
        // Cut to half a turn (0..180°, the +y half): a ray along x at y = -0.5 misses, one at
        // y = +0.5 hits both sides.
        let half = PartialQuadric::sphere(1.0, -1.0, 1.0, 180.0).unwrap();
        assert!(hits(&half, &ray([-3.0, -0.5, 0.0], [1.0, 0.0, 0.0])).is_empty());
        assert_eq!(
            hits(&half, &ray([-3.0, 0.5, 0.0], [1.0, 0.0, 0.0])).len(),
            2
        );
        // Along y through the centre: the +y side kept, the −y side cut.
        let t = hits(&half, &ray([0.0, -3.0, 0.1], [0.0, 1.0, 0.0]));
        assert_eq!(t.len(), 1);
        assert!((t[0] - (3.0 + (1.0f64 - 0.01).sqrt())).abs() < 1e-12);
    }

    #[test]
    fn disks_and_cylinders_are_cut_as_pbrt_cuts_them() {
        let disk = PartialQuadric::disk(0.5, 1.0, 0.4, 90.0).unwrap();
        let down = |x: f64, y: f64| hits(&disk, &ray([x, y, 2.0], [0.0, 0.0, -1.0]));
        assert_eq!(down(0.7, 0.1), vec![1.5]);
        assert!(down(0.2, 0.1).is_empty(), "in the hole");
        assert!(down(-0.7, 0.1).is_empty(), "beyond the sweep");
        assert!(down(1.1, 0.1).is_empty(), "beyond the rim");
        let cylinder = PartialQuadric::cylinder(2.0, -1.0, 1.0, 270.0).unwrap();
        // Along x through the axis: +x side kept (φ = 0), −x side (φ = 180°) kept.
        assert_eq!(
            hits(&cylinder, &ray([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0])),
            vec![3.0, 7.0]
        );
        // Along y: the −y side (φ = 270°) kept at the edge, the +y side (90°) kept.
        assert_eq!(
            hits(&cylinder, &ray([0.5, -5.0, 0.0], [0.0, 1.0, 0.0])).len(),
            1,
            "φ of (0.5, −1.94) is past 270°"
        );
        assert!(hits(&cylinder, &ray([-5.0, 0.0, 1.5], [1.0, 0.0, 0.0])).is_empty());
    }

    #[test]
    fn uv_and_points_agree_and_follow_pbrt() {
        let shapes = [
            PartialQuadric::sphere(1.5, -0.5, 1.2, 250.0).unwrap(),
            PartialQuadric::disk(0.3, 2.0, 0.5, 300.0).unwrap(),
            PartialQuadric::cylinder(0.7, -1.0, 2.0, 120.0).unwrap(),
        ];
        for q in shapes {
            for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.95)] {
                let p = q.point_at(u, v);
                let (u2, v2) = q.uv(p);
                assert!((u - u2).abs() < 1e-12 && (v - v2).abs() < 1e-12, "{q:?}");
                // The point is on the surface: a ray towards it along its normal meets it.
                let n = q.normal_at(p);
                let t = hits(&q, &Ray::new(p + n * 3.0, -n));
                assert!(t.iter().any(|t| (t - 3.0).abs() < 1e-9), "{q:?} {t:?}");
                assert!(q.bounds().contains_point(p), "{q:?} {p}");
            }
        }
        // pbrt's whole sphere: v from the bottom pole (0) to the top (1).
        let whole = PartialQuadric::sphere(1.0, -1.0, 1.0, 360.0).unwrap();
        assert!((whole.uv(Point3::new(0.0, 0.0, -1.0)).1).abs() < 1e-12);
        assert!((whole.uv(Point3::new(1.0, 0.0, 0.0)).1 - 0.5).abs() < 1e-12);
    }

    #[test]
    fn cuts_that_leave_nothing_are_refused() {
        assert_eq!(
            PartialQuadric::sphere(1.0, 2.0, 3.0, 360.0),
            Err(CutError::Heights(2.0, 3.0))
        );
        assert_eq!(
            PartialQuadric::sphere(1.0, -1.0, 1.0, 0.0),
            Err(CutError::Sweep(0.0))
        );
        assert!(PartialQuadric::disk(0.0, 1.0, 1.0, 360.0).is_err());
        assert!(PartialQuadric::cylinder(1.0, 0.0, 0.0, 360.0).is_err());
        // Beyond a whole turn is a whole turn, as pbrt clamps it.
        let q = PartialQuadric::cylinder(1.0, 0.0, 1.0, 720.0).unwrap();
        assert_eq!(q.phi_max(), TAU);
    }

    #[test]
    fn areas_are_the_cut_areas() {
        // Against a count of the parameter grid's patches, each patch's area |∂p/∂u × ∂p/∂v|.
        let shapes = [
            PartialQuadric::sphere(1.5, -0.5, 1.2, 250.0).unwrap(),
            PartialQuadric::disk(0.3, 2.0, 0.5, 300.0).unwrap(),
            PartialQuadric::cylinder(0.7, -1.0, 2.0, 120.0).unwrap(),
        ];
        let n = 400;
        for q in shapes {
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                    let h = 1e-6;
                    let du = (q.point_at(u + h, v) - q.point_at(u - h, v)) / (2.0 * h);
                    let dv = (q.point_at(u, v + h) - q.point_at(u, v - h)) / (2.0 * h);
                    sum += du.cross(dv).length() / (n * n) as f64;
                }
            }
            assert!((sum - q.area()).abs() < 1e-4 * q.area(), "{q:?}: {sum}");
        }
    }

    #[test]
    fn points_are_drawn_uniformly_by_area_over_what_the_cut_keeps() {
        // Each draw binned in pbrt's (u, v) grid; a cell's share of the area is the patch's
        // area there (found as in `areas_are_the_cut_areas`), so uniform by area means counts
        // in proportion to those shares. A draw over the whole sphere (pbrt-v4's) fails this.
        let shapes = [
            PartialQuadric::sphere(1.5, -0.5, 1.2, 250.0).unwrap(),
            PartialQuadric::disk(0.3, 2.0, 0.5, 300.0).unwrap(),
            PartialQuadric::cylinder(0.7, -1.0, 2.0, 120.0).unwrap(),
        ];
        let (cols, rows) = (8, 8);
        for q in shapes {
            let mut expected = vec![0.0; cols * rows];
            let fine = 40;
            for i in 0..cols * fine {
                for j in 0..rows * fine {
                    let (u, v) = (
                        (i as f64 + 0.5) / (cols * fine) as f64,
                        (j as f64 + 0.5) / (rows * fine) as f64,
                    );
                    let h = 1e-6;
                    let du = (q.point_at(u + h, v) - q.point_at(u - h, v)) / (2.0 * h);
                    let dv = (q.point_at(u, v + h) - q.point_at(u, v - h)) / (2.0 * h);
                    expected[(j / fine) * cols + i / fine] += du.cross(dv).length();
                }
            }
            let total: f64 = expected.iter().sum();
            expected.iter_mut().for_each(|e| *e /= total);
            let mut counts = vec![0_u64; cols * rows];
            let mut random = SplitMix64::new(5);
            for _ in 0..200_000 {
                let (p, n) = q.sample_area([random.next_offset(), random.next_offset()]);
                assert!((n - q.normal_at(p)).length() < 1e-9);
                let (u, v) = q.uv(p);
                let (i, j) = ((u * cols as f64) as usize, (v * rows as f64) as usize);
                counts[j.min(rows - 1) * cols + i.min(cols - 1)] += 1;
            }
            let p = chi_square_p_value(&counts, &expected);
            assert!(p > 1e-4, "{q:?}: p = {p}");
        }
    }
}
