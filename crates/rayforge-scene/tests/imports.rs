//! The scene reader's modules import one way: no module imports one that imports it, however
//! long the circle. Each file's `crate::`, `super::` and child-module paths are resolved to the
//! module they name, and the graph of those arrows must have no cycle (a reader of groups
//! hands itself down through `items::nesting` instead of being imported back).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module's path inside the crate, `""` for the root (`lib.rs`).
type Module = String;

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

/// `items/camera/mod.rs` is `items::camera`, `items/lights.rs` is `items::lights`.
fn module_of(src: &Path, file: &Path) -> Module {
    let relative = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts.join("::")
}

fn join(base: &str, rest: &str) -> String {
    match (base.is_empty(), rest.is_empty()) {
        (true, _) => rest.to_string(),
        (_, true) => base.to_string(),
        _ => format!("{base}::{rest}"),
    }
}

fn parent(module: &str) -> String {
    module
        .rsplit_once("::")
        .map_or(String::new(), |(p, _)| p.to_string())
}

/// The absolute path of `tail` inside module `base`.
fn below(base: &str, tail: &[String]) -> Vec<String> {
    base.split("::")
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .chain(tail.iter().cloned())
        .collect()
}

/// The longest module that `path` (absolute, from the crate root) starts with.
fn resolve(modules: &BTreeSet<Module>, path: &[String]) -> Module {
    (0..=path.len())
        .rev()
        .map(|n| path[..n].join("::"))
        .find(|m| modules.contains(m))
        .unwrap_or_default()
}

fn identifier_at(text: &str) -> &str {
    let end = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    &text[..end]
}

/// The segments of the path that starts `text` (`a::b::C`), stopping at a group or the end.
fn segments(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    loop {
        let name = identifier_at(rest);
        if name.is_empty() {
            break;
        }
        out.push(name.to_string());
        match rest[name.len()..].strip_prefix("::") {
            Some(next) => rest = next,
            None => break,
        }
    }
    out
}

/// The modules `source`, the text of module `own`, imports.
fn imports(modules: &BTreeSet<Module>, own: &str, source: &str) -> BTreeSet<Module> {
    let mut found = BTreeSet::new();
    // A file's test module (`#[cfg(test)]`, at its end by the crate's convention) is not part
    // of the reader: its `use super::*` means the file's own module, not its parent.
    for line in source.lines().take_while(|l| l.trim() != "#[cfg(test)]") {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(i) = rest.find(|c: char| c.is_ascii_alphabetic()) {
            let before = rest[..i].chars().next_back();
            rest = &rest[i..];
            let path = segments(rest);
            let skip = identifier_at(rest).len().max(1);
            if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
                rest = &rest[skip..];
                continue;
            }
            let target = match path.first().map(String::as_str) {
                Some("crate") if path.len() > 1 => Some(resolve(modules, &path[1..])),
                Some("super") => {
                    let mut base = parent(own);
                    let mut tail = &path[1..];
                    while tail.first().is_some_and(|s| s == "super") {
                        base = parent(&base);
                        tail = &tail[1..];
                    }
                    Some(resolve(modules, &below(&base, tail)))
                }
                // A path through a child module (`use camera::CameraItem;` in `items`).
                Some(first) if path.len() > 1 && modules.contains(&join(own, first)) => {
                    Some(resolve(modules, &below(own, &path)))
                }
                _ => None,
            };
            if let Some(target) = target {
                if target != own {
                    found.insert(target);
                }
            }
            rest = &rest[skip..];
        }
    }
    found
}

/// A circle in the arrows, if there is one, as the modules along it.
fn find_circle(arrows: &BTreeMap<Module, BTreeSet<Module>>) -> Option<Vec<Module>> {
    fn visit(
        node: &Module,
        arrows: &BTreeMap<Module, BTreeSet<Module>>,
        path: &mut Vec<Module>,
        finished: &mut BTreeSet<Module>,
    ) -> Option<Vec<Module>> {
        if let Some(start) = path.iter().position(|m| m == node) {
            let mut circle = path[start..].to_vec();
            circle.push(node.clone());
            return Some(circle);
        }
        if finished.contains(node) {
            return None;
        }
        path.push(node.clone());
        for next in arrows.get(node).into_iter().flatten() {
            if let Some(circle) = visit(next, arrows, path, finished) {
                return Some(circle);
            }
        }
        path.pop();
        finished.insert(node.clone());
        None
    }
    let mut finished = BTreeSet::new();
    arrows
        .keys()
        .find_map(|m| visit(m, arrows, &mut Vec::new(), &mut finished))
}

fn show(module: &str) -> &str {
    if module.is_empty() {
        "the crate root (lib.rs)"
    } else {
        module
    }
}

#[test]
fn no_module_of_the_scene_reader_imports_one_that_imports_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let files = rust_files(&src);
    let modules: BTreeSet<Module> = files.iter().map(|f| module_of(&src, f)).collect();
    assert!(modules.contains("items::camera::pinhole"), "{modules:?}");
    let mut arrows = BTreeMap::new();
    for file in &files {
        let own = module_of(&src, file);
        let source = std::fs::read_to_string(file).expect("source readable");
        arrows.insert(own.clone(), imports(&modules, &own, &source));
    }
    assert!(
        arrows[""].contains("items"),
        "the root's imports were read: {arrows:?}"
    );
    if let Some(circle) = find_circle(&arrows) {
        let names: Vec<&str> = circle.iter().map(|m| show(m)).collect();
        panic!("a circle of imports: {}", names.join(" → "));
    }
}

#[test]
fn the_checker_resolves_paths_and_finds_circles() {
    let modules: BTreeSet<Module> = ["", "items", "items::camera", "items::lights", "source"]
        .into_iter()
        .map(String::from)
        .collect();
    let found = imports(
        &modules,
        "items::camera",
        "use crate::source::{Node, Source};\nuse super::lights::light;\n// use crate::items::x;\nfn f() -> crate::Scene { todo() }\n",
    );
    let expected: BTreeSet<Module> = ["source", "items::lights", ""]
        .into_iter()
        .map(String::from)
        .collect();
    assert_eq!(found, expected);
    assert_eq!(
        imports(&modules, "items", "use camera::CameraItem;"),
        BTreeSet::from(["items::camera".to_string()])
    );
    let mut arrows: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    arrows.insert("a".into(), BTreeSet::from(["b".to_string()]));
    arrows.insert("b".into(), BTreeSet::from(["c".to_string()]));
    assert!(find_circle(&arrows).is_none());
    arrows.insert("c".into(), BTreeSet::from(["a".to_string()]));
    assert_eq!(find_circle(&arrows).map(|c| c.len()), Some(4));
}
