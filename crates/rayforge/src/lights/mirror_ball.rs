//! Polished metal balls as a way for the sky's light to reach a surface: the reflection point
//! found directly, so that the sun's image in a mirror ball lights a diffuse surface by
//! next-event estimation instead of by the rare path that happens to bounce towards it.
//!
//! A path tracer finds light reflected by a perfect mirror onto a diffuse surface (a caustic)
//! only when the surface's own sampled direction meets the mirror just where the mirror shows
//! the light: for a small sun in a convex mirror, a tiny set of directions, so a few samples
//! carry enormous weights and the caustic stays speckled for thousands of samples. Manifold
//! next-event estimation (Hanika, Droske and Fascione, 2015) instead draws the light's
//! direction and solves for the point of the mirror that sends it to the surface. For a sphere
//! and a distant light the solution lies in the plane through the sphere's centre, the surface
//! point and the light's direction, so it is a root in one angle, bracketed and unique on the
//! part of the sphere the point sees (the reflected direction turns monotonically from straight
//! back to grazing as the reflection point moves out from the sphere's nearest point).
//!
//! The estimate needs how the mirror spreads directions: a pencil of rays of solid angle `dd`
//! leaving the surface point, reflected at distance `s` with incidence `i` by a convex sphere
//! of radius `R`, leaves as if from two virtual foci (Coddington's equations for a mirror, in
//! the plane of incidence and across it) and spans
//! `dω = dd · (1 + 2s / (R cos i)) · (1 + 2s cos i / R)`. It is 1 for a flat mirror and tends
//! to `4s² / R²` far away, where a ball spreads a parallel beam evenly over the whole sphere of
//! directions.
//!
//! Only balls that reflect the same everywhere qualify: a sphere placed by a similarity (no
//! stretch), standing still, of a smooth conductor with a plain colour and no bump map, that
//! does not glow. The path tracer weighs this strategy against the surface's BSDF sampling by
//! the power heuristic, which needs the same spread for a path that found the mirror by itself
//! ([`spread`]).
//!
//! A scene of many balls (a ball pit under a sky) would pay a solve per ball at every vertex.
//! So each ball has a share of the sky's light at a vertex ([`MirrorBall::share_from`]): its
//! reflectance `ρ` times the solid angle `Ω` it subtends, over π, what it adds to an even
//! sky's light there at most. Balls below a share are left to BSDF sampling, and of the rest
//! at most a few are solved ([`MirrorBalls::choose`]), each weighed by one over how often it
//! is chosen on average, the same factor in the density that MIS weighs the BSDF's paths to
//! the ball against ([`MirrorBalls::expected_solves`]).
//!
//! Reckoning every ball's share at every vertex costs more than the solves themselves once
//! the balls are many (a pit of 200 balls took 2.0 times the time of the same balls diffuse
//! with two solves a vertex, and 1.95 times with one: the solves were the small part). So
//! the balls are chosen as a light tree chooses lights (pbrt-v4's
//! `BVHLightSampler`): a hierarchy of boxes over their centres, split at the median, each
//! node holding its balls' summed `ρ R²`, and a descent from the root that takes each child in
//! proportion to that sum over its squared distance from the vertex (a ball's own share at
//! the leaves; 0 for a node none of whose balls can reach the cull, as no share exceeds
//! `2ρR² ∕ d²`). A choice costs two estimates per level, `log₂ n` levels, whatever the number
//! of balls; its chance is the product of the steps' chances, found again along the ball's
//! own way down where MIS asks for it. Where a scene has no more balls than the cap, each
//! ball that reaches the cull is solved, at weight 1, with no choice made.

use crate::color::Color;
use crate::math::{atan2_turns, sin_cos_turns, Point3, Vec3};
use crate::options::MirrorBallBudget;
use crate::scene::{Object, Shape};
use crate::shading::bsdf::{fresnel, MIN_ALPHA};
use crate::shading::Physical;
use std::f64::consts::{PI, TAU};

/// A polished metal ball, in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct MirrorBall {
    /// Its index in the world's objects.
    pub object: u32,
    /// Its centre.
    pub centre: Point3,
    /// Its radius.
    pub radius: f64,
    /// Real part of the metal's index of refraction, per channel.
    eta: Color,
    /// Its extinction coefficient, per channel.
    k: Color,
    /// The colour that tints its reflection.
    tint: Color,
    /// Its reflectance at normal incidence, the largest channel: the `ρ` of its share.
    albedo: f64,
}

/// How a surface point sees a direction of the sky in a mirror ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorPath {
    /// The point of the ball that reflects the sky's direction to the surface point.
    pub point: Point3,
    /// The ball's outward normal there.
    pub normal: Vec3,
    /// The unit direction from the surface point to it.
    pub direction: Vec3,
    /// How far it is.
    pub distance: f64,
    /// The cosine of the angle of incidence there.
    pub cos_incidence: f64,
}

