//! Checkpoints: the rows of an unfinished render, saved beside the output as
//! `<output>.rayforge-checkpoint` so that `--resume` continues where it stopped.
//!
//! The file is a log. A header names the render (a key hashed from the scene file, the image
//! size and every setting that changes pixels) and its size; then each finished row follows
//! as a record: its index, its linear colours as 64-bit floats (exactly what the renderer
//! computed, so a resumed image is bit for bit the uninterrupted one) and a checksum. Rows are
//! appended as they finish and flushed twice a second, so even a killed process loses at most
//! the last half second (a render's first two seconds are held in memory, and written when it
//! is interrupted: a short render costs no writing); a torn record at the end fails its
//! checksum and is dropped on reading.
//!
//! ```text
//! header: "RAYFORGE CHECKPOINT 1\n" (22 bytes), key u64, width u64, height u64, checksum u64
//! record: y u64, width × 3 f64, checksum u64                      (all little-endian)
//! ```

use crate::failure::Failure;
use rayforge::render::PartialImage;
use rayforge::Color;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::Mutex;
use std::time::{Duration, Instant};

const MAGIC: &[u8; 22] = b"RAYFORGE CHECKPOINT 1\n";
const HEADER_LEN: u64 = 22 + 4 * 8;

/// How often rows written to the log are flushed to the file.
const FLUSH_EVERY: Duration = Duration::from_millis(500);
/// How long the log holds rows before it starts writing them (see [`Log::record`]).
const QUIET_START: Duration = Duration::from_secs(2);

/// The checkpoint of the image written to `output`.
pub fn path_for(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_os_string();
    name.push(".rayforge-checkpoint");
    PathBuf::from(name)
}

/// What identifies a render: a checkpoint is only resumed by the render it was made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderKey {
    /// Hash of the scene file's bytes and every setting that changes a pixel.
    pub key: u64,
    /// Image width.
    pub width: usize,
    /// Image height.
    pub height: usize,
}

impl RenderKey {
    /// The key of rendering the scene file `scene` at `width` × `height` with `settings` (a
    /// description of everything else that changes pixels: sampling, depth, renderer version).
    pub fn new(scene: &[u8], width: usize, height: usize, settings: &str) -> Self {
        let mut h = Fnv::new();
        h.write(&(scene.len() as u64).to_le_bytes());
        h.write(scene);
        h.write(&(width as u64).to_le_bytes());
        h.write(&(height as u64).to_le_bytes());
        h.write(settings.as_bytes());
        Self {
            key: h.finish(),
            width,
            height,
        }
    }

    fn header(&self) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        for v in [self.key, self.width as u64, self.height as u64] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        let sum = fnv(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }
}

/// The rows saved in the checkpoint at `path` for the render `key`, and where its valid
/// records end. A missing file, another render's checkpoint or a damaged header is refused
/// with a message saying so.
pub fn read(path: &Path, key: &RenderKey) -> Result<(PartialImage, u64), Failure> {
    let refuse = |why: &str| {
        Failure::usage(format!(
            "cannot resume from `{}`: {why}; render without --resume to start again",
            path.display()
        ))
    };
    let mut file = match File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(refuse("there is no checkpoint (nothing was interrupted?)"))
        }
        Err(e) => return Err(refuse(&e.to_string())),
    };
    let mut header = vec![0u8; HEADER_LEN as usize];
    file.read_exact(&mut header)
        .map_err(|_| refuse("it is not a rayforge checkpoint (too short)"))?;
    if &header[..MAGIC.len()] != MAGIC {
        return Err(refuse("it is not a rayforge checkpoint"));
    }
    let field = |i: usize| {
        let at = MAGIC.len() + i * 8;
        u64::from_le_bytes(header[at..at + 8].try_into().unwrap_or([0; 8]))
    };
    if fnv(&header[..MAGIC.len() + 24]) != field(3) {
        return Err(refuse("its header is damaged"));
    }
    let (width, height) = (field(1), field(2));
    if (width, height) != (key.width as u64, key.height as u64) {
        return Err(refuse(&format!(
            "it is for a {width}×{height} image, and this render is {}×{}",
            key.width, key.height
        )));
    }
    if field(0) != key.key {
        return Err(refuse(
            "it was made from another scene file or other settings (sampling, depth, size)",
        ));
    }
    let mut image = PartialImage::new(key.width, key.height);
    let record_len = 16 + key.width as u64 * 24;
    let mut record = vec![0u8; record_len as usize];
    let mut valid_end = HEADER_LEN;
    let mut row = vec![Color::BLACK; key.width];
    // Records until the end, or until one is torn or damaged (the rest is not trusted).
    while file.read_exact(&mut record).is_ok() {
        let (body, sum) = record.split_at(record.len() - 8);
        if fnv(body) != u64::from_le_bytes(sum.try_into().unwrap_or([0; 8])) {
            break;
        }
        let y = u64::from_le_bytes(body[..8].try_into().unwrap_or([0; 8]));
        for (pixel, c) in row.iter_mut().zip(body[8..].chunks_exact(24)) {
            let f = |i: usize| f64::from_le_bytes(c[i * 8..i * 8 + 8].try_into().unwrap_or([0; 8]));
            *pixel = Color::new(f(0), f(1), f(2));
        }
        if !image.set_row(y as usize, &row) {
            break;
        }
        valid_end += record_len;
    }
    Ok((image, valid_end))
}

