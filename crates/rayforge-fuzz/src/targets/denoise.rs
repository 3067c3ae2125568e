//! The images `rayforge denoise` reads as a fuzz target: [`run`] writes the input as the
//! image and up to two guide files (`--albedo`, `--normal`) and hands them to what the command
//! does before OIDN is given them (`rayforge_cli::untrusted::denoise_inputs`: reading each
//! OpenEXR or PFM file, checking its header, size, channels and values, the guides against
//! the image, and the images as OIDN takes them), which needs no OIDN. Refusals must be the
//! command's usage errors (exit 2) and say something. An input is read one of two ways:
//!
//! - **files**, when it starts with `P` (a PFM) or OpenEXR's magic (the seeds): the image,
//!   then after each line [`SEPARATOR`] the next guide (albedo, then normal);
//! - **choices**, otherwise (what a random engine makes): each byte picks the next choice of
//!   each file: absent, a PFM with a header picked from hostile sizes and scales and as many
//!   bytes of data as it says, one fewer or more, or none; or an OpenEXR written here of a
//!   small size with the image's and guides' channels, then a few of its header's bytes
//!   changed; so that random bytes reach past the first check.
//!
//! Kept a plain function of the input's bytes, so that any engine can call it.

use rayforge_cli::failure::Failure;
use std::path::PathBuf;

/// The line between the files of an input read as files.
pub const SEPARATOR: &[u8] = b"\n--guide--\n";

/// OpenEXR's magic number.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// A PFM header's numbers as a choice picks them: ordinary, zero, negative, past 32 and 64
/// bits, past the pixel limit's side, not numbers.
const SIZES: &[&str] = &[
    "1",
    "2",
    "3",
    "0",
    "-1",
    "16385",
    "65536",
    "4294967297",
    "18446744073709551617",
    "1e3",
    "x",
    "",
];

/// A PFM's scale (its sign the byte order) as a choice picks it.
const SCALES: &[&str] = &["-1.0", "1.0", "-0.5", "0", "nan", "-inf", "one"];

/// Values a pixel may hold: ordinary, huge, negative, NaN and infinite.
const VALUES: &[f32] = &[
    0.0,
    0.5,
    1.0,
    -1.0,
    1e38,
    f32::MAX,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
];

/// Runs one input (see the [module](self)); whether the inputs were taken.
pub fn run(input: &[u8]) -> bool {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::tempdir().expect("a scratch folder");
    }
    let files = files_of(input);
    let paths: Option<Vec<PathBuf>> = DIR.with(|dir| {
        files
            .iter()
            .enumerate()
            .map(|(i, bytes)| {
                let path = dir.path().join(["image", "albedo", "normal"][i]);
                std::fs::write(&path, bytes).ok().map(|()| path)
            })
            .collect()
    });
    let Some(paths) = paths else {
        return false;
    };
    let image = &paths[0];
    let albedo = paths.get(1).map(PathBuf::as_path);
    let normal = paths.get(2).map(PathBuf::as_path);
    match rayforge_cli::untrusted::denoise_inputs(image, albedo, normal) {
        Ok(()) => true,
        Err(Failure::Input(why)) => {
            assert!(!why.trim().is_empty(), "an empty refusal");
            false
        }
        Err(other) => panic!("an input image made the denoiser fail so: {other:?}"),
    }
}

/// The image's and the guides' bytes (see the [module](self)).
fn files_of(input: &[u8]) -> Vec<Vec<u8>> {
    if input.is_empty() || input[0] == b'P' || input.starts_with(&EXR_MAGIC) {
        let mut files = Vec::new();
        let mut rest = input;
        while files.len() < 2 {
            let Some(at) = rest.windows(SEPARATOR.len()).position(|w| w == SEPARATOR) else {
                break;
            };
            files.push(rest[..at].to_vec());
            rest = &rest[at + SEPARATOR.len()..];
        }
        files.push(rest.to_vec());
        return files;
    }
    let mut choices = input.iter();
    let mut pick = |n: usize| choices.next().map_or(0, |&b| usize::from(b) % n);
    let mut files = Vec::new();
    for i in 0..3 {
        let file = match pick(3) {
            // The image is always there; a guide is left out, and then so is the next.
            0 if i > 0 => break,
            0 | 1 => pfm(&mut pick),
            _ => exr(&mut pick, i),
        };
        files.push(file);
    }
    files
}