/// `dω / dd`: how much wider in solid angle a pencil of rays leaves a convex mirror ball of
/// radius `radius` than it arrived from a point `distance` away, meeting it with incidence
/// cosine `cos_incidence` (see the [module](self) documentation).
#[inline]
pub fn spread(distance: f64, cos_incidence: f64, radius: f64) -> f64 {
    let c = cos_incidence.max(1e-12);
    (1.0 + 2.0 * distance / (radius * c)) * (1.0 + 2.0 * distance * c / radius)
}

impl MirrorBall {
    /// `object` (the world's object `index`) as a mirror ball, if it is one (see the
    /// [module](self) documentation for what qualifies).
    pub fn of(object: &Object, index: u32) -> Option<Self> {
        let material = &object.material;
        let Some(Physical::Conductor {
            eta,
            k,
            alpha_u,
            alpha_v,
        }) = material.physical
        else {
            return None;
        };
        let plain = material.pattern.is_none()
            && material.texture.is_none()
            && material.bump.is_none()
            && material.metal_rough.is_none()
            && material.physical_patterns.is_none()
            && material.emission.max_channel() <= 0.0;
        if !matches!(object.shape, Shape::Sphere)
            || object.motion.is_some()
            || alpha_u >= MIN_ALPHA
            || alpha_v >= MIN_ALPHA
            || !plain
        {
            return None;
        }
        // A similarity: the images of three unit axes are orthogonal and of one length.
        let t = &object.transform;
        let (x, y, z) = (t.vector(Vec3::X), t.vector(Vec3::Y), t.vector(Vec3::Z));
        let radius = x.length();
        let tolerance = 1e-9 * radius * radius;
        let similar = (y.length_squared() - radius * radius).abs() <= tolerance
            && (z.length_squared() - radius * radius).abs() <= tolerance
            && x.dot(y).abs() <= tolerance
            && y.dot(z).abs() <= tolerance
            && z.dot(x).abs() <= tolerance;
        if !(similar && radius.is_finite() && radius > 0.0) {
            return None;
        }
        Some(Self::new(
            index,
            t.point(Point3::ZERO),
            radius,
            eta,
            k,
            material.color,
        ))
    }

    /// The ball of world object `object` at `centre`, of `radius`, of the metal of index
    /// `eta` and extinction `k`, tinted by `tint`.
    fn new(object: u32, centre: Point3, radius: f64, eta: Color, k: Color, tint: Color) -> Self {
        let albedo = tint.hadamard(fresnel::conductor(1.0, eta, k)).max_channel();
        Self {
            object,
            centre,
            radius,
            eta,
            k,
            tint,
            albedo,
        }
    }

    /// The ball's share of the sky's light at `point`, `ρ Ω / π`, where it is at least `cull`
    /// (see the [module](self) documentation); `None` below it, and from inside the ball.
    /// `Ω = 2π (1 − √(1 − x))` with `x = R² / d²`, the cone of directions towards the ball,
    /// is taken as `2π x / (1 + √(1 − x))`, which does not cancel for a far ball. As `Ω ≤ 2π
    /// x`, most balls of a large scene are left out by a product and a comparison.
    #[inline]
    pub fn share_from(&self, point: Point3, cull: f64) -> Option<f64> {
        let d2 = (self.centre - point).length_squared();
        let r2 = self.radius * self.radius;
        if d2.is_nan() || d2 <= r2 || 2.0 * self.albedo * r2 < cull * d2 {
            return None;
        }
        let x = r2 / d2;
        let share = self.albedo * 2.0 * x / (1.0 + (1.0 - x).sqrt());
        (share >= cull).then_some(share)
    }

    /// The share of light the ball reflects at incidence cosine `cos_incidence`: the conductor
    /// Fresnel reflectance, tinted, as its BSDF gives it.
    pub fn reflectance(&self, cos_incidence: f64) -> Color {
        self.tint
            .hadamard(fresnel::conductor(cos_incidence, self.eta, self.k))
    }

