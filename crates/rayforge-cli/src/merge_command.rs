//! `rayforge merge PARTS... -o OUT`: the part files of a render's slices joined into its image.
//!
//! The headers are read first, so that parts of different renders, a slice given twice or
//! missing slices are refused before any film is read. The films are then added one at a time,
//! in slice order (so the sums of a cut by samples are added in the same order whatever order
//! the parts are given in), into one film of the image's size, which is developed and written
//! exactly as `rayforge render` develops and writes that renderer's film: the same functions,
//! the optics model's exposure and the scene's canvas items included. Path-traced parts
//! rendered with `--aovs` carry their AOVs, merged beside the image: `merge --aovs` writes
//! them as `render --aovs` does, and `merge --denoise` denoises the merged image guided by the
//! merged albedo and normal (a denoiser must see the whole image, so slices are not denoised).

use crate::args::MergeArgs;
use crate::atomic_write::{check_writable, not_an_input};
use crate::diagnostics::scene_failure;
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::memory::reserve_for_merge;
use crate::output_lock::OutputLock;
use crate::part_file::{scene_fingerprint, Development, Part, PartHeader, PART_AOVS};
use crate::path_output::PathOutputs;
use crate::render_command::{camera_at, develop_book_image, write_image_as};
use crate::slice::{Slice, MAX_SLICES};
use crate::summary::non_finite_warning;
use rayforge::camera::Camera;
use rayforge::draw2d::Overlay;
use rayforge_scene::files::read_bounded;
use rayforge_scene::{clip, LoadOptions};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How many missing slices an error lists before it says how many more there are.
const LISTED_MISSING: usize = 20;

/// The longest `--list` file read: a name a line for the most slices a render is cut into.
const MAX_LIST_BYTES: u64 = 1 << 28;

/// Runs the merge command.
pub fn run(args: &MergeArgs) -> Result<(), Failure> {
    let output = args.output.as_path();
    let format = ImageFormat::from_path(output)?;
    check_writable(output)?;
    let _lock = OutputLock::acquire(output)?;
    let started = Instant::now();
    let parts = part_paths(args)?;
    let inputs = parts.iter().map(|p| (p.as_path(), "the part"));
    let listed = args.list.iter().map(|p| (p.as_path(), "the list of parts"));
    let scene = args.scene.iter().map(|p| (p.as_path(), "the scene file"));
    not_an_input(output, inputs.chain(listed).chain(scene))?;
    let (first, slices) = in_slice_order(&parts)?;
    check_companions(args, &first)?;
    // Loaded before the films are read: without the library the merge is refused at once.
    let denoiser = args
        .denoise
        .then(|| crate::denoise::load("--denoise"))
        .transpose()?;
    if denoiser.is_some() && !first.aovs && !args.quiet {
        eprintln!(
            "warning: the parts hold no albedo and normals (their slices were rendered without \
             --aovs): the image is denoised without guides, which blurs its textures and edges \
             more; render the slices with --aovs for a guided denoise"
        );
    }
    let overlay = if first.overlay {
        Some(scene_overlay(args, &first)?)
    } else {
        None
    };
    let overlay = overlay.as_ref().map(|(o, camera)| (o, camera));
    let threads = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
    let session = denoiser.as_ref().map(|d| d.session(threads));
    let outputs = PathOutputs {
        output,
        format,
        aovs: args.aovs,
        denoiser: session.as_ref(),
        overlay,
    };
    outputs.check_writable()?;
    // The AOVs are merged only where they are written or guide the denoiser.
    let keep_aovs = first.aovs && (args.aovs || args.denoise);
    // Slice 0 covers the most rows (all of them when cut by samples).
    let largest = Slice {
        index: 0,
        ..first.slice
    };
    let films = if keep_aovs { 1 + PART_AOVS as u64 } else { 1 };
    let rows = largest.row_count(first.height);
    reserve_for_merge(first.width, first.height, rows, films)?;
    let mut merged = None;
    for (index, path) in slices {
        let part = Part::read(path)?;
        if part.header.slice.index != index || first.differs_from(&part.header).is_some() {
            return Err(Failure::usage(format!(
                "`{}` changed while it was being merged",
                path.display()
            )));
        }
        let films = match &mut merged {
            Some(films) => films,
            None => {
                let mut films = part
                    .empty_image_films()
                    .map_err(|e| Failure::usage(format!("`{}`: {e}", path.display())))?;
                if !keep_aovs {
                    films.aovs = None;
                }
                merged.insert(films)
            }
        };
        part.add_to(films)
            .map_err(|e| Failure::usage(format!("`{}`: {e}", path.display())))?;
    }
    let Some(merged) = merged else {
        return Err(Failure::internal("no part was read"));
    };
    let merged = merged.finished();
    let non_finite = match first.development {
        Development::Book(exposure) => {
            let (canvas, non_finite) = develop_book_image(&merged.film, exposure, overlay);
            write_image_as(format, &canvas, output)?;
            vec![(non_finite, output.to_path_buf())]
        }
        Development::Path => {
            let aovs = merged.aovs.map(|aovs| aovs.map(|film| film.resolve()));
            outputs.write(merged.film.resolve(), aovs, |_| ())?
        }
    };
    if !args.quiet {
        eprintln!(
            "merged {} slices (by {}) of {}×{} into `{}`{} in {:.2} s",
            first.slice.count,
            first.slice.cut.name(),
            first.width,
            first.height,
            output.display(),
            if denoiser.is_some() {
                ", denoised,"
            } else {
                ""
            },
            started.elapsed().as_secs_f64()
        );
        for (pixels, path) in non_finite {
            if let Some(warning) = non_finite_warning(pixels, &path) {
                eprintln!("{warning}");
            }
        }
    }
    Ok(())
}

