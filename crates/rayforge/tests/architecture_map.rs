//! `docs/architecture.md` names every source file of the workspace: a file the map does not
//! mention is one a newcomer cannot find from it. A file counts as named where the map has,
//! in backticks, its path below its crate's `src/` or a tail of that path (`index.rs`,
//! `scene/index.rs`); a `mod.rs` also by its folder (`mesh/`). `lib.rs` and `main.rs` are the
//! crates themselves.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Every backticked word of the map (no spaces inside).
fn backticked(doc: &str) -> BTreeSet<String> {
    doc.split('`')
        .skip(1)
        .step_by(2)
        .filter(|t| !t.is_empty() && !t.contains(char::is_whitespace))
        .map(str::to_owned)
        .collect()
}

/// The names by which the map may name `path` (relative to its crate's `src/`).
fn names_of(path: &Path) -> Vec<String> {
    let parts: Vec<String> = path
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let mut names: Vec<String> = (0..parts.len()).map(|i| parts[i..].join("/")).collect();
    if parts.last().is_some_and(|f| f == "mod.rs") {
        let folder = &parts[..parts.len() - 1];
        names.extend((0..folder.len()).map(|i| format!("{}/", folder[i..].join("/"))));
    }
    names
}

fn is_named(tokens: &BTreeSet<String>, path: &Path) -> bool {
    names_of(path).iter().any(|name| {
        tokens.contains(name)
            || tokens
                .iter()
                .any(|t| t.ends_with(&format!("/{name}")) || t.ends_with(&format!("/{name}/")))
    })
}

fn sources(src: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = walkdir::WalkDir::new(src)
        .into_iter()
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == "rs"))
        .map(|e| e.path().strip_prefix(src).unwrap().to_path_buf())
        .filter(|p| p != Path::new("lib.rs") && p != Path::new("main.rs"))
        .collect();
    files.sort();
    files
}

#[test]
fn the_architecture_map_names_every_source_file() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let doc = std::fs::read_to_string(crates.join("../docs/architecture.md")).unwrap();
    let tokens = backticked(&doc);
    let mut unnamed = Vec::new();
    let mut checked = 0;
    for entry in std::fs::read_dir(&crates).unwrap() {
        let src = entry.unwrap().path().join("src");
        if !src.is_dir() {
            continue;
        }
        for file in sources(&src) {
            checked += 1;
            if !is_named(&tokens, &file) {
                unnamed.push(src.join(&file).display().to_string());
            }
        }
    }
    assert!(checked > 100, "only {checked} source files found");
    assert!(
        unnamed.is_empty(),
        "docs/architecture.md does not name these files (add each where it belongs):\n{}",
        unnamed.join("\n")
    );
}

#[test]
fn a_file_is_named_by_a_tail_of_its_path_or_its_folder() {
    let tokens = backticked("the `scene/index.rs` and `accel/` map; `mesh/`, `x y`");
    assert!(is_named(&tokens, Path::new("scene/index.rs")));
    assert!(is_named(&tokens, Path::new("accel/mod.rs")));
    assert!(is_named(&tokens, Path::new("geometry/mesh/mod.rs")));
    assert!(!is_named(&tokens, Path::new("scene/world.rs")));
    assert!(!is_named(&tokens, Path::new("index.rs/other.rs")));
}
