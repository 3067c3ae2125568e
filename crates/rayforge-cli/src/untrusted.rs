//! The command's readers of bytes from outside that are not scene, model or image files (those
//! are `rayforge-scene`'s), each behind one entry point so that the fuzzer (`rayforge-fuzz`)
//! drives the very code the command runs: part files through the whole merge, what a
//! browser sends the live page's server (its WebSocket messages and the headers that decide
//! who may connect), and the images `rayforge denoise` reads.
//!
//! Each entry returns the command's own answer (a [`Failure`] or a message for the page); bad
//! input must get such an answer, never a panic, a hang or unbounded memory.

use crate::args::MergeArgs;
use crate::failure::Failure;
use std::path::{Path, PathBuf};

/// `rayforge merge PARTS -o OUTPUT -q`: reads and checks the part files, merges them and
/// writes the image (its format from `output`'s extension). No scene is named, so a part
/// that says its image has canvas items is refused, as the command refuses it.
pub fn merge_parts(parts: &[PathBuf], output: &Path) -> Result<(), Failure> {
    crate::merge_command::run(&MergeArgs {
        parts: parts.to_vec(),
        list: None,
        output: output.to_path_buf(),
        scene: None,
        allow_outside: false,
        max_triangles: rayforge_scene::DEFAULT_MAX_TRIANGLES,
        aovs: false,
        denoise: false,
        quiet: true,
    })
}

/// `bytes` as a part file with its checksums made right for what it holds (the header's
/// FNV-1a 64 after the header, each film's CRC-32 at its end: the image's, then the AOVs';
/// see [`crate::part_file`]'s layout), where the lengths in it allow: what else is wrong with
/// a damaged part then meets the checks behind the checksums, which a fuzzer's random changes
/// would otherwise never pass.
pub fn with_part_checksums_repaired(bytes: &[u8]) -> Vec<u8> {
    let mut part = bytes.to_vec();
    let Some(header_len) = part.get(12..16) else {
        return part;
    };
    let header_end = 16 + u32::from_le_bytes(header_len.try_into().expect("4 bytes")) as usize;
    let film_start = header_end + 8;
    if part.len() < film_start {
        return part;
    }
    let checksum = crate::checkpoint::fnv(&part[..header_end]);
    part[header_end..film_start].copy_from_slice(&checksum.to_le_bytes());
    let mut films = &mut part[film_start..];
    // Each film as long as its width and height say (45 bytes, 32 a pixel, its CRC), the last
    // one (or one whose size does not fit) to the end of the file.
    while !films.is_empty() {
        let size = |at: usize| {
            films
                .get(at..at + 8)
                .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
        };
        let len = size(12)
            .zip(size(20))
            .and_then(|(w, h)| w.checked_mul(h)?.checked_mul(32)?.checked_add(45 + 4))
            .and_then(|len| usize::try_from(len).ok())
            .filter(|&len| len <= films.len())
            .unwrap_or(films.len());
        let (film, rest) = films.split_at_mut(len);
        if let Some(body) = film.len().checked_sub(4) {
            let crc = crc32fast::hash(&film[..body]);
            film[body..].copy_from_slice(&crc.to_le_bytes());
        }
        films = rest;
    }
    part
}

/// What `rayforge denoise IMAGE [--albedo A] [--normal N]` does with its inputs before OIDN
/// is given them (it needs no OIDN): reads each file (OpenEXR or PFM) and checks it, its
/// guides (the files', else the image's own layers) against it, and the images as OIDN would
/// be given them.
pub fn denoise_inputs(
    image: &Path,
    albedo: Option<&Path>,
    normal: Option<&Path>,
) -> Result<(), Failure> {
    let inputs = crate::denoise_command::read_inputs(image, albedo, normal)?;
    let guides = inputs.albedo.as_ref().map(|albedo| crate::denoise::Guides {
        albedo,
        normal: inputs.normal.as_ref(),
    });
    crate::denoise::check(&inputs.image, guides, &format!("`{}`", image.display()))
}

pub use crate::serve::page_message;