/// Refuses `--aovs` and `--denoise` where the parts cannot give them: AOVs only from parts
/// that hold them, either only for the path tracer's images.
fn check_companions(args: &MergeArgs, first: &PartHeader) -> Result<(), Failure> {
    let asked = [("--aovs", args.aovs), ("--denoise", args.denoise)];
    let Some((flag, _)) = asked.iter().find(|(_, given)| *given) else {
        return Ok(());
    };
    if first.development != Development::Path {
        return Err(Failure::usage(format!(
            "{flag} is for path-traced images: these parts are not the path tracer's (their \
             slices were rendered without --renderer path)"
        )));
    }
    if args.aovs && !first.aovs {
        return Err(Failure::usage(
            "--aovs: the parts hold no AOVs; render the slices with --aovs (each part then \
             keeps its albedo, normal, depth and sample count) to merge them",
        ));
    }
    Ok(())
}

/// The parts to merge: those named on the command line, then those `--list` names, at most
/// as many as a render has slices.
fn part_paths(args: &MergeArgs) -> Result<Vec<PathBuf>, Failure> {
    let mut parts = args.parts.clone();
    if let Some(list) = &args.list {
        parts.extend(read_list(list)?);
    }
    if parts.is_empty() {
        return Err(Failure::usage(format!(
            "`{}` names no part file",
            args.list.as_deref().unwrap_or(Path::new("")).display()
        )));
    }
    if parts.len() as u64 > MAX_SLICES {
        return Err(Failure::usage(format!(
            "{} part files are more than the {MAX_SLICES} slices a render may be cut into",
            parts.len()
        )));
    }
    Ok(parts)
}

