//! pbrt-v4's curves (hair, fur, grass): cubic Bézier segments with a width that varies
//! linearly along them, intersected as pbrt-v4's `Curve::Intersect` does, described here in
//! our own words. The segment's control points are taken to a frame whose z is the ray: there
//! the curve is a flat band seen edge-on to the ray, and it is split in halves at u = ½
//! (de Casteljau) until each piece is nearly straight (to a twentieth of the width, pbrt's
//! rule for the depth, at most 10 splits). A straight piece is hit where the ray's foot on
//! its chord lies between the planes through its ends perpendicular to its end tangents and
//! within half the width of the curve there; the hit's t is the depth of that curve point,
//! taken only beyond the curve's width from the ray's origin (a ray leaving a curve must not
//! meet it again: pbrt-v4 starts such rays beyond the width it bounds the hit's error by).
//!
//! Three kinds, as pbrt-v4's `type`: `Flat` faces the ray (its normal is the ray's direction
//! made perpendicular to the tangent), `Cylinder` is hit as `Flat` but its normal turns about
//! the tangent from −90° at one edge to +90° at the other (a tube's, turned as pbrt-v4 turns
//! it: leaning in across the band, see [`Curve::normal`]), and `Ribbon` is oriented
//! by normals at its ends (slerped along it): its width shrinks with the cosine between that
//! normal and the ray. u runs along the segment, v across it from 0 to 1 (pbrt-v4's uv).
//!
//! The B-spline and quadratic bases are turned into cubic Bézier segments as pbrt-v4's
//! `Curve::Create` does ([`bezier_segments`]).

use crate::math::{Aabb, Point3, Ray, Vec3};

/// How a curve faces the ray (pbrt-v4's `type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveKind {
    /// A band always facing the ray.
    Flat,
    /// A flat band shaded as a tube.
    Cylinder,
    /// A band oriented by the normals at its ends.
    Ribbon,
}

/// The basis a curve's control points are in (pbrt-v4's `basis`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveBasis {
    /// Bézier segments sharing their end points.
    Bezier,
    /// A uniform B-spline, one segment per control point past the degree.
    BSpline,
}

/// Why control points make no curve.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CurveError {
    /// The degree is not 2 or 3.
    Degree(i64),
    /// Too few control points, or a Bézier count that is not `degree + 1 + n·degree`.
    Count {
        /// How many were given.
        found: usize,
        /// The degree.
        degree: usize,
        /// The basis.
        basis: CurveBasis,
    },
}

impl std::fmt::Display for CurveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CurveError::Degree(d) => write!(f, "a curve's degree is 2 or 3, found {d}"),
            CurveError::Count {
                found,
                degree,
                basis: CurveBasis::Bezier,
            } => write!(
                f,
                "a degree-{degree} Bézier curve has {} + n·{degree} control points, found {found}",
                degree + 1
            ),
            CurveError::Count { found, degree, .. } => write!(
                f,
                "a degree-{degree} B-spline curve has at least {} control points, found {found}",
                degree + 1
            ),
        }
    }
}

impl std::error::Error for CurveError {}

/// How many cubic segments `count` control points of `degree` (2 or 3) in `basis` make.
pub fn segment_count(count: usize, degree: i64, basis: CurveBasis) -> Result<usize, CurveError> {
    if degree != 2 && degree != 3 {
        return Err(CurveError::Degree(degree));
    }
    let d = degree as usize;
    let bad = CurveError::Count {
        found: count,
        degree: d,
        basis,
    };
    match basis {
        CurveBasis::Bezier if count > d && (count - 1) % d == 0 => Ok((count - 1) / d),
        CurveBasis::BSpline if count > d => Ok(count - d),
        _ => Err(bad),
    }
}