/// A PFM file from choices: colour or grey, a header of picked numbers, then as many values
/// as it says (when that is small), one byte fewer or more, or none.
pub fn pfm(pick: &mut impl FnMut(usize) -> usize) -> Vec<u8> {
    let magic = ["PF", "Pf"][pick(2)];
    let (width, height) = (SIZES[pick(SIZES.len())], SIZES[pick(SIZES.len())]);
    let scale = SCALES[pick(SCALES.len())];
    let mut bytes = format!("{magic}\n{width} {height}\n{scale}\n").into_bytes();
    let channels = if magic == "PF" { 3 } else { 1 };
    let values = width
        .parse::<usize>()
        .ok()
        .zip(height.parse::<usize>().ok())
        .and_then(|(w, h)| w.checked_mul(h)?.checked_mul(channels))
        .filter(|&n| n <= 64)
        .unwrap_or(1);
    for _ in 0..values {
        bytes.extend_from_slice(&VALUES[pick(VALUES.len())].to_le_bytes());
    }
    match pick(4) {
        0 => {
            bytes.pop();
        }
        1 => bytes.push(0),
        2 => bytes.truncate(bytes.len() - 4 * values),
        _ => {}
    }
    bytes
}

/// An OpenEXR file from choices: 1 to 3 pixels a side, the channels of the image and (for
/// the first file) guides' layers, or a grey `Y` alone, values picked; then up to four of its
/// first 400 bytes (the header) changed. Written by the `exr` crate.
pub fn exr(pick: &mut impl FnMut(usize) -> usize, file: usize) -> Vec<u8> {
    use exr::prelude::{
        AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
        WritableImage,
    };
    let (width, height) = (1 + pick(3), 1 + pick(3));
    let prefixes: &[&str] = match (file, pick(4)) {
        (0, 0) => &["", "albedo.", "normal."],
        (0, 1) => &["", "normal."],
        (_, 2) => &["Y"],
        _ => &[""],
    };
    let mut channels = Vec::new();
    for prefix in prefixes {
        let names: Vec<String> = if *prefix == "Y" {
            vec!["Y".into()]
        } else {
            ["R", "G", "B"]
                .iter()
                .map(|c| format!("{prefix}{c}"))
                .collect()
        };
        for name in names {
            let values = (0..width * height)
                .map(|_| VALUES[pick(VALUES.len())])
                .collect();
            channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(values)));
        }
    }
    let layer = Layer::new(
        (width, height),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    if Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .is_err()
    {
        return EXR_MAGIC.to_vec();
    }
    let mut bytes = bytes.into_inner();
    for _ in 0..pick(5) {
        let at = pick(400.min(bytes.len()));
        bytes[at] = [0, 1, 0x7f, 0x80, 0xff][pick(5)];
    }
    bytes
}

/// Seeds made here: a PFM image alone; a PFM image with PFM guides of its size; an OpenEXR
/// image with its own albedo and normal layers; OpenEXR guides beside a PFM image.
pub fn seeds() -> Vec<Vec<u8>> {
    let choices = |bytes: &'static [u8]| {
        let mut bytes = bytes.iter();
        move |n: usize| bytes.next().map_or(0, |&b| usize::from(b) % n)
    };
    let plain_pfm = |w: usize, h: usize| {
        let mut bytes = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
        for i in 0..w * h * 3 {
            bytes.extend_from_slice(&(i as f32 * 0.125).to_le_bytes());
        }
        bytes
    };
    let joined = |files: &[Vec<u8>]| files.join(SEPARATOR);
    // 2 × 1 pixels, the three layers, values 0.5 and 1, the header kept.
    let layered = &[
        1, 0, 0, 1, 2, 1, 2, 1, 2, 1, 2, 1, 2, 1, 2, 1, 2, 1, 2, 1, 2, 0,
    ];
    // 1 × 1 pixels, the colour channels alone, values 0.5, the header kept.
    let guide = &[0, 0, 3, 1, 1, 1, 0];
    vec![
        plain_pfm(3, 2),
        joined(&[plain_pfm(2, 2), plain_pfm(2, 2), plain_pfm(2, 2)]),
        exr(&mut choices(layered), 0),
        joined(&[plain_pfm(1, 1), exr(&mut choices(guide), 1)]),
    ]
}
