//! Watching a render: `--display-server` streams it to a tev viewer (here a fake one that
//! decodes tev's packets and rebuilds the image), and `--time` refines a path-traced image in
//! passes. The viewer's last image equals the file written; a viewer that goes away mid-render
//! costs one warning; an image made in passes equals the one-pass image at the samples reached.
use std::io::Read;
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::thread::JoinHandle;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn render(scene: &str, out: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(repo().join(scene))
        .arg("-o")
        .arg(out)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The PFM's floats after its header (bottom row first, as PFM stores them).
fn pfm_floats(path: &Path) -> (usize, usize, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]).into_owned();
    let mut lines = text.lines();
    lines.next();
    let mut size = lines.next().unwrap().split_whitespace();
    let width: usize = size.next().unwrap().parse().unwrap();
    let height: usize = size.next().unwrap().parse().unwrap();
    let floats = bytes[bytes.len() - width * height * 12..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    (width, height, floats)
}

/// What a fake tev saw: the image it created and rebuilt from updates.
#[derive(Debug, Default)]
struct Viewer {
    name: String,
    width: usize,
    height: usize,
    channels: Vec<String>,
    /// Per channel, row-major from the top.
    pixels: Vec<Vec<f32>>,
    updates: usize,
}

fn cstring(bytes: &[u8], at: &mut usize) -> String {
    let end = *at + bytes[*at..].iter().position(|&b| b == 0).unwrap();
    let s = String::from_utf8(bytes[*at..end].to_vec()).unwrap();
    *at = end + 1;
    s
}

fn int<const N: usize>(bytes: &[u8], at: &mut usize) -> i64 {
    let mut b = [0u8; 8];
    b[..N].copy_from_slice(&bytes[*at..*at + N]);
    *at += N;
    if N == 4 {
        i64::from(i32::from_le_bytes(b[..4].try_into().unwrap()))
    } else {
        i64::from_le_bytes(b)
    }
}

/// Decodes tev's packets from `stream` until it closes, rebuilding the image; with
/// `hang_up_after`, closes the connection after that many packets instead.
fn serve(mut stream: TcpStream, hang_up_after: Option<usize>) -> Viewer {
    let mut viewer = Viewer::default();
    let mut packets = 0;
    loop {
        if hang_up_after == Some(packets) {
            return viewer;
        }
        let mut len = [0u8; 4];
        if stream.read_exact(&mut len).is_err() {
            return viewer;
        }
        let len = u32::from_le_bytes(len) as usize;
        let mut body = vec![0u8; len - 4];
        stream.read_exact(&mut body).unwrap();
        packets += 1;
        let mut at = 1;
        match body[0] {
            4 => {
                assert_eq!(body[at], 1, "grab focus");
                at += 1;
                viewer.name = cstring(&body, &mut at);
                viewer.width = int::<4>(&body, &mut at) as usize;
                viewer.height = int::<4>(&body, &mut at) as usize;
                let n = int::<4>(&body, &mut at) as usize;
                viewer.channels = (0..n).map(|_| cstring(&body, &mut at)).collect();
                viewer.pixels = vec![vec![f32::NAN; viewer.width * viewer.height]; n];
                assert_eq!(at, body.len());
            }
            6 => {
                at += 1;
                assert_eq!(cstring(&body, &mut at), viewer.name);
                let n = int::<4>(&body, &mut at) as usize;
                let names: Vec<String> = (0..n).map(|_| cstring(&body, &mut at)).collect();
                let [x, y, w, h] = [0; 4].map(|_| int::<4>(&body, &mut at) as usize);
                let offsets: Vec<i64> = (0..n).map(|_| int::<8>(&body, &mut at)).collect();
                let strides: Vec<i64> = (0..n).map(|_| int::<8>(&body, &mut at)).collect();
                let samples: Vec<f32> = body[at..]
                    .chunks_exact(4)
                    .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                    .collect();
                assert_eq!(samples.len(), w * h * n);
                for (c, name) in names.iter().enumerate() {
                    let channel = viewer.channels.iter().position(|v| v == name).unwrap();
                    for py in 0..h {
                        for px in 0..w {
                            let i = (offsets[c] + strides[c] * (py * w + px) as i64) as usize;
                            viewer.pixels[channel][(y + py) * viewer.width + x + px] = samples[i];
                        }
                    }
                }
                viewer.updates += 1;
            }
            kind => panic!("unexpected packet kind {kind}"),
        }
    }
}

/// A fake tev on a free port of 127.0.0.1: its address and the thread that serves one
/// connection.
fn fake_tev(hang_up_after: Option<usize>) -> (String, JoinHandle<Viewer>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let handle = std::thread::spawn(move || {
        let (stream, _) = listener.accept().unwrap();
        serve(stream, hang_up_after)
    });
    (address, handle)
}