    /// Where the ball reflects light arriving from the far direction `towards` (unit, pointing
    /// away from the ball to where the light comes from) into the point `from`: `None` when
    /// `from` is inside or on the ball, or when no point of the ball that `from` sees sends
    /// that direction to it (it lies beyond the grazing reflections, behind the ball).
    pub fn reflection_towards(&self, from: Point3, towards: Vec3) -> Option<MirrorPath> {
        let r = self.radius;
        let offset = from - self.centre;
        let d = offset.length();
        if d.is_nan() || d <= r * (1.0 + 1e-9) || !towards.is_finite() {
            return None;
        }
        // The plane of the centre, the point and the direction: e1 towards the point, e2
        // towards the direction's side. In it the normal is (cos α, sin α), α from 0 (the
        // nearest point) to the edge the point sees, acos(R / d).
        let e1 = offset / d;
        let along = towards.dot(e1);
        let across = towards - e1 * along;
        let side = across.length();
        let omega = [along, side];
        let e2 = if side > 1e-12 {
            across / side
        } else if along > 0.0 {
            // Straight back along the axis: the nearest point reflects it.
            return Some(self.path(from, e1));
        } else {
            return None;
        };
        // At the point of normal angle α the reflected direction has angle ψ(α) = 2α + β(α),
        // β the angle at the ball's point between the centre's line and the surface point
        // (tan β = R sin α / (d − R cos α)). ψ rises from 0 at α = 0 to π/2 + edge at the edge
        // of what the point sees, α = acos(R / d); ω's angle φ in (0, π] is reached once, if
        // below that. `ahead(α)` is sin(φ − ψ) times the distance to the surface point, which
        // needs no inverse trigonometry: positive before the root, negative after it.
        // acos(R / d), and the sine of it, by the crate's arctangent (libm's `acos` and
        // `atan2` were 3 % of an environment-lit render).
        let (cos_edge, sin_edge) = (r / d, (1.0 - (r / d) * (r / d)).max(0.0).sqrt());
        let edge = TAU * atan2_turns(sin_edge, cos_edge);
        let (cos_phi, sin_phi) = (omega[0], omega[1]);
        let ahead = |alpha: f64| {
            let (sin, cos) = sin_cos_turns(alpha / TAU);
            let (sin_2a, cos_2a) = (2.0 * sin * cos, cos * cos - sin * sin);
            // sin(φ − 2α) and cos(φ − 2α), then sin(φ − 2α − β)·L with cos β·L = d − R cos α
            // and sin β·L = R sin α.
            let sin_rest = sin_phi * cos_2a - cos_phi * sin_2a;
            let cos_rest = cos_phi * cos_2a + sin_phi * sin_2a;
            let length_squared = d * d + r * r - 2.0 * d * r * cos;
            let value = sin_rest * (d - r * cos) - cos_rest * r * sin;
            // ψ'(α) = 2 + β'(α), β' = R (d cos α − R) / L².
            let slope = 2.0 + r * (d * cos - r) / length_squared;
            (value / length_squared.sqrt(), slope)
        };
        // Behind the ball: φ is not below ψ(edge) = π/2 + edge, whose cosine is −sin(edge).
        // (Both sides are finite: `towards` is, and R / d lies in (0, 1).)
        if cos_phi <= -sin_edge {
            return None;
        }
        // Newton's method on φ − ψ (read as its sine, so a far step falls short rather than
        // overshooting), kept within a bracket that shrinks with every value seen; from the
        // bisector of the point's direction and ω (right for a far point), three steps reach
        // the limit of precision.
        let (mut lo, mut hi) = (0.0, edge);
        let mut alpha = (PI * atan2_turns(side, along)).clamp(0.0, edge);
        for _ in 0..60 {
            let (value, slope) = ahead(alpha);
            if value == 0.0 || value.is_nan() {
                break;
            }
            if value > 0.0 {
                lo = alpha;
            } else {
                hi = alpha;
            }
            let newton = alpha + value / slope;
            let in_bracket = (lo..=hi).contains(&newton);
            let next = if in_bracket { newton } else { 0.5 * (lo + hi) };
            let step = (next - alpha).abs();
            alpha = next;
            // A Newton step leaves an error of about its square times ψ''/ψ' (at most of the
            // order of 1/edge²): below 10⁻⁸·edge, the point is as good as the arithmetic. (A
            // bisection's step says nothing of the error, only the bracket does.)
            if (in_bracket && step <= 1e-8 * edge) || hi - lo <= 1e-15 * edge {
                break;
            }
        }
        let (sin, cos) = sin_cos_turns(alpha / TAU);
        Some(self.path(from, e1 * cos + e2 * sin))
    }

    /// The path from `from` to the point of the ball with outward normal `normal`.
    fn path(&self, from: Point3, normal: Vec3) -> MirrorPath {
        let point = self.centre + normal * self.radius;
        let to = point - from;
        let distance = to.length();
        let direction = to / distance;
        MirrorPath {
            point,
            normal,
            direction,
            distance,
            cos_incidence: (-direction.dot(normal)).max(0.0),
        }
    }
}

/// The mirror balls of a scene, and a hierarchy over them by which a vertex chooses the
/// balls it solves without reckoning every ball's share (see the [module](self)
/// documentation).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MirrorBalls {
    balls: Vec<MirrorBall>,
    /// Per world object, its ball's index in `balls`, or `u32::MAX`.
    of_object: Vec<u32>,
    /// The hierarchy, depth first: a node's first child follows it (none where there are no
    /// balls).
    nodes: Vec<BallNode>,
    /// Per ball, the way from the root to its leaf: bit `k` set where the `k`-th step takes
    /// the second child.
    trails: Vec<u64>,
}

