//! The build and scaling comparisons, one sweep over bumpy spheres of growing size: each is
//! built R times (the fastest BVH build counts, on both sides; its bytes are counted), then
//! traced with the same 1920×1080 rays by rayforge and, when installed, Embree. The targets: at least 5 M triangles
//! per second built on 2 cores and at most 100 bytes per triangle beyond the vertex data for
//! large meshes; time per primary ray growing at most 1.8× from 1 k to 10 M triangles (the second
//! performance issue's line; the first allowed 2×).

use super::plot::{self, Series};
use super::report::{seconds, si, times, Check, Report, Table};
use super::shapes::bumpy_sphere;
use super::trace::{self, Traced};
use super::{embree, files, rays, Bench};
use rayforge_cli::atomic_write::write_atomically;
use rayforge_cli::failure::Failure;
use std::time::Instant;

/// Build rate the issue asks for, in triangles per second.
const TARGET_BUILD_RATE: f64 = 5e6;
/// Bytes per triangle beyond the vertex data the issue allows.
const TARGET_BYTES: f64 = 100.0;
/// How much the time per ray may grow from the smallest mesh to the largest.
const TARGET_GROWTH: f64 = 1.8;
/// Meshes from this size on count as large for the build targets.
const LARGE: usize = 1_000_000;

/// Half-decade steps from 1 k to 10 M triangles.
const SIZES: [usize; 9] = [
    1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000, 3_000_000, 10_000_000,
];

/// One mesh of the sweep.
struct Measured {
    triangles: usize,
    build_seconds: f64,
    index_bytes: usize,
    traced: Option<Traced>,
    /// The smallest mesh's fastest pass, traced in turns with this one's.
    reference: Option<Traced>,
    embree: Option<Result<embree::EmbreeRun, String>>,
}

/// Runs the sweep and prints the tables asked for.
pub fn run(bench: &Bench, report: &mut Report, build: bool, scaling: bool) -> Result<(), Failure> {
    let sizes: Vec<usize> = match (bench.settings.quick, scaling) {
        (true, _) => vec![1_000, 3_000],
        (false, true) => SIZES.to_vec(),
        (false, false) => SIZES.iter().copied().filter(|&s| s >= LARGE).collect(),
    };
    let (width, height) = bench.image_size();
    // One camera for every size: every mesh samples the same surface, so the same rays see
    // the same picture and only the triangle count changes.
    let rays = rays::framing_rays(&bumpy_sphere(1_000), width, height);
    let rays_file = bench.out("sweep.rfrays");
    if bench.peers.embree.is_some() {
        files::write_rays(&rays_file, &rays).map_err(|e| bench.write_error(&rays_file, e))?;
    }
    let mut measured = Vec::new();
    // The smallest mesh stays built, to be traced in turns with each larger one.
    let mut smallest: Option<rayforge::geometry::Mesh> = None;
    for &size in &sizes {
        bench.progress(&format!(
            "sweep: bumpy sphere of {} triangles",
            si(size as f64)
        ));
        let soup = bumpy_sphere(size);
        // Built R times, like Embree's side: the first build also pays for waking the
        // threads and touching fresh memory. The fastest counts; the last is traced.
        let mut build_seconds = f64::INFINITY;
        let mut built = None;
        for _ in 0..bench.settings.repeat.max(1) {
            let (positions, faces) = soup.mesh_parts();
            drop(built.take());
            let start = Instant::now();
            let mesh = bench
                .pool
                .install(|| rayforge::geometry::Mesh::new(positions, Vec::new(), faces))
                .map_err(|e| Failure::internal(format!("the generated mesh is invalid: {e}")))?;
            build_seconds = build_seconds.min(start.elapsed().as_secs_f64());
            built = Some(mesh);
        }
        let mesh = built.expect("built at least once");
        let index_bytes = mesh.index_bytes();
        let repeat = bench.settings.repeat;
        let (traced, reference) = match (scaling, &smallest) {
            (false, _) => (None, None),
            (true, None) => {
                let traced = trace::trace(&mesh, &rays, &bench.pool, repeat);
                (Some(traced), Some(traced))
            }
            (true, Some(reference)) => {
                let (traced, reference) =
                    trace::trace_alongside(&mesh, reference, &rays, &bench.pool, repeat);
                (Some(traced), Some(reference))
            }
        };
        if scaling && smallest.is_none() {
            smallest = Some(mesh);
        } else {
            drop(mesh);
        }
        let embree = match bench.peers.embree.as_deref() {
            Some(harness) => {
                let mesh_file = bench.out("sweep.rfmesh");
                files::write_mesh(&mesh_file, &soup)
                    .map_err(|e| bench.write_error(&mesh_file, e))?;
                bench.progress("sweep: the same with Embree");
                let repeat = bench.settings.repeat;
                Some(embree::run(
                    harness,
                    &mesh_file,
                    &rays_file,
                    bench.settings.threads,
                    repeat,
                ))
            }
            None => None,
        };
        measured.push(Measured {
            triangles: soup.triangles.len(),
            build_seconds,
            index_bytes,
            traced,
            reference,
            embree,
        });
    }
    if build {
        build_table(bench, report, &measured);
    }
    if scaling {
        scaling_table(bench, report, &measured, rays.len())?;
    }
    Ok(())
}

