//! The film file: a film written and read back losslessly, to be merged or developed later
//! (the slices of a render split over a cluster, a render continued tomorrow).
//!
//! ```text
//! offset  size  field
//!      0     8  magic "RAYFILM\n"
//!      8     4  format version, u32 (1)
//!     12     8  width, u64
//!     20     8  height, u64
//!     28     1  pixel filter: 0 box, 1 tent, 2 Gaussian
//!     29     8  filter radius, f64 (0.5 for the box)
//!     37     8  brightest sample channel, f64 (the optics model's exposure)
//!     45  32·n  per pixel, row-major from the top-left (n = width × height):
//!               red, green, blue sums of weighted colours and the sum of weights, 4 × f64
//!  45+32n    4  CRC-32 (IEEE, as zip and PNG use) of every byte before it, u32
//! ```
//!
//! Every number is little-endian and every float is stored as its bits, so a film read back
//! is the film written, to the bit (negative zeros and NaNs included). Reading checks the
//! magic, the version, the filter, the size against [`MAX_FILM_PIXELS`] before anything is
//! allocated for the pixels, that nothing is missing, and the checksum.

use super::{Film, FilmError, PixelFilter};
use crate::color::Color;
use std::io::{Read, Write};

/// The first bytes of every film file.
pub const FILM_MAGIC: &[u8; 8] = b"RAYFILM\n";
/// The format version this build writes and reads.
pub const FILM_VERSION: u32 = 1;
/// The most pixels a film file may hold (32 bytes each: 8 GiB). Reading refuses larger sizes
/// before allocating, so a damaged or hostile header cannot ask for unbounded memory.
pub const MAX_FILM_PIXELS: u64 = 1 << 28;

/// Bytes before the pixels.
const HEADER_LEN: usize = 45;
/// Bytes per pixel.
const PIXEL_LEN: usize = 32;
/// Pixels read at a time (the buffers grow as data arrives, not as the header claims).
const CHUNK_PIXELS: usize = 1 << 14;

impl Film {
    /// Writes the film in the film file format (see [the layout](crate::film::file)).
    pub fn write_to(&self, out: &mut impl Write) -> Result<(), FilmError> {
        let mut crc = crc32fast::Hasher::new();
        let mut put = |bytes: &[u8]| -> std::io::Result<()> {
            crc.update(bytes);
            out.write_all(bytes)
        };
        let mut header = Vec::with_capacity(HEADER_LEN);
        header.extend_from_slice(FILM_MAGIC);
        header.extend_from_slice(&FILM_VERSION.to_le_bytes());
        header.extend_from_slice(&(self.width as u64).to_le_bytes());
        header.extend_from_slice(&(self.height as u64).to_le_bytes());
        header.push(self.filter.code());
        header.extend_from_slice(&self.filter.radius().to_le_bytes());
        header.extend_from_slice(&self.brightest.to_le_bytes());
        put(&header)?;
        let mut chunk = Vec::with_capacity(CHUNK_PIXELS * PIXEL_LEN);
        for (sums, weights) in self
            .sums
            .chunks(CHUNK_PIXELS)
            .zip(self.weights.chunks(CHUNK_PIXELS))
        {
            chunk.clear();
            for (sum, weight) in sums.iter().zip(weights) {
                for v in [sum.red, sum.green, sum.blue, *weight] {
                    chunk.extend_from_slice(&v.to_le_bytes());
                }
            }
            put(&chunk)?;
        }
        let sum = crc.finalize();
        out.write_all(&sum.to_le_bytes())?;
        Ok(())
    }

    /// The film file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER_LEN + self.sums.len() * PIXEL_LEN + 4);
        // Writing to a vector cannot fail.
        let _ = self.write_to(&mut out);
        out
    }

    /// Reads a film written by [`write_to`](Self::write_to), checking it (see
    /// [the layout](crate::film::file)).
    /// Reads exactly the film's bytes: whatever follows is left in `input`.
    pub fn read_from(input: &mut impl Read) -> Result<Film, FilmError> {
        let mut crc = crc32fast::Hasher::new();
        let mut take = |buf: &mut [u8]| -> Result<(), FilmError> {
            input.read_exact(buf).map_err(|e| match e.kind() {
                std::io::ErrorKind::UnexpectedEof => FilmError::Truncated,
                _ => FilmError::Io(e),
            })?;
            crc.update(buf);
            Ok(())
        };
        let mut magic = [0u8; 8];
        take(&mut magic)?;
        if &magic != FILM_MAGIC {
            return Err(FilmError::BadMagic);
        }
        let mut header = [0u8; HEADER_LEN - 8];
        take(&mut header)?;
        let u64_at = |at: usize| u64::from_le_bytes(array(&header[at..]));
        let f64_at = |at: usize| f64::from_le_bytes(array(&header[at..]));
        let version = u32::from_le_bytes(array(&header[..]));
        if version != FILM_VERSION {
            return Err(FilmError::UnsupportedVersion(version));
        }
        let (width, height) = (u64_at(4), u64_at(12));
        let pixels = width
            .checked_mul(height)
            .filter(|&n| n <= MAX_FILM_PIXELS)
            .ok_or(FilmError::TooLarge(width, height))?;
        let filter = PixelFilter::from_code(header[20], f64_at(21))?;
        let brightest = f64_at(29);
        // Within the limit, so these fit in usize on any platform able to hold the film.
        let (width, height, pixels) = (width as usize, height as usize, pixels as usize);
        let mut sums = Vec::with_capacity(pixels.min(CHUNK_PIXELS));
        let mut weights = Vec::with_capacity(pixels.min(CHUNK_PIXELS));
        let mut chunk = vec![0u8; CHUNK_PIXELS * PIXEL_LEN];
        let mut left = pixels;
        while left > 0 {
            let n = left.min(CHUNK_PIXELS);
            let bytes = &mut chunk[..n * PIXEL_LEN];
            take(bytes)?;
            for p in bytes.chunks_exact(PIXEL_LEN) {
                let v = |i: usize| f64::from_le_bytes(array(&p[i * 8..]));
                sums.push(Color::new(v(0), v(1), v(2)));
                weights.push(v(3));
            }
            left -= n;
        }
        let found = crc.finalize();
        let mut recorded = [0u8; 4];
        input
            .read_exact(&mut recorded)
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::UnexpectedEof => FilmError::Truncated,
                _ => FilmError::Io(e),
            })?;
        let expected = u32::from_le_bytes(recorded);
        if expected != found {
            return Err(FilmError::BadChecksum { expected, found });
        }
        Ok(Film {
            width,
            height,
            filter,
            sums,
            weights,
            brightest,
        })
    }

    /// Reads a film from the whole of `bytes` (refusing bytes after its checksum).
    pub fn from_bytes(bytes: &[u8]) -> Result<Film, FilmError> {
        let mut input = bytes;
        let film = Self::read_from(&mut input)?;
        match input.len() {
            0 => Ok(film),
            extra => Err(FilmError::TrailingBytes(extra)),
        }
    }
}

/// The first `N` bytes of `bytes` (which the callers' fixed layouts guarantee are there).
fn array<const N: usize>(bytes: &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    out.copy_from_slice(&bytes[..N]);
    out
}
