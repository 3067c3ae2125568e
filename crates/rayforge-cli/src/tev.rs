//! Streaming the image to the tev HDR viewer while it renders (`--display-server HOST:PORT`).
//!
//! tev listens on TCP (port 14158 by default) for packets that create an image and update
//! rectangles of it; pbrt-v4 and Mitsuba stream renders to it the same way. Each packet is its
//! length (u32, counting itself), its kind (u8) and a payload, little-endian throughout, with
//! strings ending in a NUL:
//!
//! ```text
//! create image (4): grab focus u8, name, width i32, height i32, channels i32, channel names
//! update image (6): grab focus u8, name, channels i32, channel names, x i32, y i32,
//!                   width i32, height i32, channel offsets i64 × channels,
//!                   channel strides i64 × channels, f32 samples
//! ```
//!
//! The protocol is three small packet layouts, and no Rust client crate for it is maintained,
//! so it is written here. The viewer is a convenience: when it cannot be reached, or goes away
//! mid-render, one warning is printed and the render goes on without it. Packets go out on a
//! thread of their own (see [`crate::checkpointed`]), so a slow viewer never holds a worker.
//!
//! A viewer that stops reading is dropped once one packet has taken its timeout
//! (`--display-timeout`, [`DEFAULT_TIMEOUT`] unless told), however it
//! trickles (the socket's own timeout bounded each write, and a packet is many: a viewer that
//! accepted and never read held a 2.2 s render for 15.9 s), and at once when the render is
//! interrupted ([`Display::stop_on`]): Ctrl-C exited 8.9 s late behind a stalled viewer.

use rayforge::canvas::Canvas;
use rayforge::color::Color;
use std::io::{ErrorKind, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The packet kind that creates an image.
const CREATE_IMAGE: u8 = 4;
/// The packet kind that updates a rectangle of an image (tev's third version of it).
const UPDATE_IMAGE: u8 = 6;

/// The port tev listens on unless told otherwise.
pub const DEFAULT_PORT: u16 = 14158;

/// How long connecting to the viewer, and sending it one packet, may take before it counts as
/// gone, unless `--display-timeout` says otherwise: a viewer that stops reading must not
/// stall the render's end.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(5);

/// How long one write to the viewer may block: how often a send looks at its deadline and at
/// the stop flag.
const WRITE_SLICE: Duration = Duration::from_millis(50);

/// How many samples (floats) one update packet carries at most: rows are batched up to this,
/// about 4 MB, well under what tev accepts in one packet.
const MAX_PACKET_FLOATS: usize = 1 << 20;

/// The create-image packet for an image `name` of `width` × `height` with `channels`.
pub fn create_image_packet(name: &str, width: usize, height: usize, channels: &[&str]) -> Vec<u8> {
    let mut p = Packet::new(CREATE_IMAGE);
    p.u8(1);
    p.string(name);
    p.i32(width);
    p.i32(height);
    p.i32(channels.len());
    for channel in channels {
        p.string(channel);
    }
    p.finish()
}

/// The update-image packet that sets the rectangle at (`x`, `y`) of `width` × `height` pixels
/// of image `name`: `samples` holds each pixel's channels in turn, row by row.
pub fn update_image_packet(
    name: &str,
    channels: &[&str],
    (x, y): (usize, usize),
    (width, height): (usize, usize),
    samples: &[f32],
) -> Vec<u8> {
    let mut p = Packet::new(UPDATE_IMAGE);
    p.u8(0);
    p.string(name);
    p.i32(channels.len());
    for channel in channels {
        p.string(channel);
    }
    for v in [x, y, width, height] {
        p.i32(v);
    }
    // Interleaved: channel c of pixel i is sample c + i × channels.
    for c in 0..channels.len() {
        p.i64(c);
    }
    for _ in channels {
        p.i64(channels.len());
    }
    p.bytes.reserve(samples.len() * 4);
    for s in samples {
        p.bytes.extend_from_slice(&s.to_le_bytes());
    }
    p.finish()
}

/// A packet being written: its length is filled in at the end.
struct Packet {
    bytes: Vec<u8>,
}

impl Packet {
    fn new(kind: u8) -> Self {
        let mut bytes = vec![0; 4];
        bytes.push(kind);
        Self { bytes }
    }

    fn u8(&mut self, v: u8) {
        self.bytes.push(v);
    }

    /// A count or coordinate: images are far below 2³¹ pixels a side (the image size limit).
    fn i32(&mut self, v: usize) {
        let v = i32::try_from(v).unwrap_or(i32::MAX);
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }

    fn i64(&mut self, v: usize) {
        let v = i64::try_from(v).unwrap_or(i64::MAX);
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }

    /// A NUL-terminated string (a NUL inside it would end it early, so it is left out).
    fn string(&mut self, s: &str) {
        self.bytes.extend(s.bytes().filter(|&b| b != 0));
        self.bytes.push(0);
    }

    fn finish(mut self) -> Vec<u8> {
        let len = u32::try_from(self.bytes.len()).unwrap_or(u32::MAX);
        self.bytes[..4].copy_from_slice(&len.to_le_bytes());
        self.bytes
    }
}

/// Which layers an image shown in tev has, and which of them the rows fill.
#[derive(Debug, Clone, Copy)]
pub struct Layout<'a> {
    /// Layers sent only as whole images ([`Display::layer`]), first in the viewer: with
    /// `--denoise`, `denoised`.
    pub whole: &'a [&'a str],
    /// The layers each row holds, in order ([`Display::row`]): the image's own (`""` for tev's
    /// bare `R`, `G`, `B`; `noisy` beside a denoised layer), then each AOV's.
    pub rows: &'a [&'a str],
}