/// A node of the balls' hierarchy: what it holds, as bounds on the shares of its balls.
#[derive(Debug, Clone, PartialEq)]
struct BallNode {
    /// The box of its balls' centres.
    low: Point3,
    high: Point3,
    /// `Σ ρ R²` over its balls: its share at a distance `d` is about this over `d²`.
    power: f64,
    /// The largest `ρ R²` among them: no ball's share exceeds twice this over the squared
    /// distance to the box.
    brightest: f64,
    /// The smallest `R²` among them: no point outside the balls is nearer a centre.
    nearest: f64,
    /// Its one ball, or where its second child is.
    link: BallLink,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum BallLink {
    Ball(u32),
    Split(u32),
}

/// The largest number below 1, where a descent's rescaled number must stay.
const ONE_BELOW: f64 = 1.0 - f64::EPSILON / 2.0;

impl MirrorBalls {
    /// The mirror balls among `objects` (the world's, in its order), and their hierarchy.
    pub fn of_objects(objects: &[Object]) -> Self {
        let balls = (objects.iter().enumerate())
            .filter_map(|(i, object)| MirrorBall::of(object, i as u32))
            .collect();
        Self::new(balls, objects.len())
    }

    /// `balls` (of a world of `objects` objects), and their hierarchy.
    fn new(balls: Vec<MirrorBall>, objects: usize) -> Self {
        let mut of_object = vec![u32::MAX; objects];
        for (i, ball) in balls.iter().enumerate() {
            of_object[ball.object as usize] = i as u32;
        }
        let mut set = Self {
            trails: vec![0; balls.len()],
            balls,
            of_object,
            nodes: Vec::new(),
        };
        let mut order: Vec<u32> = (0..set.balls.len() as u32).collect();
        if !order.is_empty() {
            set.build(&mut order, 0, 0);
        }
        set
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.balls.is_empty()
    }

    /// The balls, in the order of the world's objects.
    pub fn balls(&self) -> &[MirrorBall] {
        &self.balls
    }

    /// The index among [`balls`](Self::balls) of the ball that world object `index` is, if
    /// it is one.
    #[inline]
    pub fn of_object(&self, index: usize) -> Option<usize> {
        let at = *self.of_object.get(index)?;
        (at != u32::MAX).then_some(at as usize)
    }

    /// Builds the node over the balls of `order` (`depth` steps below the root, reached by
    /// `trail`), splitting them at the median of their centres along the box's longest
    /// side, so that the hierarchy is `log₂ n` deep.
    fn build(&mut self, order: &mut [u32], depth: u32, trail: u64) {
        let (mut low, mut high) = (
            Point3::splat(f64::INFINITY),
            Point3::splat(f64::NEG_INFINITY),
        );
        let (mut power, mut brightest, mut nearest) = (0.0, 0.0_f64, f64::INFINITY);
        for &i in order.iter() {
            let ball = &self.balls[i as usize];
            low = low.min(ball.centre);
            high = high.max(ball.centre);
            let r2 = ball.radius * ball.radius;
            power += ball.albedo * r2;
            brightest = brightest.max(ball.albedo * r2);
            nearest = nearest.min(r2);
        }
        let at = self.nodes.len();
        self.nodes.push(BallNode {
            low,
            high,
            power,
            brightest,
            nearest,
            link: BallLink::Ball(order[0]),
        });
        if let [only] = order {
            self.trails[*only as usize] = trail;
            return;
        }
        let extent = high - low;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let middle = order.len() / 2;
        let balls = &self.balls;
        order.select_nth_unstable_by(middle, |&a, &b| {
            let (a, b) = (
                balls[a as usize].centre[axis],
                balls[b as usize].centre[axis],
            );
            a.total_cmp(&b)
        });
        let (first, second) = order.split_at_mut(middle);
        self.build(first, depth + 1, trail);
        self.nodes[at].link = BallLink::Split(self.nodes.len() as u32);
        self.build(second, depth + 1, trail | 1 << depth);
    }

    /// How much node `node` is worth choosing from `point`, for balls of at least the share
    /// `cull`: a ball's share itself (0 below the cull); a node's power over the squared
    /// distance to its box (no nearer than its nearest ball's radius), or 0 where no ball of
    /// it can reach the cull.
    #[inline]
    fn importance(&self, node: &BallNode, point: Point3, cull: f64) -> f64 {
        match node.link {
            BallLink::Ball(i) => self.balls[i as usize]
                .share_from(point, cull)
                .unwrap_or(0.0),
            BallLink::Split(_) => {
                let gap = (node.low - point).max(point - node.high).max(Vec3::ZERO);
                let d2 = gap.length_squared();
                if 2.0 * node.brightest < cull * d2 {
                    0.0
                } else {
                    node.power / d2.max(node.nearest)
                }
            }
        }
    }

