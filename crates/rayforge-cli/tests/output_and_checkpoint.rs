//! What `rayforge render` writes and saves, under hostile scenes, forged checkpoints, two
//! renders racing for one output, failing writes and scarce memory (issue 21, findings 6 to 8;
//! docs/reliability.md describes each behaviour).
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

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
    assert_eq!(values[(4 * 8 + 4) * 3..(4 * 8 + 4) * 3 + 3], ["0", "0", "0"]);
    for floats in [pfm_floats(&d.path("ray.pfm")), exr_floats(&d.path("ray.exr"))] {
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
    assert!(pfm_floats(&d.path("path.pfm")).iter().all(|v| v.is_finite()));
    assert!(exr_floats(&d.path("path.exr")).iter().all(|v| v.is_finite()));

    // --quiet prints nothing, the warning included.
    let o = render(&scene, &d.path("quiet.pfm"), &["-q", "--renderer", "path"]);
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
}
