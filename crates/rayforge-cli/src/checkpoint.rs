//! Checkpoints: the rows of an unfinished render, saved beside the output as
//! `<output>.rayforge-checkpoint` so that `--resume` continues where it stopped.
//!
//! The file is a log. A header names the render (a key hashed from the scene file, the image
//! size and every setting that changes pixels) and its size; then each finished row follows
//! as a record: its index, its linear colours as 64-bit floats (exactly what the renderer
//! computed, so a resumed image is bit for bit the uninterrupted one) and a checksum. Rows are
//! written twice a second from the first, so even a killed process loses at most the last half
//! second; a torn record at the end fails its checksum and is dropped on reading. The file is
//! created with its first rows and removed when it holds none, so no checkpoint is ever a
//! header alone.
//!
//! ```text
//! header: "RAYFORGE CHECKPOINT 1\n" (22 bytes), key u64, width u64, height u64, checksum u64
//! record: y u64, width × 3 f64, checksum u64                      (all little-endian)
//! ```

use crate::failure::Failure;
use rayforge::render::PartialImage;
use rayforge::Color;
use rayforge_scene::files::open_regular_to_update;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::Mutex;
use std::time::Duration;

const MAGIC: &[u8; 22] = b"RAYFORGE CHECKPOINT 1\n";
const HEADER_LEN: u64 = 22 + 4 * 8;

/// How often finished rows are written to the checkpoint (the most a killed render loses).
const FLUSH_EVERY: Duration = Duration::from_millis(500);

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
/// with a message saying so. A torn last record (a killed process) fails its checksum and is
/// dropped with whatever follows; a record whose checksum holds but which no render writes (a
/// row past the image, a row saved twice, a value that is not a finite number: a forged or
/// corrupted file) refuses the whole checkpoint, since nothing in it can then be trusted.
pub fn read(path: &Path, key: &RenderKey) -> Result<(PartialImage, u64), Failure> {
    let refuse = |why: &str| {
        Failure::usage(format!(
            "cannot resume from `{}`: {why}; render without --resume to start again",
            path.display()
        ))
    };
    if path
        .symlink_metadata()
        .is_err_and(|e| e.kind() == std::io::ErrorKind::NotFound)
    {
        return Err(refuse("there is no checkpoint (nothing was interrupted?)"));
    }
    // Opened as the file that will be continued: a named pipe or a link there is refused
    // before anything waits on it or is written through it.
    let mut file = open_regular_to_update(path).map_err(|why| refuse(&why))?;
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
        let forged = |what: String| {
            refuse(&format!(
                "{what} (at byte {valid_end}); the checkpoint is damaged or was not written by \
                 rayforge"
            ))
        };
        if y >= key.height as u64 {
            return Err(forged(format!(
                "a record is for row {y}, past the image's {} rows",
                key.height
            )));
        }
        if image.is_done(y as usize) {
            return Err(forged(format!("row {y} is saved twice")));
        }
        if !is_finite(&row) {
            return Err(forged(format!(
                "row {y} holds a value that is not a finite number"
            )));
        }
        image.set_row(y as usize, &row);
        valid_end += record_len;
    }
    Ok((image, valid_end))
}

/// Whether every channel of every pixel is a finite number. A row that is not is never saved
/// (resuming renders it again, to the same pixels), so none is ever read back.
fn is_finite(row: &[Color]) -> bool {
    row.iter()
        .all(|c| c.to_array().iter().all(|v| v.is_finite()))
}

/// Where finished rows are saved: the checkpoint at `path`, created with its first rows (so no
/// checkpoint ever holds a header alone) or continued after the rows of an interrupted render.
pub struct Log {
    path: PathBuf,
    file: LogFile,
    /// The rows the checkpoint holds, those it was resumed with included.
    saved: usize,
    /// Where its last whole record ends: a failed write is cut back to it.
    len: u64,
    /// Whether to keep a failure to write to itself (the final message still reports it).
    quiet: bool,
}

