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
        let seconds = start.elapsed().as_secs_f64();
        let pass = Traced {
            seconds,
            hits: per_thread.iter().map(|p| p.0).sum(),
            t_sum: per_thread.iter().map(|p| p.1).sum(),
        };
        if best.is_none_or(|b| pass.seconds < b.seconds) {
            best = Some(pass);
        }
    }
    best.expect("at least one pass")
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
    use crate::bench::{rays::framing_rays, shapes::bumpy_sphere};

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
    fn agreement_allows_a_few_edge_rays() {
        assert!(agree(1000, 5000.0, 1002, 5001.0, 2_000_000));
        assert!(!agree(1000, 5000.0, 1500, 5000.0, 2_000_000));
        assert!(!agree(1000, 5000.0, 1000, 6000.0, 2_000_000));
    }
}