/// A layer's three channels as tev names them: `R`, `G`, `B` for `""`, else `NAME.R`, ….
fn layer_channels(layer: &str) -> [String; 3] {
    ["R", "G", "B"].map(|c| {
        if layer.is_empty() {
            c.to_string()
        } else {
            format!("{layer}.{c}")
        }
    })
}

/// An image shown in tev while it renders: created when the display connects, updated row by
/// row and layer by layer. Every failure turns it off with one warning.
pub struct Display {
    /// The connection, until it fails.
    stream: Option<TcpStream>,
    /// Where the viewer is, for the warning.
    address: String,
    /// The image's name in the viewer (the output file's).
    name: String,
    /// The image's channels: the whole layers', then the rows' (R, G, B or `noisy.R`, …, then
    /// each extra layer's).
    channels: Vec<String>,
    /// The layers' names, in the order of `channels`.
    layers: Vec<String>,
    /// How many of the first layers are sent whole only.
    whole: usize,
    width: usize,
    quiet: bool,
    /// Rows waiting to go out together: the first row's index and the samples.
    pending: Option<(usize, Vec<f32>)>,
    pending_rows: usize,
    /// How long one packet may take (`--display-timeout`).
    timeout: Duration,
    /// The render's stop flag: once set, nothing more is sent.
    stop: Option<&'static AtomicBool>,
}

impl Display {
    /// Connects to tev at `address` (`HOST:PORT`, or `HOST` for the default port) and creates
    /// the image `name` of `width` × `height` with the channels of the layers `layout` names
    /// (`R`, `G`, `B` for the image's own, `albedo.R`, … for the others); connecting, and
    /// each packet, may take `timeout`. Unreachable: a display that shows nothing, after one
    /// warning.
    pub fn connect_with(
        address: &str,
        name: &str,
        (width, height): (usize, usize),
        layout: &Layout<'_>,
        quiet: bool,
        timeout: Duration,
    ) -> Self {
        let layers: Vec<String> = layout
            .whole
            .iter()
            .chain(layout.rows)
            .map(|l| l.to_string())
            .collect();
        let channels = layers.iter().flat_map(|l| layer_channels(l)).collect();
        let mut display = Self {
            stream: None,
            address: address.to_string(),
            name: name.to_string(),
            channels,
            layers,
            whole: layout.whole.len(),
            width,
            quiet,
            pending: None,
            pending_rows: 0,
            timeout,
            stop: None,
        };
        match connect(address, timeout) {
            Ok(stream) => {
                display.stream = Some(stream);
                let channels: Vec<&str> = display.channels.iter().map(String::as_str).collect();
                let packet = create_image_packet(name, width, height, &channels);
                display.send(&packet);
            }
            Err(why) => display.give_up(&why),
        }
        display
    }

    /// Stops sending (and drops the viewer, without a warning) once `stop` is set: an
    /// interrupted render does not wait for its viewer.
    pub fn stop_on(&mut self, stop: &'static AtomicBool) {
        self.stop = Some(stop);
    }

    /// The channels the rows fill.
    fn row_channels(&self) -> Vec<&str> {
        self.channels[3 * self.whole..]
            .iter()
            .map(String::as_str)
            .collect()
    }

