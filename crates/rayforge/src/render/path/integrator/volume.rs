//! The volumetric path loop (pbrt-v4's `VolPathIntegrator`), which the path tracer runs for
//! a world with media ([`World::has_media`]); a world without keeps the surface loop of the
//! parent module, bit for bit.
//!
//! Along each ray through a medium, null-collision (delta) tracking against the medium's
//! majorants ([`sample_majorant`]) chooses where the path is absorbed, scatters or goes on;
//! at a scattering point the phase function is sampled, and light is sampled as at a
//! surface. Shadow rays cross index-matched boundaries and collect each medium's
//! transmittance on the way (Beer–Lambert in a homogeneous medium, ratio tracking in a grid:
//! [`transmittance`]); any other surface blocks them. A medium's colour is tracked without
//! bias by a hero channel chosen uniformly per path and the densities of the other channels
//! carried as ratios (`r_u` for the unidirectional strategy, `r_l` for light sampling), and
//! light found both ways is weighed by the balance heuristic over strategies and channels at
//! once, as in pbrt-v4. Russian roulette follows the surface loop's rule and switch.
//!
//! In a homogeneous medium each ray segment also draws one point by equiangular sampling
//! towards the lamps ([`Equiangular`]) and lights it by next-event estimation: a third
//! strategy for light scattered once more, which the balance heuristic weighs against the
//! other two by its density ratio `r_e` (the point's equiangular density over the hero
//! channel's density of the strategy that made it), added to light sampling's ratios, since
//! both end in a sampled light point.
//!
//! Random numbers: each vertex keeps the surface loop's layout of its dimensions (the
//! direction, the light's point, the layer, the light, the roulette's coin, and one for the
//! first distance drawn in a medium); the rest of the tracking (further distances, the
//! choice of event at each collision, the hero channel, the shadow rays' ratio tracking,
//! the equiangular points and their lights)
//! comes from a generator seeded by the camera's spare dimension, so a sample is still a
//! pure function of the pixel, its index and the seed.
//!
//! The surface loop's glass split, mirror-ball sampling and learned continuations are not
//! run here: they rest on paths through vacuum.

use super::{
    object_index, unit, FirstHit, PathContext, PathLog, SurfaceVertex, CAMERA_DIMENSIONS,
    VERTEX_DIMENSIONS,
};
use crate::color::Color;
use crate::math::random::{Jitter, SplitMix64};
use crate::math::{Point3, Ray, Vec3};
use crate::media::tracking::{clamp_zero, sample_majorant, transmittance, Transmitted};
use crate::media::{average, beer, channel, Equiangular, Homogeneous, Medium, MediumId};
use crate::render::path::sampler::SampleStream;
use crate::scene::surface_offset;

/// σs·e^(−σt·t) per channel in the homogeneous medium `m`: what a point at `t` along a ray
/// scatters of the light that left the ray's start, and the density (per unit length) with
/// which delta tracking in each channel scatters there.
#[inline]
fn scattered_at(m: &Homogeneous, t: f64) -> Color {
    m.sigma_s.hadamard(beer(m.sigma_t(), t))
}

/// How many boundaries one ray (a path's leg or a shadow ray) may cross without meeting
/// anything else before it is given up: only a degenerate scene (a ray caught between two
/// coincident index-matched surfaces) reaches it.
pub const MAX_CROSSINGS: u32 = 1024;

/// Where the camera's spare dimension is, whose number seeds the path's generator.
const SEED_DIMENSION: u32 = CAMERA_DIMENSIONS - 1;

/// What a path through media carries (pbrt-v4's `beta`, `r_u`, `r_l`).
struct Carried {
    beta: Color,
    r_u: Color,
    r_l: Color,
    radiance: Color,
}

impl Carried {
    /// Whether the path still carries anything.
    fn alive(&self) -> bool {
        self.beta.max_channel() > 0.0 && self.r_u.max_channel() > 0.0
    }
}

