//! The pbrt-v4 reader as a fuzz target: [`run`] writes the input as a scene's files into a
//! folder of its own and reads the top-level one with small limits, then renders what the
//! reader made of it. An input is read one of two ways:
//!
//! - **text**, when it starts with a letter, `#` or white space (the seeds in
//!   `corpus/pbrt/`): the top-level file `main.pbrt` up to the first line `#file NAME`, then
//!   each such line starts the file `NAME` (`Include`d, `Import`ed, a `plymesh`'s PLY); a name
//!   ending in `.gz` is written gzip-compressed, so the inflater is met through `Include`;
//! - **words**, otherwise (what a random engine makes): each byte picks one of [`WORDS`]
//!   (directives, types, declarations, numbers, brackets, file names), so that random bytes
//!   are near-valid pbrt and reach past the lexer. The folder then also holds a small include,
//!   its gzip, one that includes itself, and a PLY model, which the words name.
//!
//! Kept a plain function of the input's bytes, so that any engine can call it.

use rayforge_scene::pbrt::PbrtLimits;
use rayforge_scene::{load_file_with, LoadOptions, SceneError};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Small limits, so that an input that includes a file many times or writes millions of
/// numbers is refused quickly (the defaults would let one input read a gigabyte).
pub(crate) const FUZZ_LIMITS: PbrtLimits = PbrtLimits {
    file_bytes: 1 << 20,
    total_bytes: 4 << 20,
    include_depth: 8,
    values: 1 << 20,
    lens_rows: 16,
    // Few, so that the banding of an emitting mesh of many sizes is reached too.
    radiances: 16,
};

/// The words of the second reading: one per byte value (modulo their count).
pub const WORDS: &[&str] = &[
    "WorldBegin",
    "Camera",
    "Film",
    "Sampler",
    "Integrator",
    "PixelFilter",
    "LookAt",
    "Translate",
    "Scale",
    "Rotate",
    "Transform",
    "ConcatTransform",
    "Identity",
    "CoordinateSystem",
    "CoordSysTransform",
    "ReverseOrientation",
    "ActiveTransform",
    "TransformTimes",
    "AttributeBegin",
    "AttributeEnd",
    "Attribute",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Shape",
    "Material",
    "MakeNamedMaterial",
    "NamedMaterial",
    "Texture",
    "LightSource",
    "AreaLightSource",
    "MakeNamedMedium",
    "MediumInterface",
    "Include",
    "Import",
    "ColorSpace",
    "Option",
    "\"sphere\"",
    "\"trianglemesh\"",
    "\"plymesh\"",
    "\"disk\"",
    "\"cylinder\"",
    "\"bilinearmesh\"",
    "\"diffuse\"",
    "\"conductor\"",
    "\"dielectric\"",
    "\"thindielectric\"",
    "\"coateddiffuse\"",
    "\"coatedconductor\"",
    "\"diffusetransmission\"",
    "\"interface\"",
    "\"mix\"",
    "\"point\"",
    "\"spot\"",
    "\"distant\"",
    "\"infinite\"",
    "\"perspective\"",
    "\"orthographic\"",
    "\"rgb\"",
    "\"gbuffer\"",
    "\"independent\"",
    "\"volpath\"",
    "\"gaussian\"",
    "\"box\"",
    "\"float\"",
    "\"spectrum\"",
    "\"checkerboard\"",
    "\"scale\"",
    "\"imagemap\"",
    "\"constant\"",
    "\"homogeneous\"",
    "\"All\"",
    "\"StartTime\"",
    "\"m\"",
    "\"obj\"",
    "\"tex\"",
    "\"float radius\"",
    "\"integer indices\"",
    "\"point3 P\"",
    "\"normal N\"",
    "\"point2 uv\"",
    "\"rgb reflectance\"",
    "\"spectrum eta\"",
    "\"spectrum k\"",
    "\"float roughness\"",
    "\"bool remaproughness\"",
    "\"rgb L\"",
    "\"blackbody L\"",
    "\"float scale\"",
    "\"float power\"",
    "\"bool twosided\"",
    "\"texture reflectance\"",
    "\"string filename\"",
    "\"float fov\"",
    "\"integer xresolution\"",
    "\"integer yresolution\"",
    "\"integer pixelsamples\"",
    "\"integer maxdepth\"",
    "\"float eta\"",
    "\"rgb I\"",
    "\"point3 from\"",
    "\"point3 to\"",
    "\"float coneangle\"",
    "\"float zmin\"",
    "\"float height\"",
    "\"float tex1\"",
    "\"texture displacement\"",
    "\"float edgelength\"",
    "\"float displacementedgescale\"",
    "\"rgb tex2\"",
    "\"string mapping\"",
    "\"float uscale\"",
    "\"rgb sigma_a\"",
    "\"spectrum reflectance\"",
    "\"metal-Cu-eta\"",
    "\"glass-BK7\"",
    "\"inc.pbrt\"",
    "\"inc.pbrt.gz\"",
    "\"self.pbrt\"",
    "\"m.ply\"",
    "\"uv.ply\"",
    "\"missing.pbrt\"",
    "\"../out.pbrt\"",
    "[",
    "]",
    "[",
    "]",
    "0",
    "1",
    "-1",
    "0.5",
    "2",
    "3",
    "10",
    "90",
    "-0.25",
    "1e30",
    "-1e-30",
    "nan",
    "inf",
    "4294967296",
    "true",
    "false",
    "\"true\"",
    "\"\"",
    "\"",
    "#",
    "\n",
];

