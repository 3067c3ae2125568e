//! `rayforge serve`: the server started as a user starts it, on a free port, talked to over
//! HTTP and its WebSocket as the page talks to it. Its first image arrives; an edit of the scene
//! file brings an image equal to `rayforge render`'s of the edited file; a broken file brings an
//! error with its line and column; nothing but the page and its socket is served; malformed or
//! oversized messages are answered or refused without harm.
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;
use tokio::net::TcpStream as AsyncTcpStream;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream};

/// The longest a test waits for any one message.
const PATIENCE: Duration = Duration::from_secs(120);

type Socket = WebSocketStream<MaybeTlsStream<AsyncTcpStream>>;

/// A scene of a `colour` sphere before a grey wall, small enough to render at once.
fn scene(colour: &str) -> String {
    format!(
        "\
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
    color: {colour}
    diffuse: 0.8
"
    )
}

/// The running server, stopped when dropped.
struct Server {
    child: Child,
    port: u16,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `rayforge serve SCENE --port 0` and reads the address it prints.
fn serve(scene: &Path) -> (Server, String) {
    serve_with(scene, &[])
}

/// [`serve`] with more flags.
fn serve_with(scene: &Path, flags: &[&str]) -> (Server, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("serve")
        .arg(scene)
        .args(["--port", "0", "--threads", "2"])
        .args(flags)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts rayforge serve");
    let stdout = child.stdout.take().expect("its stdout");
    let mut line = String::new();
    BufReader::new(stdout)
        .read_line(&mut line)
        .expect("reads the address");
    let address = line.trim().to_string();
    let port = address
        .strip_prefix("http://127.0.0.1:")
        .and_then(|rest| rest.strip_suffix('/'))
        .and_then(|port| port.parse().ok())
        .unwrap_or_else(|| panic!("the address is on 127.0.0.1: `{address}`"));
    (Server { child, port }, address)
}

/// A plain HTTP/1.1 GET of `path` with `host` as its Host; the status code and the body.
fn get(port: u16, path: &str, host: &str) -> (u16, String) {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).expect("connects");
    stream
        .set_read_timeout(Some(PATIENCE))
        .expect("sets a timeout");
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
    )
    .expect("sends the request");
    let mut response = String::new();
    stream
        .read_to_string(&mut response)
        .expect("reads the response");
    let status = response
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    (status, response)
}

/// The next message, text as JSON or a binary image.
enum Received {
    Json(serde_json::Value),
    Image(Vec<u8>),
    Closed,
}

async fn next(socket: &mut Socket) -> Received {
    use futures_util::StreamExt;
    loop {
        let message = tokio::time::timeout(PATIENCE, socket.next())
            .await
            .expect("a message within the time");
        match message {
            Some(Ok(Message::Text(text))) => {
                return Received::Json(serde_json::from_str(&text).expect("JSON"))
            }
            Some(Ok(Message::Binary(bytes))) => return Received::Image(bytes.to_vec()),
            Some(Ok(Message::Ping(_) | Message::Pong(_) | Message::Frame(_))) => continue,
            Some(Ok(Message::Close(_)) | Err(_)) | None => return Received::Closed,
        }
    }
}

/// Reads until a job's last pass, and returns its image's pixels and the job; fails on an
/// error message.
async fn final_image(socket: &mut Socket, after_job: u64) -> (image::RgbImage, u64) {
    loop {
        let Received::Json(message) = next(socket).await else {
            panic!("a JSON message before an image");
        };
        assert_ne!(message["type"], "error", "{message}");
        let job = message["job"].as_u64().unwrap_or(0);
        if message["type"] != "frame" {
            continue;
        }
        let Received::Image(png) = next(socket).await else {
            panic!("the image after its frame message");
        };
        if job > after_job && message["pass"] == message["passes"] {
            let image = image::load_from_memory(&png).expect("a PNG").to_rgb8();
            return (image, job);
        }
    }
}

async fn send(socket: &mut Socket, text: String) {
    use futures_util::SinkExt;
    socket
        .send(Message::Text(text.into()))
        .await
        .expect("sends");
}