/// The cubic Bézier control points of each segment of a curve given by `points` of `degree`
/// in `basis` (see [`segment_count`] for the counts allowed): quadratics are raised to cubics
/// and B-splines converted to Bézier form, segment by segment.
pub fn bezier_segments(
    points: &[Point3],
    degree: i64,
    basis: CurveBasis,
) -> Result<Vec<[Point3; 4]>, CurveError> {
    let n = segment_count(points.len(), degree, basis)?;
    let raise = |q: [Point3; 3]| {
        [
            q[0],
            q[0] / 3.0 + q[1] * (2.0 / 3.0),
            q[1] * (2.0 / 3.0) + q[2] / 3.0,
            q[2],
        ]
    };
    Ok((0..n)
        .map(|s| match (basis, degree) {
            (CurveBasis::Bezier, 2) => raise([points[2 * s], points[2 * s + 1], points[2 * s + 2]]),
            (CurveBasis::Bezier, _) => [
                points[3 * s],
                points[3 * s + 1],
                points[3 * s + 2],
                points[3 * s + 3],
            ],
            (CurveBasis::BSpline, 2) => {
                let (p0, p1, p2) = (points[s], points[s + 1], points[s + 2]);
                raise([(p0 + p1) * 0.5, p1, (p1 + p2) * 0.5])
            }
            (CurveBasis::BSpline, _) => {
                let (p0, p1, p2, p3) = (points[s], points[s + 1], points[s + 2], points[s + 3]);
                [
                    (p0 + p1 * 4.0 + p2) / 6.0,
                    (p1 * 2.0 + p2) / 3.0,
                    (p1 + p2 * 2.0) / 3.0,
                    (p1 + p2 * 4.0 + p3) / 6.0,
                ]
            }
        })
        .collect())
}

/// The point of the cubic Bézier `cp` at `u`, and its derivative there.
pub fn evaluate(cp: &[Point3; 4], u: f64) -> (Point3, Vec3) {
    let a = [
        cp[0].lerp(cp[1], u),
        cp[1].lerp(cp[2], u),
        cp[2].lerp(cp[3], u),
    ];
    let b = [a[0].lerp(a[1], u), a[1].lerp(a[2], u)];
    let d = if (b[1] - b[0]).length_squared() > 0.0 {
        3.0 * (b[1] - b[0])
    } else {
        // A doubled end point: the chord's direction stands in for the tangent.
        cp[3] - cp[0]
    };
    (b[0].lerp(b[1], u), d)
}

/// The control points of the part of `cp` between `u0` and `u1` (its blossoms).
fn sub_curve(cp: &[Point3; 4], u0: f64, u1: f64) -> [Point3; 4] {
    let blossom = |a: f64, b: f64, c: f64| {
        let l1 = [
            cp[0].lerp(cp[1], a),
            cp[1].lerp(cp[2], a),
            cp[2].lerp(cp[3], a),
        ];
        let l2 = [l1[0].lerp(l1[1], b), l1[1].lerp(l1[2], b)];
        l2[0].lerp(l2[1], c)
    };
    [
        blossom(u0, u0, u0),
        blossom(u0, u0, u1),
        blossom(u0, u1, u1),
        blossom(u1, u1, u1),
    ]
}

/// The two halves of `cp` split at u = ½.
fn halves(cp: &[Point3; 4]) -> [[Point3; 4]; 2] {
    let a = [
        cp[0].lerp(cp[1], 0.5),
        cp[1].lerp(cp[2], 0.5),
        cp[2].lerp(cp[3], 0.5),
    ];
    let b = [a[0].lerp(a[1], 0.5), a[1].lerp(a[2], 0.5)];
    let m = b[0].lerp(b[1], 0.5);
    [[cp[0], a[0], b[0], m], [m, b[1], a[2], cp[3]]]
}

/// One cubic Bézier curve segment with its widths and kind; a part of it (`u_min..u_max`,
/// pbrt-v4's `splitdepth` pieces) is what a BVH leaf holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curve {
    /// The segment's control points.
    pub cp: [Point3; 4],
    /// Widths at u = 0 and u = 1.
    pub width: [f64; 2],
    /// How it faces the ray.
    pub kind: CurveKind,
    /// The unit normals at its ends (ribbons only).
    pub normals: [Vec3; 2],
    /// The part of the segment this piece covers.
    pub u_min: f64,
    /// See `u_min`.
    pub u_max: f64,
}

/// A hit on a curve: its distance, and u along the segment, v across it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveHit {
    /// Distance along the ray.
    pub t: f64,
    /// Along the segment, 0 to 1.
    pub u: f64,
    /// Across it, 0 to 1.
    pub v: f64,
}