    /// Queues row `y`: `values` holds the image's row, then each layer's, `width` colours
    /// each (as the layout's `rows` name them). Rows that follow one another go out in one
    /// packet.
    pub fn row(&mut self, y: usize, values: &[Color]) {
        if self.stream.is_none() {
            return;
        }
        let layers = self.layers.len() - self.whole;
        let follows = matches!(&self.pending, Some((first, _)) if *first + self.pending_rows == y);
        if !follows {
            self.flush();
        }
        let (_, samples) = self.pending.get_or_insert_with(|| (y, Vec::new()));
        for x in 0..self.width {
            for layer in 0..layers {
                let c = values
                    .get(layer * self.width + x)
                    .copied()
                    .unwrap_or(Color::BLACK);
                samples.extend([c.red as f32, c.green as f32, c.blue as f32]);
            }
        }
        self.pending_rows += 1;
        if samples.len() >= MAX_PACKET_FLOATS {
            self.flush();
        }
    }

    /// Sends the rows queued.
    pub fn flush(&mut self) {
        if let Some((first, samples)) = self.pending.take() {
            let rows = std::mem::take(&mut self.pending_rows);
            let channels = self.row_channels();
            let packet = update_image_packet(
                &self.name,
                &channels,
                (0, first),
                (self.width, rows),
                &samples,
            );
            self.send(&packet);
        }
    }

    /// Sends the finished image (as written to the file, its colour channels): the viewer's
    /// last state is then the file's.
    pub fn image(&mut self, canvas: &Canvas) {
        self.layer("", canvas);
    }

    /// Sends `canvas` whole as the layer `layer` (`""`: the bare `R`, `G`, `B`), after the rows
    /// queued; a layer the image does not have is not sent.
    pub fn layer(&mut self, layer: &str, canvas: &Canvas) {
        self.flush();
        if self.stream.is_none() || !self.layers.iter().any(|l| l == layer) {
            return;
        }
        let channels = layer_channels(layer);
        let channels = [&*channels[0], &*channels[1], &*channels[2]];
        let width = canvas.width();
        let rows_per_packet = (MAX_PACKET_FLOATS / (3 * width.max(1))).max(1);
        let pixels = canvas.pixels();
        for (band, chunk) in pixels.chunks(rows_per_packet * width.max(1)).enumerate() {
            let samples: Vec<f32> = chunk
                .iter()
                .flat_map(|c| [c.red as f32, c.green as f32, c.blue as f32])
                .collect();
            let packet = update_image_packet(
                &self.name,
                &channels,
                (0, band * rows_per_packet),
                (width, chunk.len() / width.max(1)),
                &samples,
            );
            self.send(&packet);
        }
    }

    /// Sends `packet` within [`Display::timeout`], unless the stop flag is set first.
    fn send(&mut self, packet: &[u8]) {
        let Some(stream) = &mut self.stream else {
            return;
        };
        let deadline = Instant::now() + self.timeout;
        let mut rest = packet;
        while !rest.is_empty() {
            if self.stop.is_some_and(|stop| stop.load(Ordering::Relaxed)) {
                self.stream = None;
                return;
            }
            match stream.write(rest) {
                Ok(0) => return self.give_up("it went away"),
                Ok(written) => rest = &rest[written..],
                Err(e) if is_blocked(&e) => {
                    if Instant::now() >= deadline {
                        let why = format!(
                            "it has not taken a packet in {} s, so it counts as gone",
                            self.timeout.as_secs_f64()
                        );
                        return self.give_up(&why);
                    }
                }
                Err(e) => return self.give_up(&format!("it went away ({e})")),
            }
        }
    }

    fn give_up(&mut self, why: &str) {
        self.stream = None;
        if !self.quiet {
            eprintln!(
                "warning: cannot show the render in tev at {}: {why}; the render goes on",
                self.address
            );
        }
    }
}

/// Whether a write failed only for want of room: the socket's timeout ran out, or a signal
/// came.
fn is_blocked(error: &std::io::Error) -> bool {
    matches!(
        error.kind(),
        ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted
    )
}