fn embree_ok(m: &Measured) -> Option<&embree::EmbreeRun> {
    m.embree.as_ref().and_then(|r| r.as_ref().ok())
}

fn skipped_or_failed(table: &mut Table, bench: &Bench, measured: &[Measured]) {
    if bench.peers.embree.is_none() {
        table.note(format!(
            "Embree was skipped: {}.",
            super::peers::Peer::Embree.skipped_hint()
        ));
    }
    for m in measured {
        if let Some(Err(message)) = &m.embree {
            table.note(format!("{} triangles: {message}", si(m.triangles as f64)));
        }
    }
}

fn build_table(bench: &Bench, report: &mut Report, measured: &[Measured]) {
    let threads = bench.settings.threads;
    let mut table = Table::new(
        format!("BVH build ({threads} threads; bumpy spheres)"),
        &[
            "triangles",
            "rayforge build",
            "rayforge triangles/s",
            "bytes/triangle beyond vertices",
            "Embree build",
            "Embree triangles/s",
        ],
    );
    let large = |m: &&Measured| bench.settings.quick || m.triangles >= LARGE;
    for m in measured.iter().filter(large) {
        let rate = m.triangles as f64 / m.build_seconds;
        let bytes = m.index_bytes as f64 / m.triangles as f64;
        let (em_time, em_rate) = match embree_ok(m) {
            Some(e) => (
                seconds(e.build_seconds),
                format!("{}/s", si(m.triangles as f64 / e.build_seconds)),
            ),
            None => ("—".into(), "—".into()),
        };
        table.row(vec![
            si(m.triangles as f64),
            seconds(m.build_seconds),
            format!("{}/s", si(rate)),
            format!("{bytes:.1}"),
            em_time,
            em_rate,
        ]);
        report.check(Check {
            what: format!("BVH build rate, {} triangles", si(m.triangles as f64)),
            measured: format!("{}/s", si(rate)),
            target: format!("≥ {}/s", si(TARGET_BUILD_RATE)),
            met: Some(rate >= TARGET_BUILD_RATE),
        });
        report.check(Check {
            what: format!("mesh and BVH memory, {} triangles", si(m.triangles as f64)),
            measured: format!("{bytes:.1} bytes/triangle"),
            target: format!("≤ {TARGET_BYTES:.0} bytes/triangle"),
            met: Some(bytes <= TARGET_BYTES),
        });
    }
    table.note(
        "Bytes per triangle are `Mesh::index_bytes()` (faces and BVH) over the triangle count; \
         the vertex data comes on top. The Embree build is `rtcCommitScene` with its default \
         settings, for reference.",
    );
    skipped_or_failed(&mut table, bench, measured);
    report.table(&table);
}

