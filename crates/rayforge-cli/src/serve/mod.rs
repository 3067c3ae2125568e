//! `rayforge serve`: a live page for a scene. A local web server (axum on tokio) serves one
//! page, built into the binary, and its WebSocket; the page asks for renders (renderer,
//! lighting, samples, size, an orbit of the camera) and shows them refining pass by pass, and
//! an edit of the scene on disk renders it again.
//!
//! What it exposes is small on purpose: `GET /` (the page) and `GET /ws` (the WebSocket);
//! everything else is 404, no path reaches the file system, and the only files read are the
//! scene and those it names, exactly as `rayforge render` reads them. It listens on 127.0.0.1
//! unless told otherwise, and answers only requests addressed to it by that name (see
//! [`guard`]).
//!
//! What it holds is bounded ([`Limits`]): HTTP requests being answered, each within a time
//! ([`connections`]; one past the limit is answered 503), pages open (a page past the limit is
//! told why and its socket closed), renders at once (a page's request waits for a slot), and the memory of the
//! renders in flight ([`budget`]); a page is a task, and the threads are a fixed few: the
//! network's two, the renders' (`--max-renders`, each rendering on the shared `--threads`
//! pool), and the watch's.
//!
//! Modules: [`protocol`] (the messages), [`session`] (one page's connection), [`worker`] (its
//! renders), [`budget`] (their memory), [`orbit`] (the camera's orbit), [`watch`] (edits on
//! disk), [`guard`] (who may connect).

mod budget;
mod connections;
mod guard;
mod orbit;
mod protocol;
mod session;
mod watch;
mod worker;

use crate::args::ServeArgs;
use crate::failure::Failure;
use axum::extract::ws::WebSocketUpgrade;
use axum::extract::State;
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use rayon::ThreadPool;
use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use tokio::sync::watch as channel;
use tokio::sync::Semaphore;

/// The page: HTML with its style and script inline, so that one response is all it needs.
const PAGE: &str = include_str!("page.html");

/// What the page may load and where it may connect: nothing but itself, its inline style and
/// script, its own WebSocket and the images it makes from the messages.
const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'unsafe-inline'; \
     style-src 'unsafe-inline'; img-src blob:; connect-src 'self'; base-uri 'none'; \
     form-action 'none'; frame-ancestors 'none'";

/// The server's settings from the command line, fixed while it runs.
pub struct Config {
    /// The scene file.
    pub scene: PathBuf,
    /// `--max-pixels`: the largest image a page may ask for.
    pub max_pixels: u64,
    /// `--threads`.
    pub threads: Option<usize>,
    /// `--allow-outside`.
    pub allow_outside: bool,
    /// The files the scene read the last time it loaded, which the watch counts as the
    /// scene's (a model's material library, which the scene's text does not name).
    pub files: Arc<watch::SceneFiles>,
    /// What the server may hold at once.
    pub limits: Limits,
}

/// What the server may hold at once (the flags' defaults are in `crate::args`).
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// `--max-connections`: pages open, and HTTP requests being answered.
    pub pages: u32,
    /// `--request-timeout`: how long a connection has for its HTTP request and answer.
    pub request_timeout: std::time::Duration,
    /// `--max-renders`: renders at once, every page's together.
    pub renders: u32,
    /// `--max-render-memory`, in bytes: the memory of the renders in flight together.
    pub render_memory: u64,
}

/// What every connection shares.
pub struct Server {
    /// The settings.
    config: Arc<Config>,
    /// The worker threads every page's renders run on (one render at a time per page).
    pool: Arc<ThreadPool>,
    /// The places for pages (`--max-connections`).
    pages: Arc<Semaphore>,
    /// The render slots (`--max-renders`).
    renders: Arc<Semaphore>,
    /// The memory of the renders in flight (`--max-render-memory`).
    budget: Arc<budget::MemoryBudget>,
    /// The generation of the scene's files (see [`watch`]).
    changes: channel::Receiver<u64>,
    /// The address it listens on, which requests must name (see [`guard`]).
    address: SocketAddr,
}

/// Runs the server until it is stopped (Ctrl-C): prints the page's address on stdout.
pub fn run(args: ServeArgs) -> Result<ExitCode, Failure> {
    let config = Config {
        scene: args.scene,
        max_pixels: args.max_pixels,
        threads: args.threads,
        allow_outside: args.allow_outside,
        files: Arc::default(),
        limits: Limits {
            pages: args.max_connections,
            request_timeout: std::time::Duration::from_secs(args.request_timeout),
            renders: args.max_renders,
            render_memory: args.max_render_memory.saturating_mul(1 << 20),
        },
    };
    // The flags are checked as `rayforge render` checks them, before anything starts.
    let settings = worker::settings_for(&config, &protocol::Request::default())?;
    if !config.scene.is_file() {
        return Err(Failure::usage(format!(
            "the scene `{}` is not a file",
            config.scene.display()
        )));
    }
    let pool = crate::render_command::thread_pool(&settings)?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        // The network needs little; the cores are for rendering.
        .worker_threads(2)
        // The renders' threads: one per render slot, so never more than the slots.
        .max_blocking_threads(config.limits.renders as usize)
        .enable_io()
        .enable_time()
        .build()
        .map_err(|e| Failure::internal(format!("cannot start the server's runtime: {e}")))?;
    runtime.block_on(serve(config, pool, (args.listen, args.port).into()))
}

