//! The world's acceleration index: a BVH over every bounded object, plus the unbounded ones
//! (planes, infinite cylinders and cones) that are tested on every ray.

use super::ball::Ball;
use super::cuboid::Cuboid;
use super::intersection::{sort_intersections, Intersection};
use super::level::{Level, Probe};
use super::object::Object;
use super::shape::Shape;
use super::world::World;
use crate::accel::Bvh;
use crate::geometry::LocalHit;
use crate::math::{Aabb, Point3, Ray, Vec3};
use std::ops::ControlFlow;
use std::sync::atomic::AtomicBool;

/// Worlds of at most this many bounded objects skip the hierarchy (see `WorldIndex::few`).
const FEW_OBJECTS: usize = 8;

/// What [`WorldIndex::blocked`] starts from when no object is remembered.
pub const NO_OBJECT: u32 = u32::MAX;

/// Spatial index over a [`World`]'s objects. Build it once per render; it borrows nothing, so
/// it stays valid only while the world's object list is unchanged.
#[derive(Debug, Clone, Default)]
pub struct WorldIndex {
    bvh: Bvh,
    /// Objects whose bounds are infinite (never in the BVH).
    unbounded: Vec<u32>,
    /// For a world of at most [`FEW_OBJECTS`] bounded objects, those objects, tried in turn
    /// instead of walking the BVH: setting a walk up (the ray in the hierarchy's single
    /// precision, the dispatch to the vector unit) costs more per ray than testing a few
    /// objects, and most scenes of a book hold one to four solids.
    few: Option<FewObjects>,
    /// How each object's world normal is found, by object: see [`normal_at_hit`](Self::normal_at_hit).
    normals: Vec<SurfaceNormal>,
}

/// How the world normal at a hit on an object is found. Through the object's transform, its
/// shape's normal is a point taken into object space, the shape's normal there and the
/// normal matrix; a path tracer asks it at every vertex, and for the commonest surfaces of a
/// scene far less will do.
#[derive(Debug, Clone, Copy, Default)]
enum SurfaceNormal {
    /// Through the object's transform (any object).
    #[default]
    Transformed,
    /// The same everywhere: a plane, rectangle or ring that stands still (the very normal
    /// its transform gives, taken once).
    Flat(Vec3),
    /// A round ball: from its centre (see [`Ball::normal_at`]).
    Round(Ball),
    /// A still box: the face the point lies on (see [`Cuboid::normal_at`]). Its hits are
    /// found outright too, when a search visits it.
    Boxy(Cuboid),
}

impl SurfaceNormal {
    /// The rule for `object`.
    fn of(object: &Object) -> Self {
        let flat = matches!(
            object.shape,
            Shape::Plane | Shape::Rectangle | Shape::Ring { .. }
        );
        if object.motion.is_some() {
            Self::Transformed
        } else if flat {
            Self::Flat(object.normal_to_world(Vec3::Y))
        } else if let Some(ball) = Ball::of(object) {
            Self::Round(ball)
        } else if let Some(cuboid) = Cuboid::of(object).filter(|_| !object.has_alpha()) {
            Self::Boxy(cuboid)
        } else {
            Self::Transformed
        }
    }
}

/// The objects of a world of few: level rectangles and round balls, which a nearest-hit
/// search tests outright in world space (see [`Level`] and [`Ball`]), and the others, each
/// behind its box (widened by a billionth, for rounding).
#[derive(Debug, Clone, Default)]
struct FewObjects {
    levels: Vec<(u32, Level)>,
    /// Each with its box, for the searches whose visitor decides.
    balls: Vec<(u32, Ball, Aabb)>,
    boxed: Vec<(u32, Aabb)>,
}

impl FewObjects {
    /// Whether any object is tested outright.
    fn outright(&self) -> bool {
        !self.levels.is_empty() || !self.balls.is_empty()
    }
}

/// The intersection of `ray` with `object` at `t`, found outright in world space.
#[inline]
fn outright_hit<'w>(object: &'w Object, ray: &Ray, t: f64) -> Intersection<'w> {
    let hit = LocalHit {
        time: ray.time,
        ..LocalHit::at(t)
    };
    Intersection::from_local(object, hit)
}

/// Visits, in turn, each object of `boxes` whose box `ray` (`probe`) meets within
/// `[t_min, t_max]`, `t_max` lowered as the visitor finds hits; `Break` once it stops.
#[inline]
fn visit_boxes<'a>(
    boxes: impl Iterator<Item = (u32, &'a Aabb)>,
    ray: &Ray,
    probe: &Probe,
    t_min: f64,
    t_max: &mut f64,
    visit: &mut impl FnMut(usize, &mut f64) -> ControlFlow<()>,
) -> ControlFlow<()> {
    let inv_direction = probe.inv_direction();
    for (i, b) in boxes {
        if b.hit_by(ray.origin, inv_direction, t_min, *t_max).is_some() {
            visit(i as usize, t_max)?;
        }
    }
    ControlFlow::Continue(())
}

