//! Participating media read from scenes as a fuzz target: [`run`] writes a scene that makes
//! a medium (pbrt-v4's `MakeNamedMedium` of each type, or a YAML `medium:` item) into a
//! folder of its own, reads it with the scene reader, and path traces what it built at 3 × 2
//! pixels with the medium around the camera and inside a sphere. An input is read one of two
//! ways:
//!
//! - **text**, when it starts with a letter, `#`, `-` or white space (the seeds in
//!   `corpus/media/`): a YAML scene when its first character is `-` (or `#` before one), else
//!   a pbrt-v4 scene, up to the first line `#file NAME`, each such line starting the file
//!   `NAME` of the folder (as in the `pbrt` target);
//! - **choices**, otherwise (what a random engine makes): each byte picks the next choice of
//!   a template (a pbrt-v4 scene when the first byte is even, else a YAML scene of a
//!   homogeneous, grid or cloud medium): the medium's type, which parameters it gives and their values from [`NUMBERS`] (huge, negative, NaN,
//!   past 32 and 64 bits), grid sizes whose product overflows, and data as long as the grid,
//!   one off, or unrelated; so that random bytes reach the media's readers and the renderer
//!   rather than the lexer's first refusal.
//!
//! The folder always holds three Mitsuba `.vol` files beside the scene (a 2 × 2 × 1 grid, a
//! header claiming (2³¹ − 1)³ samples, one claiming negative sizes), and a fourth made from
//! the input's own bytes, which the scenes may name. Kept a plain function of the input's
//! bytes, so that any engine can call it.

use super::check_error;
use rayforge::film::{Film, SharedFilm};
use rayforge::options::PathOptions;
use rayforge::render::path::{render_path, PathJob};
use rayforge::{Camera, World};
use rayforge_scene::{load_file_with, LoadOptions};
use std::path::{Path, PathBuf};

/// The numbers a choice picks from: ordinary, edge and hostile values (for an integer
/// parameter too, whose reader must refuse what is not one).
pub const NUMBERS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "0.5",
    "-1",
    "-0.25",
    "0.99",
    "1.5",
    "4",
    "16",
    "512",
    "513",
    "100000",
    "2147483647",
    "4294967296",
    "18446744073709551616",
    "1e30",
    "-1e30",
    "1e300",
    "1e-300",
    "nan",
    "inf",
    "-inf",
];

/// The pbrt-v4 medium types tried (and two that are refused).
const PBRT_TYPES: &[&str] = &[
    "homogeneous",
    "uniformgrid",
    "rgbgrid",
    "cloud",
    "nanovdb",
    "",
];

/// Runs one input (see the [module](self)); whether the reader accepted the scene. An error
/// must say something and, when it points into the scene written, lie inside its text.
pub fn run(input: &[u8]) -> bool {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::tempdir().expect("a scratch folder");
    }
    let (main, files) = files_of(input);
    let Some(folder) = DIR.with(|dir| write_files(dir.path(), &files, input)) else {
        return false;
    };
    let path = folder.join(&main);
    let text = files
        .iter()
        .find(|(name, _)| *name == main)
        .map(|(_, text)| text.clone())
        .unwrap_or_default();
    let options = LoadOptions {
        max_triangles: super::FUZZ_MAX_TRIANGLES,
        pbrt: super::pbrt::FUZZ_LIMITS,
        ..LoadOptions::default()
    };
    match load_file_with(&path, &options) {
        Ok(scene) => {
            for w in &scene.warnings {
                check_error(w, &path, &text);
            }
            tiny_path_render(&scene.camera.resized(3, 2), &scene.world);
            true
        }
        Err(e) => {
            check_error(&e, &path, &text);
            false
        }
    }
}

/// The scene's file name and the files of the folder, by name (see the [module](self)).
fn files_of(input: &[u8]) -> (String, Vec<(String, String)>) {
    let as_text = input.first().is_none_or(|b| {
        b.is_ascii_alphabetic() || *b == b'#' || *b == b'-' || b.is_ascii_whitespace()
    });
    if !as_text {
        let mut choices = Choices(input[1..].iter());
        return if input[0] % 2 == 0 {
            (
                "main.pbrt".into(),
                vec![("main.pbrt".into(), pbrt_scene(&mut choices))],
            )
        } else {
            (
                "main.yml".into(),
                vec![("main.yml".into(), yaml_scene(&mut choices))],
            )
        };
    }
    let text = String::from_utf8_lossy(input);
    let yaml = text
        .lines()
        .find(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .is_some_and(|l| l.starts_with('-'));
    let main = if yaml { "main.yml" } else { "main.pbrt" };
    let mut files = vec![(main.to_string(), String::new())];
    for line in text.split_inclusive('\n') {
        match line.strip_prefix("#file ") {
            Some(name) => files.push((plain_name(name.trim()), String::new())),
            None => files.last_mut().expect("main is first").1.push_str(line),
        }
    }
    files.retain(|(name, _)| !name.is_empty());
    (main.to_string(), files)
}

/// `name` as a plain file name of the folder (see the `pbrt` target's).
fn plain_name(name: &str) -> String {
    let kept: String = name
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || ".-_".contains(*c))
        .collect();
    kept.trim_start_matches('.').to_string()
}

