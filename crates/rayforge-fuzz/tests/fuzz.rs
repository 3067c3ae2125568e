//! Every fuzz target as a test on the bolero engine.
//!
//! `cargo test -p rayforge-fuzz --test fuzz` replays each target's seeds (`corpus::seeds`:
//! deterministic, a few seconds) and then what bolero keeps in `tests/__fuzz__/NAME/`
//! (inputs a fuzzing run saved, its crashes). Fuzzing proper, for a time budget:
//!
//! - stable Rust, bolero's random engine:
//!   `BOLERO_RANDOM_TEST_TIME_MS=3600000 cargo test --release -p rayforge-fuzz --test fuzz scene`
//! - coverage-guided, libFuzzer (nightly; `cargo install cargo-bolero`):
//!   `cargo bolero test -p rayforge-fuzz scene --toolchain nightly --sanitizer NONE -T 3600s`
//!
//! See `docs/reliability.md`. A new target is one line below (and its seeds in `corpus/NAME/`).

use rayforge_fuzz::corpus;

/// `fuzz_target!(NAME)`: the test `NAME` of the target `rayforge_fuzz::targets::NAME` (any
/// function of `&[u8]`; what it returns is ignored). The bolero macro is expanded here, in the
/// test, as bolero finds its targets by their test's path.
macro_rules! fuzz_target {
    ($name:ident) => {
        #[test]
        fn $name() {
            let name = stringify!($name);
            let target = |input: &[u8]| {
                rayforge_fuzz::targets::$name(input);
            };
            prepare(name, &target);
            bolero::check!(name = name)
                .with_max_len(corpus::MAX_LEN)
                .with_iterations(random_inputs())
                .for_each(target);
        }
    };
}

fuzz_target!(scene);
fuzz_target!(obj);
fuzz_target!(gltf);
fuzz_target!(ply);
fuzz_target!(pbrt);
fuzz_target!(media);
fuzz_target!(denoise);
fuzz_target!(image);
fuzz_target!(part);
fuzz_target!(page);

/// Before the engine runs: under `cargo test`, every seed of the target, each a failure of
/// its own if it panics; under `cargo bolero test` (`--cfg fuzzing`), the seeds written into
/// the engine's corpus, where it starts from them.
fn prepare(name: &str, target: &dyn Fn(&[u8])) {
    if cfg!(fuzzing) {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/__fuzz__")
            .join(name)
            .join("corpus");
        let n = corpus::write_seeds(name, &dir).expect("the engine's corpus folder");
        eprintln!("{name}: {n} seeds in {}", dir.display());
        return;
    }
    let seeds = corpus::seeds(name);
    for (i, seed) in seeds.iter().enumerate() {
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| target(seed)));
        assert!(
            run.is_ok(),
            "{name}: seed {i} of {} ({} bytes) panicked (the message is above)",
            seeds.len(),
            seed.len()
        );
    }
}

/// Random inputs after the replay: none (a test is deterministic), unless a time budget is
/// given in `BOLERO_RANDOM_TEST_TIME_MS`; `BOLERO_RANDOM_ITERATIONS` sets a count instead
/// (bolero reads both, and either takes precedence over this).
fn random_inputs() -> usize {
    if std::env::var_os("BOLERO_RANDOM_TEST_TIME_MS").is_some() {
        usize::MAX
    } else {
        0
    }
}

/// The seeds reach past the first checks: every part merges, every medium is read and
/// rendered, every denoiser input taken, and the page's requests from
/// this machine's browser are taken while the one from another site is refused. (A seed that
/// is refused at once would leave the fuzzer mutating only the refusal.)
#[test]
fn the_seeds_are_accepted_where_they_should_be() {
    let parts = corpus::seeds("part");
    let models = corpus::seeds("ply");
    assert_eq!(models.len(), 8);
    for model in &models {
        assert!(rayforge_fuzz::targets::ply(model));
    }
    // broken.pbrt, curves.pbrt, displaced.pbrt, includes.pbrt, patches.pbrt, room.pbrt,
    // sky-square.pbrt, textures-sky-media.pbrt, then the four read as words (the last includes
    // itself past the depth).
    let scenes: Vec<bool> = corpus::seeds("pbrt")
        .iter()
        .map(|s| rayforge_fuzz::targets::pbrt(s))
        .collect();
    assert_eq!(
        scenes,
        [false, true, true, true, true, true, true, true, true, true, true, false]
    );
    // cloud.pbrt, grid.yml, homogeneous.pbrt, rgbgrid.pbrt, uniformgrid.pbrt, vol.yml: every
    // medium type of both formats read and path traced.
    let media = corpus::seeds("media");
    assert_eq!(media.len(), 6);
    for scene in &media {
        assert!(
            rayforge_fuzz::targets::media(scene),
            "{}",
            String::from_utf8_lossy(scene)
        );
    }
    // A PFM image; PFM guides of its size; an OpenEXR with its albedo and normal layers; an
    // OpenEXR guide beside a PFM image.
    let images = corpus::seeds("denoise");
    assert_eq!(images.len(), 4);
    for image in &images {
        assert!(rayforge_fuzz::targets::denoise(image));
    }
    assert!(parts.len() >= 5, "{} part seeds", parts.len());
    for part in &parts {
        assert!(rayforge_fuzz::targets::part(part));
    }
    for request in corpus::seeds("page") {
        let text = String::from_utf8(request.clone()).unwrap();
        let taken = !text.starts_with("evil") && !text.contains("stop") && !text.contains("[1");
        assert_eq!(rayforge_fuzz::targets::page(&request), taken, "{text}");
    }
}
