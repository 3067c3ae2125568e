//! The pbrt-v4 reader's limits, each set low through `LoadOptions::pbrt` (the command's
//! `--max-pbrt-*`): going over one is an error at the place it happened naming its flag, and
//! the same scene under the defaults reads.

use rayforge_scene::pbrt::PbrtLimits;
use rayforge_scene::{LoadOptions, SceneError};
use std::path::Path;

const HEAD: &str = "Camera \"perspective\"\nWorldBegin\n";

fn load(dir: &Path, limits: PbrtLimits) -> Result<rayforge_scene::Scene, SceneError> {
    let options = LoadOptions {
        pbrt: limits,
        ..LoadOptions::default()
    };
    rayforge_scene::load_file_with(&dir.join("s.pbrt"), &options)
}

fn refused(dir: &Path, limits: PbrtLimits, flag: &str) -> SceneError {
    assert!(
        load(dir, PbrtLimits::DEFAULT).is_ok(),
        "not read under the defaults"
    );
    let e = load(dir, limits).expect_err("read past its limit");
    assert!(e.message.contains(flag), "{flag} not named: {e}");
    e
}

#[test]
fn parameter_values_are_counted_as_they_are_read() {
    let dir = tempfile::tempdir().unwrap();
    // 3 + 9 + 1 values: the budget of 12 is spent at the radius, the 13th.
    let text = format!(
        "{HEAD}Shape \"trianglemesh\" \"integer indices\" [0 1 2]\n  \"point3 P\" [0 0 0  1 0 0  \
         0 1 0]\nShape \"sphere\" \"float radius\" 2\n"
    );
    std::fs::write(dir.path().join("s.pbrt"), &text).unwrap();
    let limits = PbrtLimits {
        values: 12,
        ..PbrtLimits::DEFAULT
    };
    let e = refused(dir.path(), limits, "--max-pbrt-values");
    let span = e.span.expect("a place");
    assert_eq!((span.line, span.column), (5, 31), "{e}");
    assert_eq!(e.key.as_deref(), Some("float radius"), "{e}");
    let enough = PbrtLimits {
        values: 13,
        ..PbrtLimits::DEFAULT
    };
    assert!(load(dir.path(), enough).is_ok());
}

#[test]
fn includes_nest_at_most_the_depth_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.pbrt"),
        format!("{HEAD}Include \"a.pbrt\"\n"),
    )
    .unwrap();
    std::fs::write(dir.path().join("a.pbrt"), "Include \"b.pbrt\"\n").unwrap();
    std::fs::write(dir.path().join("b.pbrt"), "Shape \"sphere\"\n").unwrap();
    let two = PbrtLimits {
        include_depth: 2,
        ..PbrtLimits::DEFAULT
    };
    let e = refused(dir.path(), two, "--max-pbrt-include-depth");
    assert!(e.path.ends_with("a.pbrt"), "{e}");
    let three = PbrtLimits {
        include_depth: 3,
        ..PbrtLimits::DEFAULT
    };
    assert!(load(dir.path(), three).is_ok());
}

#[test]
fn a_file_and_all_files_are_held_to_their_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{HEAD}Include \"a.pbrt\"\nInclude \"a.pbrt\"\n");
    std::fs::write(dir.path().join("s.pbrt"), &text).unwrap();
    let shape = "Shape \"sphere\" \"float radius\" 1\n";
    std::fs::write(dir.path().join("a.pbrt"), shape).unwrap();
    let (main, inner) = (text.len() as u64, shape.len() as u64);
    let small_file = PbrtLimits {
        file_bytes: main - 1,
        ..PbrtLimits::DEFAULT
    };
    refused(dir.path(), small_file, "--max-pbrt-file-bytes");
    // The included file counts each time it is read: the second time goes over.
    let small_total = PbrtLimits {
        total_bytes: main + 2 * inner - 1,
        ..PbrtLimits::DEFAULT
    };
    let e = refused(dir.path(), small_total, "--max-pbrt-total-bytes");
    assert_eq!(e.span.map(|s| s.line), Some(4), "{e}");
    let exact = PbrtLimits {
        total_bytes: main + 2 * inner,
        ..PbrtLimits::DEFAULT
    };
    assert!(load(dir.path(), exact).is_ok());
}

/// An emitting mesh with `power` is cut into a piece per size of triangle (pbrt-v4 gives each
/// triangle the power), at most `--max-pbrt-radiances` of them: past it, bands of sizes share
/// a radiance, with a warning naming the flag, and the power stays the mesh's.
#[test]
fn an_emitting_meshs_radiances_are_as_many_as_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    // Three triangles of areas 0.5, 2 and 4.5, each given power 1.
    std::fs::write(
        dir.path().join("s.pbrt"),
        format!(
            "{HEAD}AreaLightSource \"diffuse\" \"float power\" 1\n\
             Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  0 0 1  2 0 1  0 2 1  \
             0 0 2  3 0 2  0 3 2] \"integer indices\" [0 1 2  3 4 5  6 7 8]\n"
        ),
    )
    .unwrap();
    let power = |scene: &rayforge_scene::Scene| -> (usize, f64) {
        let objects = &scene.world.objects;
        let total = objects
            .iter()
            .map(|o| {
                let rayforge::Shape::Mesh(m) = &o.shape else {
                    panic!("a mesh")
                };
                let p = m.positions();
                let area: f64 = m
                    .faces()
                    .map(|f| {
                        let [a, b, c] = f.vertices.map(|i| p[i as usize]);
                        (b - a).cross(c - a).length() / 2.0
                    })
                    .sum();
                o.material.emission.green * area * std::f64::consts::PI
            })
            .sum();
        (objects.len(), total)
    };
    let all = load(dir.path(), PbrtLimits::DEFAULT).unwrap();
    assert!(all.warnings.is_empty(), "{:?}", all.warnings);
    let (pieces, total) = power(&all);
    assert_eq!(pieces, 3);
    assert!((total - 3.0).abs() < 1e-9, "{total}");
    let two = PbrtLimits {
        radiances: 2,
        ..PbrtLimits::DEFAULT
    };
    let banded = load(dir.path(), two).unwrap();
    let (pieces, total) = power(&banded);
    assert_eq!(pieces, 2);
    assert!((total - 3.0).abs() < 1e-9, "{total}");
    assert_eq!(banded.warnings.len(), 1, "{:?}", banded.warnings);
    assert!(
        banded.warnings[0].message.contains("--max-pbrt-radiances"),
        "{}",
        banded.warnings[0]
    );
}