fn scaling_table(
    bench: &Bench,
    report: &mut Report,
    measured: &[Measured],
    ray_count: usize,
) -> Result<(), Failure> {
    let (width, height) = bench.image_size();
    let threads = bench.settings.threads;
    let mut table = Table::new(
        format!(
            "Time per primary ray against triangle count ({width}×{height} rays, {threads} threads, best of {})",
            bench.settings.repeat
        ),
        &[
            "triangles",
            "rayforge per ray",
            "rayforge rays/s",
            "relative to smallest",
            "Embree per ray",
            "Embree rays/s",
            "hits rayforge / Embree",
        ],
    );
    let per_ray = |s: f64| s / ray_count as f64 * 1e9;
    let mut ours = Vec::new();
    let mut growth = None;
    let mut theirs = Vec::new();
    for m in measured {
        let (Some(t), Some(reference)) = (m.traced, m.reference) else {
            continue;
        };
        let ns = per_ray(t.seconds);
        ours.push((m.triangles as f64, ns));
        let relative = t.seconds / reference.seconds;
        growth = Some(relative);
        let mut cells = vec![
            si(m.triangles as f64),
            format!("{ns:.0} ns"),
            format!("{}/s", si(ray_count as f64 / t.seconds)),
            times(relative),
        ];
        match embree_ok(m) {
            Some(e) => {
                let agree = trace::agree(t.hits, t.t_sum, e.hits, e.t_sum, ray_count);
                theirs.push((m.triangles as f64, per_ray(e.trace_seconds)));
                cells.extend([
                    format!("{:.0} ns", per_ray(e.trace_seconds)),
                    format!("{}/s", si(ray_count as f64 / e.trace_seconds)),
                    format!(
                        "{} / {}{}",
                        t.hits,
                        e.hits,
                        if agree { "" } else { " (DISAGREE)" }
                    ),
                ]);
            }
            None => cells.extend(["—".into(), "—".into(), format!("{} / —", t.hits)]),
        }
        table.row(cells);
    }
    table.note(
        "Relative to smallest: each mesh's fastest pass over the fastest pass of the smallest \
         mesh, the two traced in turns (a pass of one, then of the other, R times), so that \
         both bests come from the same stretch of the machine's time; the smallest mesh's row \
         is its own best.",
    );
    skipped_or_failed(&mut table, bench, measured);
    if let (Some(growth), Some(first_m), Some(last_m)) = (growth, measured.first(), measured.last())
    {
        report.check(Check {
            what: format!(
                "time per primary ray from {} to {} triangles",
                si(first_m.triangles as f64),
                si(last_m.triangles as f64)
            ),
            measured: format!("grows {}", times(growth)),
            target: format!("≤ {}", times(TARGET_GROWTH)),
            met: Some(growth <= TARGET_GROWTH),
        });
    }
    let plot_path = bench.out("scaling.png");
    let mut series = vec![Series {
        name: "rayforge".into(),
        color: [200, 50, 40],
        points: ours,
    }];
    if !theirs.is_empty() {
        let version = measured
            .iter()
            .find_map(embree_ok)
            .map(|e| e.version.clone())
            .unwrap_or_default();
        series.push(Series {
            name: format!("Embree {version}"),
            color: [40, 90, 190],
            points: theirs,
        });
    }
    let png = plot::png(
        "time per primary ray against triangle count",
        &format!(
            "bumpy spheres, {width}×{height} rays, {threads} threads, best of {}",
            bench.settings.repeat
        ),
        &series,
    )?;
    write_atomically(&plot_path, &png)?;
    table.note(format!("Plot: `{}`.", plot_path.display()));
    if let Some(copy) = &bench.settings.plot {
        write_atomically(copy, &png)?;
        table.note(format!("Copied to `{}`.", copy.display()));
    }
    report.table(&table);
    Ok(())
}