/// Asks for a rasterized frame `width` pixels wide and waits for it (after job `after_job`).
async fn raster_frame(socket: &mut Socket, width: u32, after_job: u64) -> (image::RgbImage, u64) {
    let request = format!(r#"{{"type": "render", "width": {width}, "renderer": "raster"}}"#);
    send(socket, request).await;
    final_image(socket, after_job).await
}

/// A temporary folder holding `scene.yml`, the [`scene`] of a red sphere, and the file's path
/// (the folder goes when the first is dropped).
fn red_scene() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("scene.yml");
    std::fs::write(&path, scene("[1, 0.2, 0.2]")).expect("writes the scene");
    (dir, path)
}

/// [`red_scene`] served with `flags`, and a page open on it.
async fn red_page(flags: &[&str]) -> (tempfile::TempDir, Server, Socket) {
    let (dir, path) = red_scene();
    let (server, _) = serve_with(&path, flags);
    let page = open_page(server.port).await;
    (dir, server, page)
}

/// Asks for a rasterized frame at the scene's size (48×32) and checks that it comes whole:
/// the page is served again after whatever a test did to the server.
async fn a_whole_frame_comes(socket: &mut Socket) {
    let (image, _) = raster_frame(socket, 48, 0).await;
    assert_eq!(image.dimensions(), (48, 32));
}

/// `rayforge render`'s image of `scene`, as a PNG's pixels.
fn rendered(scene: &Path, out: &Path) -> image::RgbImage {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("--quiet")
        .output()
        .expect("runs rayforge render");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    image::open(out).expect("reads the render").to_rgb8()
}

