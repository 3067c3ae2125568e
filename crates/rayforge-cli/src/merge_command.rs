//! `rayforge merge PARTS... -o OUT`: the part files of a render's slices joined into its image.
//!
//! The headers are read first, so that parts of different renders, a slice given twice or
//! missing slices are refused before any film is read. The films are then added one at a time,
//! in slice order (so the sums of a cut by samples are added in the same order whatever order
//! the parts are given in), into one film of the image's size, which is developed and written
//! exactly as `rayforge render` develops and writes that renderer's film: the same functions,
//! the optics model's exposure and the scene's canvas items included.

use crate::args::MergeArgs;
use crate::atomic_write::check_writable;
use crate::diagnostics::scene_failure;
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::memory::reserve_for_merge;
use crate::output_lock::OutputLock;
use crate::part_file::{scene_fingerprint, Development, Part, PartHeader};
use crate::path_command::develop_path_image;
use crate::render_command::{camera_at, develop_book_image, write_image_as};
use crate::slice::Slice;
use crate::summary::non_finite_warning;
use rayforge::camera::Camera;
use rayforge::draw2d::Overlay;
use rayforge_scene::LoadOptions;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How many missing slices an error lists before it says how many more there are.
const LISTED_MISSING: usize = 20;

/// Runs the merge command.
pub fn run(args: &MergeArgs) -> Result<(), Failure> {
    let output = args.output.as_path();
    let format = ImageFormat::from_path(output)?;
    check_writable(output)?;
    let _lock = OutputLock::acquire(output)?;
    let started = Instant::now();
    let headers = args
        .parts
        .iter()
        .map(|path| Ok((path.clone(), Part::read_header(path)?)))
        .collect::<Result<Vec<_>, Failure>>()?;
    let slices = in_slice_order(&headers)?;
    // Not empty: clap requires one part at least.
    let (_, first) = &headers[0];
    let overlay = if first.overlay {
        Some(scene_overlay(first)?)
    } else {
        None
    };
    // Slice 0 covers the most rows (all of them when cut by samples).
    let largest = Slice {
        index: 0,
        ..first.slice
    };
    reserve_for_merge(first.width, first.height, largest.row_count(first.height))?;
    let mut film = None;
    for (path, header) in slices {
        let part = Part::read(path)?;
        if part.header != *header {
            return Err(Failure::usage(format!(
                "`{}` changed while it was being merged",
                path.display()
            )));
        }
        let film = match &mut film {
            Some(film) => film,
            None => film.insert(
                part.empty_image_film()
                    .map_err(|e| Failure::usage(format!("`{}`: {e}", path.display())))?,
            ),
        };
        part.add_to(film)
            .map_err(|e| Failure::usage(format!("`{}`: {e}", path.display())))?;
    }
    let Some(film) = film else {
        return Err(Failure::internal("no part was read"));
    };
    let overlay = overlay.as_ref().map(|(o, camera)| (o, camera));
    let (canvas, non_finite) = match first.development {
        Development::Book(exposure) => develop_book_image(&film, exposure, overlay),
        Development::Path => develop_path_image(&film, format, overlay),
    };
    write_image_as(format, &canvas, output)?;
    if !args.quiet {
        eprintln!(
            "merged {} slices (by {}) of {}×{} into `{}` in {:.2} s",
            first.slice.count,
            first.slice.cut.name(),
            first.width,
            first.height,
            output.display(),
            started.elapsed().as_secs_f64()
        );
        if let Some(warning) = non_finite_warning(non_finite, output) {
            eprintln!("{warning}");
        }
    }
    Ok(())
}

