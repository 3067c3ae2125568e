//! Denoising while the image refines: `rayforge render --display-server … --denoise` streams a
//! `denoised` layer beside the rows' `noisy` one to a (fake) tev viewer, its last state the
//! written image; without `--denoise` the viewer gets the plain image and no denoised layer.
//! The live page's `denoise` box: raw passes, then denoised ones flagged so, the last frame
//! `rayforge render --denoise`'s image; the box off, nothing denoised; another renderer ignores
//! it; without the library, the page is told how to install it. (That a pass offered while the
//! denoiser is busy is skipped, not queued, is tested without timing in `live_denoise.rs`.)
//!
//! The tests that run Intel Open Image Denoise skip, saying so on stderr, where it is not
//! installed (`tools/oidn/install.sh`), unless `RAYFORGE_REQUIRE_OIDN` is set or `CI` is
//! `true`, where its absence fails them.

use exr::prelude::{read_all_flat_layers_from_file, FlatSamples};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;
use tokio::net::TcpStream as AsyncTcpStream;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream};

/// The longest a test waits for any one message.
const PATIENCE: Duration = Duration::from_secs(120);

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Whether OIDN is installed; where it is not and not required, says the test skipped.
fn oidn_present(test: &str) -> bool {
    if rayforge_denoise::Denoiser::load().is_ok() {
        return true;
    }
    let required = std::env::var_os("RAYFORGE_REQUIRE_OIDN").is_some()
        || std::env::var("CI").is_ok_and(|v| v == "true");
    assert!(
        !required,
        "Intel Open Image Denoise is required here (tools/oidn/install.sh)"
    );
    use std::io::Write;
    let _ = writeln!(
        std::io::stderr(),
        "skipped: {test}: Intel Open Image Denoise is not installed (tools/oidn/install.sh)"
    );
    false
}

/// A packet as tev reads it: its kind (4 create, 6 update), channels and samples.
#[derive(Debug)]
struct Packet {
    kind: u8,
    channels: Vec<String>,
    samples: Vec<f32>,
}

/// The packets of a tev stream.
fn packets(mut bytes: &[u8]) -> Vec<Packet> {
    let mut out = Vec::new();
    while bytes.len() >= 5 {
        let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        let (packet, rest) = bytes.split_at(len);
        bytes = rest;
        let kind = packet[4];
        let mut at = 6;
        let string = |at: &mut usize| {
            let end = *at + packet[*at..].iter().position(|&b| b == 0).unwrap();
            let s = String::from_utf8(packet[*at..end].to_vec()).unwrap();
            *at = end + 1;
            s
        };
        string(&mut at);
        if kind == 4 {
            at += 8;
        }
        let count = i32::from_le_bytes(packet[at..at + 4].try_into().unwrap()) as usize;
        at += 4;
        let channels: Vec<String> = (0..count).map(|_| string(&mut at)).collect();
        let samples = if kind == 6 {
            at += 16 + 16 * count;
            packet[at..]
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                .collect()
        } else {
            Vec::new()
        };
        out.push(Packet {
            kind,
            channels,
            samples,
        });
    }
    out
}

/// Renders the Cornell box path traced (32 pixels wide, 8 samples: passes of 1, 1, 2, 4) to
/// `out`, streamed to a fake tev viewer, with `extra` flags (its summary lines on stderr);
/// the command's output and every packet the viewer received.
fn render_to_viewer(out: &Path, extra: &[&str]) -> (Output, Vec<Packet>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a port");
    let address = listener.local_addr().expect("its address").to_string();
    let viewer = std::thread::spawn(move || {
        let (mut stream, _) = listener.accept().expect("the render connects");
        let mut bytes = Vec::new();
        stream.read_to_end(&mut bytes).expect("reads the stream");
        bytes
    });
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(repo().join("scenes/pbr/cornell.yml"))
        .arg("-o")
        .arg(out)
        .args(["--renderer", "path", "--width", "32", "--spp", "8"])
        .args(["--display-server", &address])
        .args(extra)
        .output()
        .expect("runs rayforge");
    let bytes = viewer.join().expect("the viewer");
    (o, packets(&bytes))
}

/// A layer's channels as tev names them.
fn rgb(layer: &str) -> Vec<String> {
    ["R", "G", "B"]
        .iter()
        .map(|c| {
            if layer.is_empty() {
                c.to_string()
            } else {
                format!("{layer}.{c}")
            }
        })
        .collect()
}

/// Every channel of an OpenEXR file's first layer, by name.
fn exr_channels(path: &Path) -> BTreeMap<String, Vec<f32>> {
    let image = read_all_flat_layers_from_file(path).expect("reads the EXR");
    image.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| {
            let values = match &c.sample_data {
                FlatSamples::F32(v) => v.clone(),
                other => other.values_as_f32().collect(),
            };
            (c.name.to_string(), values)
        })
        .collect()
}

