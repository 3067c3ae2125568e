//! Integrators: what colour a camera ray brings back, one lighting model each.
//!
//! - [`Whitted`]: The Ray Tracer Challenge's Phong model, shadows, reflection and refraction;
//! - [`Cgfs`]: Computer Graphics from Scratch's model, unlit ([`CgfsFlat`]) or lit ([`CgfsLit`]),
//!   bit for bit;
//! - [`Optics`]: Fundamentals of Ray Tracing's matte, gloss and Fresnel optics.
//!
//! They all work on a [`TraceState`]: the world and its index, the scratch buffers, the count of
//! rays cast, the per-pixel jitter generator, the shadow hints and the bailout weight, one per
//! thread, so that tracing a ray allocates nothing and takes no lock. They report what they do
//! to a [`TraceObserver`], which for normal renders is [`NoTrace`](super::NoTrace) and compiles
//! away.
//!
//! The render loop chooses the integrator once per render from the world's
//! [`LightingModel`] ([`dispatch`]) and runs a loop monomorphised for it: no dynamic call and no
//! match on the model per ray. Another integrator is one more file here and one more arm in
//! [`dispatch`].

mod cgfs;
mod optics;
mod state;
mod whitted;

pub use cgfs::{Cgfs, CgfsFlat, CgfsLit};
pub use optics::Optics;
pub use state::{Stopped, TraceState, DEFAULT_MAX_RAYS_PER_SAMPLE};
pub use whitted::Whitted;

use super::observer::TraceObserver;
use crate::color::Color;
use crate::math::Ray;
use crate::scene::LightingModel;

/// A way of finding the colour a camera ray brings back: a small value (a lighting model's
/// settings), copied to every thread, that works on the thread's [`TraceState`].
pub trait Integrator: Copy + Send + Sync {
    /// Whether the finished image is exposed by its brightest sample (every channel divided by
    /// it) and its pixels with no colour repaired from their neighbours: the optics model's
    /// automatic exposure.
    const AUTO_EXPOSURE: bool = false;

    /// The colour seen along the camera ray `ray`, following secondary rays at most
    /// `max_depth` deep, telling `observer` what happens; `None` when the sample has no colour
    /// (the optics model's ambiguous hits), which the render loop leaves out of its pixel.
    fn radiance<O: TraceObserver>(
        &self,
        state: &mut TraceState<'_>,
        ray: &Ray,
        max_depth: u32,
        observer: &mut O,
    ) -> Option<Color>;
}

/// Work to do with an integrator, whichever it is: [`dispatch`] calls [`IntegratorJob::run`]
/// with the one the lighting model names, so the work is compiled once per integrator.
pub trait IntegratorJob {
    /// What the work returns.
    type Output;

    /// Does the work with `integrator`.
    fn run<I: Integrator>(self, integrator: I) -> Self::Output;
}

/// Runs `job` with the integrator of lighting model `model`: the one place that maps lighting
/// models to integrators.
pub fn dispatch<J: IntegratorJob>(model: LightingModel, job: J) -> J::Output {
    match model {
        LightingModel::Phong => job.run(Whitted),
        LightingModel::Flat => job.run(Cgfs::<false>),
        LightingModel::Cgfs => job.run(Cgfs::<true>),
        LightingModel::Optics => job.run(Optics),
    }
}