    /// At split node `at`, the chance of taking its first child from `point`, and the index
    /// of its second; `None` where neither child is worth anything.
    #[inline]
    fn step(&self, at: usize, second: u32, point: Point3, cull: f64) -> Option<f64> {
        let a = self.importance(&self.nodes[at + 1], point, cull);
        let b = self.importance(&self.nodes[second as usize], point, cull);
        let total = a + b;
        (total > 0.0 && total.is_finite()).then(|| a / total)
    }

    /// The ball a descent by the number `u` in [0, 1) chooses from `point`, and how likely
    /// it was chosen: at each split, a child in proportion to its importance; `None` where
    /// no ball there reaches the share `cull`.
    fn pick(&self, point: Point3, cull: f64, mut u: f64) -> Option<(usize, f64)> {
        let (mut at, mut chance) = (0, 1.0);
        loop {
            match self.nodes.get(at)?.link {
                BallLink::Ball(i) => {
                    let ball = &self.balls[i as usize];
                    return ball.share_from(point, cull).map(|_| (i as usize, chance));
                }
                BallLink::Split(second) => {
                    let first = self.step(at, second, point, cull)?;
                    if u < first {
                        u = (u / first).min(ONE_BELOW);
                        chance *= first;
                        at += 1;
                    } else {
                        u = ((u - first) / (1.0 - first)).min(ONE_BELOW);
                        chance *= 1.0 - first;
                        at = second as usize;
                    }
                }
            }
        }
    }

    /// How likely a descent from `point` chooses ball `ball` ([`pick`](Self::pick)'s
    /// chance, found along the ball's own way down).
    fn chance(&self, ball: usize, point: Point3, cull: f64) -> f64 {
        let trail = self.trails[ball];
        let (mut at, mut chance, mut depth) = (0, 1.0, 0);
        while let Some(BallLink::Split(second)) = self.nodes.get(at).map(|n| n.link) {
            let Some(first) = self.step(at, second, point, cull) else {
                return 0.0;
            };
            if trail >> depth & 1 == 0 {
                chance *= first;
                at += 1;
            } else {
                chance *= 1.0 - first;
                at = second as usize;
            }
            depth += 1;
        }
        chance
    }

    /// The balls solved at `point` within `budget`: `solve` is called with each ball, the
    /// mean number of times a vertex there solves it, and the weight of its light. Where
    /// there are no more balls than the cap, every ball whose share is at least the cull,
    /// each solved once at weight 1. Else the cap's descents through the hierarchy, their
    /// numbers `(j + u) / cap` spread evenly from the one `u` (drawn only then): a ball
    /// chosen `c` times is solved once at weight `c / (cap × chance)`, its mean number of
    /// solves being `cap × chance`, so that the sum over the chosen of weight × a ball's
    /// light has the sum over all of them as its mean.
    pub fn choose(
        &self,
        point: Point3,
        budget: MirrorBallBudget,
        u: impl FnOnce() -> f64,
        mut solve: impl FnMut(&MirrorBall, f64, f64),
    ) {
        if self.balls.len() <= budget.cap as usize {
            for ball in &self.balls {
                if ball.share_from(point, budget.cull).is_some() {
                    solve(ball, 1.0, 1.0);
                }
            }
            return;
        }
        let (u, cap) = (u(), f64::from(budget.cap));
        // A descent is monotonic in its number: a ball chosen twice is chosen by neighbours.
        let mut last: Option<(usize, f64, u32)> = None;
        for j in 0..budget.cap {
            let Some((ball, chance)) = self.pick(point, budget.cull, (f64::from(j) + u) / cap)
            else {
                continue;
            };
            match &mut last {
                Some((previous, _, count)) if *previous == ball => *count += 1,
                _ => {
                    if let Some((ball, chance, count)) = last {
                        solve(
                            &self.balls[ball],
                            cap * chance,
                            f64::from(count) / (cap * chance),
                        );
                    }
                    last = Some((ball, chance, 1));
                }
            }
        }
        if let Some((ball, chance, count)) = last {
            solve(
                &self.balls[ball],
                cap * chance,
                f64::from(count) / (cap * chance),
            );
        }
    }