/// Where finished rows are appended.
pub struct Log {
    file: BufWriter<File>,
    path: PathBuf,
}

impl Log {
    /// A new checkpoint for the render `key` at `path`, replacing any there (the header is
    /// written atomically, so a checkpoint is never half a header).
    pub fn create(path: &Path, key: &RenderKey) -> Result<Self, Failure> {
        crate::atomic_write::write_atomically(path, &key.header())?;
        Self::append_at(path, HEADER_LEN)
    }

    /// The checkpoint at `path` continued after its valid records (a torn tail is cut off).
    pub fn append_at(path: &Path, valid_end: u64) -> Result<Self, Failure> {
        let fail = |e: std::io::Error| {
            Failure::internal(format!(
                "cannot write the checkpoint `{}`: {e}",
                path.display()
            ))
        };
        let mut file = OpenOptions::new().write(true).open(path).map_err(fail)?;
        file.set_len(valid_end).map_err(fail)?;
        file.seek(SeekFrom::Start(valid_end)).map_err(fail)?;
        Ok(Self {
            file: BufWriter::with_capacity(1 << 20, file),
            path: path.to_path_buf(),
        })
    }

    /// Appends one finished row.
    pub fn append(&mut self, y: usize, pixels: &[Color]) -> std::io::Result<()> {
        let mut record = Vec::with_capacity(16 + pixels.len() * 24);
        record.extend_from_slice(&(y as u64).to_le_bytes());
        for c in pixels {
            for v in c.to_array() {
                record.extend_from_slice(&v.to_le_bytes());
            }
        }
        let sum = fnv(&record);
        record.extend_from_slice(&sum.to_le_bytes());
        self.file.write_all(&record)
    }

    /// Writes the rows the render leaves in `rows`, collecting them every half second (the
    /// render threads only push to the list: no thread is woken per row), until `done` is
    /// disconnected (the render is over); then writes what is left, flushes and syncs the
    /// file. The first failure stops the logging (the render goes on; the caller reports it).
    ///
    /// For its first [`QUIET_START`] the log only holds the rows: most renders finish sooner,
    /// and writing (and checksumming) every row of a short render would take a core's time
    /// from the render for a file deleted a moment later. When the render ends within that
    /// time, the held rows are written only if `complete` says the image is not finished (it
    /// was interrupted); after it, the held rows are written and the rest follow.
    pub fn record(
        mut self,
        rows: &Mutex<Vec<FinishedRow>>,
        done: Receiver<()>,
        complete: impl Fn() -> bool,
    ) -> Result<(), Failure> {
        let fail = |path: &Path, e: std::io::Error| {
            Failure::internal(format!(
                "cannot write the checkpoint `{}`: {e}",
                path.display()
            ))
        };
        let started = Instant::now();
        let take = || std::mem::take(&mut *rows.lock().unwrap_or_else(|e| e.into_inner()));
        let mut held = Some(Vec::new());
        loop {
            let over = matches!(
                done.recv_timeout(FLUSH_EVERY),
                Err(RecvTimeoutError::Disconnected)
            );
            let mut new = take();
            if let Some(rows) = &mut held {
                rows.append(&mut new);
                if over && complete() {
                    // A short render that finished: its checkpoint is about to be deleted.
                    return Ok(());
                }
                if over || started.elapsed() >= QUIET_START {
                    new = held.take().unwrap_or_default();
                }
            }
            for (y, pixels) in new {
                self.append(y, &pixels).map_err(|e| fail(&self.path, e))?;
            }
            self.file.flush().map_err(|e| fail(&self.path, e))?;
            if over {
                break;
            }
        }
        self.file
            .get_ref()
            .sync_all()
            .map_err(|e| fail(&self.path, e))
    }
}

