//! rayforge's side of the primary-ray comparison, scheduled as the Embree harness schedules
//! its own: every thread of the pool takes chunks of 4096 consecutive rays from a shared
//! counter and traces each with [`Mesh::closest_hit`]; the fastest of several passes counts.

use super::rays::{to_ray, StoredRay};
use rayforge::geometry::Mesh;
use rayon::ThreadPool;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Rays per chunk, the same as the harness's `CHUNK`: enough that the counter is not
/// contended, few enough that the threads finish together.
const CHUNK: usize = 4096;

/// What tracing every ray found, and how long the fastest pass took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traced {
    /// Wall time of the fastest pass.
    pub seconds: f64,
    /// Rays that hit the mesh.
    pub hits: u64,
    /// The sum of the hit distances (to check both sides saw the same thing).
    pub t_sum: f64,
}

/// Traces `rays` through `mesh` `repeat` times (at least once) on `pool`.
pub fn trace(mesh: &Mesh, rays: &[StoredRay], pool: &ThreadPool, repeat: u32) -> Traced {
    let mut best: Option<Traced> = None;
    for _ in 0..repeat.max(1) {
        best = Some(faster(best, pass(mesh, rays, pool)));
    }
    best.expect("at least one pass")
}

/// Traces `rays` through `mesh` and through `reference` `repeat` times each, the passes
/// taking turns, and returns the fastest of each: the two bests then come from the same
/// stretch of the machine's time, so a ratio of them is not swayed by what its neighbours
/// did meanwhile (which moves a lone time by ±15 % on a shared machine).
pub fn trace_alongside(
    mesh: &Mesh,
    reference: &Mesh,
    rays: &[StoredRay],
    pool: &ThreadPool,
    repeat: u32,
) -> (Traced, Traced) {
    let (mut best, mut best_reference) = (None, None);
    for _ in 0..repeat.max(1) {
        best_reference = Some(faster(best_reference, pass(reference, rays, pool)));
        best = Some(faster(best, pass(mesh, rays, pool)));
    }
    (
        best.expect("at least one pass"),
        best_reference.expect("at least one pass"),
    )
}

/// The faster of a best so far and a new pass.
pub fn faster(best: Option<Traced>, pass: Traced) -> Traced {
    match best {
        Some(b) if b.seconds <= pass.seconds => b,
        _ => pass,
    }
}

/// One pass over every ray, chunks shared out among the pool's threads.
pub fn pass(mesh: &Mesh, rays: &[StoredRay], pool: &ThreadPool) -> Traced {
    let next = AtomicUsize::new(0);
    let start = Instant::now();
    let per_thread = pool.broadcast(|_| {
        let (mut hits, mut t_sum) = (0u64, 0.0f64);
        loop {
            let first = next.fetch_add(CHUNK, Ordering::Relaxed);
            if first >= rays.len() {
                break;
            }
            for r in &rays[first..(first + CHUNK).min(rays.len())] {
                if let Some(hit) = mesh.closest_hit(&to_ray(r), 0.0, f64::INFINITY) {
                    hits += 1;
                    t_sum += hit.t;
                }
            }
        }
        (hits, t_sum)
    });
    Traced {
        seconds: start.elapsed().as_secs_f64(),
        hits: per_thread.iter().map(|p| p.0).sum(),
        t_sum: per_thread.iter().map(|p| p.1).sum(),
    }
}

/// Whether two sides' hit counts and distance sums agree: a handful of rays through shared
/// edges and vertices may go either way between two correct tracers (one in f32, one in f64),
/// but no more than one in ten thousand.
pub fn agree(hits_a: u64, t_sum_a: f64, hits_b: u64, t_sum_b: f64, rays: usize) -> bool {
    let allowed = (rays as f64 * 1e-4).max(2.0);
    let hits_ok = (hits_a as f64 - hits_b as f64).abs() <= allowed;
    let mean = (t_sum_a.abs() + t_sum_b.abs()) / 2.0;
    let t_ok = mean == 0.0 || (t_sum_a - t_sum_b).abs() <= mean * 1e-3;
    hits_ok && t_ok
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{rays::framing_rays, shapes::bumpy_sphere};

    #[test]
    fn any_thread_count_finds_the_same_hits() {
        let soup = bumpy_sphere(200);
        let mesh = soup.to_mesh().unwrap();
        let rays = framing_rays(&soup, 120, 80); // more than two chunks
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let one = trace(&mesh, &rays, &pool(1), 1);
        let two = trace(&mesh, &rays, &pool(2), 2);
        assert_eq!(one.hits, two.hits);
        assert!((one.t_sum - two.t_sum).abs() < 1e-6 * one.t_sum);
        assert!(one.hits > 0);
    }

    #[test]
    fn meshes_traced_in_turns_find_what_they_find_alone() {
        let small = bumpy_sphere(200).to_mesh().unwrap();
        let soup = bumpy_sphere(2_000);
        let large = soup.to_mesh().unwrap();
        let rays = framing_rays(&soup, 60, 40);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (l, s) = trace_alongside(&large, &small, &rays, &pool, 2);
        let (l_alone, s_alone) = (
            trace(&large, &rays, &pool, 1),
            trace(&small, &rays, &pool, 1),
        );
        assert_eq!((l.hits, s.hits), (l_alone.hits, s_alone.hits));
        assert!(l.hits > 0 && l.t_sum != s.t_sum);
    }

    #[test]
    fn the_faster_pass_is_kept() {
        let pass = |seconds| Traced {
            seconds,
            hits: 1,
            t_sum: 1.0,
        };
        assert_eq!(faster(None, pass(2.0)).seconds, 2.0);
        assert_eq!(faster(Some(pass(1.0)), pass(2.0)).seconds, 1.0);
        assert_eq!(faster(Some(pass(3.0)), pass(2.0)).seconds, 2.0);
    }

    #[test]
    fn agreement_allows_a_few_edge_rays() {
        assert!(agree(1000, 5000.0, 1002, 5001.0, 2_000_000));
        assert!(!agree(1000, 5000.0, 1500, 5000.0, 2_000_000));
        assert!(!agree(1000, 5000.0, 1000, 6000.0, 2_000_000));
    }
}