/// Where a path last scattered: what the density of the light's sampling is asked from.
#[derive(Clone, Copy)]
struct Previous {
    point: Point3,
    normal: Option<Vec3>,
}

/// What delta tracking found along a ray.
enum Event {
    /// Nothing: the ray reached its end.
    Passed,
    /// Absorbed (or out of bounces, or carrying nothing).
    Ended,
    /// A scattering at `t`.
    Scattered(f64),
}

impl<'w> PathContext<'w> {
    /// The radiance arriving along the camera ray `ray` through the world's media, and what
    /// its first hit looks like.
    pub(super) fn radiance_in_media(
        &mut self,
        ray: Ray,
        stream: &mut SampleStream,
        log: &mut impl PathLog,
    ) -> (Color, FirstHit) {
        let world = self.world;
        let mut first = FirstHit::default();
        stream.seek(SEED_DIMENSION);
        let mut rng = SplitMix64::new(stream.next_1d().to_bits() ^ 0x6d65_6469_6121_u64);
        let hero = (rng.next_offset() * 3.0) as usize;
        let mut ray = Ray {
            direction: unit(ray.direction),
            ..ray
        };
        let mut medium = world.camera_medium;
        let mut path = Carried {
            beta: Color::WHITE,
            r_u: Color::WHITE,
            r_l: Color::WHITE,
            radiance: Color::BLACK,
        };
        let mut specular = true;
        let mut depth = 0u32;
        let mut previous = Previous {
            point: ray.origin,
            normal: None,
        };
        let mut crossings = 0u32;
        loop {
            self.rays += 1;
            let hit = self.index.closest_hit(world, &ray);
            let t_hit = hit.as_ref().map_or(f64::INFINITY, |h| h.t);
            if let Some(id) = medium {
                // What the path carried into this segment: the equiangular strategy starts
                // from it.
                let (beta_in, r_in) = (path.beta, path.r_u);
                let equiangular = self.equiangular_along(world.media.get(id), &ray, t_hit, depth);
                if let Some((m, draw)) = &equiangular {
                    path.radiance += self.equiangular_light(
                        m,
                        &ray,
                        draw,
                        (beta_in, r_in),
                        medium,
                        &mut rng,
                        hero,
                    );
                }
                let stop = CAMERA_DIMENSIONS + depth * VERTEX_DIMENSIONS + 7;
                stream.seek(stop);
                let u = stream.next_1d();
                let event = self.track(
                    world.media.get(id),
                    &ray,
                    t_hit,
                    u,
                    &mut rng,
                    hero,
                    &mut path,
                    depth,
                );
                match event {
                    Event::Ended => break,
                    Event::Scattered(t) => {
                        depth += 1;
                        crossings = 0;
                        let point = ray.position(t);
                        let phase = world.media.get(id).phase();
                        let numbers = CAMERA_DIMENSIONS + depth * VERTEX_DIMENSIONS;
                        // The equiangular strategy's density of this point, as a ratio to
                        // the hero channel's density of distance sampling it (what the path's
                        // `r_u` holds for the other channels).
                        let r_e = equiangular.as_ref().map_or(Color::BLACK, |(m, draw)| {
                            let p_hero = channel(scattered_at(m, t), hero);
                            if p_hero > 0.0 {
                                r_in * (draw.pdf(t) / p_hero)
                            } else {
                                Color::BLACK
                            }
                        });
                        // Without MIS the equiangular point alone samples the lights here.
                        let lights_here = equiangular.is_none() || self.techniques.mis;
                        if self.techniques.next_event && lights_here {
                            stream.seek(numbers + 5);
                            let u_pick = stream.next_1d();
                            stream.seek(numbers + 2);
                            let u_point = stream.next_2d();
                            let travel = ray.direction;
                            let light = self.light_through_media(
                                point,
                                None,
                                medium,
                                ray.time,
                                (u_pick, u_point),
                                (path.r_u, r_e),
                                &mut rng,
                                hero,
                                |wi| {
                                    let p = phase.eval(travel, wi);
                                    (Color::new(p, p, p), p)
                                },
                            );
                            path.radiance += light.hadamard(path.beta);
                        }
                        stream.seek(numbers);
                        let sample = phase.sample(ray.direction, stream.next_2d());
                        // The sampling is exact: the weight p / pdf is 1. A light it meets
                        // could also have been sampled from an equiangular point here.
                        path.r_l = (path.r_u + r_e) * (1.0 / sample.pdf);
                        previous = Previous {
                            point,
                            normal: None,
                        };
                        specular = false;
                        ray = Ray {
                            origin: point,
                            direction: sample.wi,
                            time: ray.time,
                            t_min: 0.0,
                        };
                        if !self.roulette_in_media(&mut path, depth, numbers, stream, log) {
                            break;
                        }
                        continue;
                    }
                    Event::Passed => {}
                }
            }
            let Some(hit) = hit else {
                let (sky, pdf) = self.emitters.sky_radiance_and_pdf(ray.direction);
                path.radiance += self.found_light(&path, sky, pdf, specular);
                if depth == 0 {
                    first.albedo = sky;
                    first.depth = f64::INFINITY;
                }
                break;
            };
            self.vertices += 1;
            let vertex = self.surface_vertex(hit, &ray);
            let interface = vertex.hit.object.media;
            if interface.is_some_and(|i| i.index_matched) {
                // A boundary between media only: the ray goes on, unbent, in the other.
                crossings += 1;
                if crossings > MAX_CROSSINGS {
                    break;
                }
                medium = interface.and_then(|i| i.towards(vertex.geometric, ray.direction));
                ray = vertex.leaving(ray.direction);
                continue;
            }
            crossings = 0;
            if depth == 0 && specular {
                first.depth = vertex.hit.t;
            }
            let shading = vertex.shading_normal();
            if let Some(emission) =
                self.emitters
                    .object_radiance(vertex.surface, &vertex.at, vertex.cos_out())
            {
                let pdf = if specular {
                    0.0
                } else {
                    self.emitters.object_pdf(
                        world,
                        object_index(world, vertex.hit.object),
                        previous.point,
                        previous.normal,
                        vertex.point,
                        ray.direction,
                        &vertex.local,
                    )
                };
                path.radiance += self.found_light(&path, emission, pdf, specular);
            }
            if depth >= self.max_depth {
                break;
            }
            if !vertex.surface.material.two_sided && vertex.cos_out() < 0.0 {
                break;
            }
            let scattering = vertex.scattering(world);
            if depth == 0 && self.first_hit_shading {
                first.albedo = scattering.albedo();
                first.normal = if shading.dot(vertex.wo) < 0.0 {
                    -shading
                } else {
                    shading
                };
            }
            let numbers = CAMERA_DIMENSIONS + depth * VERTEX_DIMENSIONS;
            let u_lobe = if scattering.chooses() {
                stream.seek(numbers + 4);
                stream.next_1d()
            } else {
                0.0
            };
            let (layer, u_lobe) = scattering.pick(u_lobe);
            let frame = vertex.frame(shading, &layer.bsdf);
            let wo_local = frame.to_local(vertex.wo);
            let side = |direction: Vec3| match interface {
                Some(i) => i.towards(vertex.geometric, direction),
                None => medium,
            };
            if !layer.bsdf.is_delta() && self.techniques.next_event {
                stream.seek(numbers + 5);
                let u_pick = stream.next_1d();
                stream.seek(numbers + 2);
                let u_point = stream.next_2d();
                let bsdf = &layer.bsdf;
                let light = self.light_through_media_from_surface(
                    &vertex,
                    frame.n,
                    &side,
                    (u_pick, u_point),
                    (path.r_u, Color::BLACK),
                    &mut rng,
                    hero,
                    |wi| {
                        let wi_local = frame.to_local(wi);
                        (
                            bsdf.eval(wo_local, wi_local) * layer.scale,
                            bsdf.pdf(wo_local, wi_local),
                        )
                    },
                );
                path.radiance += light.hadamard(path.beta);
            }
            stream.seek(numbers);
            let u_direction = stream.next_2d();
            let Some(sample) = layer.bsdf.sample(wo_local, u_lobe, u_direction) else {
                break;
            };
            path.beta = path.beta.hadamard(sample.weight) * layer.scale;
            specular = sample.delta;
            if !sample.delta {
                path.r_l = path.r_u * (1.0 / sample.pdf);
            }
            let direction = unit(frame.to_world(sample.wi));
            medium = side(direction);
            previous = Previous {
                point: vertex.point,
                normal: Some(frame.n),
            };
            ray = vertex.leaving(direction);
            depth += 1;
            if !self.roulette_in_media(&mut path, depth, numbers, stream, log) {
                break;
            }
            if !path.alive() {
                break;
            }
        }
        log.branch_ended(path.radiance);
        (path.radiance, first)
    }