/// Files every input in words has beside it (the words name them).
const HELPERS: &[(&str, &str)] = &[
    ("inc.pbrt", "Shape \"sphere\" \"float radius\" 0.5\n"),
    ("self.pbrt", "Translate 0 0 1\nInclude \"self.pbrt\"\n"),
    (
        "m.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    ),
    // With uv, so that a displacement texture named by the words can move it.
    (
        "uv.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nproperty float u\nproperty float v\nelement face 1\n\
         property list uchar int vertex_indices\nend_header\n\
         0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n",
    ),
];

/// Runs one input (see the [module](self)); whether the reader accepted it. An error must say
/// something and, when it points into one of the files written, lie inside that file's text.
pub fn run(input: &[u8]) -> bool {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::tempdir().expect("a scratch folder");
    }
    let files = files_of(input);
    let written = DIR.with(|dir| write_files(dir.path(), &files));
    let Some((folder, texts)) = written else {
        return false;
    };
    let main = folder.join("main.pbrt");
    let options = LoadOptions {
        max_triangles: super::FUZZ_MAX_TRIANGLES,
        pbrt: FUZZ_LIMITS,
        ..LoadOptions::default()
    };
    let accepted = match load_file_with(&main, &options) {
        Ok(scene) => {
            for w in &scene.warnings {
                check_error(w, &texts);
            }
            let camera = scene.camera.resized(3, 2);
            super::tiny_render(&camera, &scene.world);
            true
        }
        Err(e) => {
            check_error(&e, &texts);
            false
        }
    };
    if let Err(e) = rayforge_scene::pbrt::film_output(&main, &options) {
        check_error(&e, &texts);
    }
    accepted
}

