//! Primary-ray throughput against Embree: the same rays through the same million-triangle
//! meshes, both on the same number of threads, scheduled alike (see `trace.rs` and the
//! harness). The second performance issue's target: rayforge at 75 % of Embree's rays per second or
//! better.

use super::report::{seconds, si, Check, Report, Table};
use super::shapes::{bumpy_sphere, read_obj, subdivide_until, Soup};
use super::{embree, files, rays, trace, Bench};
use rayforge_cli::failure::Failure;

/// rayforge's throughput as a share of Embree's that the issue asks for.
const TARGET_SHARE: f64 = 0.75;

/// Runs the comparison on the bumpy sphere and, when the model is there, the subdivided dragon.
pub fn run(bench: &Bench, report: &mut Report) -> Result<(), Failure> {
    let size = if bench.settings.quick {
        2_000
    } else {
        1_000_000
    };
    let (width, height) = bench.image_size();
    let mut table = Table::new(
        format!(
            "Primary rays against Embree ({width}×{height} rays in 8×8 tiles, {} threads, best of {})",
            bench.settings.threads, bench.settings.repeat
        ),
        &[
            "mesh",
            "triangles",
            "rayforge",
            "Embree",
            "ratio (share of Embree)",
            "rayforge rays/s",
            "Embree rays/s",
            "hits rayforge / Embree",
        ],
    );

    bench.progress(&format!(
        "generating a bumpy sphere of {} triangles",
        si(size as f64)
    ));
    let sphere = bumpy_sphere(size);
    compare(bench, report, &mut table, "bumpy sphere", "sphere", &sphere)?;
    drop(sphere);

    let dragon_path = bench.settings.models.join("dragon.obj");
    if dragon_path.is_file() {
        bench.progress("reading and subdividing the dragon");
        let dragon = read_obj(&dragon_path).map_err(Failure::usage)?;
        let original = dragon.triangles.len();
        let dragon = subdivide_until(dragon, size);
        let name = format!("Stanford dragon ({} subdivided)", si(original as f64));
        compare(bench, report, &mut table, &name, "dragon", &dragon)?;
    } else {
        table.note(format!(
            "The dragon was skipped: `{}` is not there (it lives beside the repository, in \
             shared/models).",
            dragon_path.display()
        ));
    }
    if bench.peers.embree.is_none() {
        table.note(format!(
            "Embree was skipped: {}.",
            super::peers::Peer::Embree.skipped_hint()
        ));
    }
    report.table(&table);
    Ok(())
}

/// One mesh: rayforge's passes and Embree's on the same files, in turns; one row and one
/// check.
fn compare(
    bench: &Bench,
    report: &mut Report,
    table: &mut Table,
    name: &str,
    file_stem: &str,
    soup: &Soup,
) -> Result<(), Failure> {
    let (width, height) = bench.image_size();
    let rays = rays::framing_rays(soup, width, height);
    bench.progress(&format!(
        "{name}: building rayforge's BVH over {} triangles",
        si(soup.triangles.len() as f64)
    ));
    let mesh = bench.build_mesh(soup)?;
    // Both sides take turns, one pass each per round, so that the two bests come from the
    // same stretch of the machine's time.
    let mut ours = None;
    let mut our_pass = || ours = Some(trace::faster(ours, trace::pass(&mesh, &rays, &bench.pool)));
    let theirs = match bench.peers.embree.as_deref() {
        None => {
            bench.progress(&format!("{name}: tracing {} rays", si(rays.len() as f64)));
            for _ in 0..bench.settings.repeat.max(1) {
                our_pass();
            }
            None
        }
        Some(harness) => {
            let mesh_file = bench.out(&format!("{file_stem}.rfmesh"));
            let rays_file = bench.out(&format!("{file_stem}.rfrays"));
            files::write_mesh(&mesh_file, soup).map_err(|e| bench.write_error(&mesh_file, e))?;
            files::write_rays(&rays_file, &rays).map_err(|e| bench.write_error(&rays_file, e))?;
            bench.progress(&format!(
                "{name}: tracing {} rays with rayforge and Embree in turns",
                si(rays.len() as f64)
            ));
            Some(embree::run_in_turns(
                harness,
                &mesh_file,
                &rays_file,
                bench.settings.threads,
                bench.settings.repeat,
                &mut our_pass,
            ))
        }
    };
    drop(mesh);
    let ours = ours.expect("at least one pass");

    let rate = |s: f64| format!("{}/s", si(rays.len() as f64 / s));
    let mut cells = vec![
        name.to_string(),
        si(soup.triangles.len() as f64),
        seconds(ours.seconds),
    ];
    let what = format!(
        "primary rays, {name}, {} triangles, vs Embree",
        si(soup.triangles.len() as f64)
    );
    let target = format!("≥ {:.0} %", TARGET_SHARE * 100.0);
    match theirs {
        None => {
            cells.extend([
                "skipped".into(),
                "—".into(),
                rate(ours.seconds),
                "—".into(),
                format!("{} / —", ours.hits),
            ]);
            report.check(Check {
                what,
                measured: "Embree not installed".into(),
                target,
                met: None,
            });
        }
        Some(Ok(theirs)) => {
            let share = theirs.trace_seconds / ours.seconds;
            let agree = trace::agree(ours.hits, ours.t_sum, theirs.hits, theirs.t_sum, rays.len());
            cells.extend([
                seconds(theirs.trace_seconds),
                format!("{:.0} %", share * 100.0),
                rate(ours.seconds),
                rate(theirs.trace_seconds),
                format!(
                    "{} / {}{}",
                    ours.hits,
                    theirs.hits,
                    if agree { "" } else { " (DISAGREE)" }
                ),
            ]);
            if !agree {
                table.note(format!(
                    "{name}: the two sides disagree on what the rays hit (t sums {:.3} \
                     and {:.3}): the times are not comparable.",
                    ours.t_sum, theirs.t_sum
                ));
            }
            report.check(Check {
                what,
                measured: format!(
                    "{:.0} % of Embree (Embree {})",
                    share * 100.0,
                    theirs.version
                ),
                target,
                met: agree.then_some(share >= TARGET_SHARE),
            });
        }
        Some(Err(message)) => {
            cells.extend(["failed".into(), "—".into(), rate(ours.seconds)]);
            table.note(format!("{name}: {message}"));
            report.check(Check {
                what,
                measured: "Embree failed".into(),
                target,
                met: None,
            });
        }
    }
    table.row(cells);
    Ok(())
}