#[test]
fn only_the_page_and_its_socket_are_served_on_127_0_0_1() {
    let (_dir, path) = red_scene();
    let (server, address) = serve(&path);
    let port = server.port;
    assert_eq!(address, format!("http://127.0.0.1:{port}/"));
    let host = format!("127.0.0.1:{port}");
    let (status, page) = get(port, "/", &host);
    assert_eq!(status, 200, "{page}");
    assert!(page.contains("<title>rayforge serve</title>"), "{page}");
    assert!(page.contains("Content-Security-Policy") || page.contains("content-security-policy"));
    assert!(
        !page.contains("http://") && !page.contains("https://"),
        "no outside address"
    );
    for path in [
        "/scene.yml",
        "/index.html",
        "/../scene.yml",
        "/%2e%2e/scene.yml",
        "/etc/passwd",
        "/ws/scene.yml",
    ] {
        let (status, response) = get(port, path, &host);
        assert_eq!(status, 404, "{path}: {response}");
    }
    // A page under another name (DNS rebinding) is refused.
    let (status, _) = get(port, "/", &format!("attacker.example:{port}"));
    assert_eq!(status, 403);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_ray_tracer_on_the_page_says_it_ignores_media_as_the_command_does() {
    // The red scene with its ball filled with fog, inside a boundary that only bounds it: the
    // ray tracer draws it in vacuum (the boundary left out), and the page is told so.
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("scene.yml");
    let foggy = format!(
        "- medium: fog\n  sigma-s: 2\n{}\
         - add: sphere\n  material: interface\n  interior: fog\n  \
         transform: [[scale, 1.5, 1.5, 1.5], [translate, 0, 0.6, 0]]\n",
        scene("[1, 0.2, 0.2]")
    );
    std::fs::write(&path, foggy).expect("writes the scene");
    let (server, _) = serve(&path);
    let mut socket = open_page(server.port).await;
    send(&mut socket, r#"{"type": "render"}"#.to_string()).await;
    let started = loop {
        match next(&mut socket).await {
            Received::Json(m) if m["type"] == "started" => break m,
            Received::Closed => panic!("the socket closed"),
            _ => {}
        }
    };
    let warnings = started["warnings"].as_array().expect("a list of warnings");
    assert!(
        warnings.iter().any(|w| w.as_str().is_some_and(
            |w| w.contains("participating media are rendered by the path tracer only")
        )),
        "{started}"
    );
    let (image, _) = final_image(&mut socket, 0).await;
    assert_eq!(image, rendered(&path, &dir.path().join("vacuum.png")));
    // And the image is the scene's without its fog.
    let plain = dir.path().join("plain.yml");
    std::fs::write(&plain, scene("[1, 0.2, 0.2]")).expect("writes the scene");
    assert_eq!(image, rendered(&plain, &dir.path().join("plain.png")));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_follows_the_scene_file() {
    let (dir, path) = red_scene();
    let (server, _) = serve(&path);
    let mut socket = open_page(server.port).await;

    send(&mut socket, r#"{"type": "render"}"#.to_string()).await;
    let (first, job) = final_image(&mut socket, 0).await;
    assert_eq!(first.dimensions(), (48, 32));
    assert_eq!(first, rendered(&path, &dir.path().join("first.png")));

    // An edit on disk: the page gets the edited scene's image, as `rayforge render` makes it.
    std::fs::write(&path, scene("[0.2, 0.3, 1]")).expect("edits the scene");
    let (edited, job) = final_image(&mut socket, job).await;
    assert_ne!(edited, first);
    assert_eq!(edited, rendered(&path, &dir.path().join("edited.png")));

    // A warning (a transform with a number too many, ignored) reaches the page with the next
    // render, with its place, and goes when the scene is fixed.
    let warned = scene("[0.2, 0.3, 1]").replace("[translate, 0, 0, 3]", "[translate, 0, 0, 3, 9]");
    std::fs::write(&path, warned).expect("writes the scene");
    let started = loop {
        match next(&mut socket).await {
            Received::Json(m) if m["type"] == "started" && m["job"].as_u64() > Some(job) => {
                break m
            }
            Received::Closed => panic!("the socket closed"),
            _ => {}
        }
    };
    let warnings = started["warnings"].as_array().expect("a list of warnings");
    assert_eq!(warnings.len(), 1, "{started}");
    let warning = warnings[0].as_str().unwrap_or_default();
    assert!(
        warning.contains("scene.yml:14:") && warning.contains("ignored"),
        "{warning}"
    );
    let (_, job) = final_image(&mut socket, job).await;

    // A broken file: an error with its place; the server goes on.
    let broken = scene("[0.2, 0.3, 1]").replace("field-of-view: 0.9", "field-of-view: wide");
    std::fs::write(&path, broken).expect("breaks the scene");
    let error = loop {
        match next(&mut socket).await {
            Received::Json(m) if m["type"] == "error" => break m,
            Received::Closed => panic!("the socket closed"),
            _ => {}
        }
    };
    assert_eq!(error["line"], 4, "{error}");
    assert_eq!(error["column"], 18, "{error}");
    assert_eq!(error["key"], "field-of-view", "{error}");
    assert!(
        error["text"].as_str().is_some_and(|t| t.contains("wide")),
        "{error}"
    );
    assert!(error["job"].as_u64() > Some(job), "{error}");

    // Requests after an error: bad ones are answered, good ones rendered once the file is fixed.
    send(&mut socket, "{not json".to_string()).await;
    let Received::Json(answer) = next(&mut socket).await else {
        panic!("an answer to malformed JSON");
    };
    assert_eq!(answer["type"], "error");
    assert!(
        answer["message"]
            .as_str()
            .is_some_and(|m| m.contains("not JSON")),
        "{answer}"
    );
    std::fs::write(&path, scene("[0.2, 1, 0.3]")).expect("fixes the scene");
    let (fixed, job) = final_image(&mut socket, job).await;
    let (small, job) = raster_frame(&mut socket, 24, job).await;
    assert_eq!(small.dimensions(), (24, 16));
    // The page's rasterizer keeps its buffers between frames: a frame at another size, then
    // the first size again, are each the image `rayforge render --renderer raster` writes.
    let (other, job) = raster_frame(&mut socket, 30, job).await;
    assert_eq!(other.dimensions(), (30, 20));
    let (again, _) = raster_frame(&mut socket, 24, job).await;
    assert_eq!(again, small);
    let raster = |width: &str, name: &str| {
        rendered_with(
            &path,
            &dir.path().join(name),
            &["--renderer", "raster", "--width", width],
        )
    };
    assert_eq!(small, raster("24", "raster-24.png"));
    assert_eq!(other, raster("30", "raster-30.png"));
    assert_eq!(fixed, rendered(&path, &dir.path().join("fixed.png")));

    // A size over --max-pixels is refused in `rayforge render`'s words.
    send(
        &mut socket,
        r#"{"type": "render", "width": 100000, "height": 100000}"#.to_string(),
    )
    .await;
    let refusal = loop {
        match next(&mut socket).await {
            Received::Json(m) if m["type"] == "error" => break m,
            Received::Closed => panic!("the socket closed"),
            _ => {}
        }
    };
    assert!(
        refusal["message"]
            .as_str()
            .is_some_and(|m| m.contains("--max-pixels")),
        "{refusal}"
    );

    // A message over 64 KiB closes the socket; the server serves the next page.
    send(
        &mut socket,
        format!(r#"{{"type": "render", "pad": "{}"}}"#, "x".repeat(70_000)),
    )
    .await;
    loop {
        if let Received::Closed = next(&mut socket).await {
            break;
        }
    }
    let (status, _) = get(server.port, "/", &format!("127.0.0.1:{}", server.port));
    assert_eq!(status, 200);
}

/// `rayforge render`'s image of `scene` with extra flags, as a PNG's pixels.
fn rendered_with(scene: &Path, out: &Path, flags: &[&str]) -> image::RgbImage {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("--quiet")
        .args(flags)
        .output()
        .expect("runs rayforge render");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    image::open(out).expect("reads the render").to_rgb8()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_path_tracer_refines_in_passes_and_the_camera_orbits() {
    let (dir, path) = red_scene();
    let (server, _) = serve(&path);
    let mut socket = open_page(server.port).await;

    // Passes of 1, 1, 2, 4 samples into one film: the last is the one-pass render of 8.
    send(
        &mut socket,
        r#"{"type": "render", "renderer": "path", "samples": 8}"#.to_string(),
    )
    .await;
    let mut samples = Vec::new();
    let last = loop {
        let Received::Json(message) = next(&mut socket).await else {
            panic!("a JSON message");
        };
        assert_ne!(message["type"], "error", "{message}");
        if message["type"] == "frame" {
            samples.push(message["samples"].as_u64().unwrap_or(0));
            let Received::Image(png) = next(&mut socket).await else {
                panic!("the image after its frame message");
            };
            if message["pass"] == message["passes"] {
                break image::load_from_memory(&png).expect("a PNG").to_rgb8();
            }
        }
    };
    assert_eq!(samples, [1, 2, 4, 8]);
    let flags = ["--renderer", "path", "--spp", "8"];
    assert_eq!(
        last,
        rendered_with(&path, &dir.path().join("path.png"), &flags)
    );

    // A quarter turn about the up: the eye at [-5, 1, 0], as a scene placing it there renders.
    send(&mut socket, r#"{"type": "render", "yaw": 90}"#.to_string()).await;
    let (turned, _) = final_image(&mut socket, 1).await;
    let moved = dir.path().join("moved.yml");
    std::fs::write(
        &moved,
        scene("[1, 0.2, 0.2]").replace("from: [0, 1, -5]", "from: [-5, 1, 0]"),
    )
    .expect("writes the moved scene");
    let expected = rendered(&moved, &dir.path().join("moved.png"));
    // The same camera up to rounding: at most a pixel or two a step apart.
    let differing = turned
        .pixels()
        .zip(expected.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 1))
        .count();
    assert!(differing <= 2, "{differing} pixels differ");
    assert_ne!(turned, rendered(&path, &dir.path().join("unturned.png")));
}

#[test]
fn a_missing_scene_or_a_bad_flag_stops_before_listening() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let missing = dir.path().join("missing.yml");
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("serve")
        .arg(&missing)
        .args(["--port", "0"])
        .output()
        .expect("runs rayforge serve");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("is not a file"));
    assert!(o.stdout.is_empty(), "no address printed");
    let path = dir.path().join("scene.yml");
    std::fs::write(&path, scene("[1, 0.2, 0.2]")).expect("writes the scene");
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("serve")
        .arg(&path)
        .args(["--port", "0", "--threads", "0"])
        .output()
        .expect("runs rayforge serve");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--threads must be between 1"));
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("serve")
        .arg(&path)
        .args(["--port", "0", "--request-timeout", "0"])
        .output()
        .expect("runs rayforge serve");
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("'--request-timeout <SECONDS>'") && stderr.contains("1..=3600"),
        "{stderr}"
    );
}

/// A camera placed without `from`, `to` and `up` (Computer Graphics from Scratch's viewport
/// camera at the origin, looking along +z at a red sphere 5 units away) orbits about the point
/// its image's centre sees, the sphere's near side 4 units away: half a turn puts the eye
/// behind the sphere, looking back at it (the sphere still fills the image's centre), and a
/// whole turn gives back the first view.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_camera_placed_otherwise_orbits_about_what_its_centre_sees() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("scene.yml");
    std::fs::write(
        &path,
        "\
- add: camera
  width: 24
  height: 24
  viewport: [1, 1]
  distance: 1
- add: light
  type: ambient
  intensity: 1
- add: sphere
  transform:
    - [translate, 0, 0, 5]
  material:
    color: [1, 0, 0]
",
    )
    .expect("writes the scene");
    let (server, _) = serve(&path);
    let mut socket = open_page(server.port).await;
    let view = |yaw: u32| format!(r#"{{"type": "render", "renderer": "ray", "yaw": {yaw}}}"#);
    send(&mut socket, view(0)).await;
    let Received::Json(started) = next(&mut socket).await else {
        panic!("a JSON message");
    };
    assert_eq!(started["type"], "started", "{started}");
    assert_eq!(started["orbits"], true, "{started}");
    let (unturned, job) = final_image(&mut socket, 0).await;
    send(&mut socket, view(180)).await;
    let (behind, job) = final_image(&mut socket, job).await;
    send(&mut socket, view(360)).await;
    let (again, _) = final_image(&mut socket, job).await;
    let red = |image: &image::RgbImage, x, y| {
        // Lit by the ambient term only, on black.
        let p = image.get_pixel(x, y).0;
        p[0] > 10 && p[1] == 0 && p[2] == 0
    };
    assert!(red(&unturned, 12, 12) && red(&behind, 12, 12));
    // From 4 units beyond the sphere's near side the sphere looks smaller than from the origin.
    let count = |image: &image::RgbImage| {
        (0..24)
            .flat_map(|y| (0..24).map(move |x| (x, y)))
            .filter(|&(x, y)| red(image, x, y))
            .count()
    };
    assert!(
        count(&behind) > 0 && count(&behind) != count(&unturned),
        "{} red pixels behind, {} before",
        count(&behind),
        count(&unturned)
    );
    let differing = again
        .pixels()
        .zip(unturned.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 1))
        .count();
    assert!(
        differing <= 2,
        "{differing} pixels differ after a whole turn"
    );
}

/// Opens the page's WebSocket.
async fn open_page(port: u16) -> Socket {
    let (socket, _) = tokio_tungstenite::connect_async(format!("ws://127.0.0.1:{port}/ws"))
        .await
        .expect("the WebSocket opens");
    socket
}

/// The threads of process `pid` (Linux's `/proc`).
#[cfg(target_os = "linux")]
fn threads_of(pid: u32) -> usize {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).expect("its status");
    status
        .lines()
        .find_map(|l| l.strip_prefix("Threads:"))
        .and_then(|n| n.trim().parse().ok())
        .expect("a thread count")
}

/// The finding: a thread per WebSocket, without limit (3,000 connections reached 2,216 threads
/// and aborted). Now pages past `--max-connections` are told why and closed, the threads stay
/// a fixed few however many pages are open, and a page that leaves frees its place.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pages_past_the_limit_are_refused_and_pages_cost_no_threads() {
    let (_dir, path) = red_scene();
    const PAGES: usize = 40;
    let (server, _) = serve_with(&path, &["--max-connections", "40", "--max-renders", "2"]);
    let mut pages = Vec::new();
    for _ in 0..PAGES {
        let mut page = open_page(server.port).await;
        // Served: its render comes back.
        raster_frame(&mut page, 24, 0).await;
        pages.push(page);
    }
    #[cfg(target_os = "linux")]
    {
        // The network's 2, the renders' 2, the rendering pool's 2, the main thread, the
        // watch's and its watcher's: a thread per page would be over 40.
        let threads = threads_of(server.child.id());
        assert!(threads <= 16, "{threads} threads for {PAGES} pages");
    }
    let mut refused = open_page(server.port).await;
    let Received::Json(message) = next(&mut refused).await else {
        panic!("a message saying why");
    };
    assert_eq!(message["type"], "error", "{message}");
    let text = message["message"].as_str().unwrap_or_default();
    assert!(
        text.contains("40 pages open") && text.contains("--max-connections"),
        "{text}"
    );
    assert!(matches!(next(&mut refused).await, Received::Closed));
    // A page leaves: a new one is served once the server has seen it go.
    let mut leaving = pages.pop().expect("a page");
    leaving.close(None).await.expect("closes");
    drop(leaving);
    let deadline = std::time::Instant::now() + PATIENCE;
    loop {
        let mut page = open_page(server.port).await;
        send(
            &mut page,
            r#"{"type": "render", "renderer": "raster", "width": 24}"#.into(),
        )
        .await;
        match next(&mut page).await {
            Received::Json(m) if m["type"] == "started" => break,
            Received::Json(m) if m["type"] == "error" => {}
            other => panic!(
                "neither served nor refused: {}",
                matches!(other, Received::Closed)
            ),
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the place was not freed"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// The finding: large requests at once each passed the memory check alone and together
/// aborted. A render over `--max-render-memory` alone is refused, naming the flag; a smaller
/// one then renders.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_render_over_the_memory_budget_is_refused_naming_the_flag() {
    let (_dir, _server, mut page) = red_page(&["--max-render-memory", "1"]).await;
    // 400 × 400 pixels at 80 bytes each: 12.2 MiB.
    let large = r#"{"type": "render", "renderer": "raster", "width": 400, "height": 400}"#;
    send(&mut page, large.into()).await;
    let error = loop {
        match next(&mut page).await {
            Received::Json(m) if m["type"] == "error" => break m,
            Received::Json(m) => assert_ne!(m["type"], "frame", "{m}"),
            Received::Image(_) => panic!("an image over the budget"),
            Received::Closed => panic!("closed"),
        }
    };
    let text = error["message"].as_str().unwrap_or_default();
    assert!(
        text.contains("a 400×400 render needs about 13 MiB")
            && text.contains("--max-render-memory"),
        "{text}"
    );
    a_whole_frame_comes(&mut page).await;
}

/// The finding: a page that accepts and never reads held its render (and so every page's,
/// past `--max-renders`) for as long as it kept the connection. Here page A starts a long
/// render and stops reading while it floods the server with messages whose answers fill its
/// socket; page B's render, waiting for the only render slot, comes once the server has
/// dropped A (its send timed out, A's render was cancelled and its slot freed).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_page_that_stops_reading_is_dropped_and_frees_its_render() {
    use futures_util::SinkExt;
    let (_dir, server, mut stalled) = red_page(&["--max-renders", "1"]).await;
    // Minutes of path tracing, in passes.
    let long = r#"{"type": "render", "renderer": "path", "samples": 1048576, "width": 200}"#;
    send(&mut stalled, long.into()).await;
    let Received::Json(started) = next(&mut stalled).await else {
        panic!("a JSON message");
    };
    assert_eq!(started["type"], "started", "{started}");
    // Each `{}` is answered with an error of about 80 bytes: 200,000 of them are 16 MB of
    // answers, more than any socket holds, and A never reads one.
    let flood = tokio::spawn(async move {
        for _ in 0..200_000 {
            if stalled.send(Message::Text("{}".into())).await.is_err() {
                break;
            }
        }
        stalled
    });
    let mut waiting = open_page(server.port).await;
    a_whole_frame_comes(&mut waiting).await;
    flood.abort();
}

/// Plain HTTP is bounded too: connections that open and never send hold a place only for
/// `--request-timeout`, and one past `--max-connections` is refused at once with a 503 that
/// says why. (Before, `axum::serve` took every connection and waited on each for ever.)
#[test]
fn idle_connections_are_dropped_and_one_past_the_limit_is_refused() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("scene.yml");
    std::fs::write(&path, scene("[1, 0.2, 0.2]")).expect("writes the scene");
    let timeout = Duration::from_secs(2);
    let (server, _) = serve_with(&path, &["--max-connections", "2", "--request-timeout", "2"]);
    let started = std::time::Instant::now();
    // Two clients that connect and never send a byte: they take both places.
    let idle: Vec<TcpStream> = (0..2)
        .map(|_| TcpStream::connect(("127.0.0.1", server.port)).expect("connects"))
        .collect();
    let host = format!("127.0.0.1:{}", server.port);
    let (status, response) = get(server.port, "/", &host);
    assert_eq!(status, 503, "{response}");
    assert!(
        response.contains("more than 2 connections at once (--max-connections)"),
        "{response}"
    );
    for mut client in idle {
        client
            .set_read_timeout(Some(PATIENCE))
            .expect("sets a timeout");
        let mut byte = [0u8; 1];
        // Dropped: the server closes it (end of stream, or a reset), sending nothing.
        match client.read(&mut byte) {
            Ok(n) => assert_eq!(n, 0, "the server sent something to a silent client"),
            Err(e) => assert_eq!(e.kind(), std::io::ErrorKind::ConnectionReset, "{e}"),
        }
        // Not before its time (the server's timer starts after the client's connect).
        assert!(started.elapsed() >= timeout, "{:?}", started.elapsed());
    }
    // Their places are free again: the page is served.
    let (status, response) = get(server.port, "/", &host);
    assert_eq!(status, 200, "{response}");
}