/// The files an input stands for, by name: `main.pbrt` first (see the [module](self)).
fn files_of(input: &[u8]) -> Vec<(String, Vec<u8>)> {
    let as_text = input
        .first()
        .is_none_or(|b| b.is_ascii_alphabetic() || *b == b'#' || b.is_ascii_whitespace());
    if !as_text {
        let mut main = String::new();
        for &b in input {
            main.push_str(WORDS[usize::from(b) % WORDS.len()]);
            main.push(' ');
        }
        let mut files: Vec<(String, Vec<u8>)> = vec![("main.pbrt".into(), main.into_bytes())];
        for (name, text) in HELPERS {
            files.push((name.to_string(), text.as_bytes().to_vec()));
        }
        files.push(("inc.pbrt.gz".into(), gzip(HELPERS[0].1.as_bytes())));
        return files;
    }
    let text = String::from_utf8_lossy(input);
    let mut files = vec![("main.pbrt".to_string(), String::new())];
    for line in text.split_inclusive('\n') {
        match line.strip_prefix("#file ") {
            Some(name) => files.push((plain_name(name.trim()), String::new())),
            None => files.last_mut().expect("main is first").1.push_str(line),
        }
    }
    files
        .into_iter()
        .filter(|(name, _)| !name.is_empty())
        .map(|(name, text)| {
            let bytes = if name.ends_with(".gz") {
                gzip(text.as_bytes())
            } else {
                text.into_bytes()
            };
            (name, bytes)
        })
        .collect()
}

/// `name` as a plain file name of the folder: its letters, digits, `.`, `-` and `_`, no
/// leading dot (so never `..` nor a hidden file).
fn plain_name(name: &str) -> String {
    let kept: String = name
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || ".-_".contains(*c))
        .collect();
    kept.trim_start_matches('.').to_string()
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(bytes).expect("writing to memory");
    encoder.finish().expect("writing to memory")
}

/// Writes `files` into a fresh folder under `dir` (the last input's files gone first); the
/// folder and the texts of the files not compressed, by path.
fn write_files(
    dir: &Path,
    files: &[(String, Vec<u8>)],
) -> Option<(PathBuf, HashMap<PathBuf, String>)> {
    let folder = dir.join("scene");
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir(&folder).ok()?;
    let mut texts = HashMap::new();
    for (name, bytes) in files {
        let path = folder.join(name);
        std::fs::write(&path, bytes).ok()?;
        if !name.ends_with(".gz") {
            texts.insert(path, String::from_utf8_lossy(bytes).into_owned());
        }
    }
    Some((folder, texts))
}

/// A refusal or warning says something; a place in a file written lies within that file's
/// text, on character boundaries (the command shows that line).
fn check_error(e: &SceneError, texts: &HashMap<PathBuf, String>) {
    match texts.get(&e.path) {
        Some(text) => super::check_error(e, &e.path, text),
        None => assert!(!e.message.trim().is_empty(), "an empty message: {e}"),
    }
}

/// Seeds made here beside the corpus's text files: a few byte strings of the word reading
/// (a sphere under a light; a mesh; includes of each helper; a file that includes itself).
pub fn seeds() -> Vec<Vec<u8>> {
    let word = |w: &str| WORDS.iter().position(|x| *x == w).expect("a word") as u8;
    let sentence = |words: &[&str]| words.iter().map(|w| word(w)).collect::<Vec<u8>>();
    vec![
        sentence(&[
            "Camera",
            "\"perspective\"",
            "WorldBegin",
            "LightSource",
            "\"point\"",
            "\"rgb I\"",
            "[",
            "1",
            "1",
            "1",
            "]",
            "Shape",
            "\"sphere\"",
            "\"float radius\"",
            "2",
        ]),
        sentence(&[
            "WorldBegin",
            "Shape",
            "\"trianglemesh\"",
            "\"point3 P\"",
            "[",
            "0",
            "0",
            "0",
            "1",
            "0",
            "0",
            "0",
            "1",
            "0",
            "]",
            "\"integer indices\"",
            "[",
            "0",
            "1",
            "2",
            "]",
        ]),
        sentence(&[
            "WorldBegin",
            "Include",
            "\"inc.pbrt\"",
            "Include",
            "\"inc.pbrt.gz\"",
            "Shape",
            "\"plymesh\"",
            "\"string filename\"",
            "\"m.ply\"",
        ]),
        // Refused past the include depth.
        sentence(&["WorldBegin", "Include", "\"self.pbrt\""]),
    ]
    .into_iter()
    // A first byte that is not text, so that they are read as words.
    .filter(|s| s.first().is_some_and(|b| !b.is_ascii_alphabetic()))
    .collect()
}