impl Curve {
    /// The piece `u_min..u_max` of a segment (normals, used by ribbons, are normalised here).
    pub fn new(
        cp: [Point3; 4],
        width: [f64; 2],
        kind: CurveKind,
        normals: [Vec3; 2],
        u_min: f64,
        u_max: f64,
    ) -> Self {
        Self {
            cp,
            width,
            kind,
            normals: normals.map(|n| n.normalize_or_zero()),
            u_min,
            u_max,
        }
    }

    fn width_at(&self, u: f64) -> f64 {
        self.width[0] + (self.width[1] - self.width[0]) * u
    }

    /// The box around the piece: its control points' hull grown by half its widest width.
    pub fn bounds(&self) -> Aabb {
        let cp = sub_curve(&self.cp, self.u_min, self.u_max);
        let mut b = Aabb::EMPTY;
        for p in cp {
            b.add_point(p);
        }
        let r = 0.5 * self.width_at(self.u_min).max(self.width_at(self.u_max));
        Aabb::new(b.min - Vec3::splat(r), b.max + Vec3::splat(r))
    }

    /// The ribbon's normal at `u` (the ends' normals slerped).
    pub fn ribbon_normal(&self, u: f64) -> Vec3 {
        let [n0, n1] = self.normals;
        let angle = n0.dot(n1).clamp(-1.0, 1.0).acos();
        if angle < 1e-9 {
            return n0;
        }
        let s = angle.sin();
        (((1.0 - u) * angle).sin() / s * n0 + (u * angle).sin() / s * n1).normalize_or_zero()
    }

    /// The nearest hit on the piece with `ray.t_min <= t < t_max`, if any, no nearer the ray's
    /// origin than the curve's width there (see the [module](self)).
    pub fn intersect(&self, ray: &Ray, t_max: f64) -> Option<CurveHit> {
        let length = ray.direction.length();
        if length == 0.0 {
            return None;
        }
        let z = ray.direction / length;
        let cp = sub_curve(&self.cp, self.u_min, self.u_max);
        let mut x = z.cross(cp[3] - cp[0]);
        if x.length_squared() == 0.0 {
            x = z.any_orthonormal_vector();
        }
        let x = x.normalize();
        let y = z.cross(x);
        let to_ray = |p: Point3| {
            let q = p - ray.origin;
            Point3::new(q.dot(x), q.dot(y), q.dot(z))
        };
        let local = cp.map(to_ray);
        // The depth at which the curve flattens to a twentieth of its width.
        let mut l0: f64 = 0.0;
        for i in 0..2 {
            let d = (local[i] - 2.0 * local[i + 1] + local[i + 2]).abs();
            l0 = l0.max(d.max_element());
        }
        let eps = self.width[0].max(self.width[1]) * 0.05;
        let depth = if l0 > 0.0 && eps > 0.0 {
            let r = (std::f64::consts::SQRT_2 * 6.0 * l0 / (8.0 * eps)).log2() * 0.5;
            r.floor().clamp(0.0, 10.0) as u32
        } else {
            0
        };
        let span = Span {
            ray_dir: z,
            z_min: ray.t_min * length,
            z_max: t_max * length,
        };
        let mut best = None;
        self.recurse(&span, &local, self.u_min, self.u_max, depth, &mut best);
        best.map(|(zh, u, v)| CurveHit {
            t: zh / length,
            u,
            v,
        })
    }

    /// Whether the ray-space piece `cp` (u from `u0` to `u1`) can be hit in the span.
    fn overlaps(&self, span: &Span, cp: &[Point3; 4], u0: f64, u1: f64) -> bool {
        let r = 0.5 * self.width_at(u0).max(self.width_at(u1));
        let mut b = Aabb::EMPTY;
        for p in cp {
            b.add_point(*p);
        }
        b.min.x - r <= 0.0
            && b.max.x + r >= 0.0
            && b.min.y - r <= 0.0
            && b.max.y + r >= 0.0
            && b.min.z - r <= span.z_max
            && b.max.z + r >= span.z_min
    }