    /// Delta tracking along `ray` through `medium` up to `t_max`: the medium's emission
    /// gathered at every collision, and the event that ends the walk; `path`'s throughput and
    /// ratios updated for what the walk passed through.
    #[allow(clippy::too_many_arguments)] // the ray, its medium and the path's state, each its own
    fn track(
        &self,
        medium: &Medium,
        ray: &Ray,
        t_max: f64,
        u: f64,
        rng: &mut SplitMix64,
        hero: usize,
        path: &mut Carried,
        depth: u32,
    ) -> Event {
        let mut event = Event::Passed;
        let emits = medium.emits() && depth < self.max_depth;
        let max_depth = self.max_depth;
        let t_maj = sample_majorant(
            medium,
            ray,
            t_max,
            u,
            rng,
            hero,
            |t, p, sigma_maj, t_maj, rng| {
                if !path.alive() {
                    event = Event::Ended;
                    return false;
                }
                let h = |c: Color| channel(c, hero);
                if emits && p.emission.max_channel() > 0.0 {
                    let pdf = h(sigma_maj) * h(t_maj);
                    let r_e = path.r_u.hadamard(sigma_maj).hadamard(t_maj) * (1.0 / pdf);
                    if average(r_e) > 0.0 {
                        let beta = path.beta.hadamard(t_maj) * (1.0 / pdf);
                        path.radiance +=
                            beta.hadamard(p.sigma_a).hadamard(p.emission) * (1.0 / average(r_e));
                    }
                }
                let p_absorb = h(p.sigma_a) / h(sigma_maj);
                let p_scatter = h(p.sigma_s) / h(sigma_maj);
                let u_mode = rng.next_offset();
                if u_mode < p_absorb {
                    event = Event::Ended;
                    false
                } else if u_mode < p_absorb + p_scatter {
                    if depth >= max_depth {
                        event = Event::Ended;
                        return false;
                    }
                    let pdf = h(t_maj) * h(p.sigma_s);
                    let ratio = t_maj.hadamard(p.sigma_s) * (1.0 / pdf);
                    path.beta = path.beta.hadamard(ratio);
                    path.r_u = path.r_u.hadamard(ratio);
                    event = if path.alive() {
                        Event::Scattered(t)
                    } else {
                        Event::Ended
                    };
                    false
                } else {
                    let sigma_n = clamp_zero(sigma_maj - p.sigma_a - p.sigma_s);
                    let pdf = h(t_maj) * h(sigma_n);
                    if pdf <= 0.0 {
                        path.beta = Color::BLACK;
                    } else {
                        path.beta = path.beta.hadamard(t_maj.hadamard(sigma_n)) * (1.0 / pdf);
                        path.r_u = path.r_u.hadamard(t_maj.hadamard(sigma_n)) * (1.0 / pdf);
                        path.r_l = path.r_l.hadamard(t_maj.hadamard(sigma_maj)) * (1.0 / pdf);
                    }
                    path.alive()
                }
            },
        );
        if let Event::Passed = event {
            let hero_t = channel(t_maj, hero);
            if hero_t <= 0.0 {
                return Event::Ended;
            }
            let ratio = t_maj * (1.0 / hero_t);
            path.beta = path.beta.hadamard(ratio);
            path.r_u = path.r_u.hadamard(ratio);
            path.r_l = path.r_l.hadamard(ratio);
            if !path.alive() {
                return Event::Ended;
            }
        }
        event
    }

