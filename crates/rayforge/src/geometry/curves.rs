//! A group of curve segments (one pbrt-v4 `curve` shape: a hair, a blade of grass) shared by
//! the objects that place it, with its own BVH, as a mesh has over its faces. Each segment is
//! cut into `2^depth` equal parts of u (pbrt-v4's `splitdepth`, which makes each part a shape
//! of its own with its own box), and the BVH holds the parts: a long bent segment's one box
//! would be mostly empty, its parts' boxes hug it. The parts are not stored: part `i` is
//! segment `i >> depth`, the `i & (2^depth − 1)`-th slice of its u.
//!
//! The hits come from [`Curve::intersect`] (pbrt-v4's recursive splitting in the ray's
//! frame). A flat curve's normal depends on the ray that met it, not on the point alone, so
//! each hit carries its normal ([`LocalHit::normal`]), found for the ray that made it; the
//! hit's `face` is the part, its `u` along the segment and `v` across it (pbrt-v4's uv).

use super::curve::{Curve, CurveHit};
use super::LocalHit;
use crate::accel::Bvh;
use crate::math::{Aabb, Ray, Vec3};
use std::ops::ControlFlow;
use std::sync::atomic::AtomicBool;

/// The most `depth` a group is cut to: each level doubles the parts (the BVH's boxes), and
/// past 2¹⁰ parts a segment's boxes are finer than its own intersection refines.
pub const MAX_SPLIT_DEPTH: u32 = 10;

/// Curve segments cut into parts, each behind a box of one BVH.
#[derive(Debug, Clone, PartialEq)]
pub struct Curves {
    segments: Vec<Curve>,
    depth: u32,
    bvh: Bvh,
}

impl Curves {
    /// The group of `segments` (each over its whole u, 0 to 1), each cut into `2^depth` parts
    /// (`depth` at most [`MAX_SPLIT_DEPTH`]).
    pub fn new(segments: Vec<Curve>, depth: u32) -> Self {
        Self::new_until(segments, depth, None)
            .expect("a build without a stop flag is never stopped")
    }

    /// [`Curves::new`] that gives up, `None`, once `stop` is set while its BVH is built.
    pub fn new_until(segments: Vec<Curve>, depth: u32, stop: Option<&AtomicBool>) -> Option<Self> {
        let depth = depth.min(MAX_SPLIT_DEPTH);
        let mut curves = Self {
            segments,
            depth,
            bvh: Bvh::default(),
        };
        let boxes: Vec<Aabb> = (0..curves.part_count())
            .map(|i| curves.part(i as u32).bounds())
            .collect();
        curves.bvh = Bvh::build_until(&boxes, stop)?;
        Some(curves)
    }

    /// The segments, each over its whole u.
    pub fn segments(&self) -> &[Curve] {
        &self.segments
    }

    /// How many parts each segment is cut into is `2^depth`.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// How many parts the BVH holds.
    pub fn part_count(&self) -> usize {
        self.segments.len() << self.depth
    }

    /// Part `i`: its segment, limited to its slice of u.
    #[inline]
    pub fn part(&self, i: u32) -> Curve {
        let segment = &self.segments[(i >> self.depth) as usize];
        let n = (1u32 << self.depth) as f64;
        let k = (i & ((1u32 << self.depth) - 1)) as f64;
        Curve {
            u_min: segment.u_min + (segment.u_max - segment.u_min) * k / n,
            u_max: segment.u_min + (segment.u_max - segment.u_min) * (k + 1.0) / n,
            ..*segment
        }
    }

    /// The box around every part (empty for no segments).
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Bytes held on the heap: the segments and the BVH.
    pub fn heap_bytes(&self) -> usize {
        self.segments.capacity() * std::mem::size_of::<Curve>() + self.bvh.heap_bytes()
    }

