//! What every integrator works with while it traces: the world and its index, scratch
//! buffers, the count of rays cast, the per-pixel jitter generator, the bailout and the weight
//! of the ray being traced, and the shadow hints; and the one shadow-ray loop they all use.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::math::random::SplitMix64;
use crate::math::Ray;
use crate::scene::{Intersection, Object, World, WorldIndex, NO_OBJECT};
use crate::shading::Light;

/// Lights whose last blocker a tracing state remembers at once.
const SHADOW_HINTS: usize = 4;

/// The default of [`TraceState::set_ray_budget`]: rays one camera ray may lead to (its
/// reflections, refractions and shadow rays, all of them). The book's cover casts about 20;
/// a glass scene five bounces deep under 16 area lights of 4096 samples each about 4 million.
/// A ray tree that doubles at every bounce reaches it at 22 bounces, in a few seconds.
pub const DEFAULT_MAX_RAYS_PER_SAMPLE: u64 = 1 << 22;

/// Why a tracing state stopped casting rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stopped {
    /// A camera ray led to more rays than the budget allows.
    OverBudget,
    /// A stop flag was set (the user's interrupt, or another thread's failure).
    Cancelled,
}

/// One thread's tracing state over one world (see the [module](self)). Tracing a ray with it
/// allocates nothing once its buffers have grown to the scene's needs.
#[derive(Debug)]
pub struct TraceState<'w> {
    /// The world traced.
    pub(super) world: &'w World,
    /// Its index, built from it.
    pub(super) index: &'w WorldIndex,
    /// Intersections along a ray (refraction's containers are read from them).
    pub(super) xs: Vec<Intersection<'w>>,
    /// The objects a ray is inside, with their refractive indices.
    pub(super) containers: Vec<(&'w Object, f64)>,
    /// Every ray cast so far: camera, secondary and shadow rays.
    pub(super) rays: u64,
    /// Sample offsets for jittered area lights, reseeded per pixel by the render loop.
    pub(super) jitter: SplitMix64,
    /// Secondary rays and shadow rays that would bring less than this fraction of their light
    /// to the pixel are not traced (see [`TraceState::set_bailout`]).
    pub(super) bailout: f64,
    /// How much of the ray being traced reaches the pixel: the product of the reflectivities
    /// and transparencies on its way from the camera.
    pub(super) weight: f64,
    /// The last object that blocked a shadow ray towards each of a few lights (keyed by the
    /// light's address), tried first by the next (see [`WorldIndex::blocked`]).
    shadow_hints: [(usize, u32); SHADOW_HINTS],
    /// Rays one camera ray may lead to ([`TraceState::set_ray_budget`]).
    budget: u64,
    /// The ray count past which the current sample is over its budget.
    limit: u64,
    /// The ray count from which on every ray goes to [`TraceState::check`]: the first ray
    /// past the budget, or 0 once the state has stopped.
    next_check: u64,
    /// Flags that stop the tracing when set, looked at before every ray (a load of a flag no
    /// thread writes while the render runs, which stays in each core's cache: next to nothing
    /// beside the intersections of a ray).
    /// A stop is so seen within one ray's time, however long a ray takes; looked at every
    /// 4,096 rays, as before, a scene whose every ray meets thousands of huge overlapping
    /// objects stopped 3.5 to 45 s after Ctrl-C.
    stop_flags: [Option<&'w AtomicBool>; 2],
    /// Set once the state has stopped: every later ray is refused.
    stopped: Option<Stopped>,
}

impl<'w> TraceState<'w> {
    /// A state for tracing `world`, which `index` must have been built from.
    pub fn new(world: &'w World, index: &'w WorldIndex) -> Self {
        Self {
            world,
            index,
            xs: Vec::with_capacity(16),
            containers: Vec::with_capacity(8),
            rays: 0,
            jitter: SplitMix64::new(0),
            bailout: 0.0,
            weight: 1.0,
            shadow_hints: [(0, NO_OBJECT); SHADOW_HINTS],
            budget: DEFAULT_MAX_RAYS_PER_SAMPLE,
            limit: DEFAULT_MAX_RAYS_PER_SAMPLE,
            next_check: DEFAULT_MAX_RAYS_PER_SAMPLE + 1,
            stop_flags: [None; 2],
            stopped: None,
        }
    }

    /// The most rays one camera ray may lead to, all its reflections, refractions and shadow
    /// rays counted. A ray tree can grow without bound in every lighting model (a mirror box
    /// under the cgfs model is a tree of 2^depth rays; area lights multiply every hit), so this,
    /// not the depth, is what bounds a pixel's work. Past it the sample stops casting rays
    /// and [`TraceState::stopped`] says so; the render fails rather than show a wrong pixel.
    pub fn set_ray_budget(&mut self, budget: u64) {
        self.budget = budget.max(1);
        self.begin_sample();
    }

    /// Flags that stop the tracing, even inside one pixel's work, when one of them is set: the
    /// user's interrupt, and the render's own flag that a thread sets when it fails.
    pub fn set_stop_flags(&mut self, flags: [Option<&'w AtomicBool>; 2]) {
        self.stop_flags = flags;
    }

    /// Starts a camera ray's budget: the rays cast from here on count against it.
    pub fn begin_sample(&mut self) {
        self.limit = self.rays.saturating_add(self.budget);
        self.next_check = match self.stopped {
            Some(_) => 0,
            None => self.limit.saturating_add(1),
        };
    }

    /// Lets a state stopped by its budget cast rays again (for the next sample of a record
    /// that shows every sample); one stopped by a flag stays stopped.
    pub fn resume(&mut self) {
        if self.stopped == Some(Stopped::OverBudget) {
            self.stopped = None;
            self.next_check = self.limit.saturating_add(1);
        }
    }

    /// Why the state has stopped casting rays, if it has.
    pub fn stopped(&self) -> Option<Stopped> {
        self.stopped
    }

    /// Counts a ray about to be cast; `false` when it must not be (the state has stopped),
    /// and the integrator then returns at once with no light for it.
    #[inline]
    pub(super) fn count_ray(&mut self) -> bool {
        self.rays += 1;
        (self.rays < self.next_check && !self.flagged()) || self.check()
    }

    /// Whether a stop flag is set.
    #[inline]
    fn flagged(&self) -> bool {
        self.stop_flags
            .iter()
            .flatten()
            .any(|flag| flag.load(Ordering::Relaxed))
    }

    /// Looks at the budget and the stop flags: whether tracing may go on. A ray refused is
    /// not counted as cast.
    #[cold]
    fn check(&mut self) -> bool {
        let stop = if self.stopped.is_some() {
            self.stopped
        } else if self.rays > self.limit {
            Some(Stopped::OverBudget)
        } else if self.flagged() {
            Some(Stopped::Cancelled)
        } else {
            None
        };
        if stop.is_some() {
            self.stopped = stop;
            self.next_check = 0;
            self.rays -= 1;
            return false;
        }
        true
    }

    /// The world traced.
    pub fn world(&self) -> &'w World {
        self.world
    }

    /// Adaptive depth control (POV-Ray's `adc_bailout`): under the Phong model, a reflected or
    /// refracted ray whose weight (the product of the reflectivities and transparencies that
    /// lead to it from the camera, with Schlick's share on surfaces that both reflect and
    /// refract) is below `bailout` is not traced, however much depth remains; nor is a shadow
    /// ray whose light, at the weight of the ray that hit, could add less than `bailout` (the
    /// light counts as blocked: see [`crate::shading::most_light`]). With `1/512`, what is left
    /// out is at most about a fifth of one step of an 8-bit channel per ray skipped, and a room
    /// of surfaces that all reflect a little no longer costs `max_depth` rays per pixel. `0`
    /// (the default) follows the book: every bounce up to the depth limit, every shadow ray.
    pub fn set_bailout(&mut self, bailout: f64) {
        self.bailout = if bailout.is_finite() {
            bailout.max(0.0)
        } else {
            0.0
        };
    }

    /// Restarts the sample sequence from `seed` (the render loop passes the pixel's index, so
    /// every pixel's samples are the same whichever thread renders it).
    pub fn reseed(&mut self, seed: u64) {
        self.jitter = SplitMix64::new(seed);
    }

    /// How many rays (camera, reflected, refracted and shadow) have been cast.
    pub fn rays_cast(&self) -> u64 {
        self.rays
    }

    /// Casts a shadow ray (counted): whether an object for which `blocks` holds lies along
    /// `ray` between `t_min` and `t_max` (what `blocks` tests exactly is each lighting model's
    /// own rule). Stops at the first blocker; with `light` given, tries first the object that
    /// last blocked a ray towards it.
    pub fn shadow_test(
        &mut self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        light: Option<&Light>,
        blocks: impl FnMut(&'w Object) -> bool,
    ) -> bool {
        if !self.count_ray() {
            // Stopped: the sample is thrown away, so the answer does not matter; blocked
            // casts nothing more.
            return true;
        }
        let mut none = NO_OBJECT;
        let last = match light {
            Some(light) => {
                // The light's address names it for as long as the world lives.
                let key = light as *const Light as usize;
                let slot = (key / std::mem::size_of::<Light>().max(1)) % SHADOW_HINTS;
                if self.shadow_hints[slot].0 != key {
                    self.shadow_hints[slot] = (key, NO_OBJECT);
                }
                &mut self.shadow_hints[slot].1
            }
            None => &mut none,
        };
        self.index
            .blocked(self.world, ray, t_min, t_max, last, blocks)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The finding: with the flags looked at every 4,096 rays, a scene whose rays each cost
    /// milliseconds ran on for seconds after a stop. Now the first ray after the flag is set
    /// is refused, and every one after it.
    #[test]
    fn a_stop_is_seen_at_the_next_ray() {
        let world = World::new();
        let index = WorldIndex::build(&world);
        let mut state = TraceState::new(&world, &index);
        let stop = AtomicBool::new(false);
        state.set_stop_flags([Some(&stop), None]);
        state.begin_sample();
        for _ in 0..10 {
            assert!(state.count_ray());
        }
        stop.store(true, Ordering::Relaxed);
        assert!(!state.count_ray());
        assert_eq!(state.stopped(), Some(Stopped::Cancelled));
        assert_eq!(state.rays_cast(), 10);
        // A stop by a flag stays, through a new sample and a resume.
        state.begin_sample();
        state.resume();
        assert!(!state.count_ray());
    }

    #[test]
    fn the_budget_still_stops_a_sample_and_a_resume_lifts_it() {
        let world = World::new();
        let index = WorldIndex::build(&world);
        let mut state = TraceState::new(&world, &index);
        state.set_ray_budget(3);
        assert!((0..3).all(|_| state.count_ray()));
        assert!(!state.count_ray());
        assert!(!state.count_ray());
        assert_eq!(state.stopped(), Some(Stopped::OverBudget));
        state.resume();
        state.begin_sample();
        assert!((0..3).all(|_| state.count_ray()));
        assert!(!state.count_ray());
        assert_eq!(state.rays_cast(), 6);
    }
}
