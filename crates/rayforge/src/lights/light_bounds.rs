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
    /// Bounds of no light, what a union starts from.
    pub const NONE: Self = Self {
        bounds: Aabb::EMPTY,
        power: 0.0,
        cone: Cone::EVERYWHERE,
        two_sided: false,
    };

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

    /// What a cluster of these bounds costs the tree, by Conty Estevez and Kulla's measure
    /// (pbrt-v4's `EvaluateCost`): its power, times the solid angle its cone sends light into
    /// (each direction weighed by the cosine to the nearest normal), times its box's surface
    /// area, times `stretch` (how much longer the parent's box is along its longest axis
    /// than along the axis being cut; cutting a long cluster across is penalised). A split
    /// whose two sides cost least keeps bright lights, lights far apart and lights facing
    /// apart in different subtrees, where the walk can tell them apart.
    pub fn cost(&self, stretch: f64) -> f64 {
        if self.power <= 0.0 {
            return 0.0;
        }
        stretch * self.power * self.cone.measure() * 2.0 * self.bounds.half_area()
    }

    /// The form [`importance`](NodeBounds::importance) reads quickly (a walk weighs two
    /// nodes a level).
    pub fn prepared(&self) -> NodeBounds {
        let radius2 = if self.power > 0.0 {
            0.25 * self.bounds.extent().length_squared()
        } else {
            0.0
        };
        let (sin_o, cos_o) = self.cone.theta_o.sin_cos();
        NodeBounds {
            centre: self.centroid(),
            radius2,
            axis: self.cone.axis,
            cos_o,
            sin_o: sin_o.max(0.0),
            cos_e: self.cone.theta_e.cos(),
            power: self.power,
            two_sided: self.two_sided,
        }
    }

    /// How much light it may bring to `point` (see [`NodeBounds::importance`]).
    #[cfg(test)]
    pub fn importance(&self, point: Point3, normal: Option<Vec3>) -> f64 {
        self.prepared().importance(point, normal)
    }
}

impl Cone {
    /// The measure of the directions it sends light into, each weighed by the cosine of its
    /// angle to the nearest normal of the cone, as Conty Estevez and Kulla define it
    /// (π for a flat lamp's hemisphere, 4π for light in every direction).
    fn measure(&self) -> f64 {
        let (o, e) = (self.theta_o, self.theta_e);
        let w = (o + e).min(PI);
        let (sin_o, cos_o) = o.sin_cos();
        2.0 * PI * (1.0 - cos_o)
            + FRAC_PI_2 * (2.0 * w * sin_o - (o - 2.0 * w).cos() - 2.0 * o * sin_o + cos_o)
    }
}

/// A cluster's [`LightBounds`] as a walk down the tree weighs it: the box as the sphere
/// around it, the cone's angles as cosines, so that the importance takes square roots and no
/// inverse trigonometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeBounds {
    centre: Point3,
    /// The square of the radius of the sphere around the box.
    radius2: f64,
    axis: Vec3,
    cos_o: f64,
    sin_o: f64,
    cos_e: f64,
    power: f64,
    two_sided: bool,
}

impl NodeBounds {
    /// The cluster's power.
    pub fn power(&self) -> f64 {
        self.power
    }

