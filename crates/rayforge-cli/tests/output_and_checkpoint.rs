//! What `rayforge render` writes and saves, under hostile scenes, forged checkpoints, two
//! renders racing for one output, failing writes and scarce memory (issue 21, findings 6 to 8;
//! docs/reliability.md describes each behaviour).
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStderr, Command, Output, Stdio};
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

struct Dir(tempfile::TempDir);

impl Dir {
    fn new() -> Self {
        Dir(tempfile::tempdir().unwrap())
    }
    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }
}

fn render(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args([Path::new("render"), scene, Path::new("-o"), out])
        .args(extra)
        .output()
        .expect("runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
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

/// The 32-bit floats of a PFM file.
fn pfm_floats(path: &Path) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    let header = b"-1.0\n";
    let at = bytes.windows(5).position(|w| w == header).unwrap() + 5;
    bytes[at..]
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect()
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
/// happens next does not depend on how fast the machine renders.
struct Paused {
    child: Child,
    err: BufReader<ChildStderr>,
    /// What it printed so far.
    said: String,
}

impl Paused {
    /// Starts `command` (a render with `--pause-after-rows 1`) and returns once it has paused.
    fn start(mut command: Command) -> Self {
        let mut child = command.stderr(Stdio::piped()).spawn().expect("runs");
        let err = BufReader::new(child.stderr.take().unwrap());
        let mut paused = Paused {
            child,
            err,
            said: String::new(),
        };
        paused.wait_for("paused after 1 rows");
        paused
    }

    /// Reads its stderr until a line contains `text`.
    fn wait_for(&mut self, text: &str) {
        loop {
            let mut line = String::new();
            let n = self.err.read_line(&mut line).unwrap();
            self.said.push_str(&line);
            assert!(n > 0, "it ended before saying `{text}`: {}", self.said);
            if line.contains(text) {
                return;
            }
        }
    }

    /// Sends it `signal` and returns its exit code and everything it printed.
    fn signal(mut self, signal: &str) -> (Option<i32>, String) {
        let kill = Command::new("kill")
            .args(["-s", signal, &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
        self.err.read_to_string(&mut self.said).unwrap();
        let status = self.child.wait().unwrap();
        (status.code(), self.said)
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

/// Waits (a guard against a hang, not a measure of speed) until `path` holds `len` bytes.
fn wait_for_size(path: &Path, len: u64) {
    let deadline = Instant::now() + Duration::from_secs(300);
    while size(path) < len {
        assert!(Instant::now() < deadline, "`{}` never grew", path.display());
        std::thread::sleep(Duration::from_millis(10));
    }
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
    let first = Paused::start(paused_render(&scene, &out));
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