    /// Light `emitted` that a path found by scattering (or the camera, or a delta bounce,
    /// where `specular`), which light sampling draws with density `pdf`, weighed against it.
    fn found_light(&self, path: &Carried, emitted: Color, pdf: f64, specular: bool) -> Color {
        if emitted.max_channel() <= 0.0 {
            return Color::BLACK;
        }
        let weight_of = |r: Color| {
            let mean = average(r);
            if mean > 0.0 {
                path.beta.hadamard(emitted) * (1.0 / mean)
            } else {
                Color::BLACK
            }
        };
        if specular || !self.techniques.next_event || pdf <= 0.0 {
            weight_of(path.r_u)
        } else if !self.techniques.mis {
            Color::BLACK
        } else {
            weight_of(path.r_u + path.r_l * pdf)
        }
    }

    /// Next-event estimation from a surface vertex: as [`light_through_media`], the shadow
    /// ray leaving from the surface on the light's side, in the medium on that side.
    ///
    /// [`light_through_media`]: Self::light_through_media
    #[allow(clippy::too_many_arguments)] // the vertex and its scattering, each its own
    fn light_through_media_from_surface(
        &mut self,
        vertex: &SurfaceVertex,
        normal: Vec3,
        side: &impl Fn(Vec3) -> Option<MediumId>,
        numbers: (f64, [f64; 2]),
        ratios: (Color, Color),
        rng: &mut SplitMix64,
        hero: usize,
        scatter: impl Fn(Vec3) -> (Color, f64),
    ) -> Color {
        let (u_pick, u_point) = numbers;
        let time = vertex.hit.time;
        let Some(light) = self.emitters.sample(
            self.world,
            vertex.point,
            Some(normal),
            time,
            u_pick,
            u_point,
        ) else {
            return Color::BLACK;
        };
        let (f, scatter_pdf) = scatter(light.direction);
        if f.max_channel() <= 0.0 {
            return Color::BLACK;
        }
        let ray = vertex.leaving(light.direction);
        let reach = if light.distance.is_finite() {
            let target = vertex.point + light.direction * light.distance;
            (target - ray.origin).length() - 2.0 * surface_offset(target)
        } else {
            f64::INFINITY
        };
        let medium = side(light.direction);
        self.weighed_light(
            ray,
            reach,
            medium,
            &light,
            (f, scatter_pdf),
            ratios,
            rng,
            hero,
        )
    }

