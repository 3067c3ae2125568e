//! What `rayforge render` writes and saves, under hostile scenes, forged checkpoints, two
//! renders racing for one output, failing writes and scarce memory (issue 21, findings 6 to 8;
//! docs/reliability.md describes each behaviour).
#[path = "support/pfm.rs"]
mod pfm;
#[path = "support/scratch.rs"]
mod scratch;

use pfm::pfm_floats;
use scratch::{render, stderr, Dir};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// A sphere whose colour and light are both 1e308: every lit pixel overflows to infinity.
const OVERFLOWING: &str = "
- add: camera
  width: 8
  height: 8
  field-of-view: 0.8
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1e308, 1e308, 1e308]
- add: sphere
  material:
    color: [1e308, 1e308, 1e308]
";

/// An emitter of 1e308 for the path tracer: the sum of its samples overflows to infinity.
const OVERFLOWING_EMITTER: &str = "
- add: camera
  width: 8
  height: 8
  field-of-view: 0.8
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: sphere
  material:
    color: [1, 1, 1]
    emission: [1e308, 1e308, 1e308]
";

/// 150 rows of 200 pixels, reflective enough that a row takes a moment; the renders below
/// are held with `--pause-after-rows`, so its speed does not matter.
const SLOW_SCENE: &str = "
- add: camera
  width: 200
  height: 150
  field-of-view: 1.0
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: plane
  material:
    color: [0.8, 0.8, 0.8]
    reflective: 0.3
- add: sphere
  transform:
    - [translate, 0, 1, 0]
  material:
    color: [0.1, 0.1, 0.1]
    reflective: 0.9
";

/// The checkpoint's header, and one record of a `SLOW_SCENE` row, in bytes (see
/// `checkpoint.rs`).
const CHECKPOINT_HEADER: u64 = 22 + 32;
const SLOW_ROW_RECORD: u64 = 16 + 200 * 24;

/// The names of the files in the scratch folder: what a failed render left behind.
fn files_in(d: &Dir) -> Vec<std::ffi::OsString> {
    std::fs::read_dir(d.0.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect()
}

fn checkpoint_of(output: &Path) -> PathBuf {
    PathBuf::from(format!("{}.rayforge-checkpoint", output.display()))
}

fn lock_of(output: &Path) -> PathBuf {
    PathBuf::from(format!("{}.rayforge-lock", output.display()))
}

fn size(p: &Path) -> u64 {
    std::fs::metadata(p).map_or(0, |m| m.len())
}

/// Every float channel of an OpenEXR file.
fn exr_floats(path: &Path) -> Vec<f32> {
    use exr::prelude::{read_first_rgba_layer_from_file, Vec2};
    let image = read_first_rgba_layer_from_file(
        path,
        |size, _| vec![0.0f32; size.width() * size.height() * 3],
        |pixels: &mut Vec<f32>, Vec2(x, y), (r, g, b, _): (f32, f32, f32, f32)| {
            let at = (y * 8 + x) * 3;
            pixels[at..at + 3].copy_from_slice(&[r, g, b]);
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels
}

/// A render held after its first row by `--pause-after-rows 1` (one thread), so that what
/// happens next does not depend on how fast the machine renders. Killed when dropped, so a
/// failing test leaves no render waiting.
struct Paused {
    child: Child,
    /// Its stderr, line by line, from a thread reading it (so that waiting can time out).
    lines: Receiver<String>,
    /// What it printed so far.
    said: String,
}

impl Paused {
    /// Starts `command` (a render with `--pause-after-rows 1`) and returns once it has paused.
    fn start(command: Command) -> Self {
        Self::start_until(command, "paused after 1 rows")
    }

    /// Starts `command` and returns once it has printed a line containing `pause`.
    fn start_until(mut command: Command, pause: &str) -> Self {
        let mut child = command.stderr(Stdio::piped()).spawn().expect("runs");
        let err = BufReader::new(child.stderr.take().unwrap());
        let (send, lines) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in err.lines().map_while(Result::ok) {
                if send.send(line).is_err() {
                    break;
                }
            }
        });
        let mut paused = Paused {
            child,
            lines,
            said: String::new(),
        };
        paused.wait_for(pause);
        paused
    }

    /// Waits until it prints a line containing `text` (the deadline is a guard against a
    /// hang, not a measure of speed).
    fn wait_for(&mut self, text: &str) {
        let deadline = Instant::now() + Duration::from_secs(300);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    self.said.push_str(&line);
                    self.said.push('\n');
                    if line.contains(text) {
                        return;
                    }
                }
                Err(RecvTimeoutError::Timeout) => panic!("it never said `{text}`: {}", self.said),
                Err(RecvTimeoutError::Disconnected) => {
                    panic!("it ended before saying `{text}`: {}", self.said)
                }
            }
        }
    }

    /// Sends it `signal` and returns its exit code and everything it printed.
    fn signal(&mut self, signal: &str) -> (Option<i32>, String) {
        let kill = Command::new("kill")
            .args(["-s", signal, &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
        let status = self.child.wait().unwrap();
        // The reader ends with its stderr.
        for line in self.lines.iter() {
            self.said.push_str(&line);
            self.said.push('\n');
        }
        (status.code(), std::mem::take(&mut self.said))
    }
}

impl Drop for Paused {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `rayforge render SCENE -o OUT --threads 1 --pause-after-rows 1`.
fn paused_render(scene: &Path, out: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command
        .args([Path::new("render"), scene, Path::new("-o"), out])
        .args(["--threads", "1", "--pause-after-rows", "1"]);
    command
}

/// `command` run by `sh` under `limits` (`ulimit` arguments), with SIGXFSZ ignored so that a
/// write past the file size limit fails with an error instead of killing the process.
#[cfg(target_os = "linux")]
fn limited(limits: &str, command: &Command) -> Command {
    let mut sh = Command::new("sh");
    sh.arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit {limits} && exec \"$0\" \"$@\""
        ))
        .arg(command.get_program())
        .args(command.get_args());
    sh
}