/// Listens, prints the address, watches the files and serves until stopped.
async fn serve(config: Config, pool: ThreadPool, listen: SocketAddr) -> Result<ExitCode, Failure> {
    let listener = tokio::net::TcpListener::bind(listen).await.map_err(|e| {
        let hint = if e.kind() == std::io::ErrorKind::AddrInUse {
            " (another program uses that port: choose another with --port, or --port 0 for any)"
        } else {
            ""
        };
        Failure::usage(format!("cannot listen on {listen}: {e}{hint}"))
    })?;
    let address = listener
        .local_addr()
        .map_err(|e| Failure::internal(format!("cannot read the address listened on: {e}")))?;
    let (generation, changes) = channel::channel(0);
    let _watch = watch::start(&config.scene, config.files.clone(), generation)?;
    let limits = config.limits;
    let server = Arc::new(Server {
        config: Arc::new(config),
        pool: Arc::new(pool),
        pages: Arc::new(Semaphore::new(limits.pages as usize)),
        renders: Arc::new(Semaphore::new(limits.renders as usize)),
        budget: Arc::new(budget::MemoryBudget::new(limits.render_memory)),
        changes,
        address,
    });
    let app = Router::new()
        .route("/", get(page))
        .route("/ws", get(socket))
        .with_state(server.clone());
    // The address alone on stdout, for scripts and tests; the rest on stderr.
    println!("http://{address}/");
    let _ = std::io::stdout().flush();
    eprintln!(
        "rayforge serve: showing `{}`; open the address above in a browser, Ctrl-C stops",
        server.config.scene.display()
    );
    connections::serve(listener, app, limits.pages, limits.request_timeout)
        .await
        .map_err(|e| Failure::internal(format!("the server stopped: {e}")))?;
    Ok(ExitCode::SUCCESS)
}

/// `GET /`: the page.
async fn page(State(server): State<Arc<Server>>, headers: HeaderMap) -> Response {
    if let Err(refusal) = guard::check(&headers, server.address) {
        return (StatusCode::FORBIDDEN, refusal).into_response();
    }
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CONTENT_SECURITY_POLICY, CONTENT_SECURITY_POLICY),
            (header::CACHE_CONTROL, "no-store"),
            (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
        ],
        PAGE,
    )
        .into_response()
}

/// `GET /ws`: the page's WebSocket, its messages from the page bounded in size; past the
/// limit of pages, a socket that says why and closes.
async fn socket(
    State(server): State<Arc<Server>>,
    headers: HeaderMap,
    upgrade: WebSocketUpgrade,
) -> Response {
    if let Err(refusal) = guard::check(&headers, server.address) {
        return (StatusCode::FORBIDDEN, refusal).into_response();
    }
    let upgrade = upgrade
        .max_message_size(protocol::MAX_MESSAGE_BYTES)
        .max_frame_size(protocol::MAX_MESSAGE_BYTES);
    match server.pages.clone().try_acquire_owned() {
        Ok(page) => upgrade.on_upgrade(move |socket| session::run(socket, server, page)),
        Err(_) => {
            let limit = server.config.limits.pages;
            upgrade.on_upgrade(move |socket| session::refuse(socket, limit))
        }
    }
}

/// What the server does with a page's message, without a network: the `Host` and `Origin`
/// headers of the WebSocket's request checked as [`guard`] checks them for a server on
/// 127.0.0.1:`port`, `message` read as a render request, and its orbit applied to a camera
/// five units from the origin. The error is what the browser or the page would be told. For
/// the fuzzer (`crate::untrusted`), which so drives the code that answers a browser.
pub fn page_message(
    host: &str,
    origin: Option<&str>,
    port: u16,
    message: &str,
) -> Result<(), String> {
    use axum::http::HeaderValue;
    let mut headers = HeaderMap::new();
    // A value HTTP cannot carry never reaches the guard: the request is refused before it.
    let value = |text: &str| HeaderValue::from_str(text).map_err(|e| e.to_string());
    headers.insert(header::HOST, value(host)?);
    if let Some(origin) = origin {
        headers.insert(header::ORIGIN, value(origin)?);
    }
    guard::check(&headers, SocketAddr::from(([127, 0, 0, 1], port)))?;
    let request = protocol::parse_request(message)?;
    let look_at = rayforge_scene::LookAt {
        from: glam::DVec3::new(0.0, 1.5, -5.0),
        to: glam::DVec3::ZERO,
        up: glam::DVec3::Y,
    };
    let camera = rayforge::camera::Camera::new(4, 3, 1.0).with_transform(
        rayforge::math::view_transform(look_at.from, look_at.to, look_at.up),
    );
    orbit::orbit(&camera, &look_at, request.yaw, request.pitch)
        .map(|_| ())
        .ok_or_else(|| "the camera cannot be turned so".to_string())
}

#[cfg(test)]
mod tests {
    /// The layer rule: nothing in the command depends on the server; only `lib.rs` names it,
    /// to run it, and `untrusted.rs`, to hand its message reading to the fuzzer.
    #[test]
    fn nothing_outside_the_server_uses_it() {
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let files = std::fs::read_dir(&src).expect("the sources");
        for file in files.filter_map(Result::ok).map(|e| e.path()) {
            let named = file
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            // `untrusted` hands the fuzzer the server's reading of a page's message.
            let entry = named == "lib.rs" || named == "untrusted.rs";
            if entry || file.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let text = std::fs::read_to_string(&file).expect("a source file");
            assert!(
                !text.contains("crate::serve") && !text.contains("mod serve"),
                "{named} uses the server"
            );
        }
    }
}