/// The viewer's colour channels as PFM rows (bottom first), to compare with the file.
fn as_pfm(viewer: &Viewer) -> Vec<f32> {
    let mut out = Vec::new();
    for y in (0..viewer.height).rev() {
        for x in 0..viewer.width {
            for c in 0..3 {
                out.push(viewer.pixels[c][y * viewer.width + x]);
            }
        }
    }
    out
}

#[test]
fn tev_is_shown_each_pass_and_ends_on_the_written_image() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cornell.pfm");
    let (address, viewer) = fake_tev(None);
    let o = render(
        "scenes/pbr/cornell.yml",
        &out,
        &[
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "8",
            "--aovs",
            "--display-server",
            &address,
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let viewer = viewer.join().unwrap();
    assert_eq!(viewer.name, out.display().to_string());
    assert_eq!((viewer.width, viewer.height), (16, 12));
    assert_eq!(
        viewer.channels,
        [
            "R",
            "G",
            "B",
            "albedo.R",
            "albedo.G",
            "albedo.B",
            "normal.R",
            "normal.G",
            "normal.B",
            "depth.R",
            "depth.G",
            "depth.B",
            "samples.R",
            "samples.G",
            "samples.B"
        ]
    );
    // Four passes (1, 1, 2, 4 samples), each row at least once, then the final image.
    assert!(viewer.updates >= 5, "{} updates", viewer.updates);
    let (_, _, file) = pfm_floats(&out);
    assert_eq!(as_pfm(&viewer), file);
    // The albedo layer came too: every pixel of it was set.
    assert!(viewer.pixels[3].iter().all(|v| v.is_finite()));
}

#[test]
fn tev_shows_the_ray_tracer_row_by_row() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("world.pfm");
    let (address, viewer) = fake_tev(None);
    let o = render(
        "scenes/trtc/ch07-world.yml",
        &out,
        &[
            "--width",
            "20",
            "--height",
            "10",
            "--display-server",
            &address,
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let viewer = viewer.join().unwrap();
    assert_eq!(viewer.channels, ["R", "G", "B"]);
    let (_, _, file) = pfm_floats(&out);
    assert_eq!(as_pfm(&viewer), file);
}

#[test]
fn the_render_survives_the_viewer_going_away() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cornell.pfm");
    // The viewer reads the create packet and one update, then hangs up.
    let (address, viewer) = fake_tev(Some(2));
    let o = render(
        "scenes/pbr/cornell.yml",
        &out,
        &[
            "--width",
            "32",
            "--height",
            "24",
            "--spp",
            "64",
            "--display-server",
            &address,
        ],
    );
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(out.exists());
    viewer.join().unwrap();
    assert!(
        err.matches("cannot show the render in tev").count() <= 1,
        "{err}"
    );
}

#[test]
fn an_absent_viewer_costs_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("world.pfm");
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let o = render(
        "scenes/trtc/ch07-world.yml",
        &out,
        &[
            "--width",
            "8",
            "--height",
            "6",
            "--display-server",
            &format!("127.0.0.1:{port}"),
        ],
    );
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert_eq!(
        err.matches("warning: cannot show the render in tev")
            .count(),
        1,
        "{err}"
    );
}