    /// How much light the cluster may bring to `point`, of the receiving surface's normal
    /// `normal` where it has one: its power over the squared distance, times the bound on
    /// the cosine at the emitter (the smallest angle between the cone and the direction to
    /// `point`, over every point of the box) and on the cosine at the receiver (the smallest
    /// angle between the normal's line and a direction into the box). 0 only where no point
    /// of it can light `point` (behind every one-sided normal it has, or outside a
    /// spotlight's cone).
    ///
    /// Each bound is the cosine of an angle less another, clamped at 0 (`cos(max(0, a - b))`):
    /// 1 where `a <= b`, else `cos a cos b + sin a sin b`.
    #[inline]
    pub fn importance(&self, point: Point3, normal: Option<Vec3>) -> f64 {
        if self.power <= 0.0 {
            return 0.0;
        }
        let offset = point - self.centre;
        let distance2 = offset.length_squared();
        // The half-angle the sphere around the box subtends from `point`; within the sphere
        // every direction is possible (cos = -1).
        let (cos_b, sin_b) = if distance2 <= self.radius2 {
            (-1.0, 0.0)
        } else {
            let sin2 = self.radius2 / distance2;
            ((1.0 - sin2).sqrt(), sin2.sqrt())
        };
        let towards = if distance2 > 0.0 {
            offset * distance2.sqrt().recip()
        } else {
            self.axis
        };
        // Near the box, the distance to its centre says little: held at half the sphere's
        // radius at least.
        let distance2 = distance2.max(0.25 * self.radius2).max(f64::MIN_POSITIVE);
        let mut cos_w = self.axis.dot(towards).clamp(-1.0, 1.0);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        // The angle from the cone's nearest normal to `towards`, less the sphere's half-angle.
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let (cos_x, sin_x) = minus(cos_w, sin_w, self.cos_o, self.sin_o);
        let (cos_emit, _) = minus(cos_x, sin_x, cos_b, sin_b);
        // Strictly beyond the spread of emission: no light (a spotlight, θe = 0, lights only
        // within its cone, where the bound is 1).
        if cos_emit < self.cos_e {
            return 0.0;
        }
        let mut importance = self.power * cos_emit.max(0.0) / distance2;
        if let Some(normal) = normal {
            let cos_i = normal.dot(towards).abs().min(1.0);
            let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
            let (cos_receive, _) = minus(cos_i, sin_i, cos_b, sin_b);
            importance *= cos_receive.max(0.0);
        }
        importance
    }
}
/// The cosine and sine of `max(0, a - b)` for angles `a` and `b` in [0, π], from theirs.
#[inline]
fn minus(cos_a: f64, sin_a: f64, cos_b: f64, sin_b: f64) -> (f64, f64) {
    if cos_a >= cos_b {
        return (1.0, 0.0);
    }
    (
        cos_a * cos_b + sin_a * sin_b,
        (sin_a * cos_b - cos_a * sin_b).max(0.0),
    )
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

    /// The importance as its doc comment says it, with the angles themselves: what the
    /// cosine identities of [`NodeBounds::importance`] must equal.
    fn importance_by_angles(b: &LightBounds, point: Point3, normal: Option<Vec3>) -> f64 {
        let centre = b.bounds.centroid();
        let radius = 0.5 * b.bounds.extent().length();
        let offset = point - centre;
        let d2 = offset.length_squared();
        let theta_b = if d2 <= radius * radius {
            PI
        } else {
            (radius / d2.sqrt()).asin()
        };
        let towards = offset.normalize();
        let mut cos_w = b.cone.axis.dot(towards);
        if b.two_sided {
            cos_w = cos_w.abs();
        }
        let theta = (cos_w.acos() - b.cone.theta_o - theta_b).max(0.0);
        if theta > b.cone.theta_e + 1e-9 {
            return 0.0;
        }
        let mut importance = b.power * theta.cos().max(0.0) / d2.max(0.25 * radius * radius);
        if let Some(n) = normal {
            let theta_i = (n.dot(towards).abs().min(1.0).acos() - theta_b).max(0.0);
            importance *= theta_i.cos().max(0.0);
        }
        importance
    }

    #[test]
    fn the_importance_by_cosines_is_the_importance_by_angles() {
        use crate::math::random::{Jitter, SplitMix64};
        let mut random = SplitMix64::new(5);
        let mut r = move || random.next_offset();
        let mut compared = 0;
        for _ in 0..20_000 {
            let at = Point3::new(r() * 4.0 - 2.0, r() * 4.0 - 2.0, r() * 4.0 - 2.0);
            let size = Vec3::new(r(), r(), r()) * if r() < 0.3 { 0.0 } else { 1.5 };
            let axis = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize();
            let bounds = LightBounds {
                bounds: Aabb::new(at, at + size),
                power: 0.5 + r(),
                cone: Cone {
                    axis,
                    theta_o: if r() < 0.2 { PI } else { r() * PI },
                    theta_e: if r() < 0.2 { 0.0 } else { r() * FRAC_PI_2 },
                },
                two_sided: r() < 0.3,
            };
            let point = Point3::new(r() * 8.0 - 4.0, r() * 8.0 - 4.0, r() * 8.0 - 4.0);
            let normal = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize();
            for normal in [None, Some(normal)] {
                let fast = bounds.importance(point, normal);
                let slow = importance_by_angles(&bounds, point, normal);
                // Where the emitter's bound lies on the edge of its spread, rounding may
                // put the two on either side: only clear cases are compared.
                if (fast == 0.0) != (slow == 0.0) {
                    continue;
                }
                assert!(
                    (fast - slow).abs() <= 1e-6 * slow.max(1e-3),
                    "{fast} vs {slow} for {bounds:?} at {point:?}, {normal:?}"
                );
                compared += 1;
            }
        }
        assert!(compared > 39_000, "{compared}");
    }

    #[test]
    fn the_orientation_measure_of_a_hemisphere_is_pi_and_of_every_direction_four_pi() {
        let flat = Cone {
            axis: Vec3::Y,
            theta_o: 0.0,
            theta_e: FRAC_PI_2,
        };
        assert!((flat.measure() - PI).abs() < 1e-12);
        assert!((Cone::EVERYWHERE.measure() - 4.0 * PI).abs() < 1e-12);
        // A spotlight's cone: the solid angle of its cone, 2π(1 - cos θo).
        let spot = Cone {
            theta_o: 0.3,
            theta_e: 0.0,
            ..flat
        };
        assert!((spot.measure() - 2.0 * PI * (1.0 - 0.3f64.cos())).abs() < 1e-12);
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
