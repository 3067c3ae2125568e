//! What a path still has to gather past a diffuse vertex, learned per place by the roulette's
//! pilot, so that Russian roulette can end a path into that estimate instead of into
//! darkness.
//!
//! Plain roulette ends a path with probability `1 − q` and weighs a survivor by `1 / q`: the
//! light `V` still to come (per unit of throughput) is replaced by `V / q` or 0, which adds
//! `E[V²] (1/q − 1)` of variance. Where light keeps coming (a bright closed room) `E[V²]` is
//! large, and the learned roulette can only lower that noise by letting paths live longer.
//! With a prediction `c` of `V`, a path that ends adds `T c` and a survivor adds `T (V − (1 −
//! q) c) / q`: the mean is still `T V` for any `c` that does not look at the path's future (a
//! control variate), and the added variance is `E[(V − c)²] (1/q − 1)`, only what the
//! prediction misses. Where it misses little, paths can end early and cheaply.
//!
//! The prediction is the mean of `V` over the pilot's diffuse vertices in a cell of a grid
//! over the places they lay, and the side of the surface they faced (the axis of their
//! normal nearest it, one of six): a Lambertian surface scatters alike whatever the path
//! came from, so `V` there depends on the place alone. A cell predicts only where it has seen
//! [`MIN_VERTICES`] vertices whose `V` spread about their mean by at most [`MAX_MISS`] of it:
//! elsewhere (near a small bright lamp, under a sky with a sun, where a caustic falls) the
//! path plays the plain roulette. Like the roulette's scale it is a pure function of the
//! scene, the camera and the options, so the image stays the same for any thread count and
//! sample ranges rendered apart still merge exactly.
//!
//! Written here rather than taken from a crate: it is a few dozen lines of a grid, and its
//! rules (what a cell may predict) belong to the roulette.

use super::moments::Moments;
use crate::color::Color;
use crate::math::{Point3, Vec3};

/// The fewest pilot vertices a cell predicts from.
const MIN_VERTICES: f64 = 24.0;
/// The most a cell's values may spread about their mean (root mean square, relative to the
/// mean's own size) for it to predict. Inside the closed furnace they spread by about a
/// ninth; on the environment-lit scene's diffuse ball, whose paths mostly escape at once,
/// by 0.26 to 0.3, and predicting there saved half a percent of the rays for 3 % more error.
const MAX_MISS: f64 = 0.25;
/// About how many pilot vertices a cell should hold: the grid's step follows from it.
const VERTICES_PER_CELL: f64 = 256.0;
/// The most cells along the grid's longest side.
const MAX_CELLS_PER_AXIS: f64 = 32.0;

/// One pilot vertex: where it lay, which side it faced, and the light its path gathered past
/// it per unit of its throughput.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sighting {
    pub point: Point3,
    pub facing: Vec3,
    pub light: Color,
}

/// The side a surface faces as one of six: the axis its unit `facing` normal is nearest,
/// and that axis's sign.
#[inline]
fn side(facing: Vec3) -> usize {
    let a = facing.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(facing[axis] < 0.0)
}

/// The predictions: a grid over the pilot's diffuse vertices, each cell's six sides.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationCache {
    origin: Point3,
    /// One over the cells' edge length.
    inverse_step: f64,
    /// Cells along each axis.
    cells: [usize; 3],
    /// Per cell and side, the prediction where there is one.
    predictions: Vec<Option<Color>>,
}