/// The input's bytes as a template's choices; past its end every choice is the first.
struct Choices<'a>(std::slice::Iter<'a, u8>);

impl Choices<'_> {
    /// A number below `n` (at least 1).
    fn pick(&mut self, n: usize) -> usize {
        self.0.next().map_or(0, |&b| usize::from(b) % n)
    }

    /// Whether to give the next optional part (the first of a byte's two halves).
    fn give(&mut self) -> bool {
        self.pick(2) == 0
    }

    /// One of [`NUMBERS`].
    fn number(&mut self) -> &'static str {
        NUMBERS[self.pick(NUMBERS.len())]
    }

    /// `n` numbers, space-separated.
    fn numbers(&mut self, n: usize) -> String {
        (0..n).map(|_| self.number()).collect::<Vec<_>>().join(" ")
    }

    /// How many values a grid's data holds: as many as its samples (when that is small), one
    /// fewer or more, none, one, or a few.
    fn count(&mut self, samples: Option<usize>) -> usize {
        let exact = samples.filter(|&n| n <= 4096);
        match (self.pick(6), exact) {
            (0 | 1, Some(n)) => n,
            (2, Some(n)) => n.saturating_sub(1),
            (3, Some(n)) => n + 1,
            (4, _) => 0,
            (_, _) => 1 + self.pick(27),
        }
    }

    /// A grid's three sizes as the scene writes them, and how many samples they make when
    /// they are whole numbers that fit.
    fn sizes(&mut self) -> ([&'static str; 3], Option<usize>) {
        let size = [0, 1, 2].map(|_| self.number());
        let samples = size.iter().try_fold(1usize, |n, s| {
            s.parse::<usize>().ok().and_then(|s| n.checked_mul(s))
        });
        (size, samples)
    }
}

/// A pbrt-v4 scene from `choices`: a camera inside the medium `m`, a light, and a sphere
/// bounding it, `m` of a type with parameters picked.
fn pbrt_scene(choices: &mut Choices<'_>) -> String {
    let kind = PBRT_TYPES[choices.pick(PBRT_TYPES.len())];
    let mut medium = format!("MakeNamedMedium \"m\" \"string type\" \"{kind}\"\n");
    let (size, samples) = choices.sizes();
    for (axis, n) in ["nx", "ny", "nz"].iter().zip(size) {
        if choices.give() {
            medium.push_str(&format!("  \"integer {axis}\" {n}\n"));
        }
    }
    for (name, kind, per) in [
        ("density", "float", 1),
        ("sigma_a", "rgb", 3),
        ("sigma_s", "rgb", 3),
        ("Le", "rgb", 3),
        ("Lescale", "float", 1),
        ("temperature", "float", 1),
    ] {
        if choices.give() {
            // As many values as the grid takes, or not; or one value (a homogeneous medium's
            // or a cloud's own parameter).
            let n = if choices.give() {
                per
            } else {
                per * choices.count(samples)
            };
            medium.push_str(&format!("  \"{kind} {name}\" [ {} ]\n", choices.numbers(n)));
        }
    }
    for (name, kind, n) in [
        ("scale", "float", 1),
        ("g", "float", 1),
        ("Lescale", "float", 1),
        ("wispiness", "float", 1),
        ("frequency", "float", 1),
        ("temperatureoffset", "float", 1),
        ("temperaturescale", "float", 1),
        ("p0", "point3", 3),
        ("p1", "point3", 3),
    ] {
        if choices.give() {
            medium.push_str(&format!("  \"{kind} {name}\" [ {} ]\n", choices.numbers(n)));
        }
    }
    if choices.give() {
        let preset = ["Wholemilk", "Ketchup", "no such medium"][choices.pick(3)];
        medium.push_str(&format!("  \"string preset\" \"{preset}\"\n"));
    }
    let placement = if choices.give() {
        format!("Scale {}\n", choices.numbers(3))
    } else {
        String::new()
    };
    let radius = choices.number();
    let camera_medium = if choices.give() {
        "MediumInterface \"\" \"m\"\n"
    } else {
        ""
    };
    format!(
        "LookAt 0.5 0.5 -2  0.5 0.5 0.5  0 1 0\n{camera_medium}\
         Camera \"perspective\" \"float fov\" 45\n\
         Film \"rgb\" \"integer xresolution\" 3 \"integer yresolution\" 2\n\
         WorldBegin\n\
         LightSource \"point\" \"rgb I\" [4 4 4] \"point3 from\" [0.5 2 -1]\n\
         AttributeBegin\n{placement}{medium}AttributeEnd\n\
         AttributeBegin\nMediumInterface \"m\" \"\"\nMaterial \"interface\"\n\
         Translate 0.5 0.5 0.5\nShape \"sphere\" \"float radius\" {radius}\nAttributeEnd\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 -1 -2 3 -1 -2 3 -1 3] \
         \"integer indices\" [0 1 2]\n"
    )
}