/// The part files a `--list` file names: one a line, blank lines skipped, relative names
/// taken from the list's folder. The file is read as input from outside (a regular file of at
/// most [`MAX_LIST_BYTES`]); a line that is not UTF-8 is refused, naming it.
fn read_list(list: &Path) -> Result<Vec<PathBuf>, Failure> {
    let bytes = read_bounded(list, MAX_LIST_BYTES).map_err(|e| {
        Failure::usage(format!(
            "cannot read the list of parts `{}`: {e}",
            list.display()
        ))
    })?;
    let folder = list.parent().unwrap_or(Path::new(""));
    let mut parts = Vec::new();
    for (number, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let name = std::str::from_utf8(line).map_err(|_| {
            Failure::usage(format!(
                "{}:{}: the name of a part is not UTF-8 text",
                list.display(),
                number + 1
            ))
        })?;
        if parts.len() as u64 == MAX_SLICES {
            return Err(Failure::usage(format!(
                "{}:{}: the list names more than the {MAX_SLICES} slices a render may be cut \
                 into",
                list.display(),
                number + 1
            )));
        }
        parts.push(folder.join(name));
    }
    Ok(parts)
}

/// The first part's header and every part's path by slice index, once each part's header
/// has been checked to be of the same render as the first, no slice given twice and none
/// missing (the missing ones named). Only the first header is kept: a merge of a million
/// slices holds a million paths, not a million headers.
fn in_slice_order(parts: &[PathBuf]) -> Result<(PartHeader, BTreeMap<u64, &Path>), Failure> {
    // Not empty: `part_paths` refuses none.
    let mut slices = Slices::new(&parts[0], Part::read_header(&parts[0])?);
    for path in &parts[1..] {
        slices.add(path, Part::read_header(path)?)?;
    }
    slices.complete()
}

/// The slices met so far, by index, each checked against the first.
struct Slices<'a> {
    first_path: &'a Path,
    first: PartHeader,
    by_index: BTreeMap<u64, &'a Path>,
}

impl<'a> Slices<'a> {
    fn new(path: &'a Path, first: PartHeader) -> Self {
        let by_index = BTreeMap::from([(first.slice.index, path)]);
        Self {
            first_path: path,
            first,
            by_index,
        }
    }

    /// Adds the part at `path`, refused when it is of another render or a slice given twice.
    fn add(&mut self, path: &'a Path, header: PartHeader) -> Result<(), Failure> {
        if let Some(why) = self.first.differs_from(&header) {
            return Err(Failure::usage(format!(
                "`{}` and `{}` are not slices of the same render: {why}",
                self.first_path.display(),
                path.display()
            )));
        }
        if let Some(earlier) = self.by_index.insert(header.slice.index, path) {
            return Err(Failure::usage(format!(
                "slice {} is given twice: `{}` and `{}`",
                header.slice,
                earlier.display(),
                path.display()
            )));
        }
        Ok(())
    }

    /// The first header and the paths in slice order, refused with slices missing (the first
    /// few named, the rest counted).
    fn complete(self) -> Result<(PartHeader, BTreeMap<u64, &'a Path>), Failure> {
        let count = self.first.slice.count;
        let by_index = &self.by_index;
        let missing: Vec<u64> = (0..count).filter(|i| !by_index.contains_key(i)).collect();
        if missing.is_empty() {
            return Ok((self.first, self.by_index));
        }
        let mut listed: Vec<String> = missing
            .iter()
            .take(LISTED_MISSING)
            .map(u64::to_string)
            .collect();
        if missing.len() > LISTED_MISSING {
            listed.push(format!("and {} more", missing.len() - LISTED_MISSING));
        }
        Err(Failure::usage(format!(
            "{} of the {count} slices {} missing: {} (render each with --slice I/{count})",
            missing.len(),
            if missing.len() == 1 { "is" } else { "are" },
            listed.join(", ")
        )))
    }
}