/// A finished row on its way to the log: its index and its pixels.
pub type FinishedRow = (usize, Vec<Color>);

/// FNV-1a, 64-bit, incrementally.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

fn fnv(bytes: &[u8]) -> u64 {
    let mut h = Fnv::new();
    h.write(bytes);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> RenderKey {
        RenderKey::new(b"- add: camera", 3, 4, "centre depth 5")
    }

    fn row(v: f64) -> Vec<Color> {
        vec![Color::new(v, -v, v / 3.0); 3]
    }

    #[test]
    fn rows_written_are_read_back_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("o.png.rayforge-checkpoint");
        let mut log = Log::create(&path, &key()).ok().unwrap();
        log.append(2, &row(0.1)).unwrap();
        log.append(0, &row(1e-300)).unwrap();
        drop(log);
        let (image, end) = read(&path, &key()).ok().unwrap();
        assert_eq!(image.finished_rows(), 2);
        assert_eq!(image.row(2), Some(&row(0.1)[..]));
        assert_eq!(image.row(0), Some(&row(1e-300)[..]));
        assert_eq!(image.row(1), None);
        assert_eq!(end, std::fs::metadata(&path).unwrap().len());
    }

    #[test]
    fn a_torn_last_record_is_dropped_and_cut_off_on_append() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cp");
        let mut log = Log::create(&path, &key()).ok().unwrap();
        log.append(1, &row(0.5)).unwrap();
        log.append(3, &row(0.25)).unwrap();
        drop(log);
        let full = std::fs::metadata(&path).unwrap().len();
        let f = OpenOptions::new().write(true).open(&path).unwrap();
        f.set_len(full - 5).unwrap();
        let (image, end) = read(&path, &key()).ok().unwrap();
        assert_eq!(image.finished_rows(), 1);
        let mut log = Log::append_at(&path, end).ok().unwrap();
        log.append(2, &row(0.75)).unwrap();
        drop(log);
        let (image, _) = read(&path, &key()).ok().unwrap();
        assert!(image.is_done(1) && image.is_done(2) && !image.is_done(3));
    }

    #[test]
    fn another_renders_checkpoint_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cp");
        drop(Log::create(&path, &key()).ok().unwrap());
        let other = RenderKey::new(b"- add: camera", 3, 4, "centre depth 6");
        let message = |f: Failure| match f {
            Failure::Input(m) => m,
            other => panic!("{other:?}"),
        };
        let m = message(read(&path, &other).err().unwrap());
        assert!(m.contains("another scene file or other settings"), "{m}");
        let bigger = RenderKey::new(b"- add: camera", 4, 4, "centre depth 5");
        let m = message(read(&path, &bigger).err().unwrap());
        assert!(m.contains("3×4"), "{m}");
        let m = message(read(&dir.path().join("none"), &key()).err().unwrap());
        assert!(m.contains("no checkpoint"), "{m}");
        std::fs::write(&path, b"P3\n1 1\n255\n0 0 0\n").unwrap();
        let m = message(read(&path, &key()).err().unwrap());
        assert!(m.contains("not a rayforge checkpoint"), "{m}");
    }

    #[test]
    fn the_checkpoint_sits_beside_the_output() {
        assert_eq!(
            path_for(Path::new("out/cover.png")),
            Path::new("out/cover.png.rayforge-checkpoint")
        );
    }
}