    /// The mean number of times a vertex at `point` solves ball `ball` (an index among
    /// [`balls`](Self::balls)) within `budget` ([`choose`](Self::choose)); `None` where its
    /// share there is below the cull (or `point` is inside it), which leaves the ball to
    /// BSDF sampling. The density of the mirror-ball sampling's directions towards the ball
    /// is the sky's, narrowed by the spread, times this.
    pub fn expected_solves(
        &self,
        ball: usize,
        point: Point3,
        budget: MirrorBallBudget,
    ) -> Option<f64> {
        self.balls[ball].share_from(point, budget.cull)?;
        if self.balls.len() <= budget.cap as usize {
            Some(1.0)
        } else {
            Some(f64::from(budget.cap) * self.chance(ball, point, budget.cull))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{Transform, EPSILON};
    use crate::shading::Material;
    use glam::DMat4;
    use std::f64::consts::PI;

    fn ball(centre: Point3, radius: f64) -> MirrorBall {
        let (eta, k) = (Color::new(1.6, 0.9, 0.5), Color::new(9.2, 6.3, 4.8));
        MirrorBall::new(0, centre, radius, eta, k, Color::WHITE)
    }

    #[test]
    fn a_balls_share_is_its_reflectance_times_its_solid_angle_over_pi() {
        let mirror = ball(Point3::ZERO, 0.5);
        let albedo = mirror.reflectance(1.0).max_channel();
        for d in [0.6, 1.0, 3.0, 40.0, 1e4] {
            let x: f64 = 0.25 / (d * d);
            let cone = 2.0 * PI * (1.0 - (1.0 - x).sqrt());
            let share = mirror.share_from(Point3::new(0.0, d, 0.0), 0.0).unwrap();
            let expected = albedo * cone / PI;
            // The cone's form cancels far away: compare loosely there.
            let tolerance = if d > 100.0 { 1e-6 } else { 1e-12 };
            assert!(
                (share - expected).abs() <= tolerance * expected,
                "{d}: {share}"
            );
        }
        // Far balls are left out below the cull, near ones kept; none from inside.
        let far = Point3::new(0.0, 40.0, 0.0);
        let share = mirror.share_from(far, 0.0).unwrap();
        assert!(mirror.share_from(far, share * 1.001).is_none());
        assert_eq!(mirror.share_from(far, share), Some(share));
        assert!(mirror.share_from(Point3::new(0.0, 0.3, 0.0), 0.0).is_none());
    }

    /// 40 balls of several sizes scattered over a floor, and points among and around them.
    fn pit() -> (MirrorBalls, Vec<Point3>) {
        let mut rng = SplitMix64::new(11);
        let balls = (0..40)
            .map(|i| {
                let radius = 0.1 + 0.3 * rng.next_offset();
                let (x, z) = (8.0 * rng.next_offset() - 4.0, 6.0 * rng.next_offset() - 3.0);
                let mut b = ball(Point3::new(x, radius, z), radius);
                b.object = i;
                b
            })
            .collect();
        let set = MirrorBalls::new(balls, 40);
        let points = (0..12)
            .map(|_| {
                Point3::new(
                    12.0 * rng.next_offset() - 6.0,
                    0.02,
                    10.0 * rng.next_offset() - 5.0,
                )
            })
            .filter(|&p| set.balls.iter().all(|b| b.share_from(p, 0.0).is_some()))
            .collect();
        (set, points)
    }

    #[test]
    fn a_descent_chooses_each_ball_as_often_as_its_chance_says() {
        let (set, points) = pit();
        assert!(points.len() >= 8);
        for cull in [0.0, 0.002, 0.02] {
            for &p in &points {
                let chances: Vec<f64> = (0..40).map(|i| set.chance(i, p, cull)).collect();
                let reached: Vec<bool> = set
                    .balls
                    .iter()
                    .map(|b| b.share_from(p, cull).is_some())
                    .collect();
                // Every ball that reaches the cull may be chosen; none that does not is.
                for i in 0..40 {
                    assert_eq!(chances[i] > 0.0, reached[i], "{p} {cull} {i}");
                }
                // A descent may end at a node whose bound reaches the cull though none of
                // its balls does: then no ball is chosen. Without a cull, one always is.
                let total: f64 = chances.iter().sum();
                assert!(total <= 1.0 + 1e-12, "{p} {cull}: {total}");
                if cull == 0.0 {
                    assert!((total - 1.0).abs() < 1e-12, "{p}: {total}");
                }
                // The descents by evenly spread numbers take each ball as often as its chance.
                let n = 100_000;
                let mut counts = [0.0; 40];
                for j in 0..n {
                    let u = (j as f64 + 0.5) / n as f64;
                    if let Some((i, chance)) = set.pick(p, cull, u) {
                        assert!((chance - chances[i]).abs() <= 1e-12 * chance);
                        counts[i] += 1.0;
                    }
                }
                for i in 0..40 {
                    let share = counts[i] / n as f64;
                    assert!((share - chances[i]).abs() < 1e-4, "{p} {cull} {i}");
                }
            }
        }
    }

    #[test]
    fn the_chosen_balls_weights_have_mean_one_and_their_solves_are_as_foreseen() {
        let (set, points) = pit();
        for cap in [1, 2, 3, 7] {
            let budget = MirrorBallBudget { cap, cull: 0.002 };
            for &p in &points {
                let n = 20_000;
                let (mut weights, mut solves) = ([0.0; 40], [0.0; 40]);
                for j in 0..n {
                    let u = (j as f64 + 0.5) / n as f64;
                    let mut seen = Vec::new();
                    set.choose(
                        p,
                        budget,
                        || u,
                        |b, expected, weight| {
                            let i = b.object as usize;
                            // Each ball once a vertex, its mean solves what MIS is told.
                            assert!(!seen.contains(&i));
                            seen.push(i);
                            let foreseen = set.expected_solves(i, p, budget).unwrap();
                            assert!((expected - foreseen).abs() <= 1e-12 * foreseen);
                            let taken = weight * expected;
                            assert!((taken - taken.round()).abs() < 1e-9 && taken.round() >= 1.0);
                            weights[i] += weight;
                            solves[i] += taken;
                        },
                    );
                    assert!(seen.len() <= cap as usize);
                }
                for (i, b) in set.balls.iter().enumerate() {
                    match set.expected_solves(i, p, budget) {
                        Some(expected) => {
                            // Evenly spread numbers miss a ball's mean by at most a
                            // number at each end of each descent's interval for it.
                            let slack = 2.0 * f64::from(cap);
                            assert!(
                                (solves[i] - n as f64 * expected).abs() <= slack,
                                "{cap} {i}"
                            );
                            // Every ball's light counts at its full size on average.
                            let mean = weights[i] / n as f64;
                            assert!(
                                (mean - 1.0).abs() <= slack / (n as f64 * expected),
                                "{cap} {i}"
                            );
                        }
                        None => {
                            assert!(b.share_from(p, budget.cull).is_none());
                            assert_eq!(weights[i], 0.0);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn with_no_more_balls_than_the_cap_every_ball_is_solved_once() {
        let balls = vec![
            ball(Point3::new(-1.0, 0.3, 0.0), 0.3),
            ball(Point3::new(1.0, 0.3, 0.0), 0.3),
        ];
        let set = MirrorBalls::new(balls, 2);
        let budget = MirrorBallBudget { cap: 2, cull: 0.0 };
        let mut solved = 0;
        // No number is drawn: no choice is made.
        set.choose(
            Point3::new(0.0, 0.0, 2.0),
            budget,
            || unreachable!(),
            |_, solves, weight| {
                assert_eq!((solves, weight), (1.0, 1.0));
                solved += 1;
            },
        );
        assert_eq!(solved, 2);
        assert_eq!(
            set.expected_solves(1, Point3::new(0.0, 0.0, 2.0), budget),
            Some(1.0)
        );
        // From inside a ball, or past the cull, it is left to BSDF sampling.
        assert_eq!(
            set.expected_solves(0, Point3::new(-1.0, 0.3, 0.0), budget),
            None
        );
        let far = MirrorBallBudget { cap: 2, cull: 0.5 };
        assert_eq!(
            set.expected_solves(0, Point3::new(0.0, 0.0, 2.0), far),
            None
        );
    }

    fn unit_on_sphere(rng: &mut SplitMix64) -> Vec3 {
        let z = 1.0 - 2.0 * rng.next_offset();
        let phi = TAU * rng.next_offset();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    #[test]
    fn the_reflection_point_sends_the_direction_to_the_point() {
        let mirror = ball(Point3::new(0.3, -0.2, 1.0), 0.7);
        let mut rng = SplitMix64::new(5);
        let (mut found, mut tries) = (0, 0);
        while tries < 20_000 {
            tries += 1;
            let from = mirror.centre + unit_on_sphere(&mut rng) * (0.71 + 5.0 * rng.next_offset());
            let towards = unit_on_sphere(&mut rng);
            let Some(path) = mirror.reflection_towards(from, towards) else {
                continue;
            };
            found += 1;
            // On the ball, seen from the front, reflecting the ray into `towards`.
            assert!(((path.point - mirror.centre).length() - 0.7).abs() < 1e-12);
            assert!(path.cos_incidence > 0.0);
            let d = path.direction;
            let reflected = d - path.normal * (2.0 * d.dot(path.normal));
            assert!(
                (reflected - towards).length() < 1e-12,
                "{reflected} vs {towards} from {from}"
            );
            // The point is the first the ray meets (the near side of the ball).
            let oc = from - mirror.centre;
            let b = oc.dot(d);
            let c = oc.length_squared() - 0.7 * 0.7;
            let near = -b - (b * b - c).max(0.0).sqrt();
            assert!((near - path.distance).abs() < 1e-9 * path.distance.max(1.0));
        }
        // Most directions are reachable: all but those behind the ball.
        assert!(found > 10_000, "{found}");
        // From inside the ball, or on it, there is none.
        assert!(mirror
            .reflection_towards(mirror.centre + Vec3::X * 0.5, Vec3::Y)
            .is_none());
    }

    #[test]
    fn directions_behind_the_ball_are_not_reflected() {
        let mirror = ball(Point3::ZERO, 1.0);
        let from = Point3::new(0.0, 0.0, 3.0);
        // Straight away from the point, through the ball: no reflection reaches it.
        assert!(mirror.reflection_towards(from, -Vec3::Z).is_none());
        // Straight back: the nearest point.
        let path = mirror.reflection_towards(from, Vec3::Z).unwrap();
        assert!((path.point - Point3::new(0.0, 0.0, 1.0)).length() < 1e-12);
        assert!((path.distance - 2.0).abs() < 1e-12);
        assert!((path.cos_incidence - 1.0).abs() < 1e-12);
    }

    /// Every direction from a point that meets the ball leaves it reflected; together they
    /// cover the cap of directions around the axis out to the grazing reflection. So the
    /// spread, integrated over the directions towards the ball, is that cap's solid angle.
    #[test]
    fn the_spread_integrates_to_the_solid_angle_of_the_reflections() {
        for (distance, radius) in [(3.0, 1.0), (1.2, 1.0), (40.0, 0.5)] {
            let mirror = ball(Point3::ZERO, radius);
            let from = Point3::new(0.0, 0.0, distance);
            // Directions towards the ball: a cone of half-angle β about −Z, by the midpoint
            // rule in cos and azimuth (the integrand does not depend on the azimuth).
            let beta = (radius / distance).asin();
            let n = 20_000;
            let mut total = 0.0;
            for i in 0..n {
                let cos = 1.0 - (1.0 - beta.cos()) * (i as f64 + 0.5) / n as f64;
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let d = Vec3::new(sin, 0.0, -cos);
                let oc = from - mirror.centre;
                let b = oc.dot(d);
                let c = oc.length_squared() - radius * radius;
                let disc = b * b - c;
                if disc < 0.0 {
                    continue;
                }
                let s = -b - disc.sqrt();
                let normal = (from + d * s - mirror.centre) / radius;
                total += spread(s, -d.dot(normal), radius);
            }
            total *= 2.0 * PI * (1.0 - beta.cos()) / n as f64;
            let expected = 2.0 * PI * (1.0 + beta.cos());
            assert!(
                (total - expected).abs() < 2e-3 * expected,
                "{distance}, {radius}: {total} vs {expected}"
            );
        }
        // A flat mirror does not spread.
        assert!((spread(2.0, 0.6, 1e12) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn only_still_plain_polished_metal_balls_qualify() {
        let metal = Material {
            physical: Some(Physical::Conductor {
                eta: Color::new(1.6, 0.9, 0.5),
                k: Color::new(9.2, 6.3, 4.8),
                alpha_u: 0.0,
                alpha_v: 0.0,
            }),
            ..Material::DEFAULT
        };
        let placed = Transform::new(
            DMat4::from_translation(Vec3::new(1.0, 2.0, 3.0))
                * DMat4::from_rotation_y(0.4)
                * DMat4::from_scale(Vec3::splat(0.5)),
        );
        let mut sphere = Object::sphere();
        sphere.material = metal.clone();
        sphere.transform = placed;
        let found = MirrorBall::of(&sphere, 7).expect("a mirror ball");
        assert_eq!(found.object, 7);
        assert!((found.centre - Point3::new(1.0, 2.0, 3.0)).length() < EPSILON);
        assert!((found.radius - 0.5).abs() < 1e-12);
        // Stretched, rough, of another material or another shape: not one.
        let mut stretched = sphere.clone();
        stretched.transform = Transform::new(DMat4::from_scale(Vec3::new(1.0, 2.0, 1.0)));
        assert!(MirrorBall::of(&stretched, 0).is_none());
        let mut rough = sphere.clone();
        rough.material.physical = Some(Physical::Conductor {
            eta: Color::WHITE,
            k: Color::WHITE,
            alpha_u: 0.2,
            alpha_v: 0.2,
        });
        assert!(MirrorBall::of(&rough, 0).is_none());
        let mut diffuse = sphere.clone();
        diffuse.material.physical = Some(Physical::Diffuse);
        assert!(MirrorBall::of(&diffuse, 0).is_none());
        let mut cube = Object::cube();
        cube.material = metal;
        assert!(MirrorBall::of(&cube, 0).is_none());
        // Its reflectance is the conductor's Fresnel term.
        let f = found.reflectance(0.5);
        assert_eq!(
            f,
            fresnel::conductor(0.5, Color::new(1.6, 0.9, 0.5), Color::new(9.2, 6.3, 4.8))
        );
    }
}