    /// Next-event estimation from a point in a medium (`normal` `None`) or on a surface: a
    /// light sampled with `numbers`, its light carried back through the media between
    /// (starting in `medium`), scattered by `scatter` (the value and density of the phase
    /// function or BSDF towards a direction), weighed against the path's own sampling.
    /// `ratios` are the densities of the point by distance sampling (`r_p`, per channel) and
    /// by equiangular sampling (`r_e`), each over the density the point was drawn with.
    #[allow(clippy::too_many_arguments)] // the vertex, its medium and its numbers, each its own
    fn light_through_media(
        &mut self,
        point: Point3,
        normal: Option<Vec3>,
        medium: Option<MediumId>,
        time: f64,
        numbers: (f64, [f64; 2]),
        ratios: (Color, Color),
        rng: &mut SplitMix64,
        hero: usize,
        scatter: impl Fn(Vec3) -> (Color, f64),
    ) -> Color {
        let (u_pick, u_point) = numbers;
        let Some(light) = self
            .emitters
            .sample(self.world, point, normal, time, u_pick, u_point)
        else {
            return Color::BLACK;
        };
        let (f, scatter_pdf) = scatter(light.direction);
        if f.max_channel() <= 0.0 {
            return Color::BLACK;
        }
        let ray = Ray {
            origin: point,
            direction: light.direction,
            time,
            t_min: 0.0,
        };
        let reach = if light.distance.is_finite() {
            let target = point + light.direction * light.distance;
            light.distance - 2.0 * surface_offset(target)
        } else {
            f64::INFINITY
        };
        self.weighed_light(
            ray,
            reach,
            medium,
            &light,
            (f, scatter_pdf),
            ratios,
            rng,
            hero,
        )
    }

