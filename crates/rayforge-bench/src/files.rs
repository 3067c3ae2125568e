//! The mesh and rays files handed to the Embree harness (`bench/peers/embree/primary.c` reads
//! them): little-endian, an 8-byte magic, `u64` counts, then the arrays.

use super::rays::StoredRay;
use super::shapes::Soup;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// `RFMESH01`, u64 vertex count, u64 triangle count, 3 f32 per vertex, 3 u32 per triangle.
pub fn write_mesh(path: &Path, soup: &Soup) -> std::io::Result<()> {
    let mut out = BufWriter::new(File::create(path)?);
    out.write_all(b"RFMESH01")?;
    out.write_all(&(soup.positions.len() as u64).to_le_bytes())?;
    out.write_all(&(soup.triangles.len() as u64).to_le_bytes())?;
    for p in &soup.positions {
        for c in p {
            out.write_all(&c.to_le_bytes())?;
        }
    }
    for t in &soup.triangles {
        for i in t {
            out.write_all(&i.to_le_bytes())?;
        }
    }
    out.flush()
}

/// `RFRAYS01`, u64 count, 6 f32 per ray (origin, direction), in the order to trace them.
pub fn write_rays(path: &Path, rays: &[StoredRay]) -> std::io::Result<()> {
    let mut out = BufWriter::new(File::create(path)?);
    out.write_all(b"RFRAYS01")?;
    out.write_all(&(rays.len() as u64).to_le_bytes())?;
    for r in rays {
        for c in r {
            out.write_all(&c.to_le_bytes())?;
        }
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_files_have_the_layout_the_harness_reads() {
        let dir = tempfile::tempdir().unwrap();
        let soup = Soup {
            positions: vec![[0.0, 1.0, 2.0], [3.0, 4.0, 5.0], [6.0, 7.0, 8.0]],
            triangles: vec![[0, 1, 2]],
        };
        let mesh = dir.path().join("m");
        write_mesh(&mesh, &soup).unwrap();
        let bytes = std::fs::read(&mesh).unwrap();
        assert_eq!(bytes.len(), 8 + 16 + 9 * 4 + 3 * 4);
        assert_eq!(&bytes[..8], b"RFMESH01");
        assert_eq!(bytes[8], 3);
        assert_eq!(bytes[16], 1);
        assert_eq!(f32::from_le_bytes(bytes[28..32].try_into().unwrap()), 1.0);
        assert_eq!(u32::from_le_bytes(bytes[64..68].try_into().unwrap()), 1);

        let rays = dir.path().join("r");
        write_rays(&rays, &[[1.0, 2.0, 3.0, 0.0, 0.0, 1.0]]).unwrap();
        let bytes = std::fs::read(&rays).unwrap();
        assert_eq!(bytes.len(), 8 + 8 + 24);
        assert_eq!(&bytes[..8], b"RFRAYS01");
        assert_eq!(f32::from_le_bytes(bytes[36..40].try_into().unwrap()), 1.0);
    }
}