/// A connection to `address`, with [`DEFAULT_PORT`] when it names none, made within
/// `timeout`.
fn connect(address: &str, timeout: Duration) -> Result<TcpStream, String> {
    let with_port = if address
        .rsplit_once(':')
        .is_some_and(|(_, p)| p.parse::<u16>().is_ok())
    {
        address.to_string()
    } else {
        format!("{address}:{DEFAULT_PORT}")
    };
    let addresses = with_port
        .to_socket_addrs()
        .map_err(|e| format!("cannot resolve it ({e})"))?;
    let mut last = "it has no address".to_string();
    for a in addresses {
        match TcpStream::connect_timeout(&a, timeout) {
            Ok(stream) => {
                let _ = stream.set_write_timeout(Some(WRITE_SLICE));
                let _ = stream.set_nodelay(true);
                return Ok(stream);
            }
            Err(e) => last = format!("no viewer listens there ({e})"),
        }
    }
    Err(last)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The image's colour alone.
    const PLAIN: Layout<'static> = Layout {
        whole: &[],
        rows: &[""],
    };

    #[test]
    fn a_create_image_packet_has_tevs_layout() {
        let p = create_image_packet("a.exr", 3, 2, &["R", "G", "B"]);
        let mut expected = Vec::new();
        expected.extend_from_slice(&(p.len() as u32).to_le_bytes());
        expected.push(4);
        expected.push(1);
        expected.extend_from_slice(b"a.exr\0");
        for v in [3i32, 2, 3] {
            expected.extend_from_slice(&v.to_le_bytes());
        }
        expected.extend_from_slice(b"R\0G\0B\0");
        assert_eq!(p, expected);
    }

    #[test]
    fn an_update_image_packet_has_tevs_layout() {
        let samples = [1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0];
        let p = update_image_packet("x", &["R", "G", "B"], (1, 2), (2, 1), &samples);
        let mut expected = Vec::new();
        expected.extend_from_slice(&(p.len() as u32).to_le_bytes());
        expected.push(6);
        expected.push(0);
        expected.extend_from_slice(b"x\0");
        expected.extend_from_slice(&3i32.to_le_bytes());
        expected.extend_from_slice(b"R\0G\0B\0");
        for v in [1i32, 2, 2, 1] {
            expected.extend_from_slice(&v.to_le_bytes());
        }
        for v in [0i64, 1, 2, 3, 3, 3] {
            expected.extend_from_slice(&v.to_le_bytes());
        }
        for s in samples {
            expected.extend_from_slice(&s.to_le_bytes());
        }
        assert_eq!(p, expected);
        assert_eq!(p.len(), 4 + 1 + 1 + 2 + 4 + 6 + 16 + 48 + 24);
    }

    #[test]
    fn a_nul_in_a_name_cannot_end_it_early() {
        let p = create_image_packet("a\0b", 1, 1, &["R"]);
        assert!(p.windows(3).any(|w| w == b"ab\0"));
    }

    /// A packet as tev reads it: its kind, its channels' names and (for an update) its
    /// rectangle's samples.
    #[derive(Debug)]
    struct Received {
        kind: u8,
        channels: Vec<String>,
        samples: Vec<f32>,
    }

    /// The packets in `bytes`, read as tev reads them.
    fn packets(mut bytes: &[u8]) -> Vec<Received> {
        let mut out = Vec::new();
        while bytes.len() >= 5 {
            let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
            let (packet, rest) = bytes.split_at(len);
            bytes = rest;
            let kind = packet[4];
            let mut at = 6; // length, kind, grab focus
            let string = |at: &mut usize| {
                let end = *at + packet[*at..].iter().position(|&b| b == 0).unwrap();
                let s = String::from_utf8(packet[*at..end].to_vec()).unwrap();
                *at = end + 1;
                s
            };
            let int = |at: &mut usize| {
                let v = i32::from_le_bytes(packet[*at..*at + 4].try_into().unwrap());
                *at += 4;
                v as usize
            };
            string(&mut at);
            if kind == CREATE_IMAGE {
                at += 8; // width, height
            }
            let count = int(&mut at);
            let channels: Vec<String> = (0..count).map(|_| string(&mut at)).collect();
            let mut samples = Vec::new();
            if kind == UPDATE_IMAGE {
                at += 16 + 16 * count; // rectangle, offsets, strides
                samples = packet[at..]
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                    .collect();
            }
            out.push(Received {
                kind,
                channels,
                samples,
            });
        }
        out
    }

    #[test]
    fn a_viewer_gets_the_rows_in_their_layers_and_a_whole_layer_in_its_own() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
        let address = listener.local_addr().expect("its address").to_string();
        let viewer = std::thread::spawn(move || {
            let (mut stream, _) = listener.accept().expect("a connection");
            let mut bytes = Vec::new();
            std::io::Read::read_to_end(&mut stream, &mut bytes).expect("reads");
            bytes
        });
        let layout = Layout {
            whole: &["denoised"],
            rows: &["noisy", "albedo"],
        };
        let mut display =
            Display::connect_with(&address, "x", (2, 1), &layout, true, DEFAULT_TIMEOUT);
        let grey = Color::WHITE * 0.5;
        display.row(0, &[Color::WHITE, Color::WHITE, grey, grey]);
        display.layer("denoised", &Canvas::from_pixels(2, 1, vec![grey; 2]));
        // A layer the image lacks is not sent.
        display.layer("", &Canvas::new(2, 1));
        drop(display);
        let received = packets(&viewer.join().expect("the viewer"));
        let names = |list: &[&str]| list.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let rgb = |layer: &str| ["R", "G", "B"].map(|c| format!("{layer}.{c}"));
        assert_eq!(received.len(), 3, "{received:?}");
        assert_eq!(received[0].kind, CREATE_IMAGE);
        let all: Vec<String> = ["denoised", "noisy", "albedo"]
            .iter()
            .flat_map(|l| rgb(l))
            .collect();
        assert_eq!(received[0].channels, all);
        // The row: its pixels' noisy colour, then their albedo, in the rows' channels.
        let row: Vec<String> = ["noisy", "albedo"].iter().flat_map(|l| rgb(l)).collect();
        assert_eq!(received[1].channels, row);
        assert_eq!(
            received[1].samples,
            [1.0, 1.0, 1.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 0.5, 0.5, 0.5]
        );
        assert_eq!(
            received[2].channels,
            names(&["denoised.R", "denoised.G", "denoised.B"])
        );
        assert_eq!(received[2].samples, [0.5; 6]);
    }

    #[test]
    fn an_absent_viewer_leaves_a_display_that_shows_nothing() {
        // A port nothing listens on: bind one, note it, close it.
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let address = format!("127.0.0.1:{port}");
        let mut display =
            Display::connect_with(&address, "x", (2, 2), &PLAIN, true, DEFAULT_TIMEOUT);
        display.row(0, &[Color::WHITE; 2]);
        display.flush();
        assert!(display.stream.is_none());
    }

    /// A viewer that accepts and never reads (its socket kept open), and a display of a
    /// `width` × `height` image connected to it, quiet.
    fn stalled_viewer(width: usize, height: usize) -> (std::net::TcpListener, Display) {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
        let address = listener.local_addr().expect("its address").to_string();
        let display = Display::connect_with(
            &address,
            "x",
            (width, height),
            &PLAIN,
            true,
            DEFAULT_TIMEOUT,
        );
        assert!(display.stream.is_some(), "connected");
        (listener, display)
    }

    /// Sends a canvas far larger than the sockets' buffers to `display` on a thread of its
    /// own; whether the display gave up, or `None` if it has not returned within a minute.
    fn send_large_image(mut display: Display) -> Option<bool> {
        let (sent, received) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            // 2048 × 1024 pixels: 24 MiB of samples in six packets.
            let canvas = Canvas::new(2048, 1024);
            display.image(&canvas);
            let _ = sent.send(display.stream.is_none());
        });
        received.recv_timeout(Duration::from_secs(60)).ok()
    }

    /// The finding: a viewer that never read held the render well past the timeout. Here
    /// one packet's timeout, cut to a second, drops it, however the writes trickle.
    #[test]
    fn a_viewer_that_stops_reading_is_dropped_after_its_timeout() {
        let (_listener, mut display) = stalled_viewer(2048, 1024);
        display.timeout = Duration::from_secs(1);
        assert_eq!(send_large_image(display), Some(true), "dropped");
    }

    /// With an hour's timeout, the stop flag set while a packet waits to go out drops the
    /// viewer at once: Ctrl-C exited 8.9 s late behind a stalled viewer.
    #[test]
    fn an_interrupt_drops_a_stalled_viewer_while_a_frame_is_sent() {
        static STOP: AtomicBool = AtomicBool::new(false);
        let (_listener, mut display) = stalled_viewer(2048, 1024);
        display.timeout = Duration::from_secs(3600);
        display.stop_on(&STOP);
        let setter = std::thread::spawn(|| {
            // Whenever it comes, before the send or during it, the send ends.
            std::thread::sleep(Duration::from_millis(300));
            STOP.store(true, Ordering::Relaxed);
        });
        assert_eq!(send_large_image(display), Some(true), "dropped");
        setter.join().expect("set the flag");
    }
}