    /// The light of `light` along the shadow ray `ray` (clear for `reach`, starting in
    /// `medium`), scattered by `f` (whose sampling density is `scatter_pdf`), the path's
    /// ratios being `r_p` (and `r_e`, the equiangular strategy's, 0 where it did not run),
    /// still to be multiplied by the path's throughput: the balance heuristic between
    /// strategies and channels, or light sampling alone for a delta light.
    #[allow(clippy::too_many_arguments)] // the shadow ray and the light's sample, each its own
    fn weighed_light(
        &mut self,
        ray: Ray,
        reach: f64,
        medium: Option<MediumId>,
        light: &crate::lights::LightSample,
        (f, scatter_pdf): (Color, f64),
        (r_p, r_e): (Color, Color),
        rng: &mut SplitMix64,
        hero: usize,
    ) -> Color {
        if reach <= 0.0 {
            return Color::BLACK;
        }
        let Some(through) = self.transmitted(ray, reach, medium, rng, hero) else {
            return Color::BLACK;
        };
        let r_l = through.r_l.hadamard(r_p + r_e) * light.pdf;
        let r_u = through.r_u.hadamard(r_p) * scatter_pdf;
        let denominator = if light.delta || !self.techniques.mis {
            average(r_l)
        } else {
            average(r_l + r_u)
        };
        if denominator <= 0.0 {
            return Color::BLACK;
        }
        f.hadamard(through.t_ray).hadamard(light.radiance) * (1.0 / denominator)
    }

    /// What reaches the end of the shadow ray `ray` (clear for `reach`, starting in
    /// `medium`): `None` where a surface other than an index-matched boundary (or one that
    /// casts no shadow) blocks it; else the media's transmittance, crossing boundaries.
    fn transmitted(
        &mut self,
        mut ray: Ray,
        mut reach: f64,
        mut medium: Option<MediumId>,
        rng: &mut SplitMix64,
        hero: usize,
    ) -> Option<Transmitted> {
        let world = self.world;
        let mut through = Transmitted::CLEAR;
        for _ in 0..MAX_CROSSINGS {
            self.rays += 1;
            let hit = self.index.closest_hit(world, &ray).filter(|h| h.t < reach);
            let end = hit.as_ref().map_or(reach, |h| h.t);
            if let Some(id) = medium {
                transmittance(world.media.get(id), &ray, end, rng, hero, &mut through);
                if through.t_ray.max_channel() <= 0.0 {
                    return None;
                }
            }
            let Some(hit) = hit else {
                return Some(through);
            };
            let interface = hit.object.media;
            let passes = interface.is_some_and(|i| i.index_matched) || !hit.object.casts_shadow;
            if !passes {
                return None;
            }
            let point = ray.position(hit.t);
            let normal = self.index.normal_at_hit(world, point, &hit);
            if let Some(i) = interface {
                medium = i.towards(normal, ray.direction);
            }
            let side = if normal.dot(ray.direction) >= 0.0 {
                1.0
            } else {
                -1.0
            };
            let origin = point + normal * (side * surface_offset(point));
            reach -= (origin - ray.origin).dot(ray.direction);
            ray.origin = origin;
        }
        None
    }