/// A YAML scene from `choices`: the medium `m` (homogeneous or a grid, from `data` or a
/// `.vol` file), the camera in it or the world's medium, a light, and a sphere bounding it.
fn yaml_scene(choices: &mut Choices<'_>) -> String {
    let kind = ["homogeneous", "grid", "cloud", "smoke"][choices.pick(4)];
    let mut medium = format!("- medium: m\n  type: {kind}\n");
    let triple = |choices: &mut Choices<'_>| format!("[{}]", choices.numbers(3).replace(' ', ", "));
    for key in ["sigma-a", "sigma-s", "albedo", "emission"] {
        if choices.give() {
            let value = if choices.give() {
                choices.number().to_string()
            } else {
                triple(choices)
            };
            medium.push_str(&format!("  {key}: {value}\n"));
        }
    }
    for key in ["density", "scale", "g", "wispiness", "frequency"] {
        if choices.give() {
            medium.push_str(&format!("  {key}: {}\n", choices.number()));
        }
    }
    let (size, samples) = choices.sizes();
    if choices.give() {
        medium.push_str(&format!("  size: [{}]\n", size.join(", ")));
    }
    match choices.pick(3) {
        0 => {
            let n = choices.count(samples);
            medium.push_str(&format!(
                "  data: [{}]\n",
                choices.numbers(n).replace(' ', ", ")
            ));
        }
        1 => {
            let file = [
                "grid.vol",
                "huge.vol",
                "negative.vol",
                "input.vol",
                "none.vol",
            ][choices.pick(5)];
            medium.push_str(&format!("  file: {file}\n"));
        }
        _ => {}
    }
    if choices.give() {
        medium.push_str(&format!(
            "  bounds: [{}, {}]\n",
            triple(choices),
            triple(choices)
        ));
    }
    if choices.give() {
        medium.push_str(&format!(
            "  transform: [[scale, {}]]\n",
            choices.numbers(3).replace(' ', ", ")
        ));
    }
    let around = if choices.give() {
        "- world:\n    medium: m\n"
    } else {
        ""
    };
    let camera_medium = if around.is_empty() && choices.give() {
        "  medium: m\n"
    } else {
        ""
    };
    let radius = choices.number();
    format!(
        "{medium}{around}- add: camera\n  width: 3\n  height: 2\n  field-of-view: 1\n  \
         from: [0.5, 0.5, -2]\n  to: [0.5, 0.5, 0.5]\n  up: [0, 1, 0]\n{camera_medium}\
         - add: light\n  at: [0.5, 2, -1]\n  intensity: [1, 1, 1]\n\
         - add: sphere\n  material: interface\n  interior: m\n  \
         transform: [[scale, {radius}, {radius}, {radius}], [translate, 0.5, 0.5, 0.5]]\n\
         - add: plane\n  transform: [[translate, 0, -1, 0]]\n"
    )
}

/// A Mitsuba grid volume's bytes: its header (version 3, encoding 1, `size`, one channel,
/// the unit box) and `values`.
pub fn vol(size: [i32; 3], values: &[f32]) -> Vec<u8> {
    let mut bytes = b"VOL\x03".to_vec();
    for i in [1, size[0], size[1], size[2], 1] {
        bytes.extend(i.to_le_bytes());
    }
    for f in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        bytes.extend(f.to_le_bytes());
    }
    for v in values {
        bytes.extend(v.to_le_bytes());
    }
    bytes
}

/// Writes `files` and the `.vol` files (see the [module](self)) into a fresh folder under
/// `dir`, the last input's files gone first.
fn write_files(dir: &Path, files: &[(String, String)], input: &[u8]) -> Option<PathBuf> {
    let folder = dir.join("scene");
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir(&folder).ok()?;
    let vols = [
        ("grid.vol", vol([2, 2, 1], &[0.0, 1.0, 0.5, 2.0])),
        ("huge.vol", vol([i32::MAX; 3], &[1.0; 4])),
        ("negative.vol", vol([-1, 2, -3], &[1.0; 6])),
    ];
    for (name, bytes) in &vols {
        std::fs::write(folder.join(name), bytes).ok()?;
    }
    // The input's own bytes after a header: a `.vol` of its first 12 bytes as sizes.
    let mut own = b"VOL\x03\x01\0\0\0".to_vec();
    own.extend_from_slice(input);
    std::fs::write(folder.join("input.vol"), own).ok()?;
    for (name, text) in files {
        std::fs::write(folder.join(name), text).ok()?;
    }
    Some(folder)
}

/// The scene path traced: 2 samples a pixel, 3 bounces at most.
fn tiny_path_render(camera: &Camera, world: &World) {
    let job = PathJob::new(
        PathOptions {
            max_depth: 3,
            ..PathOptions::default()
        },
        0..2,
    );
    let film = SharedFilm::from(Film::new(camera.hsize(), camera.vsize()));
    let mut done = vec![false; camera.vsize()];
    let rendered = render_path(camera, world, &job, &film, None, &mut done);
    assert!(rendered.is_ok(), "the films are the camera's: {rendered:?}");
}