    /// The hit record of `hit` on part `part` of `curve`, with its normal for `ray`.
    #[inline]
    fn record(curve: &Curve, part: u32, ray: &Ray, hit: CurveHit) -> LocalHit {
        LocalHit {
            t: hit.t,
            u: hit.u,
            v: hit.v,
            face: part,
            leaf: 0,
            time: ray.time,
            normal: curve.normal(hit.u, hit.v, ray.direction),
        }
    }

    /// Calls `visit` with each part's nearest hit in `[t_min, t_max)` (the current `t_max`,
    /// which it may lower, and may stop the walk with `Break`), nearest boxes first.
    #[inline]
    fn walk(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut visit: impl FnMut(&Curve, u32, CurveHit, &mut f64) -> ControlFlow<()>,
    ) {
        let from = Ray { t_min, ..*ray };
        self.bvh
            .traverse(ray.origin, ray.direction, t_min, t_max, |i, limit| {
                let curve = self.part(i);
                match curve.intersect(&from, *limit) {
                    Some(hit) => visit(&curve, i, hit, limit),
                    None => ControlFlow::Continue(()),
                }
            });
    }

    /// Each part's nearest hit with `t <= t_max` (what the Whitted renderer's lists of hits
    /// take): a curve has no inside, so one hit a part is all its containers need, as pbrt-v4
    /// reports one. None lies behind the ray's origin, nor within the curve's width ahead of
    /// it (see [`Curve::intersect`]): a curve has no inside that a hit behind could tell of.
    pub fn intersect_up_to(&self, ray: &Ray, t_max: f64, mut hit: impl FnMut(LocalHit)) {
        self.walk(ray, f64::NEG_INFINITY, f64::INFINITY, |curve, i, h, _| {
            if h.t <= t_max {
                hit(Self::record(curve, i, ray, h));
            }
            ControlFlow::Continue(())
        });
    }