    fn recurse(
        &self,
        span: &Span,
        cp: &[Point3; 4],
        u0: f64,
        u1: f64,
        depth: u32,
        best: &mut Option<(f64, f64, f64)>,
    ) {
        if !self.overlaps(span, cp, u0, u1) {
            return;
        }
        if depth > 0 {
            let mid = 0.5 * (u0 + u1);
            let [a, b] = halves(cp);
            self.recurse(span, &a, u0, mid, depth - 1, best);
            self.recurse(span, &b, mid, u1, depth - 1, best);
            return;
        }
        // The ray (the origin of the xy plane) must lie between the planes through the ends
        // perpendicular to the end tangents.
        let start = (cp[1].y - cp[0].y) * -cp[0].y + cp[0].x * (cp[0].x - cp[1].x);
        let end = (cp[2].y - cp[3].y) * -cp[3].y + cp[3].x * (cp[3].x - cp[2].x);
        if start < 0.0 || end < 0.0 {
            return;
        }
        let chord = (cp[3] - cp[0]).truncate();
        let denom = chord.length_squared();
        if denom == 0.0 {
            return;
        }
        let w = (-cp[0].truncate()).dot(chord) / denom;
        let u = (u0 + (u1 - u0) * w).clamp(u0, u1);
        let mut width = self.width_at(u);
        if self.kind == CurveKind::Ribbon {
            width *= self.ribbon_normal(u).dot(span.ray_dir).abs();
        }
        let (pc, dpc) = evaluate(cp, w.clamp(0.0, 1.0));
        let dist2 = pc.x * pc.x + pc.y * pc.y;
        // Nothing nearer the ray's origin than the curve is wide there: a ray leaving a flat
        // curve meets the same band turned to face it, within half its width of its origin
        // (a ribbon's likewise), so without this every shadow ray would shadow its own
        // curve. pbrt-v4 bounds a curve hit's error by its width and starts the rays that
        // leave it beyond that, which comes to the same.
        let near = span.z_min.max(self.width_at(u));
        if dist2 > 0.25 * width * width || pc.z < near || pc.z >= span.z_max {
            return;
        }
        if best.is_some_and(|(z, _, _)| pc.z >= z) {
            return;
        }
        let side = dpc.x * -pc.y + pc.x * dpc.y;
        let off = dist2.sqrt() / width;
        let v = if side > 0.0 { 0.5 + off } else { 0.5 - off };
        *best = Some((pc.z, u, v));
    }

    /// The unit normal at the hit (`u`, `v`) of a ray going `direction`, facing against it:
    /// a flat curve's faces the ray, a cylinder's turns about the tangent with v, a ribbon's
    /// is its slerped end normal made perpendicular to the tangent.
    pub fn normal(&self, u: f64, v: f64, direction: Vec3) -> Vec3 {
        let (_, tangent) = evaluate(&self.cp, u);
        let t = tangent.normalize_or_zero();
        let facing = |n: Vec3| if n.dot(direction) > 0.0 { -n } else { n };
        if self.kind == CurveKind::Ribbon {
            let n = self.ribbon_normal(u);
            let n = (n - n.dot(t) * t).try_normalize().unwrap_or(n);
            return facing(n);
        }
        let d = direction.normalize_or_zero();
        let flat = match (-(d - d.dot(t) * t)).try_normalize() {
            Some(n) => n,
            None => t.any_orthonormal_vector(),
        };
        match self.kind {
            CurveKind::Cylinder => {
                // Turn about the tangent by θ from −90° at v = 0 to +90° at v = 1, as
                // pbrt-v4 turns its dpdv: towards the side v grows to at v = 0, so that the
                // normal at each edge leans in across the band. That is a tube seen from
                // inside (a lamp to one side lights the far half of the band), and pbrt-v4's
                // renders are so: kept, for the pbrt reader's pictures to be pbrt-v4's.
                let across = t.cross(flat);
                let theta = (v - 0.5) * std::f64::consts::PI;
                (flat * theta.cos() - across * theta.sin()).normalize()
            }
            _ => flat,
        }
    }
}