impl ContinuationCache {
    /// The cache `sightings` teach (in a fixed order, so the cache does not depend on the
    /// thread count); `None` where no cell could predict.
    pub(super) fn learn(sightings: &[Sighting]) -> Option<Self> {
        let (mut low, mut high) = (
            Point3::splat(f64::INFINITY),
            Point3::splat(f64::NEG_INFINITY),
        );
        for s in sightings {
            low = low.min(s.point);
            high = high.max(s.point);
        }
        let extent = (high - low).max_element();
        if !(extent.is_finite() && low.is_finite()) {
            return None;
        }
        let per_axis = (sightings.len() as f64 / VERTICES_PER_CELL)
            .sqrt()
            .clamp(1.0, MAX_CELLS_PER_AXIS);
        // A little wider than the vertices, so the farthest lie inside the last cell.
        let step = (extent.max(1e-9) / per_axis) * (1.0 + 1e-9);
        let cells = ((high - low) / step)
            .to_array()
            .map(|c| (c.floor() as usize + 1).min(MAX_CELLS_PER_AXIS as usize + 1));
        let mut grid = Self {
            origin: low,
            inverse_step: 1.0 / step,
            cells,
            predictions: vec![None; cells[0] * cells[1] * cells[2] * 6],
        };
        let mut moments = vec![Moments::default(); grid.predictions.len()];
        for s in sightings {
            if let Some(slot) = grid.slot(s.point, s.facing) {
                moments[slot].add(s.light);
            }
        }
        for (prediction, m) in grid.predictions.iter_mut().zip(&moments) {
            let mean = m.mean();
            let size =
                (mean.red * mean.red + mean.green * mean.green + mean.blue * mean.blue) / 3.0;
            if m.count() >= MIN_VERTICES && size > 0.0 && m.variance() <= MAX_MISS * MAX_MISS * size
            {
                *prediction = Some(mean);
            }
        }
        grid.predictions.iter().any(Option::is_some).then_some(grid)
    }

    /// The index of the cell and side of `point` facing `facing`; `None` outside the grid.
    #[inline]
    fn slot(&self, point: Point3, facing: Vec3) -> Option<usize> {
        let at = ((point - self.origin) * self.inverse_step).to_array();
        let mut index = 0;
        for (c, n) in at.into_iter().zip(self.cells) {
            // (NaN fails the test too.)
            if !(c >= 0.0 && c < n as f64) {
                return None;
            }
            index = index * n + c as usize;
        }
        Some(index * 6 + side(facing))
    }

