//! What the light tree knows of a light, or of a cluster of lights: where it is (a box), how
//! much it gives off (its power) and where it sends its light (an orientation cone), and from
//! that the *importance* of the cluster as seen from a shading point: a cheap, conservative
//! estimate of how much light the cluster can bring there (Conty Estevez & Kulla 2018,
//! "Importance Sampling of Many Lights with Adaptive Tree Splitting"; pbrt-v4's
//! `LightBounds`, ch. 12.6).
//!
//! The estimate only steers which light is picked, so it need not be exact; but where it is 0
//! no light of the cluster may give any light at the point, or the picks that the tree never
//! makes would be missing from the image. Every bound here errs towards more light.

use crate::math::{Aabb, Point3, Vec3};
use std::f64::consts::{FRAC_PI_2, PI};

/// The directions a light sends its light into: every direction within `theta_o` of `axis`
/// is a normal of the emitter, and each such normal sends light up to `theta_e` away from
/// itself (a flat lamp: `theta_o = 0`, `theta_e = π/2`; a sphere: `theta_o = π`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    /// The cone's axis (unit).
    pub axis: Vec3,
    /// The spread of the emitter's normals about `axis`, in radians (0 to π).
    pub theta_o: f64,
    /// How far from a normal light leaves, in radians (0 to π/2).
    pub theta_e: f64,
}

impl Cone {
    /// Light that leaves in every direction (a point light, a closed shape).
    pub const EVERYWHERE: Self = Self {
        axis: Vec3::Z,
        theta_o: PI,
        theta_e: FRAC_PI_2,
    };

    /// The smallest cone (of normals) holding both `self`'s and `other`'s, the larger spread
    /// of emission kept: what a cluster of two lights sends light into.
    fn union(self, other: Self) -> Self {
        let theta_e = self.theta_e.max(other.theta_e);
        let between = angle_between(self.axis, other.axis);
        // One holds the other already.
        if (between + other.theta_o).min(PI) <= self.theta_o {
            return Self { theta_e, ..self };
        }
        if (between + self.theta_o).min(PI) <= other.theta_o {
            return Self { theta_e, ..other };
        }
        // The arc from the far edge of one to the far edge of the other, through both axes.
        let theta_o = (self.theta_o + between + other.theta_o) / 2.0;
        if theta_o >= PI {
            return Self {
                theta_e,
                ..Self::EVERYWHERE
            };
        }
        // Turn `self.axis` towards `other.axis` by `theta_o - self.theta_o`, in their plane.
        let turn = theta_o - self.theta_o;
        let side = other.axis - self.axis * self.axis.dot(other.axis);
        let axis = if side.length_squared() > 0.0 {
            let side = side.normalize();
            self.axis * turn.cos() + side * turn.sin()
        } else {
            // Opposite axes: any plane through them will do.
            return Self {
                theta_e,
                ..Self::EVERYWHERE
            };
        };
        Self {
            axis,
            theta_o,
            theta_e,
        }
    }
}

/// A light's or a cluster's bounds, as the tree weighs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightBounds {
    /// Where its emitting points are.
    pub bounds: Aabb,
    /// Its power (the same estimate the `power` sampler picks by).
    pub power: f64,
    /// Where it sends light.
    pub cone: Cone,
    /// Whether it also sends light to the side its cone faces away from (a sheet that glows
    /// on both sides): then only the angle to the cone's axis line counts.
    pub two_sided: bool,
}

impl LightBounds {
    /// The bounds of a cluster of the two: the box around both, both powers, the cone holding
    /// both cones (two-sided if either is).
    pub fn union(&self, other: &Self) -> Self {
        if self.power <= 0.0 {
            return *other;
        }
        if other.power <= 0.0 {
            return *self;
        }
        Self {
            bounds: self.bounds.union(&other.bounds),
            power: self.power + other.power,
            cone: self.cone.union(other.cone),
            two_sided: self.two_sided || other.two_sided,
        }
    }

    /// The centre of its box, by which the tree sorts lights into clusters.
    pub fn centroid(&self) -> Point3 {
        self.bounds.centroid()
    }