#[test]
fn the_viewer_gets_a_denoised_layer_beside_the_noisy_rows_and_ends_on_the_written_image() {
    if !oidn_present("render --denoise --display-server") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.exr");
    let (o, received) = render_to_viewer(&out, &["--denoise", "--aovs"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(received[0].kind, 4, "the image is created first");
    let mut layout = rgb("denoised");
    for layer in ["noisy", "albedo", "normal", "depth", "samples"] {
        layout.extend(rgb(layer));
    }
    assert_eq!(received[0].channels, layout);
    let updates = |layer: &str| {
        received
            .iter()
            .filter(|p| p.kind == 6 && p.channels.first() == Some(&rgb(layer)[0]))
            .collect::<Vec<_>>()
    };
    // Rows fill the noisy layer and the AOVs, pass after pass; no update touches the bare
    // R, G, B, which the image does not have.
    let rows = updates("noisy");
    assert!(rows.len() >= 4, "{} row updates", rows.len());
    assert!(rows.iter().all(|p| p.channels.len() == 15));
    assert!(received.iter().all(|p| !p.channels.contains(&"R".into())));
    // The denoised layer: whole images (at least the final one), the last being the file's.
    let denoised = updates("denoised");
    assert!(!denoised.is_empty());
    assert!(denoised.iter().all(|p| p.channels == rgb("denoised")));
    let written = exr_channels(&out);
    let pixels = written["R"].len();
    let last = &denoised.last().expect("a denoised update").samples;
    let file: Vec<f32> = (0..pixels)
        .flat_map(|i| [written["R"][i], written["G"][i], written["B"][i]])
        .collect();
    assert_eq!(
        *last, file,
        "the last denoised update is the whole written image"
    );
    // The passes denoised beside the render and the final image shared one OIDN device and,
    // the size never changing, one set of filters.
    let err = stderr(&o);
    let line = err
        .lines()
        .find(|l| l.starts_with("denoised beside the render: "))
        .unwrap_or_else(|| panic!("no line about the live denoising: {err}"));
    let passes: usize = line["denoised beside the render: ".len()..]
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count of passes: {line}"));
    assert!(
        passes >= 1,
        "the first pass finds the denoiser idle: {line}"
    );
    let made = format!(
        "with the final image, {} images on 1 OIDN device (its filters made 1 time)",
        passes + 1
    );
    assert!(line.ends_with(&made), "{line}");
}

#[test]
fn without_denoise_the_viewer_gets_the_plain_image_and_no_denoised_layer() {
    let dir = tempfile::tempdir().unwrap();
    let (o, received) = render_to_viewer(&dir.path().join("c.png"), &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(received[0].channels, rgb(""));
    assert!(received.len() > 1);
    for p in &received {
        assert_eq!(p.channels, rgb(""), "{p:?}");
    }
}

type Socket = WebSocketStream<MaybeTlsStream<AsyncTcpStream>>;

/// The running server, stopped when dropped.
struct Server {
    child: Child,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A small path-traceable scene: a red sphere lit by a point light before a grey wall.
const SCENE: &str = "\
- add: camera
  width: 48
  height: 32
  field-of-view: 0.9
  from: [0, 1, -5]
  to: [0, 0.5, 0]
  up: [0, 1, 0]
- add: light
  at: [-6, 8, -8]
  intensity: [1, 1, 1]
- add: plane
  transform:
    - [rotate-x, 1.5708]
    - [translate, 0, 0, 3]
  material:
    color: [0.6, 0.6, 0.6]
- add: sphere
  transform:
    - [translate, 0, 0.6, 0]
  material:
    color: [1, 0.2, 0.2]
    diffuse: 0.8
";

/// `rayforge serve` on `scene` with `env` set, and a page open on it.
async fn serve(scene: &Path, env: &[(&str, &Path)]) -> (Server, Socket) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command
        .arg("serve")
        .arg(scene)
        .args(["--port", "0", "--threads", "2"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    for (name, value) in env {
        command.env(name, value);
    }
    let mut child = command.spawn().expect("starts rayforge serve");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("its stdout"))
        .read_line(&mut line)
        .expect("reads the address");
    let port: u16 = line
        .trim()
        .strip_prefix("http://127.0.0.1:")
        .and_then(|rest| rest.strip_suffix('/'))
        .and_then(|port| port.parse().ok())
        .unwrap_or_else(|| panic!("the address is on 127.0.0.1: `{line}`"));
    let (socket, _) = tokio_tungstenite::connect_async(format!("ws://127.0.0.1:{port}/ws"))
        .await
        .expect("the WebSocket opens");
    (Server { child }, socket)
}

/// The next message: text as JSON, or a binary image's bytes.
async fn next(socket: &mut Socket) -> Result<serde_json::Value, Vec<u8>> {
    use futures_util::StreamExt;
    loop {
        let message = tokio::time::timeout(PATIENCE, socket.next())
            .await
            .expect("a message within the time");
        match message {
            Some(Ok(Message::Text(text))) => return Ok(serde_json::from_str(&text).expect("JSON")),
            Some(Ok(Message::Binary(bytes))) => return Err(bytes.to_vec()),
            Some(Ok(Message::Ping(_) | Message::Pong(_) | Message::Frame(_))) => continue,
            other => panic!("the socket closed: {other:?}"),
        }
    }
}

/// What a job sent: its `started` message, and each frame's message with its image.
struct Job {
    started: serde_json::Value,
    frames: Vec<(serde_json::Value, image::RgbImage)>,
    error: Option<serde_json::Value>,
}

/// Sends `request` and reads its job's messages until `done` (or an error).
async fn run(socket: &mut Socket, request: &str) -> Job {
    use futures_util::SinkExt;
    socket
        .send(Message::Text(request.to_string().into()))
        .await
        .expect("sends");
    let mut job = Job {
        started: serde_json::Value::Null,
        frames: Vec::new(),
        error: None,
    };
    loop {
        let message = next(socket).await.expect("a JSON message");
        match message["type"].as_str() {
            Some("started") => job.started = message,
            Some("frame") => {
                let png = next(socket).await.expect_err("the frame's image");
                let image = image::load_from_memory(&png).expect("a PNG").to_rgb8();
                job.frames.push((message, image));
            }
            Some("error") => {
                job.error = Some(message);
                return job;
            }
            Some("done") => return job,
            _ => {}
        }
    }
}

/// `rayforge render`'s PNG of `scene` with `flags`.
fn rendered(scene: &Path, out: &Path, flags: &[&str]) -> image::RgbImage {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("--quiet")
        .args(flags)
        .output()
        .expect("runs rayforge render");
    assert!(o.status.success(), "{}", stderr(&o));
    image::open(out).expect("reads the render").to_rgb8()
}

/// How many of two images' pixels differ by more than `tolerance` in a channel.
fn differing(a: &image::RgbImage, b: &image::RgbImage, tolerance: u8) -> usize {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > tolerance))
        .count()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_pages_denoise_box_sends_denoised_passes_and_ends_on_the_denoised_render() {
    if !oidn_present("the live page's denoise box") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.yml");
    std::fs::write(&scene, SCENE).unwrap();
    let (_server, mut socket) = serve(&scene, &[]).await;

    // Denoised: raw passes 1 to 3 (those the denoiser was free for denoised beside them,
    // after them), and the last pass denoised only.
    let on = r#"{"type": "render", "renderer": "path", "samples": 8, "denoise": true}"#;
    let job = run(&mut socket, on).await;
    assert!(job.error.is_none(), "{:?}", job.error);
    assert_eq!(job.started["denoise"], true);
    let (last, image) = job.frames.last().expect("frames");
    assert_eq!(last["pass"], 4);
    assert_eq!(last["passes"], 4);
    assert_eq!(last["denoised"], true);
    let raw: Vec<u64> = job
        .frames
        .iter()
        .filter(|(m, _)| m["denoised"] == false)
        .map(|(m, _)| m["pass"].as_u64().unwrap())
        .collect();
    assert_eq!(raw, [1, 2, 3]);
    for (m, _) in &job.frames[..job.frames.len() - 1] {
        assert!(m["pass"].as_u64() < Some(4), "{m}");
    }
    let expected = rendered(
        &scene,
        &dir.path().join("denoised.png"),
        &["--renderer", "path", "--spp", "8", "--denoise"],
    );
    // Passes add the same samples in another order: the denoiser's input may differ in the
    // last bits, and its 8-bit output by one.
    assert_eq!(differing(image, &expected, 1), 0);
    let raw_render = rendered(
        &scene,
        &dir.path().join("raw.png"),
        &["--renderer", "path", "--spp", "8"],
    );
    assert!(differing(image, &raw_render, 1) > 0, "denoising changed it");

    // The box off: nothing denoised, and the last frame is the raw render.
    let off = r#"{"type": "render", "renderer": "path", "samples": 8, "denoise": false}"#;
    let job = run(&mut socket, off).await;
    assert_eq!(job.started["denoise"], false);
    assert!(job.frames.iter().all(|(m, _)| m["denoised"] == false));
    assert_eq!(job.frames.last().unwrap().1, raw_render);

    // The ray tracer ignores it.
    let ray = r#"{"type": "render", "renderer": "ray", "denoise": true}"#;
    let job = run(&mut socket, ray).await;
    assert!(job.error.is_none(), "{:?}", job.error);
    assert_eq!(job.started["denoise"], false);
    assert!(job.frames.iter().all(|(m, _)| m["denoised"] == false));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn without_the_library_the_denoise_box_says_how_to_install_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.yml");
    std::fs::write(&scene, SCENE).unwrap();
    let empty = dir.path().join("no-oidn");
    std::fs::create_dir(&empty).unwrap();
    let (_server, mut socket) = serve(&scene, &[("RAYFORGE_OIDN_DIR", &empty)]).await;
    let on = r#"{"type": "render", "renderer": "path", "samples": 2, "denoise": true}"#;
    let job = run(&mut socket, on).await;
    let error = job.error.expect("an error");
    let message = error["message"].as_str().unwrap();
    assert!(message.contains("tools/oidn/install.sh"), "{message}");
    assert!(job.frames.is_empty());
    // The page goes on: the same request without the box renders.
    let off = r#"{"type": "render", "renderer": "path", "samples": 2}"#;
    let job = run(&mut socket, off).await;
    assert!(job.error.is_none(), "{:?}", job.error);
    assert_eq!(job.frames.len(), 2);
}
