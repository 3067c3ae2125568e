//! A short, fixed-seed fuzzing run of each reader as part of `cargo test` (a few thousand
//! inputs each; the `rayforge-fuzz` binary runs longer). A crash fails the test with the
//! minimised input, written under `target/fuzz-crashes`.

use rayforge_fuzz::{fuzz, Options, Target};

/// Inputs per target: `RAYFORGE_FUZZ_ITERATIONS` or the default.
fn iterations(default: u64) -> u64 {
    std::env::var("RAYFORGE_FUZZ_ITERATIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn check(target: Target, seed: u64, default: u64) {
    match fuzz(target, &Options::quick(seed, iterations(default))) {
        Ok(report) => eprintln!(
            "{}: {} inputs ({} accepted, {} caught panics) in {:.1} s, slowest {:.3} s",
            target.name(),
            report.executed,
            report.accepted,
            report.caught_panics,
            report.elapsed.as_secs_f64(),
            report.slowest.as_secs_f64()
        ),
        Err(crash) => panic!("{crash}"),
    }
}

#[test]
fn the_scene_reader_survives_mutated_scenes() {
    check(Target::Scene, 0x5CE4E, 2500);
}

#[test]
fn the_obj_reader_survives_mutated_models() {
    check(Target::Obj, 0x0B1, 3000);
}

#[test]
fn the_gltf_reader_survives_mutated_models() {
    check(Target::Gltf, 0x617F, 1500);
}

#[test]
fn the_ply_reader_survives_mutated_models() {
    check(Target::Ply, 0x91A, 3000);
}

#[test]
fn the_image_reader_survives_mutated_images() {
    check(Target::Image, 0x1A6E, 5000);
}

#[test]
fn the_merge_survives_mutated_part_files() {
    check(Target::Part, 0x9A27, 1500);
}

#[test]
fn the_live_page_server_survives_mutated_requests() {
    check(Target::Page, 0x9A6E, 5000);
}

/// The seeds reach past the first checks: every part merges, and the page's requests from
/// this machine's browser are taken while the one from another site is refused. (A seed that
/// is refused at once would leave the fuzzer mutating only the refusal.)
#[test]
fn the_new_targets_seeds_are_accepted_where_they_should_be() {
    let models = rayforge_fuzz::corpus::seeds(Target::Ply);
    assert_eq!(models.len(), 8);
    for model in &models {
        assert_eq!(rayforge_fuzz::run_one(Target::Ply, model), Ok(true));
    }
    let parts = rayforge_fuzz::corpus::seeds(Target::Part);
    assert!(parts.len() >= 5, "{} part seeds", parts.len());
    for part in &parts {
        assert_eq!(rayforge_fuzz::run_one(Target::Part, part), Ok(true));
    }
    for request in rayforge_fuzz::corpus::seeds(Target::Page) {
        let text = String::from_utf8(request.clone()).unwrap();
        let taken = !text.starts_with("evil") && !text.contains("stop") && !text.contains("[1");
        assert_eq!(
            rayforge_fuzz::run_one(Target::Page, &request),
            Ok(taken),
            "{text}"
        );
    }
}