impl WorldIndex {
    /// Indexes the objects of `world`.
    pub fn build(world: &World) -> Self {
        Self::build_until(world, None).expect("a build without a stop flag is never stopped")
    }

    /// [`WorldIndex::build`] that gives up, `None`, once `stop` is set (Ctrl-C, a server's
    /// cancel): its BVH is looked at as each node is begun ([`Bvh::build_until`]), so a world
    /// of a million objects stops within one node's split. Not stopped, the very index
    /// [`WorldIndex::build`] makes.
    pub fn build_until(world: &World, stop: Option<&AtomicBool>) -> Option<Self> {
        let mut boxes: Vec<Aabb> = world.objects.iter().map(|o| o.bounds()).collect();
        let mut unbounded = Vec::new();
        for (i, b) in boxes.iter_mut().enumerate() {
            let finite = b.min.is_finite() && b.max.is_finite();
            if !finite && !b.is_empty() {
                unbounded.push(i as u32);
                *b = Aabb::EMPTY;
            }
        }
        let bounded: Vec<(u32, &Aabb)> = (0u32..)
            .zip(&boxes)
            .filter(|(_, b)| !b.is_empty())
            .collect();
        let few = (bounded.len() <= FEW_OBJECTS).then(|| {
            let mut few = FewObjects::default();
            for (i, b) in bounded {
                let object = &world.objects[i as usize];
                let pad = (b.max - b.min + b.min.abs() + b.max.abs()) * 1e-9;
                let widened = Aabb::new(b.min - pad, b.max + pad);
                // A cut-out surface (alpha) is found through its own test, which knows its
                // holes.
                if object.has_alpha() {
                    few.boxed.push((i, widened));
                } else if let Some(level) = Level::of(object) {
                    few.levels.push((i, level));
                } else if let Some(ball) = Ball::of(object) {
                    few.balls.push((i, ball, widened));
                } else {
                    few.boxed.push((i, widened));
                }
            }
            few
        });
        Some(Self {
            bvh: Bvh::build_until(&boxes, stop)?,
            unbounded,
            few,
            normals: world.objects.iter().map(SurfaceNormal::of).collect(),
        })
    }

    /// The unit world normal at `point`, where `hit` (on one of the world's objects) is: the
    /// object's [`normal_at_hit`](Object::normal_at_hit), found with less work on a still
    /// flat surface or a round ball.
    #[inline]
    pub fn normal_at_hit(&self, world: &World, point: Point3, hit: &Intersection<'_>) -> Vec3 {
        let size = std::mem::size_of::<Object>().max(1);
        let index = (hit.object as *const Object as usize)
            .wrapping_sub(world.objects.as_ptr() as usize)
            / size;
        let indexed = world
            .objects
            .get(index)
            .is_some_and(|o| std::ptr::eq(o, hit.object));
        match self.normals.get(index) {
            Some(SurfaceNormal::Flat(normal)) if indexed => *normal,
            Some(SurfaceNormal::Round(ball)) if indexed => ball.normal_at(point),
            Some(SurfaceNormal::Boxy(cuboid)) if indexed => cuboid.normal_at(point),
            _ => hit.object.normal_at_hit(point, hit),
        }
    }

    /// Calls `visit` with every object that the ray might meet within `[t_min, t_max]`; the
    /// visitor may lower `t_max` as it finds hits and stop early with `Break`.
    #[inline]
    pub fn candidates(
        &self,
        ray: &Ray,
        t_min: f64,
        mut t_max: f64,
        mut visit: impl FnMut(usize, &mut f64) -> ControlFlow<()>,
    ) {
        if let Some(few) = &self.few {
            let probe = Probe::new(ray.origin, ray.direction);
            for (i, level) in &few.levels {
                if level.may_meet(&probe, t_min, t_max) && visit(*i as usize, &mut t_max).is_break()
                {
                    return;
                }
            }
            let balls = few.balls.iter().map(|(i, _, b)| (*i, b));
            if visit_boxes(balls, ray, &probe, t_min, &mut t_max, &mut visit).is_break() {
                return;
            }
            self.unbounded_and_boxed(few, ray, &probe, t_min, t_max, visit);
            return;
        }
        for &i in &self.unbounded {
            if visit(i as usize, &mut t_max).is_break() {
                return;
            }
        }
        self.bvh
            .traverse(ray.origin, ray.direction, t_min, t_max, |i, t| {
                visit(i as usize, t)
            });
    }