    /// How much light it may bring to `point`, of the receiving surface's normal `normal`
    /// where it has one: its power over the squared distance, times the bound on the cosine at
    /// the emitter (the smallest angle between the cone and the direction to `point`, over
    /// every point of the box) and on the cosine at the receiver. 0 only where no point of it
    /// can light `point` (behind every one-sided normal it has, or outside a spotlight's
    /// cone).
    pub fn importance(&self, point: Point3, normal: Option<Vec3>) -> f64 {
        if self.power <= 0.0 {
            return 0.0;
        }
        let centre = self.bounds.centroid();
        let radius = 0.5 * self.bounds.extent().length();
        let offset = point - centre;
        let distance2 = offset.length_squared();
        // Within the box's sphere every direction is possible; and near it, the distance to
        // the centre says little, so it is held at the sphere's half radius at least.
        let inside = distance2 <= radius * radius;
        let theta_b = if inside {
            PI
        } else {
            (radius / distance2.sqrt()).clamp(0.0, 1.0).asin()
        };
        let distance2 = distance2.max(0.25 * radius * radius).max(f64::MIN_POSITIVE);
        let towards = if offset != Vec3::ZERO {
            offset / offset.length()
        } else {
            self.cone.axis
        };
        let mut cos_w = self.cone.axis.dot(towards).clamp(-1.0, 1.0);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let theta_w = cos_w.acos();
        let theta = (theta_w - self.cone.theta_o - theta_b).max(0.0);
        // Strictly beyond the spread of emission: no light (a spotlight, θe = 0, lights only
        // within its cone, where `theta` is 0).
        if theta > self.cone.theta_e {
            return 0.0;
        }
        let mut importance = self.power * theta.cos().max(0.0) / distance2;
        if let Some(normal) = normal {
            let cos_i = normal.dot(towards).abs().clamp(0.0, 1.0);
            let theta_i = (cos_i.acos() - theta_b).max(0.0);
            importance *= theta_i.cos().max(0.0);
        }
        importance
    }
}

/// The angle between unit vectors `a` and `b`, accurate near 0 and π.
fn angle_between(a: Vec3, b: Vec3) -> f64 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * ((a + b).length() / 2.0).clamp(0.0, 1.0).asin()
    } else {
        2.0 * ((b - a).length() / 2.0).clamp(0.0, 1.0).asin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lamp(at: Point3, axis: Vec3) -> LightBounds {
        LightBounds {
            bounds: Aabb::new(at, at),
            power: 1.0,
            cone: Cone {
                axis,
                theta_o: 0.0,
                theta_e: FRAC_PI_2,
            },
            two_sided: false,
        }
    }

    #[test]
    fn a_one_sided_lamp_is_unimportant_only_behind_it() {
        let down = lamp(Point3::new(0.0, 1.0, 0.0), -Vec3::Y);
        assert!(down.importance(Point3::ZERO, None) > 0.0);
        assert!(down.importance(Point3::new(0.3, 0.5, 0.2), None) > 0.0);
        assert_eq!(down.importance(Point3::new(0.0, 2.0, 0.0), None), 0.0);
        let both = LightBounds {
            two_sided: true,
            ..down
        };
        assert!(both.importance(Point3::new(0.0, 2.0, 0.0), None) > 0.0);
    }

    #[test]
    fn a_union_of_cones_holds_both() {
        let a = lamp(Point3::ZERO, Vec3::X);
        let b = lamp(Point3::new(1.0, 0.0, 0.0), Vec3::Y);
        let both = a.union(&b);
        for axis in [Vec3::X, Vec3::Y] {
            let angle = angle_between(both.cone.axis, axis);
            assert!(
                angle <= both.cone.theta_o + 1e-12,
                "{angle} {:?}",
                both.cone
            );
        }
        assert!((both.cone.theta_o - PI / 4.0).abs() < 1e-12);
        let opposite = a.union(&lamp(Point3::ZERO, -Vec3::X));
        assert_eq!(opposite.cone.theta_o, PI);
    }
}