/// The depths the ray may hit at, in the ray's frame (its direction as z).
struct Span {
    ray_dir: Vec3,
    z_min: f64,
    z_max: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight(kind: CurveKind, width: f64) -> Curve {
        let cp = [
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(-1.0 / 3.0, 0.0, 0.0),
            Point3::new(1.0 / 3.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
        ];
        Curve::new(cp, [width, width], kind, [Vec3::Z, Vec3::Z], 0.0, 1.0)
    }

    fn ray(o: Point3, d: Vec3) -> Ray {
        Ray::new(o, d)
    }

    /// A straight flat curve and a ribbon facing the ray are hit where the ray meets the
    /// plane z = 0 and within half the width, at the same v.
    #[test]
    fn straight_flat_curve_is_the_ribbons_analytic_hit() {
        let flat = straight(CurveKind::Flat, 0.2);
        let ribbon = straight(CurveKind::Ribbon, 0.2);
        for (x, y) in [(0.3, 0.05), (-0.7, -0.08), (0.0, 0.0), (0.9, 0.099)] {
            let r = ray(Point3::new(x, y, 5.0), Vec3::new(0.0, 0.0, -2.0));
            let a = flat.intersect(&r, f64::INFINITY).expect("flat hit");
            let b = ribbon.intersect(&r, f64::INFINITY).expect("ribbon hit");
            assert!(
                (a.t - 2.5).abs() < 1e-12 && (b.t - 2.5).abs() < 1e-12,
                "{a:?} {b:?}"
            );
            assert!((a.u - (x + 1.0) / 2.0).abs() < 1e-9);
            assert!((a.v - b.v).abs() < 1e-12);
            assert!(((a.v - 0.5).abs() - y.abs() / 0.2).abs() < 1e-9);
            let n = flat.normal(a.u, a.v, r.direction);
            assert!((n - Vec3::Z).length() < 1e-12);
            // A cylinder's normal leans in across the band, pbrt-v4's way: at the edge on
            // +y towards −y, at v = ½ it is the flat one's.
            let cylinder = straight(CurveKind::Cylinder, 0.2);
            let n = cylinder.normal(a.u, a.v, r.direction);
            let lean = (a.v - 0.5).abs() * std::f64::consts::PI;
            assert!((n.z - lean.cos()).abs() < 1e-9, "{n:?}");
            assert!(
                (n.y + y.signum() * lean.sin()).abs() < 1e-9 || y == 0.0,
                "{n:?}"
            );
        }
        for y in [0.101, -0.2, 0.5] {
            let r = ray(Point3::new(0.1, y, 5.0), Vec3::new(0.0, 0.0, -1.0));
            assert!(flat.intersect(&r, f64::INFINITY).is_none());
            assert!(ribbon.intersect(&r, f64::INFINITY).is_none());
        }
        // Nothing behind the span.
        let r = ray(Point3::new(0.1, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(flat.intersect(&r, 4.9).is_none());
    }

    /// A ray leaving a point of a curve, flat or ribbon, at any angle does not meet the
    /// curve it leaves (a flat one turns to face it), and one starting well clear still does.
    #[test]
    fn rays_leaving_a_curve_do_not_meet_it_again() {
        for kind in [CurveKind::Flat, CurveKind::Cylinder, CurveKind::Ribbon] {
            let c = straight(kind, 0.2);
            for (y, d) in [
                (0.09, Vec3::new(0.0, -1.0, 1.0)),
                (-0.09, Vec3::new(0.0, 1.0, 0.3)),
                (0.0, Vec3::new(0.3, 0.5, 1.0)),
                (0.05, Vec3::new(0.0, -1.0, -0.2)),
            ] {
                let r = ray(Point3::new(0.2, y, 0.0), d);
                assert!(
                    c.intersect(&r, f64::INFINITY).is_none(),
                    "{kind:?} {y} {d:?}"
                );
                let back = ray(r.position(-10.0), d);
                assert!(c.intersect(&back, f64::INFINITY).is_some() || kind == CurveKind::Ribbon);
            }
        }
    }

    /// Seen at 45° about its axis, a ribbon is hit only within its real half width of the
    /// axis in its plane, where a flat curve (always facing) is wider there.
    #[test]
    fn tilted_ribbon_narrows_as_its_plane_does() {
        let flat = straight(CurveKind::Flat, 0.2);
        let ribbon = straight(CurveKind::Ribbon, 0.2);
        let d = Vec3::new(0.0, -1.0, -1.0);
        // The ray crosses z = 0 at y = y0.
        let at = |y0: f64| ray(Point3::new(0.2, y0 + 3.0, 3.0), d);
        assert!(ribbon.intersect(&at(0.095), f64::INFINITY).is_some());
        assert!(ribbon.intersect(&at(0.105), f64::INFINITY).is_none());
        assert!(flat.intersect(&at(0.105), f64::INFINITY).is_some());
        assert!(flat.intersect(&at(0.15), f64::INFINITY).is_none());
    }

    fn bent() -> Curve {
        let cp = [
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(-0.3, 1.5, 0.2),
            Point3::new(0.4, -1.0, -0.3),
            Point3::new(1.0, 0.5, 0.1),
        ];
        Curve::new(cp, [0.08, 0.04], CurveKind::Flat, [Vec3::Z; 2], 0.0, 1.0)
    }

    /// The distance from `p` to the curve, and the width at the nearest point.
    fn nearest(c: &Curve, p: Point3) -> (f64, f64) {
        (0..=20000)
            .map(|i| {
                let u = i as f64 / 20000.0;
                ((evaluate(&c.cp, u).0 - p).length(), c.width_at(u))
            })
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a })
    }

    /// A curved segment's hits lie within half its width of it (give or take the
    /// flattening), and rays passing well clear of it miss.
    #[test]
    fn bent_curve_hits_lie_within_half_its_width() {
        let c = bent();
        let mut hits = 0;
        let mut state = 12345u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..3000 {
            let u = 0.05 + 0.9 * rnd();
            let (p, _) = evaluate(&c.cp, u);
            let offset = Vec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 0.3;
            let dir = Vec3::new(rnd() - 0.5, rnd() - 0.5, -2.0);
            let target = p + offset;
            let r = ray(target - dir * 4.0, dir);
            let (dist_target, w_target) = nearest(&c, target);
            match c.intersect(&r, f64::INFINITY) {
                Some(h) => {
                    hits += 1;
                    let (d, w) = nearest(&c, r.position(h.t));
                    assert!(
                        d <= 0.5 * w * 1.1 + 1e-3,
                        "hit {d} from the curve, width {w}"
                    );
                }
                None => {
                    // A ray through a point near the curve's centre line hits it.
                    assert!(dist_target > 0.25 * w_target, "missed at {dist_target} {u}");
                }
            }
        }
        assert!(hits > 100, "{hits} hits");
        // Rays parallel to z far from the curve miss.
        for i in 0..200 {
            let x = -1.0 + i as f64 / 100.0;
            let r = ray(Point3::new(x, 2.5, 5.0), Vec3::new(0.0, 0.0, -1.0));
            assert!(c.intersect(&r, f64::INFINITY).is_none());
        }
    }

    /// The box of each piece holds the swept curve's points.
    #[test]
    fn bounds_hold_sampled_points() {
        let c = bent();
        for piece in 0..8 {
            let (u0, u1) = (piece as f64 / 8.0, (piece + 1) as f64 / 8.0);
            let p = Curve {
                u_min: u0,
                u_max: u1,
                ..c
            };
            let b = p.bounds();
            for i in 0..=100 {
                let u = u0 + (u1 - u0) * i as f64 / 100.0;
                let (q, _) = evaluate(&c.cp, u);
                let r = 0.5 * c.width_at(u);
                for off in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
                    assert!(b.contains_point(q + off * r * 0.999), "{u} {b:?}");
                }
            }
        }
    }

    /// B-splines become Bézier segments that meet, starting where the spline does.
    #[test]
    fn bases_become_bezier_segments() {
        let p: Vec<Point3> = (0..6)
            .map(|i| Point3::new(i as f64, (i * i % 5) as f64, 0.0))
            .collect();
        let s = bezier_segments(&p, 3, CurveBasis::BSpline).unwrap();
        assert_eq!(s.len(), 3);
        assert!((s[0][0] - (p[0] + 4.0 * p[1] + p[2]) / 6.0).length() < 1e-12);
        for i in 0..2 {
            assert!((s[i][3] - s[i + 1][0]).length() < 1e-12);
        }
        let q = bezier_segments(&p[..5], 2, CurveBasis::Bezier).unwrap();
        assert_eq!(q.len(), 2);
        let (m, _) = evaluate(&q[0], 0.5);
        assert!((m - (p[0] * 0.25 + p[1] * 0.5 + p[2] * 0.25)).length() < 1e-12);
        assert!(bezier_segments(&p[..5], 3, CurveBasis::Bezier).is_err());
        assert_eq!(
            segment_count(3, 4, CurveBasis::Bezier),
            Err(CurveError::Degree(4))
        );
    }
}