    /// [`WorldIndex::candidates`] for a world of few objects, less those tested outright.
    #[inline]
    fn unbounded_and_boxed(
        &self,
        few: &FewObjects,
        ray: &Ray,
        probe: &Probe,
        t_min: f64,
        mut t_max: f64,
        mut visit: impl FnMut(usize, &mut f64) -> ControlFlow<()>,
    ) {
        for &i in &self.unbounded {
            if visit(i as usize, &mut t_max).is_break() {
                return;
            }
        }
        let boxed = few.boxed.iter().map(|(i, b)| (*i, b));
        let _ = visit_boxes(boxed, ray, probe, t_min, &mut t_max, &mut visit);
    }

    /// The nearest intersection with `t >= ray.t_min` (the book's `hit` of `intersect_world`,
    /// which takes `t >= 0`).
    pub fn closest_hit<'w>(&self, world: &'w World, ray: &Ray) -> Option<Intersection<'w>> {
        let mut best: Option<Intersection<'w>> = None;
        if let Some(few) = self.few.as_ref().filter(|f| f.outright()) {
            // Level rectangles and round balls are hit in world space: nothing is left for a
            // visit.
            let probe = Probe::new(ray.origin, ray.direction);
            let mut t_max = f64::INFINITY;
            for (i, level) in &few.levels {
                if let Some(t) = level.hit(&probe, ray.t_min, t_max) {
                    t_max = t;
                    best = Some(outright_hit(&world.objects[*i as usize], ray, t));
                }
            }
            for (i, ball, _) in &few.balls {
                if let Some(t) = ball.hit(&probe, ray.t_min, t_max) {
                    t_max = t;
                    best = Some(outright_hit(&world.objects[*i as usize], ray, t));
                }
            }
            // The others as always, nearer than any hit found outright.
            self.unbounded_and_boxed(few, ray, &probe, ray.t_min, t_max, |i, t_max| {
                if let Some(h) = self.nearest_on(world, i, ray, Some(&probe), *t_max) {
                    *t_max = h.t;
                    best = Some(h);
                }
                ControlFlow::Continue(())
            });
            return best;
        }
        self.candidates(ray, ray.t_min, f64::INFINITY, |i, t_max| {
            if let Some(h) = self.nearest_on(world, i, ray, None, *t_max) {
                *t_max = h.t;
                best = Some(h);
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// The nearest hit of `ray` on object `i` with `ray.t_min <= t < t_max`: a still box's
    /// found in world space or its own frame ([`Cuboid`], without the object's transform),
    /// any other object's by its own test. `probe` is the ray as a box reads it, where the
    /// search has made one (else it is made here, for a box only: a hierarchy's walk has its
    /// own, and most of its objects are not boxes).
    #[inline]
    fn nearest_on<'w>(
        &self,
        world: &'w World,
        i: usize,
        ray: &Ray,
        probe: Option<&Probe>,
        t_max: f64,
    ) -> Option<Intersection<'w>> {
        let object = &world.objects[i];
        if let Some(SurfaceNormal::Boxy(cuboid)) = self.normals.get(i) {
            let t = match probe {
                Some(probe) => cuboid.hit(probe, ray.t_min, t_max)?,
                None => cuboid.hit(&Probe::new(ray.origin, ray.direction), ray.t_min, t_max)?,
            };
            return Some(outright_hit(object, ray, t));
        }
        let local = object.ray_to_object(ray);
        let h = object.closest_local_hit(&local, ray.t_min, t_max)?;
        Some(Intersection::from_local(object, h))
    }

    /// Every intersection with `t <= t_max` (negative ones included), sorted: what refraction
    /// needs to know which objects contain the hit.
    pub fn intersections_up_to<'w>(
        &self,
        world: &'w World,
        ray: &Ray,
        t_max: f64,
        out: &mut Vec<Intersection<'w>>,
    ) {
        out.clear();
        // What `closest_hit` tests outright as it finds it: the hit it returned must be in the
        // list at the very same distance, for refraction to tell which it is.
        let outright = self.few.as_ref().filter(|f| f.outright());
        let probe = Probe::new(ray.origin, ray.direction);
        if let Some(few) = outright {
            for (i, level) in &few.levels {
                if let Some(t) = level.crossing_at(&probe).filter(|&t| t <= t_max) {
                    out.push(outright_hit(&world.objects[*i as usize], ray, t));
                }
            }
            for (i, ball, _) in &few.balls {
                if let Some((t0, t1)) = ball.crossings(&probe) {
                    let object = &world.objects[*i as usize];
                    out.extend(
                        [t0, t1]
                            .into_iter()
                            .filter(|&t| t <= t_max)
                            .map(|t| outright_hit(object, ray, t)),
                    );
                }
            }
        }
        let add = |i: usize, _: &mut f64| {
            let object = &world.objects[i];
            // A still box gives the very distances `closest_hit` gives it.
            if let Some(SurfaceNormal::Boxy(cuboid)) = self.normals.get(i) {
                if let Some((t0, t1)) = cuboid.crossings(&probe) {
                    out.extend(
                        [t0, t1]
                            .into_iter()
                            .filter(|&t| t <= t_max)
                            .map(|t| outright_hit(object, ray, t)),
                    );
                }
                return ControlFlow::Continue(());
            }
            let local = object.ray_to_object(ray);
            object.shape.hits_up_to(&local, t_max, |h| {
                out.push(Intersection::from_local(object, h))
            });
            ControlFlow::Continue(())
        };
        match outright {
            Some(few) => self.unbounded_and_boxed(few, ray, &probe, f64::NEG_INFINITY, t_max, add),
            None => self.candidates(ray, f64::NEG_INFINITY, t_max, add),
        }
        sort_intersections(out);
    }

    /// Whether an object that `casts` a shadow has a surface along `ray` at some `t` in
    /// `[t_min, t_max)`: [`WorldIndex::blocked`] for a lighting model whose rule for what
    /// blocks light is the surface itself, met at all (the path tracer's), so that the index
    /// can test level rectangles and round balls outright, as `closest_hit` does.
    pub fn shadowed<'w>(
        &self,
        world: &'w World,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        last: &mut u32,
        casts: impl Fn(&'w Object) -> bool,
    ) -> bool {
        let surface = |object: &'w Object| {
            casts(object) && object.any_local_hit(&object.ray_to_object(ray), t_min, t_max)
        };

        let Some(few) = self.few.as_ref().filter(|f| f.outright()) else {
            return self.blocked(world, ray, t_min, t_max, last, surface);
        };
        // A still box met outright, as `closest_hit` meets it.
        let boxed_surface = |i: usize, probe: &Probe| {
            let object = &world.objects[i];
            match self.normals.get(i) {
                Some(SurfaceNormal::Boxy(cuboid)) => {
                    casts(object) && cuboid.hit(probe, t_min, t_max).is_some()
                }
                _ => surface(object),
            }
        };
        // A world of few objects tries them all in turn: no blocker is remembered.
        *last = NO_OBJECT;
        let probe = Probe::new(ray.origin, ray.direction);
        let crossed = |i: u32, hit: Option<f64>| hit.is_some() && casts(&world.objects[i as usize]);
        if (few.levels.iter()).any(|&(i, level)| crossed(i, level.hit(&probe, t_min, t_max)))
            || (few.balls.iter()).any(|&(i, ball, _)| crossed(i, ball.hit(&probe, t_min, t_max)))
        {
            return true;
        }
        let mut blocked = false;
        self.unbounded_and_boxed(few, ray, &probe, t_min, t_max, |i, _| {
            blocked = boxed_surface(i, &probe);
            if blocked {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        blocked
    }

    /// Whether any object for which `blocks` holds lies along `ray` (the shadow test of every
    /// lighting model, each with its own rule in `blocks`), visiting the objects that might
    /// meet the ray within `[t_min, t_max]`; stops at the first blocker.
    ///
    /// Tries first the object in `last` (the blocker of an earlier shadow ray towards the same
    /// light, or [`NO_OBJECT`]) and leaves there the blocker it finds (or [`NO_OBJECT`] once
    /// the remembered one fails). Neighbouring points are usually shadowed by the same object,
    /// and one object's test costs far less than a walk of the hierarchy; the answer is the
    /// same either way.
    pub fn blocked<'w>(
        &self,
        world: &'w World,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        last: &mut u32,
        mut blocks: impl FnMut(&'w Object) -> bool,
    ) -> bool {
        let remembered = *last as usize;
        if remembered < world.objects.len() {
            if blocks(&world.objects[remembered]) {
                return true;
            }
            // Out of its shadow: lit points need not try it again until something blocks.
            *last = NO_OBJECT;
        }
        let mut blocked = false;
        self.candidates(ray, t_min, t_max, |i, _| {
            if i != remembered && blocks(&world.objects[i]) {
                blocked = true;
                *last = i as u32;
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        });
        blocked
    }
}