/// The parts in slice order, once each has been checked to be of the same render as the first,
/// no slice given twice and none missing (the missing ones named).
fn in_slice_order(
    headers: &[(PathBuf, PartHeader)],
) -> Result<Vec<&(PathBuf, PartHeader)>, Failure> {
    let (first_path, first) = &headers[0];
    let mut by_index: BTreeMap<u64, &(PathBuf, PartHeader)> = BTreeMap::new();
    for entry in headers {
        let (path, header) = entry;
        if let Some(why) = first.differs_from(header) {
            return Err(Failure::usage(format!(
                "`{}` and `{}` are not slices of the same render: {why}",
                first_path.display(),
                path.display()
            )));
        }
        if let Some((earlier, _)) = by_index.insert(header.slice.index, entry) {
            return Err(Failure::usage(format!(
                "slice {} is given twice: `{}` and `{}`",
                header.slice,
                earlier.display(),
                path.display()
            )));
        }
    }
    let count = first.slice.count;
    // As many as are given, at most: the first few gaps are named, the rest counted.
    let missing: Vec<u64> = (0..count).filter(|i| !by_index.contains_key(i)).collect();
    if !missing.is_empty() {
        let mut listed: Vec<String> = missing
            .iter()
            .take(LISTED_MISSING)
            .map(u64::to_string)
            .collect();
        if missing.len() > LISTED_MISSING {
            listed.push(format!("and {} more", missing.len() - LISTED_MISSING));
        }
        return Err(Failure::usage(format!(
            "{} of the {count} slices {} missing: {} (render each with --slice I/{count})",
            missing.len(),
            if missing.len() == 1 { "is" } else { "are" },
            listed.join(", ")
        )));
    }
    Ok(by_index.into_values().collect())
}

/// The scene's canvas items and the camera they are drawn for, read again from the scene file
/// the parts name, which must still be the file they were rendered from.
fn scene_overlay(header: &PartHeader) -> Result<(Overlay, Camera), Failure> {
    let path = Path::new(&header.scene);
    let needed = "the image has canvas items, drawn over it from its scene file";
    let bytes = std::fs::read(path).map_err(|e| {
        Failure::usage(format!(
            "{needed}, `{}`, which cannot be read: {e}",
            path.display()
        ))
    })?;
    let changed = || {
        Failure::usage(format!(
            "{needed}, `{}`, which (or a file it names) has changed since the slices were rendered",
            path.display()
        ))
    };
    let load = LoadOptions {
        max_triangles: usize::try_from(header.max_triangles).unwrap_or(usize::MAX),
        allow_outside: header.allow_outside,
        ..LoadOptions::default()
    };
    // Read first, as the slices read it, so that the files it names are known.
    let scene = rayforge_scene::load_file_with(path, &load).map_err(scene_failure)?;
    if scene_fingerprint(&bytes, &scene.files).map_err(Failure::usage)? != header.fingerprint {
        return Err(changed());
    }
    let camera = camera_at(&scene, header.width, header.height);
    Ok((scene.overlay, camera))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part_file::Development;
    use crate::slice::{Cut, Slice};

    fn header(index: u64, count: u64) -> (PathBuf, PartHeader) {
        let header = PartHeader {
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
            allow_outside: false,
            max_triangles: 1,
            scene: "s.yml".into(),
            settings: "ray".into(),
        };
        (PathBuf::from(format!("p{index}")), header)
    }

    fn message(headers: &[(PathBuf, PartHeader)]) -> String {
        match in_slice_order(headers) {
            Err(Failure::Input(m)) => m,
            other => panic!("not refused: {other:?}"),
        }
    }

    #[test]
    fn parts_come_back_in_slice_order_whatever_order_they_are_given_in() {
        let headers = [header(2, 3), header(0, 3), header(1, 3)];
        let order: Vec<u64> = in_slice_order(&headers)
            .unwrap()
            .iter()
            .map(|(_, h)| h.slice.index)
            .collect();
        assert_eq!(order, [0, 1, 2]);
    }

    #[test]
    fn many_missing_slices_are_listed_then_counted() {
        let m = message(&[header(0, 26)]);
        assert!(
            m.starts_with("25 of the 26 slices are missing: 1, 2, 3"),
            "{m}"
        );
        assert!(m.contains("20, and 5 more"), "{m}");
    }
}