    /// The light a path at a diffuse vertex at `point`, on the side facing `facing`, is
    /// predicted to gather past it per unit of throughput; `None` where the cell does not
    /// predict.
    #[inline]
    pub fn predict(&self, point: Point3, facing: Vec3) -> Option<Color> {
        self.predictions[self.slot(point, facing)?]
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::lights::Emitters;
    use crate::math::random::{Jitter, SplitMix64};
    use crate::math::{scaling, Ray};
    use crate::options::SamplerKind;
    use crate::render::path::{PathContext, SampleStream};
    use crate::scene::{Object, World, WorldIndex};
    use crate::shading::{EmissionSide, Material, Physical};

    fn sighting(point: Point3, facing: Vec3, light: f64) -> Sighting {
        Sighting {
            point,
            facing,
            light: Color::new(light, light, light),
        }
    }

    #[test]
    fn a_cell_predicts_the_mean_of_what_its_vertices_saw_on_each_side() {
        let mut random = SplitMix64::new(7);
        let mut sightings = Vec::new();
        for _ in 0..4000 {
            let p = Point3::new(random.next_offset(), random.next_offset(), 0.0);
            // Up-facing vertices see about 2, down-facing ones about 0.5.
            sightings.push(sighting(
                p,
                Vec3::Z,
                2.0 + 0.2 * (random.next_offset() - 0.5),
            ));
            sightings.push(sighting(p, -Vec3::Z, 0.5));
        }
        let cache = ContinuationCache::learn(&sightings).expect("every cell predicts");
        let at = Point3::new(0.5, 0.5, 0.0);
        let up = cache.predict(at, Vec3::new(0.1, 0.0, 0.9)).unwrap();
        assert!((up.red - 2.0).abs() < 0.05, "{up:?}");
        assert_eq!(
            cache.predict(at, Vec3::new(0.0, 0.2, -0.9)),
            Some(Color::new(0.5, 0.5, 0.5))
        );
        // No vertex faced sideways, and nothing is known outside the grid.
        assert_eq!(cache.predict(at, Vec3::X), None);
        assert_eq!(cache.predict(Point3::new(2.0, 0.5, 0.0), Vec3::Z), None);
        assert_eq!(cache.predict(Point3::splat(f64::NAN), Vec3::Z), None);
    }

    #[test]
    fn a_cell_whose_vertices_disagree_or_are_few_predicts_nothing() {
        let mut random = SplitMix64::new(11);
        let mut sightings = Vec::new();
        for i in 0..4000 {
            let x = random.next_offset();
            let p = Point3::new(x, random.next_offset(), 0.0);
            // The left half: mostly nothing and now and then a lamp (the mean is 0.5, the
            // spread about 2.2). The right half: steady.
            let light = if x < 0.5 {
                if i % 20 == 0 {
                    10.0
                } else {
                    0.0
                }
            } else {
                1.0
            };
            sightings.push(sighting(p, Vec3::Z, light));
        }
        let cache = ContinuationCache::learn(&sightings).expect("the right half predicts");
        assert_eq!(cache.predict(Point3::new(0.2, 0.5, 0.0), Vec3::Z), None);
        assert_eq!(
            cache.predict(Point3::new(0.8, 0.5, 0.0), Vec3::Z),
            Some(Color::WHITE)
        );
        let few: Vec<Sighting> = sightings.into_iter().take(10).collect();
        assert_eq!(ContinuationCache::learn(&few), None);
        assert_eq!(ContinuationCache::learn(&[]), None);
    }

    /// A closed sphere of albedo 0.8 that emits 0.2 inwards: every path from inside has the
    /// expected radiance 1 (the roulette's tests use it too).
    pub(in crate::render::path) fn closed_room() -> World {
        let sphere = Object::sphere()
            .with_transform(scaling(10.0, 10.0, 10.0))
            .with_material(Material {
                color: Color::new(0.8, 0.8, 0.8),
                physical: Some(Physical::Diffuse),
                emission: Color::new(0.2, 0.2, 0.2),
                emission_side: EmissionSide::Back,
                ..Material::DEFAULT
            });
        World {
            objects: vec![sphere],
            ..World::default()
        }
    }

    /// The mean of `n` paths along one ray from the centre of the [`closed_room`], the
    /// roulette ending paths into `cache`.
    fn closed_room_mean(cache: &ContinuationCache, n: u64) -> f64 {
        let world = closed_room();
        let (index, emitters) = (WorldIndex::build(&world), Emitters::new(&world));
        let mut context = PathContext::new(&world, &index, &emitters, u32::MAX, 5);
        context.continuation = Some(cache);
        let ray = Ray {
            origin: Point3::ZERO,
            direction: Vec3::new(0.3, 0.2, 1.0).normalize(),
            time: 0.0,
            t_min: 0.0,
        };
        let mut stream = SampleStream::new(SamplerKind::Independent, 3, 0, 0, 0);
        let mut sum = 0.0;
        for i in 0..n {
            stream.start(i);
            sum += context.radiance(ray, &mut stream).0.red;
        }
        sum / n as f64
    }

    /// A cache that predicts `light` everywhere on the inside of the sphere of radius 10.
    fn predicting(light: f64) -> ContinuationCache {
        let mut random = SplitMix64::new(5);
        let sightings: Vec<Sighting> = (0..20_000)
            .map(|_| {
                let z = 2.0 * random.next_offset() - 1.0;
                let phi = std::f64::consts::TAU * random.next_offset();
                let r = (1.0 - z * z).sqrt();
                let out = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                sighting(out * 10.0, -out, light)
            })
            .collect();
        ContinuationCache::learn(&sightings).expect("the wall is predicted")
    }

    #[test]
    fn a_wrong_prediction_changes_the_noise_and_not_the_mean() {
        // What a path still gathers past the wall is about 0.93; predictions far off either
        // way leave the mean where it is (each within about 5 of its standard errors).
        for light in [0.93, 0.2, 3.0] {
            let cache = predicting(light);
            let wall = Vec3::new(0.0, 0.0, 10.0);
            let predicted = cache
                .predict(wall, -Vec3::Z)
                .expect("the wall is predicted");
            assert!((predicted.red - light).abs() < 1e-9, "{predicted:?}");
            let mean = closed_room_mean(&cache, 20_000);
            assert!((mean - 1.0).abs() < 0.03, "predicting {light}: mean {mean}");
        }
    }
}