    /// The equiangular sampler of the segment of `ray` through `medium` up to `t_max`, where
    /// it runs: a homogeneous medium, the technique and next-event estimation on, lights to
    /// draw towards, and a scattering there still within the most bounces.
    fn equiangular_along<'m>(
        &self,
        medium: &'m Medium,
        ray: &Ray,
        t_max: f64,
        depth: u32,
    ) -> Option<(&'m Homogeneous, Equiangular)> {
        let on = self.techniques.equiangular && self.techniques.next_event;
        let Medium::Homogeneous(m) = medium else {
            return None;
        };
        if !on || depth >= self.max_depth || m.sigma_s.max_channel() <= 0.0 {
            return None;
        }
        let draw = self
            .emitters
            .anchors()
            .along(ray.origin, ray.direction, t_max)?;
        Some((m, draw))
    }

    /// The light scattered once towards the path from a point of the segment of `ray`
    /// drawn by `draw` (equiangular sampling), lit by next-event estimation: the path having
    /// carried `beta_in` and ratios `r_in` into the segment, the light sampled from the point
    /// weighed by the balance heuristic against distance sampling finding the point (and
    /// against the phase function finding the light), or alone without MIS.
    #[allow(clippy::too_many_arguments)] // the segment, its sampler and the path's state
    fn equiangular_light(
        &mut self,
        m: &Homogeneous,
        ray: &Ray,
        draw: &Equiangular,
        (beta_in, r_in): (Color, Color),
        medium: Option<MediumId>,
        rng: &mut SplitMix64,
        hero: usize,
    ) -> Color {
        let (u_anchor, u_t) = (rng.next_offset(), rng.next_offset());
        let u_pick = rng.next_offset();
        let u_point = [rng.next_offset(), rng.next_offset()];
        let (t, pdf) = draw.sample(u_anchor, u_t);
        if pdf.is_nan() || pdf <= 0.0 {
            return Color::BLACK;
        }
        // σs·e^(−σt·t) per channel: what the point scatters of what reaches it, and the
        // density with which distance sampling in each channel scatters there.
        let scattered = scattered_at(m, t);
        let beta = beta_in.hadamard(scattered) * (1.0 / pdf);
        let r_p = if self.techniques.mis {
            r_in.hadamard(scattered) * (1.0 / pdf)
        } else {
            Color::BLACK
        };
        let phase = m.phase;
        let travel = ray.direction;
        let light = self.light_through_media(
            ray.position(t),
            None,
            medium,
            ray.time,
            (u_pick, u_point),
            (r_p, r_in),
            rng,
            hero,
            |wi| {
                let p = phase.eval(travel, wi);
                (Color::new(p, p, p), p)
            },
        );
        light.hadamard(beta)
    }

    /// Russian roulette after a bounce in media, by the surface loop's rule on the path's
    /// throughput over its mean ratio; whether the path goes on.
    fn roulette_in_media(
        &self,
        path: &mut Carried,
        depth: u32,
        numbers: u32,
        stream: &mut SampleStream,
        log: &mut impl PathLog,
    ) -> bool {
        if !self.techniques.roulette || depth < self.roulette_depth {
            return true;
        }
        let mean = average(path.r_u);
        if mean <= 0.0 {
            return false;
        }
        stream.seek(numbers + 6);
        let u = stream.next_1d();
        let survive = (path.beta.max_channel() / mean * self.roulette_scale).min(0.95);
        if survive.is_nan() || survive <= 0.0 || u >= survive {
            log.ended();
            return false;
        }
        path.beta = path.beta * (1.0 / survive);
        log.survived(
            survive,
            path.beta.max_channel() / mean,
            path.radiance,
            self.rays,
        );
        true
    }
}