/// Waits (a guard against a hang, not a measure of speed) until `path` holds `len` bytes.
fn wait_for_size(path: &Path, len: u64) {
    let deadline = Instant::now() + Duration::from_secs(300);
    while size(path) < len {
        assert!(Instant::now() < deadline, "`{}` never grew", path.display());
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// FNV-1a, 64-bit: the checkpoint's checksum.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A record of row `y` of `SLOW_SCENE` with every channel `value`, its checksum right.
fn forged_record(y: u64, value: f64) -> Vec<u8> {
    let mut record = y.to_le_bytes().to_vec();
    for _ in 0..200 * 3 {
        record.extend_from_slice(&value.to_le_bytes());
    }
    let sum = fnv(&record);
    record.extend_from_slice(&sum.to_le_bytes());
    record
}

/// Finding 6: pixels that overflow to infinity (or NaN) are written black in every format, the
/// float formats hold only finite numbers, and the summary warns how many pixels there were.
#[test]
fn non_finite_pixels_are_written_as_0_in_every_format_and_counted() {
    let d = Dir::new();
    let scene = d.file("overflow.yml", OVERFLOWING);
    let warning = |o: &Output, out: &Path| {
        let err = stderr(o);
        assert!(o.status.success(), "{err}");
        let expected = format!(
            "warning: 12 pixels of `{}` were not finite (NaN or infinite) and were written as 0",
            out.display()
        );
        assert!(err.contains(&expected), "{err}");
    };
    for ext in ["pfm", "exr", "png", "ppm"] {
        let out = d.path(&format!("ray.{ext}"));
        warning(&render(&scene, &out, &[]), &out);
    }
    // The sphere's centre is black, not white (an infinity once clamped to 255).
    let png = image::open(d.path("ray.png")).unwrap().to_rgb8();
    assert_eq!(png.get_pixel(4, 4).0, [0, 0, 0]);
    let ppm = std::fs::read_to_string(d.path("ray.ppm")).unwrap();
    let values: Vec<&str> = ppm.split_whitespace().skip(4).collect();
    assert_eq!(
        values[(4 * 8 + 4) * 3..(4 * 8 + 4) * 3 + 3],
        ["0", "0", "0"]
    );
    for floats in [
        pfm_floats(&d.path("ray.pfm")),
        exr_floats(&d.path("ray.exr")),
    ] {
        assert_eq!(floats.len(), 8 * 8 * 3);
        assert!(floats.iter().all(|v| v.is_finite()), "{floats:?}");
    }

    // The path tracer's linear formats too.
    let scene = d.file("emitter.yml", OVERFLOWING_EMITTER);
    for ext in ["pfm", "exr"] {
        let out = d.path(&format!("path.{ext}"));
        let o = render(&scene, &out, &["--renderer", "path", "--spp", "4"]);
        warning(&o, &out);
    }
    assert!(pfm_floats(&d.path("path.pfm"))
        .iter()
        .all(|v| v.is_finite()));
    assert!(exr_floats(&d.path("path.exr"))
        .iter()
        .all(|v| v.is_finite()));

    // --quiet prints nothing, the warning included.
    let o = render(&scene, &d.path("quiet.pfm"), &["-q", "--renderer", "path"]);
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
}

/// Finding 6: a checkpoint whose records no render writes (a row past the image, a row saved
/// twice, a value that is not finite), checksums and all, is refused when resuming, exit 2,
/// and kept; the genuine one resumes.
#[cfg(unix)]
#[test]
fn forged_checkpoint_rows_are_refused_when_resuming() {
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let out = d.path("out.pfm");
    let checkpoint = checkpoint_of(&out);
    let (code, err) = Paused::start(paused_render(&scene, &out)).signal("INT");
    assert_eq!(code, Some(130), "{err}");
    let genuine = std::fs::read(&checkpoint).unwrap();
    assert_eq!(genuine.len() as u64, CHECKPOINT_HEADER + SLOW_ROW_RECORD);
    let first_record = genuine[CHECKPOINT_HEADER as usize..].to_vec();

    let saved_y = u64::from_le_bytes(first_record[..8].try_into().unwrap());
    for (forgery, why) in [
        (
            forged_record(150, 0.5),
            "a record is for row 150, past the image's 150 rows",
        ),
        (
            first_record.clone(),
            &*format!("row {saved_y} is saved twice"),
        ),
        (
            forged_record(149, f64::NAN),
            "row 149 holds a value that is not a finite number",
        ),
        (
            forged_record(149, f64::INFINITY),
            "row 149 holds a value that is not a finite number",
        ),
    ] {
        let mut forged = genuine.clone();
        forged.extend_from_slice(&forgery);
        std::fs::write(&checkpoint, &forged).unwrap();
        let o = render(&scene, &out, &["-q", "--resume"]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(why), "{err}");
        assert!(err.contains("not written by rayforge"), "{err}");
        assert_eq!(
            std::fs::read(&checkpoint).unwrap(),
            forged,
            "kept as it was"
        );
        assert!(!out.exists());
    }

    std::fs::write(&checkpoint, &genuine).unwrap();
    let o = render(&scene, &out, &["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("resuming: 1 of 150 rows"),
        "{}",
        stderr(&o)
    );
    assert!(!checkpoint.exists());
}

/// Finding 7: while one render runs, a second to the same output is refused (exit 2) naming
/// the lock and the process holding it, and leaves the first's checkpoint alone; the first
/// then saves its rows where it says; the lock goes when it ends.
#[cfg(unix)]
#[test]
fn second_render_to_the_same_output_is_refused_by_the_lock() {
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let out = d.path("out.png");
    let (checkpoint, lock) = (checkpoint_of(&out), lock_of(&out));
    let mut first = Paused::start(paused_render(&scene, &out));
    let pid = first.child.id();
    wait_for_size(&checkpoint, CHECKPOINT_HEADER + SLOW_ROW_RECORD);
    let saved = std::fs::read(&checkpoint).unwrap();
    assert_eq!(
        std::fs::read_to_string(&lock).unwrap().trim(),
        pid.to_string()
    );

    for extra in [&["-q"][..], &["-q", "--resume"], &["-q", "--threads", "2"]] {
        let o = render(&scene, &out, extra);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.contains(&format!("`{}`", lock.display())), "{err}");
        assert!(err.contains(&format!("process {pid}")), "{err}");
        assert_eq!(std::fs::read(&checkpoint).unwrap(), saved, "{extra:?}");
    }
    assert!(!out.exists());

    let (code, err) = first.signal("INT");
    assert_eq!(code, Some(130), "{err}");
    assert!(
        err.contains(&format!(
            "1 of 150 rows are saved in `{}`",
            checkpoint.display()
        )),
        "{err}"
    );
    assert_eq!(std::fs::read(&checkpoint).unwrap(), saved);
    assert!(!lock.exists(), "the lock goes with the render");

    // Free again: the next render takes the lock and finishes the image.
    let o = render(&scene, &out, &["-q", "--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists() && !checkpoint.exists() && !lock.exists());
}

/// Finding 8: rows are written to the checkpoint from the first while the render goes on
/// (they were held for the render's first two seconds), every half second, so a killed
/// render loses at most that; the killed render's lock file does not hold off the next
/// render.
///
/// The render finishes its first row and pauses, neither rendering nor ending: the row
/// reaches the checkpoint only if rows are saved while the render runs (held to the end or
/// until more rows came, it never would). The wait is bounded only against a hang, so the
/// test does not depend on the machine's speed.
#[cfg(unix)]
#[test]
fn rows_are_checkpointed_from_the_first_one_while_the_render_runs() {
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let out = d.path("out.pfm");
    let checkpoint = checkpoint_of(&out);
    let mut paused = Paused::start(paused_render(&scene, &out));
    wait_for_size(&checkpoint, CHECKPOINT_HEADER + SLOW_ROW_RECORD);
    assert!(paused.child.try_wait().unwrap().is_none(), "still paused");
    let (code, _) = paused.signal("KILL");
    assert_eq!(code, None, "killed");
    assert!(
        lock_of(&out).exists(),
        "a killed render leaves its lock file"
    );

    let o = render(&scene, &out, &["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("resuming: 1 of 150 rows"),
        "{}",
        stderr(&o)
    );
    assert!(!checkpoint.exists() && !lock_of(&out).exists());
}

/// Finding 8: a write error while checkpointing (the file size limit standing in for a full
/// disk) is warned about once, at once, and the interrupted render then says no row is saved
/// instead of claiming rows in a file that does not hold them; no checkpoint stays behind.
#[cfg(target_os = "linux")]
#[test]
fn a_checkpoint_write_error_is_reported_and_no_saved_rows_are_claimed() {
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let out = d.path("out.pfm");
    // 512 bytes: the header fits, a row's record does not.
    let mut paused = Paused::start(limited("-f 1", &paused_render(&scene, &out)));
    paused.wait_for("warning: cannot write the checkpoint");
    let (code, err) = paused.signal("INT");
    assert_eq!(code, Some(130), "{err}");
    assert_eq!(
        err.matches("cannot write the checkpoint").count(),
        2,
        "{err}"
    );
    assert!(err.to_lowercase().contains("file too large"), "{err}");
    assert!(err.contains("interrupted: no row is saved"), "{err}");
    assert!(!err.contains("rows are saved"), "{err}");
    let left = files_in(&d);
    assert_eq!(
        left,
        ["slow.yml"],
        "no checkpoint, lock, image or temporary file"
    );
}

/// Finding 8: a render that cannot write its image (the file size limit again, standing in for
/// a full disk or an immutable output) fails with a clear error and leaves no checkpoint
/// holding a header alone.
#[cfg(target_os = "linux")]
#[test]
fn a_failed_image_write_leaves_no_header_only_checkpoint() {
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let out = d.path("out.pfm");
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command.args([
        Path::new("render"),
        &scene,
        Path::new("-o"),
        &out,
        Path::new("-q"),
    ]);
    let o = limited("-f 1", &command).output().unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!("cannot write `{}`", out.display())),
        "{err}"
    );
    let left = files_in(&d);
    assert_eq!(
        left,
        ["slow.yml"],
        "no checkpoint, lock, image or temporary file"
    );
}

/// Finding 8: an image whose memory the system refuses (here a 4 GiB address-space limit
/// against a 2²⁸-pixel render) is a clear error, exit 2, before the render starts and before
/// any checkpoint, instead of an abort (exit 134) that left one behind.
#[cfg(target_os = "linux")]
#[test]
fn an_allocation_failure_is_a_clear_error_not_an_abort() {
    let d = Dir::new();
    let scene = d.file("slow.yml", SLOW_SCENE);
    let out = d.path("out.png");
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command
        .args([Path::new("render"), &scene, Path::new("-o"), &out])
        .args(["--width", "16384", "--height", "16384", "--threads", "1"]);
    let o = limited("-v 4194304", &command).output().unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("not enough memory for a 16384×16384 render"),
        "{err}"
    );
    assert!(err.contains("--width"), "{err}");
    let left = files_in(&d);
    assert_eq!(left, ["slow.yml"], "no checkpoint, lock or image");
}

/// Ctrl-C inside a raster frame (`--renderer raster`, one thread, held by
/// `--pause-after-rows 32` once its first band of tiles is drawn, so that the signal comes
/// inside the frame whatever the machine's speed): the frame stops at its next tile and the
/// command exits 130, saying how many of its tiles were drawn and that nothing was written,
/// as the docs say. The rasterizer keeps no checkpoint: an image already at the output is
/// left as it was, and nothing is left beside it (no checkpoint, no lock, no temporary file).
#[cfg(unix)]
#[test]
fn an_interrupted_raster_frame_writes_nothing_and_leaves_the_old_image() {
    let d = Dir::new();
    let scene = d.file(
        "ball.yml",
        "- add: camera\n  width: 256\n  height: 128\n  field-of-view: 1\n  from: [0, 0, -5]\n  \
         to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: light\n  at: [-5, 5, -5]\n  \
         intensity: [1, 1, 1]\n- add: sphere\n",
    );
    let out = d.path("ball.png");
    std::fs::write(&out, b"an earlier render's image").unwrap();
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command
        .args([Path::new("render"), &scene, Path::new("-o"), &out])
        .args([
            "--renderer",
            "raster",
            "--threads",
            "1",
            "--pause-after-rows",
            "32",
        ]);
    let (code, err) = Paused::start_until(command, "paused after 32 rows").signal("INT");
    assert_eq!(code, Some(130), "{err}");
    // 256 × 128 pixels are 4 × 4 tiles of 64 × 32: the first band's 4 were drawn.
    assert!(
        err.contains(
            "interrupted: the raster frame was interrupted after 4 of its 16 tiles; nothing was \
             written"
        ),
        "{err}"
    );
    assert_eq!(std::fs::read(&out).unwrap(), b"an earlier render's image");
    let mut files = files_in(&d);
    files.sort();
    assert_eq!(files, ["ball.png", "ball.yml"], "{err}");
}
