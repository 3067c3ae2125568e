//! Reading back the PFM files the renders write: their floats, for tests that check pixel
//! values exactly. Included by path (`#[path = "support/pfm.rs"]`) by the tests that read PFMs.

use std::path::Path;

/// The 32-bit floats after a PFM's three header lines (`PF` for colour or `Pf` for grey, the
/// size, the scale), which must say little-endian (a negative scale), as rayforge writes them.
pub fn pfm_floats(path: &Path) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    let mut lines = bytes.split(|&b| b == b'\n');
    let header: Vec<&[u8]> = lines.by_ref().take(3).collect();
    assert!(
        header.len() == 3 && matches!(header[0], b"PF" | b"Pf"),
        "not a PFM: {}",
        path.display()
    );
    assert!(
        header[2].starts_with(b"-"),
        "not little-endian: {}",
        path.display()
    );
    let start = header.iter().map(|line| line.len() + 1).sum::<usize>();
    bytes[start..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}
