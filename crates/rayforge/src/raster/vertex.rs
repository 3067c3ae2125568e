//! The vertex stage: every vertex of every instance moved into view space and projected onto
//! the screen once, and every normal moved into world space once, in parallel. Triangles then
//! share their corners' work.

use super::edge::FixedPoint;
use super::instance::Instance;
use super::Projection;
use crate::math::Vec3;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A vertex in view space and on the screen.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ViewVertex {
    /// View-space position (the eye at the origin, looking down +z).
    pub view: DVec3,
    /// Screen position on the subpixel grid (meaningful only in front of the near plane).
    pub screen: FixedPoint,
    /// 1/z, what the depth buffer holds.
    pub inv_z: f64,
}

/// Vertices are processed in runs of this many per task.
const RUN: usize = 4096;

/// The screen position of a view-space point in front of the eye, on the grid.
#[inline]
pub(crate) fn to_screen(projection: &Projection, view: DVec3, bits: u32) -> FixedPoint {
    let p = projection.project(view);
    FixedPoint::from_pixels(p.x, p.y, bits)
}

/// All vertices and world-space normals of `instances`, at the offsets they were given, into
/// `vertices` and `normals`, and into `outside` each vertex's outcode: bit `p` set when it lies
/// outside plane `p` of its instance's list of crossed planes (`Instance::planes`). Binning
/// reads a triangle's three outcodes where it tested each corner against each plane, work
/// that a vertex shared by six triangles did six times. The arrays are resized to fit (a
/// rasterizer keeps them from frame to frame, so a frame of the same scene allocates nothing
/// here); every element is written, unless `cancel` is set: it is looked at before each run
/// of [`RUN`] vertices or normals (a frame of millions of them stops within one run), and the
/// runs not begun are left as they were, for the caller to refuse the frame.
pub(crate) fn transform_vertices(
    instances: &[Instance<'_>],
    projection: &Projection,
    bits: u32,
    vertices: &mut Vec<ViewVertex>,
    outside: &mut Vec<u8>,
    normals: &mut Vec<Vec3>,
    cancel: Option<&AtomicBool>,
) {
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let vertex_count = instances
        .last()
        .map_or(0, |i| i.vertex_base + i.model.mesh.positions.len());
    let normal_count = instances
        .last()
        .map_or(0, |i| i.normal_base + i.model.mesh.normals.len());
    vertices.resize(vertex_count, ViewVertex::default());
    outside.resize(vertex_count, 0);
    normals.resize(normal_count, Vec3::ZERO);
    // Split the arrays into each instance's part, then work on runs of every part in parallel.
    let mut jobs = Vec::with_capacity(instances.len());
    let (mut rest_v, mut rest_o, mut rest_n) = (
        vertices.as_mut_slice(),
        outside.as_mut_slice(),
        normals.as_mut_slice(),
    );
    for instance in instances {
        let count = instance.model.mesh.positions.len();
        let (v, tail_v) = rest_v.split_at_mut(count);
        let (o, tail_o) = rest_o.split_at_mut(count);
        let (n, tail_n) = rest_n.split_at_mut(instance.model.mesh.normals.len());
        jobs.push((instance, v, o, n));
        rest_v = tail_v;
        rest_o = tail_o;
        rest_n = tail_n;
    }
    jobs.into_par_iter().for_each(|(instance, v, o, n)| {
        let mesh = &instance.model.mesh;
        let planes = &instance.planes.0[..instance.planes.1];
        v.par_chunks_mut(RUN)
            .zip(o.par_chunks_mut(RUN))
            .zip(mesh.positions.par_chunks(RUN))
            .for_each(|((out, codes), positions)| {
                if cancelled() {
                    return;
                }
                for ((o, code), &p) in out.iter_mut().zip(codes).zip(positions) {
                    let view = instance.to_view.transform_point3(p);
                    let in_front = view.z > 0.0;
                    *o = ViewVertex {
                        view,
                        screen: if in_front {
                            to_screen(projection, view, bits)
                        } else {
                            FixedPoint::default()
                        },
                        inv_z: if in_front { 1.0 / view.z } else { 0.0 },
                    };
                    *code = planes.iter().enumerate().fold(0, |code, (bit, plane)| {
                        code | u8::from(plane.signed_distance(view) < 0.0) << bit
                    });
                }
            });
        n.par_chunks_mut(RUN)
            .zip(mesh.normals.par_chunks(RUN))
            .for_each(|(out, normals)| {
                if cancelled() {
                    return;
                }
                for (o, &m) in out.iter_mut().zip(normals) {
                    *o = instance.transform.normal(m);
                }
            });
    });
}