/// The scene's canvas items and the camera they are drawn for, read from the scene file the
/// user names with `--scene` (under the merge's own `--allow-outside` and `--max-triangles`),
/// which must be the file the parts were rendered from. The path a part holds is never
/// opened: a part is untrusted input, and its checksums do not prove who wrote it.
fn scene_overlay(args: &MergeArgs, header: &PartHeader) -> Result<(Overlay, Camera), Failure> {
    let needed = "the image has canvas items, drawn over it from its scene file";
    let Some(path) = args.scene.as_deref() else {
        return Err(Failure::usage(format!(
            "{needed}: name it with --scene (the slices were rendered from `{}`)",
            clip(&header.scene)
        )));
    };
    let bytes = rayforge_scene::read_scene_file(path).map_err(|e| {
        Failure::usage(format!(
            "{needed}, `{}`, which cannot be read: {e}",
            path.display()
        ))
    })?;
    let load = LoadOptions {
        max_triangles: args.max_triangles,
        allow_outside: args.allow_outside,
        ..LoadOptions::default()
    };
    // Read first, as the slices read it, so that the files it names are known.
    let scene = rayforge_scene::load_file_with(path, &load).map_err(scene_failure)?;
    if scene_fingerprint(&bytes, &scene.files).map_err(Failure::usage)? != header.fingerprint {
        return Err(Failure::usage(format!(
            "{needed}, `{}`, which (or a file it names) is not the one the slices were \
             rendered from (`{}`), or has changed since",
            path.display(),
            clip(&header.scene)
        )));
    }
    let camera = camera_at(&scene, header.width, header.height);
    Ok((scene.overlay, camera))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part_file::Development;
    use crate::slice::{Cut, Slice};

    fn header(index: u64, count: u64) -> PartHeader {
        PartHeader {
            fingerprint: 1,
            width: 2,
            height: 2,
            slice: Slice {
                index,
                count,
                cut: Cut::Rows,
            },
            spp: 0,
            development: Development::Path,
            overlay: false,
            aovs: false,
            scene: "s.yml".into(),
            settings: "ray".into(),
        }
    }

    /// The slices of `indices` (of `count`) in order, as their paths, or the refusal.
    fn ordered(count: u64, indices: &[u64]) -> Result<Vec<PathBuf>, String> {
        let paths: Vec<PathBuf> = indices.iter().map(|i| format!("p{i}").into()).collect();
        let mut slices = Slices::new(&paths[0], header(indices[0], count));
        let message = |failure| match failure {
            Failure::Input(m) => m,
            other => panic!("not a usage error: {other:?}"),
        };
        for (path, &index) in paths.iter().zip(indices).skip(1) {
            slices.add(path, header(index, count)).map_err(message)?;
        }
        let (_, by_index) = slices.complete().map_err(message)?;
        Ok(by_index.into_values().map(Path::to_path_buf).collect())
    }

    #[test]
    fn parts_come_back_in_slice_order_whatever_order_they_are_given_in() {
        let order = ordered(3, &[2, 0, 1]).unwrap();
        assert_eq!(order, [Path::new("p0"), Path::new("p1"), Path::new("p2")]);
        let m = ordered(3, &[2, 0, 2]).unwrap_err();
        assert!(m.contains("slice 2/3 is given twice: `p2` and `p2`"), "{m}");
    }

    #[test]
    fn many_missing_slices_are_listed_then_counted() {
        let m = ordered(26, &[0]).unwrap_err();
        assert!(
            m.starts_with("25 of the 26 slices are missing: 1, 2, 3"),
            "{m}"
        );
        assert!(m.contains("20, and 5 more"), "{m}");
    }

    #[test]
    fn a_list_names_parts_a_line_from_its_folder_and_a_bad_line_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let list = dir.path().join("parts.list");
        std::fs::write(&list, "a.part\r\n\n  \n/abs/b.part\nc d.part").unwrap();
        let parts = read_list(&list).unwrap();
        assert_eq!(
            parts,
            [
                dir.path().join("a.part"),
                PathBuf::from("/abs/b.part"),
                dir.path().join("c d.part")
            ]
        );
        std::fs::write(&list, b"a.part\nb\xff.part\n").unwrap();
        let Err(Failure::Input(m)) = read_list(&list) else {
            panic!("a line that is not UTF-8 was read");
        };
        assert!(
            m.ends_with("parts.list:2: the name of a part is not UTF-8 text"),
            "{m}"
        );
    }
}