/// The checkpoint's file, once it exists.
enum LogFile {
    /// Not written yet: its header goes out with the first rows.
    New(Vec<u8>),
    /// Open for appending records.
    Open(File),
}

/// How the checkpointing went, for the final message.
#[derive(Debug)]
pub struct Logged {
    /// The rows the checkpoint holds (0: it was removed, or never written).
    pub saved: usize,
    /// Why writing it failed, when it did (the rows after the failure are not saved).
    pub failure: Option<String>,
}

impl Log {
    /// A new checkpoint for the render `key` at `path`, replacing any there: an old one is
    /// removed now, and the new one is written with its first rows.
    pub fn create(path: &Path, key: &RenderKey, quiet: bool) -> Result<Self, Failure> {
        match std::fs::remove_file(path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(Failure::usage(format!(
                    "cannot replace the checkpoint `{}`: {e}",
                    path.display()
                )))
            }
            _ => {}
        }
        Ok(Self {
            path: path.to_path_buf(),
            file: LogFile::New(key.header()),
            saved: 0,
            len: 0,
            quiet,
        })
    }

    /// The checkpoint at `path`, holding `saved` rows, continued after its valid records (a
    /// torn tail is cut off).
    pub fn append_at(
        path: &Path,
        valid_end: u64,
        saved: usize,
        quiet: bool,
    ) -> Result<Self, Failure> {
        let fail = |e: std::io::Error| {
            Failure::internal(format!(
                "cannot write the checkpoint `{}`: {e}",
                path.display()
            ))
        };
        let mut file =
            open_regular_to_update(path).map_err(|why| fail(std::io::Error::other(why)))?;
        file.set_len(valid_end).map_err(fail)?;
        file.seek(SeekFrom::Start(valid_end)).map_err(fail)?;
        Ok(Self {
            path: path.to_path_buf(),
            file: LogFile::Open(file),
            saved,
            len: valid_end,
            quiet,
        })
    }

    /// Saves finished rows (a row with a value that is not finite is left out, see
    /// [`is_finite`]) in one write, the checkpoint's header first when it is new (written
    /// atomically, so the file appears with its header and rows whole). On failure the file is
    /// cut back to its last whole record, and the message says why.
    fn save(&mut self, rows: &[FinishedRow]) -> Result<(), String> {
        let rows: Vec<&FinishedRow> = rows.iter().filter(|(_, p)| is_finite(p)).collect();
        if rows.is_empty() {
            return Ok(());
        }
        let mut bytes = match &self.file {
            LogFile::New(header) => header.clone(),
            LogFile::Open(_) => Vec::new(),
        };
        for (y, pixels) in &rows {
            bytes.extend_from_slice(&record(*y, pixels));
        }
        match &mut self.file {
            LogFile::New(_) => {
                let file = crate::atomic_write::write_atomically_and_keep(&self.path, &bytes)
                    .map_err(|why| {
                        format!(
                            "cannot write the checkpoint `{}`: {why}",
                            self.path.display()
                        )
                    })?;
                self.file = LogFile::Open(file);
            }
            LogFile::Open(file) => {
                if let Err(e) = file.write_all(&bytes) {
                    // Best effort: a record cut short would only be dropped when read.
                    let _ = file.set_len(self.len);
                    let _ = file.seek(SeekFrom::Start(self.len));
                    return Err(format!(
                        "cannot write the checkpoint `{}`: {}",
                        self.path.display(),
                        crate::atomic_write::reason(&e, &self.path)
                    ));
                }
            }
        }
        self.len += bytes.len() as u64;
        self.saved += rows.len();
        Ok(())
    }

    /// Saves the rows the render leaves in `rows`, collecting them every half second from the
    /// first (the render threads only push to the list: no thread is woken per row), until
    /// `done` is disconnected (the render is over); then saves what is left and syncs the
    /// file. So a killed process loses at most the last half second's rows.
    ///
    /// When `complete` says the render finished, its last rows are not written: the image is
    /// about to be written and the checkpoint deleted. The first failure to write is warned
    /// about at once (unless quiet) and ends the saving, but not the render: rows are still
    /// taken from the list, which would otherwise grow to the whole image. A checkpoint that
    /// holds no row at the end is removed, so none stays behind with a header alone.
    pub fn record(
        mut self,
        rows: &Mutex<Vec<FinishedRow>>,
        done: Receiver<()>,
        complete: impl Fn() -> bool,
    ) -> Logged {
        let take = || std::mem::take(&mut *rows.lock().unwrap_or_else(|e| e.into_inner()));
        let mut failure = None;
        loop {
            let over = matches!(
                done.recv_timeout(FLUSH_EVERY),
                Err(RecvTimeoutError::Disconnected)
            );
            let new = take();
            if over && complete() {
                break;
            }
            if failure.is_none() {
                if let Err(why) = self.save(&new) {
                    if !self.quiet {
                        eprintln!(
                            "warning: {why}; the render goes on, but rows finished from now on \
                             are not saved"
                        );
                    }
                    failure = Some(why);
                }
            }
            if over {
                if let (LogFile::Open(file), None) = (&self.file, &failure) {
                    if let Err(e) = file.sync_all() {
                        failure = Some(format!(
                            "cannot write the checkpoint `{}`: {}",
                            self.path.display(),
                            crate::atomic_write::reason(&e, &self.path)
                        ));
                    }
                }
                break;
            }
        }
        if self.saved == 0 {
            self.remove();
        }
        Logged {
            saved: self.saved,
            failure,
        }
    }

    /// Removes the checkpoint's file, if it was written.
    fn remove(&mut self) {
        if let LogFile::Open(_) = self.file {
            // Gone already is as good; any other failure leaves a file a resume refuses clearly.
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// One row's record: its index, its pixels' channels as 64-bit floats and the checksum.
fn record(y: usize, pixels: &[Color]) -> Vec<u8> {
    let mut record = Vec::with_capacity(16 + pixels.len() * 24);
    record.extend_from_slice(&(y as u64).to_le_bytes());
    for c in pixels {
        for v in c.to_array() {
            record.extend_from_slice(&v.to_le_bytes());
        }
    }
    let sum = fnv(&record);
    record.extend_from_slice(&sum.to_le_bytes());
    record
}

/// A finished row on its way to the log: its index and its pixels.
pub type FinishedRow = (usize, Vec<Color>);

/// FNV-1a, 64-bit, incrementally.
pub(crate) struct Fnv(u64);

impl Fnv {
    pub(crate) fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    pub(crate) fn finish(&self) -> u64 {
        self.0
    }
}

/// FNV-1a 64 of `bytes`: the checksum of checkpoint headers, and of part files' headers and
/// the fingerprint of their scene ([`crate::part_file`]).
pub(crate) fn fnv(bytes: &[u8]) -> u64 {
    let mut h = Fnv::new();
    h.write(bytes);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs::OpenOptions;

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
        let mut log = Log::create(&path, &key(), true).ok().unwrap();
        log.save(&[(2, row(0.1)), (0, row(1e-300))]).unwrap();
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
        let mut log = Log::create(&path, &key(), true).ok().unwrap();
        log.save(&[(1, row(0.5))]).unwrap();
        log.save(&[(3, row(0.25))]).unwrap();
        drop(log);
        let full = std::fs::metadata(&path).unwrap().len();
        let f = OpenOptions::new().write(true).open(&path).unwrap();
        f.set_len(full - 5).unwrap();
        let (image, end) = read(&path, &key()).ok().unwrap();
        assert_eq!(image.finished_rows(), 1);
        let mut log = Log::append_at(&path, end, 1, true).ok().unwrap();
        log.save(&[(2, row(0.75))]).unwrap();
        drop(log);
        let (image, _) = read(&path, &key()).ok().unwrap();
        assert!(image.is_done(1) && image.is_done(2) && !image.is_done(3));
    }

    #[test]
    fn the_file_appears_with_its_first_rows_and_rows_that_are_not_finite_are_not_saved() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cp");
        std::fs::write(&path, "an old checkpoint").unwrap();
        let mut log = Log::create(&path, &key(), true).ok().unwrap();
        assert!(
            !path.exists(),
            "the old checkpoint is removed, no header is written alone"
        );
        log.save(&[(0, vec![Color::new(f64::NAN, 0.0, 0.0); 3])])
            .unwrap();
        assert!(!path.exists(), "a row that is not finite is not saved");
        log.save(&[
            (1, row(0.5)),
            (2, vec![Color::new(0.0, f64::INFINITY, 0.0); 3]),
        ])
        .unwrap();
        assert_eq!(log.saved, 1);
        drop(log);
        let (image, _) = read(&path, &key()).ok().unwrap();
        assert_eq!(image.finished_rows(), 1);
        assert!(image.is_done(1));
    }

    /// Writes a header and then `records` as they are, checksums and all, as a forger would.
    fn forge(path: &Path, records: &[(usize, Vec<Color>)]) {
        let mut bytes = key().header();
        for (y, pixels) in records {
            bytes.extend_from_slice(&record(*y, pixels));
        }
        std::fs::write(path, bytes).unwrap();
    }

    #[test]
    fn forged_records_refuse_the_checkpoint() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cp");
        let message = |records: &[(usize, Vec<Color>)]| {
            forge(&path, records);
            match read(&path, &key()).err() {
                Some(Failure::Input(m)) => m,
                other => panic!("{other:?}"),
            }
        };
        let m = message(&[(1, row(0.5)), (4, row(0.5))]);
        assert!(m.contains("row 4, past the image's 4 rows"), "{m}");
        assert!(m.contains("not written by rayforge"), "{m}");
        let m = message(&[(1, row(0.5)), (1, row(0.25))]);
        assert!(m.contains("row 1 is saved twice"), "{m}");
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let m = message(&[(3, vec![Color::new(0.0, 0.0, v); 3])]);
            assert!(
                m.contains("row 3 holds a value that is not a finite number"),
                "{m}"
            );
        }
        // Finite values are the renderer's to choose, however large or negative.
        forge(&path, &[(0, row(-1e308))]);
        assert!(read(&path, &key()).is_ok());
    }

    #[test]
    fn rows_are_saved_while_the_render_runs_and_an_empty_checkpoint_is_removed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cp");
        let rows = Mutex::new(vec![(0, row(0.5))]);
        let (running, done) = std::sync::mpsc::channel::<()>();
        let logged = std::thread::scope(|scope| {
            let log = Log::create(&path, &key(), true).ok().unwrap();
            let logger = scope.spawn(|| log.record(&rows, done, || false));
            // The render is still running: the row is saved all the same.
            while read(&path, &key()).map_or(0, |(image, _)| image.finished_rows()) == 0 {
                std::thread::sleep(Duration::from_millis(10));
            }
            rows.lock().unwrap().push((3, row(0.75)));
            drop(running);
            logger.join().unwrap()
        });
        assert_eq!((logged.saved, logged.failure), (2, None));
        assert_eq!(read(&path, &key()).ok().unwrap().0.finished_rows(), 2);

        // A render interrupted before any row leaves no checkpoint.
        let (running, done) = std::sync::mpsc::channel::<()>();
        drop(running);
        let log = Log::create(&path, &key(), true).ok().unwrap();
        let logged = log.record(&Mutex::new(Vec::new()), done, || false);
        assert_eq!(logged.saved, 0);
        assert!(!path.exists());
    }

    #[test]
    fn another_renders_checkpoint_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cp");
        let mut log = Log::create(&path, &key(), true).ok().unwrap();
        log.save(&[(0, row(0.5))]).unwrap();
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