    /// The nearest hit with `t_min <= t < t_max`: farther boxes are skipped once one is
    /// found, and the normal is found for the nearest alone.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<LocalHit> {
        let mut best = None;
        self.walk(ray, t_min, t_max, |_, i, h, limit| {
            *limit = h.t;
            best = Some((i, h));
            ControlFlow::Continue(())
        });
        best.map(|(i, h)| Self::record(&self.part(i), i, ray, h))
    }

    /// [`Curves::closest_hit`] among the hits that `keep` accepts (an alpha texture's holes):
    /// a refused hit lets the walk go on to the parts behind it.
    #[inline]
    pub fn closest_hit_where(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut keep: impl FnMut(&LocalHit) -> bool,
    ) -> Option<LocalHit> {
        let mut best = None;
        self.walk(ray, t_min, t_max, |curve, i, h, limit| {
            let record = Self::record(curve, i, ray, h);
            if keep(&record) {
                *limit = h.t;
                best = Some(record);
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Whether any part meets the ray with `t_min <= t < t_max` (shadow rays): the walk stops
    /// at the first.
    #[inline]
    pub fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.any_hit_where(ray, t_min, t_max, |_| true)
    }

    /// [`Curves::any_hit`] among the hits that `keep` accepts.
    #[inline]
    pub fn any_hit_where(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut keep: impl FnMut(&LocalHit) -> bool,
    ) -> bool {
        let mut found = false;
        self.walk(ray, t_min, t_max, |curve, i, h, _| {
            if keep(&Self::record(curve, i, ray, h)) {
                found = true;
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        });
        found
    }

    /// The object-space normal at a hit: the one its ray found ([`LocalHit::normal`]); a hit
    /// made without a ray (none has one) gets the segment's normal for a ray along −z.
    #[inline]
    pub fn normal_at(&self, hit: &LocalHit) -> Vec3 {
        if hit.normal != Vec3::ZERO {
            return hit.normal;
        }
        match self.segments.get((hit.face >> self.depth) as usize) {
            Some(curve) => curve.normal(hit.u, hit.v, -Vec3::Z),
            None => Vec3::Z,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::curve::{bezier_segments, evaluate, CurveBasis, CurveKind};
    use super::*;
    use crate::math::Point3;

    /// A fan of bent segments across the unit square, each cut into 8 parts.
    fn fan(kind: CurveKind) -> Curves {
        let mut segments = Vec::new();
        for k in 0..12 {
            let x = -1.0 + k as f64 / 6.0;
            let p = [
                Point3::new(x, -1.0, 0.0),
                Point3::new(x + 0.3, -0.3, 0.2),
                Point3::new(x - 0.2, 0.4, -0.2),
                Point3::new(x + 0.1, 1.0, 0.1),
            ];
            let cp = bezier_segments(&p, 3, CurveBasis::Bezier).unwrap()[0];
            segments.push(Curve::new(cp, [0.06, 0.02], kind, [Vec3::Z; 2], 0.0, 1.0));
        }
        Curves::new(segments, 3)
    }

    /// The nearest hit through the BVH is the nearest of all parts tried one by one, its
    /// normal faces the ray, and the walk's other searches agree with it.
    #[test]
    fn the_bvh_finds_the_nearest_part_of_all() {
        for kind in [CurveKind::Flat, CurveKind::Cylinder] {
            let curves = fan(kind);
            assert_eq!(curves.part_count(), 96);
            let mut state = 99u64;
            let mut rnd = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let mut hits = 0;
            for _ in 0..4000 {
                let o = Point3::new(2.0 * rnd() - 1.0, 2.0 * rnd() - 1.0, 3.0);
                let d = Vec3::new(0.3 * (rnd() - 0.5), 0.3 * (rnd() - 0.5), -1.0);
                let ray = Ray::new(o, d);
                let brute = (0..curves.part_count() as u32)
                    .filter_map(|i| curves.part(i).intersect(&ray, f64::INFINITY))
                    .map(|h| h.t)
                    .fold(f64::INFINITY, f64::min);
                let found = curves.closest_hit(&ray, 0.0, f64::INFINITY);
                assert_eq!(found.map_or(f64::INFINITY, |h| h.t), brute);
                assert_eq!(curves.any_hit(&ray, 0.0, f64::INFINITY), found.is_some());
                assert_eq!(
                    curves.closest_hit_where(&ray, 0.0, f64::INFINITY, |_| true),
                    found
                );
                // Refusing every hit leaves none.
                assert!(curves
                    .closest_hit_where(&ray, 0.0, f64::INFINITY, |_| false)
                    .is_none());
                if let Some(h) = found {
                    hits += 1;
                    assert!(h.normal.dot(d) < 0.0, "{h:?}");
                    assert!((h.normal.length() - 1.0).abs() < 1e-9);
                    // (Short of the hit by more than the rounding of t to the ray's frame.)
                    assert!(!curves.any_hit(&ray, 0.0, h.t * (1.0 - 1e-12)));
                    let mut every = Vec::new();
                    curves.intersect_up_to(&ray, f64::INFINITY, |x| every.push(x.t));
                    assert!(every.contains(&h.t));
                }
            }
            assert!(hits > 200, "{hits}");
        }
    }

    /// Each part's box holds the points of its slice of the segment, grown by half its width.
    #[test]
    fn parts_slice_their_segment() {
        let curves = fan(CurveKind::Flat);
        for i in 0..curves.part_count() as u32 {
            let part = curves.part(i);
            let segment = &curves.segments()[(i >> 3) as usize];
            assert!((part.u_max - part.u_min - 0.125).abs() < 1e-15);
            let b = part.bounds();
            for j in 0..=20 {
                let u = part.u_min + (part.u_max - part.u_min) * j as f64 / 20.0;
                assert!(b.contains_point(evaluate(&segment.cp, u).0));
            }
            assert!(curves.bounds().contains_point(b.min));
        }
    }
}
