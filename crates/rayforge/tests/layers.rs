//! The layering rules of `docs/architecture.md`, checked: every file of the library is read, the
//! modules it names through `crate::` paths are collected, and an arrow from a module to one in
//! a higher layer (or a circle between modules of one layer, or an import through the crate
//! root's re-exports, which hides the direction) fails the test with the file and the path.
//! The scene crate is held to its own rule: it reads the scene description, never a renderer.
//!
//! A new top-level module must be added to [`LAYERS`] (the test says so) and to the table in
//! `docs/architecture.md`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's layers, lowest first: a module may import from its own layer (without a
/// circle) or any lower one. `book` is the facade of the book's API that nothing depends on.
const LAYERS: &[&[&str]] = &[
    &["color", "math"],
    &["accel", "camera", "canvas", "film", "draw2d", "options"],
    &["geometry"],
    &["shading", "media"],
    &["scene"],
    &["lights"],
    &["render", "raster"],
    &["book"],
];

/// Library modules the scene crate must not import: the renderers themselves.
const SCENE_CRATE_FORBIDDEN: &[&str] = &["render", "raster", "book"];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

/// Source text without comments (line comments and doc comments), so that prose mentioning a
/// path is not mistaken for an import.
fn strip_comments(source: &str) -> String {
    source
        .lines()
        .map(|line| match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn identifier_at(text: &str) -> &str {
    let end = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    &text[..end]
}

/// The first path segments named after `prefix` (`crate::` or `rayforge::`) in `source`,
/// including each item of a `prefix{a::.., b}` group.
fn named_after(source: &str, prefix: &str) -> BTreeSet<String> {
    let text = strip_comments(source);
    let mut names = BTreeSet::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find(prefix) {
        // `xcrate::` or `my_rayforge::` are other names.
        let before = rest[..i].chars().next_back();
        rest = &rest[i + prefix.len()..];
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        let after = rest.trim_start();
        if let Some(group) = after.strip_prefix('{') {
            let mut depth = 1;
            let mut expecting_item = true;
            for (j, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    ',' if depth == 1 => expecting_item = true,
                    c if depth == 1 && expecting_item && !c.is_whitespace() => {
                        let name = identifier_at(&group[j..]);
                        if !name.is_empty() {
                            names.insert(name.to_string());
                        }
                        expecting_item = false;
                    }
                    _ => {}
                }
            }
        } else {
            let name = identifier_at(after);
            if !name.is_empty() {
                names.insert(name.to_string());
            }
        }
    }
    names
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = walkdir::WalkDir::new(dir)
        .into_iter()
        .map(|entry| entry.expect("source directory readable").into_path())
        .filter(|path| path.extension().is_some_and(|e| e == "rs"))
        .collect();
    files.sort();
    files
}

/// The top-level module a file of `src` belongs to (`None` for `lib.rs`).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let relative = file.strip_prefix(src).ok()?;
    let first = relative.components().next()?.as_os_str().to_str()?;
    if first == "lib.rs" {
        return None;
    }
    Some(first.trim_end_matches(".rs").to_string())
}

/// The arrows between the library's modules: (from, to) with the files that draw each.
type Arrows = BTreeMap<(String, String), Vec<String>>;

/// Checks one file's imports against the layers, adding its arrows; returns the violations.
fn check_file(module: &str, file: &str, source: &str, arrows: &mut Arrows) -> Vec<String> {
    let mut problems = Vec::new();
    let Some(own) = layer_of(module) else {
        return vec![format!(
            "{file}: module `{module}` is in no layer: add it to LAYERS in tests/layers.rs and to docs/architecture.md"
        )];
    };
    for name in named_after(source, "crate::") {
        let Some(theirs) = layer_of(&name) else {
            problems.push(format!(
                "{file}: `crate::{name}` goes through the crate root's re-exports (or names a module in no layer); import from the module that defines it"
            ));
            continue;
        };
        if name == module {
            continue;
        }
        if theirs > own {
            problems.push(format!(
                "{file}: `{module}` (layer {own}) imports `{name}` (layer {theirs}), an arrow running back up"
            ));
        }
        arrows
            .entry((module.to_string(), name))
            .or_default()
            .push(file.to_string());
    }
    problems
}

/// Circles among the arrows (within one layer: arrows across layers already point down).
fn circles(arrows: &Arrows) -> Vec<String> {
    let mut problems = Vec::new();
    for ((from, to), files) in arrows {
        if let Some(back) = arrows.get(&(to.clone(), from.clone())) {
            if from < to {
                problems.push(format!(
                    "`{from}` and `{to}` import each other ({} and {})",
                    files.join(", "),
                    back.join(", ")
                ));
            }
        }
    }
    problems
}

fn workspace_crate(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(name)
        .join("src")
}

#[test]
fn the_library_s_modules_import_only_their_own_layer_or_lower_ones() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut arrows = Arrows::new();
    let mut problems = Vec::new();
    let files = rust_files(&src);
    assert!(files.len() > 20, "the library's sources were found");
    for file in &files {
        let Some(module) = module_of(&src, file) else {
            continue;
        };
        let source = std::fs::read_to_string(file).expect("source readable");
        let shown = file
            .strip_prefix(&src)
            .unwrap_or(file)
            .display()
            .to_string();
        problems.extend(check_file(&module, &shown, &source, &mut arrows));
    }
    problems.extend(circles(&arrows));
    assert!(
        problems.is_empty(),
        "layering rules broken:\n{}",
        problems.join("\n")
    );
    // Nothing in the library leans on the book's facade.
    assert!(
        !arrows
            .keys()
            .any(|(from, to)| to == "book" && from != "book"),
        "the book facade is imported: {arrows:?}"
    );
}

#[test]
fn the_scene_crate_reads_descriptions_and_never_a_renderer() {
    let src = workspace_crate("rayforge-scene");
    let mut problems = Vec::new();
    for file in rust_files(&src) {
        let source = std::fs::read_to_string(&file).expect("source readable");
        for name in named_after(&source, "rayforge::") {
            if SCENE_CRATE_FORBIDDEN.contains(&name.as_str()) {
                problems.push(format!("{}: imports `rayforge::{name}`", file.display()));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checker_sees_arrows_back_up_root_imports_and_circles() {
    let mut arrows = Arrows::new();
    // A plain path, a group, and a path inside a function body.
    let bad = "use crate::render::Sampling;\nuse crate::{math::Ray, scene::Object};\nfn f() { crate::raster::draw(); }\n// crate::book is only prose\n";
    let problems = check_file("geometry", "geometry/x.rs", bad, &mut arrows);
    assert_eq!(problems.len(), 3, "{problems:?}");
    assert!(problems.iter().any(|p| p.contains("imports `render`")));
    assert!(problems.iter().any(|p| p.contains("imports `scene`")));
    assert!(problems.iter().any(|p| p.contains("imports `raster`")));
    assert!(check_file(
        "geometry",
        "g.rs",
        "use crate::{Color, math::Ray};",
        &mut arrows
    )
    .iter()
    .any(|p| p.contains("crate::Color")));
    assert!(check_file("nowhere", "n.rs", "", &mut arrows)[0].contains("in no layer"));
    let mut two = Arrows::new();
    check_file("camera", "camera/a.rs", "use crate::film::Film;", &mut two);
    check_file("film", "film/b.rs", "use crate::camera::Camera;", &mut two);
    assert_eq!(circles(&two).len(), 1);
    assert!(named_after("use rayforge::{raster::X, math};", "rayforge::").contains("raster"));
    assert!(!named_after("use my_rayforge::raster::X;", "rayforge::").contains("raster"));
}