#[test]
fn an_image_refined_in_passes_equals_the_one_pass_image_at_the_samples_reached() {
    let dir = tempfile::tempdir().unwrap();
    let timed = dir.path().join("timed.pfm");
    let size = ["--width", "12", "--height", "9"];
    let mut args = size.to_vec();
    args.extend(["--time", "1s"]);
    let o = render("scenes/pbr/spheres-materials.yml", &timed, &args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    // "path traced 12×9 at N spp in …": N is whatever this machine reached in a second.
    let spp: u64 = err
        .split(" at ")
        .nth(1)
        .and_then(|rest| rest.split(" spp").next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    assert!(spp.is_power_of_two(), "{spp}");
    let once = dir.path().join("once.pfm");
    let mut args = size.to_vec();
    let spp_text = spp.to_string();
    // Named: without it, --spp is held to the ray tracer's 4096, which a fast second passes.
    // Passes share samples evenly; one pass would share them adaptively.
    args.extend([
        "--renderer",
        "path",
        "--spp",
        &spp_text,
        "--sample-allocation",
        "uniform",
    ]);
    let o = render("scenes/pbr/spheres-materials.yml", &once, &args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&timed).unwrap(),
        std::fs::read(&once).unwrap()
    );
}

/// The ray tracer refines in passes of 1, 4, 16, … camera rays per pixel within `--time`: the
/// image written is the one-pass render at the samples reached, whatever this machine reached
/// in the time; with a budget it cannot use up, the samples asked for (--spp 9: passes of 1, 4
/// and 9).
#[test]
fn the_ray_tracer_refines_in_passes_to_the_image_at_the_samples_reached() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "12", "--height", "9"];
    let once = |spp: &str, name: &str| {
        let out = dir.path().join(name);
        let mut args = size.to_vec();
        args.extend(["--spp", spp]);
        let o = render("scenes/trtc/ch07-world.yml", &out, &args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let timed = dir.path().join("timed.png");
    let mut args = size.to_vec();
    args.extend(["--time", "300ms"]);
    let o = render("scenes/trtc/ch07-world.yml", &timed, &args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    // "refined within 0.30 s to N camera rays per pixel (…)".
    let reached: u64 = err
        .split(" s to ")
        .nth(1)
        .and_then(|rest| rest.split(" camera rays").next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    let side = (reached as f64).sqrt() as u64;
    assert!(
        side * side == reached && side.is_power_of_two(),
        "{reached}"
    );
    assert_eq!(
        std::fs::read(&timed).unwrap(),
        once(&reached.to_string(), "once.png")
    );
    let mut args = size.to_vec();
    args.extend(["--spp", "9", "--time", "1h"]);
    let o = render("scenes/trtc/ch07-world.yml", &timed, &args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("to 9 camera rays per pixel"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(&timed).unwrap(), once("9", "nine.png"));
}

#[test]
fn durations_are_read_with_their_units_and_bad_ones_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.pfm");
    for bad in ["0s", "soon", "5 parsecs", "1e400s", "2y"] {
        let o = render(
            "scenes/pbr/furnace.yml",
            &out,
            &["--width", "4", "--height", "3", "--time", bad],
        );
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("--time takes a duration"),
            "{}",
            stderr(&o)
        );
    }
    // The rasterizer draws its image in one pass: no budget to refine within.
    let o = render(
        "scenes/trtc/ch07-world.yml",
        &out,
        &[
            "--width",
            "4",
            "--height",
            "3",
            "--renderer",
            "raster",
            "--time",
            "1s",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("rasterizer draws"), "{}", stderr(&o));
    let o = render(
        "scenes/pbr/furnace.yml",
        &out,
        &[
            "--width", "4", "--height", "3", "--spp", "4", "--time", "250ms",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The most bytes the system lets a TCP socket buffer (`/proc/sys/net/ipv4/tcp_rmem`'s and
/// `tcp_wmem`'s largest, the sender's and the receiver's together), or 64 MiB where that
/// cannot be read: what a viewer that never reads can hold before every write blocks.
fn socket_buffers_at_most() -> usize {
    let largest = |file: &str| {
        std::fs::read_to_string(file)
            .ok()?
            .split_whitespace()
            .nth(2)?
            .parse::<usize>()
            .ok()
    };
    match (
        largest("/proc/sys/net/ipv4/tcp_rmem"),
        largest("/proc/sys/net/ipv4/tcp_wmem"),
    ) {
        (Some(r), Some(w)) => r + w,
        _ => 64 << 20,
    }
}

/// A viewer that accepts the connection and never reads a byte: the render still finishes
/// and writes its image, with one warning that the viewer counts as gone once a packet has
/// waited `--display-timeout` (here 1 s). The stall does not depend on the machine's speed:
/// the image's packets (12 bytes a pixel for its rows, as many again for the finished image)
/// are twice what the two sockets' buffers can ever hold, so some packet is certain to wait
/// its whole timeout; and the outcome asserted is the warning and the image, not a time.
#[test]
fn a_viewer_that_never_reads_is_dropped_and_the_render_finishes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("sky.yml");
    // Nothing but the background: the render costs next to nothing per pixel.
    std::fs::write(
        &scene,
        "- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  \
         to: [0, 0, 0]\n  up: [0, 1, 0]\n",
    )
    .unwrap();
    let pixels = 2 * socket_buffers_at_most() / 24 + 1;
    let side = (pixels as f64).sqrt().ceil() as usize;
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let (done, hold) = std::sync::mpsc::channel::<()>();
    let viewer = std::thread::spawn(move || {
        let (stream, _) = listener.accept().unwrap();
        // Holds the connection open, unread, until the render has ended.
        let _ = hold.recv();
        drop(stream);
    });
    let out = dir.path().join("sky.pfm");
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .args(["--width", &side.to_string(), "--height", &side.to_string()])
        .args(["--display-server", &address, "--display-timeout", "1"])
        .output()
        .unwrap();
    done.send(()).unwrap();
    viewer.join().unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert_eq!(
        err.matches("warning: cannot show the render in tev")
            .count(),
        1,
        "{err}"
    );
    assert!(
        err.contains("it has not taken a packet in 1 s, so it counts as gone; the render goes on"),
        "{err}"
    );
    let (width, height, _) = pfm_floats(&out);
    assert_eq!((width, height), (side, side));
}

#[test]
fn the_display_timeout_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("world.pfm");
    for bad in ["0", "-1", "3601", "nan"] {
        let flag = format!("--display-timeout={bad}");
        let o = render("scenes/trtc/ch07-world.yml", &out, &[&flag]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            stderr(&o).contains("--display-timeout"),
            "{bad}: {}",
            stderr(&o)
        );
    }
}
