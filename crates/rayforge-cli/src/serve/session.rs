//! One page's connection: requests in from the WebSocket, jobs out to its render worker,
//! images and messages back; an edit on disk runs the page's last request again.
//!
//! A page costs a task, not a thread: its worker's renders run on the server's render threads
//! (tokio's blocking pool, [`super::Limits::renders`] of them), one render of a page at a time,
//! each taking one of the server's render slots first. The page's newest request is all that
//! waits for a slot (a newer one replaces it), so a page sending requests as fast as it can
//! holds no more than one. The server started a thread per page before: 3,000 connections
//! reached 2,216 threads and aborted.
//!
//! A page that stops reading is dropped once a message has waited [`SEND_TIMEOUT`] to go out:
//! its render is cancelled and its slot freed, where before it held them for as long as it
//! kept the connection.

use super::protocol::{self, Request};
use super::worker::{Job, Outgoing, Worker};
use super::Server;
use axum::extract::ws::{CloseFrame, Message, WebSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::{watch, OwnedSemaphorePermit};

/// How many messages for the page may wait while it is slow to take them: the render waits
/// beyond that (progress messages are dropped instead).
const QUEUE: usize = 8;

/// How long one message may take to go out before the page counts as gone: a page that
/// accepts and never reads must not hold a render.
pub const SEND_TIMEOUT: Duration = Duration::from_secs(10);

/// The WebSocket close code for "try again later" (RFC 6455's registry).
const TRY_AGAIN_LATER: u16 = 1013;

/// Tells a page past the limit of pages why it is refused, and closes its socket. It costs
/// this task only: no worker, no render slot.
pub async fn refuse(mut socket: WebSocket, limit: u32) {
    let message = format!(
        "the server has {limit} pages open, its limit (--max-connections); close one and \
         reload this page"
    );
    let error = protocol::error(None, &message);
    let _ = tokio::time::timeout(SEND_TIMEOUT, async {
        socket.send(Message::Text(error.into())).await?;
        let close = CloseFrame {
            code: TRY_AGAIN_LATER,
            reason: "too many pages open (--max-connections)".into(),
        };
        socket.send(Message::Close(Some(close))).await
    })
    .await;
}

/// Serves one page until it goes away; `_page` is its place among the open pages, given back
/// when it ends.
pub async fn run(mut socket: WebSocket, server: Arc<Server>, _page: OwnedSemaphorePermit) {
    let (out, mut outgoing) = tokio::sync::mpsc::channel(QUEUE);
    let (jobs, received) = watch::channel(None);
    let worker = Worker::new(
        server.config.clone(),
        server.pool.clone(),
        server.budget.clone(),
        out,
    );
    let runner = tokio::spawn(run_jobs(worker, received, server.clone()));
    let mut changes = server.changes.clone();
    let mut session = Session {
        jobs,
        last: None,
        cancel: Arc::new(AtomicBool::new(false)),
        next: 0,
    };
    loop {
        let reply = tokio::select! {
            incoming = socket.recv() => match incoming {
                Some(Ok(Message::Text(text))) => match protocol::parse_request(text.as_str()) {
                    Ok(request) => {
                        session.submit(request, *changes.borrow_and_update());
                        None
                    }
                    Err(message) => Some(Message::Text(protocol::error(None, &message).into())),
                },
                Some(Ok(Message::Binary(_))) => Some(Message::Text(
                    protocol::error(None, "binary messages are not understood; send JSON text")
                        .into(),
                )),
                Some(Ok(Message::Ping(_) | Message::Pong(_))) => None,
                // Closed, or broken (a message over the size limit among others).
                Some(Ok(Message::Close(_)) | Err(_)) | None => break,
            },
            Some(message) = outgoing.recv() => Some(match message {
                Outgoing::Text(text) => Message::Text(text.into()),
                Outgoing::Binary(bytes) => Message::Binary(bytes.into()),
            }),
            changed = changes.changed() => {
                if changed.is_err() {
                    break;
                }
                let generation = *changes.borrow_and_update();
                if let Some(request) = session.last {
                    session.submit(request, generation);
                }
                None
            }
        };
        if let Some(message) = reply {
            match tokio::time::timeout(SEND_TIMEOUT, socket.send(message)).await {
                Ok(Ok(())) => {}
                // Gone, or not reading.
                Ok(Err(_)) | Err(_) => break,
            }
        }
    }
    // The render stops at its next ray; the runner ends once it has, its jobs' sender being
    // dropped with the session, and the worker's messages find no one.
    session.cancel.store(true, Ordering::Relaxed);
    drop(session);
    drop(outgoing);
    let _ = runner.await;
}

/// Runs the page's jobs one after another, the newest each time, each on a render thread
/// once a render slot is free, until the session is gone (or the page, for the worker).
async fn run_jobs(mut worker: Worker, mut jobs: watch::Receiver<Option<Job>>, server: Arc<Server>) {
    while jobs.changed().await.is_ok() {
        // Waiting for a slot, a newer job may come (it is taken below) or the page may go.
        let slot = server.renders.clone().acquire_owned();
        tokio::pin!(slot);
        let slot = loop {
            tokio::select! {
                slot = &mut slot => break slot,
                changed = jobs.changed() => if changed.is_err() { return },
            }
        };
        let Ok(slot) = slot else { return };
        let Some(job) = jobs.borrow_and_update().clone() else {
            continue;
        };
        let rendered = tokio::task::spawn_blocking(move || {
            let outcome = worker.run(&job);
            drop(slot);
            (worker, outcome)
        })
        .await;
        match rendered {
            Ok((back, Ok(()))) => worker = back,
            // The page is gone, or the render panicked (its thread said so).
            Ok((_, Err(_))) | Err(_) => return,
        }
    }
}

/// The page's requests so far.
struct Session {
    /// Where jobs go to the worker: the newest only.
    jobs: watch::Sender<Option<Job>>,
    /// The last request, run again when the files change.
    last: Option<Request>,
    /// The running job's stop flag.
    cancel: Arc<AtomicBool>,
    /// The next job's number.
    next: u64,
}

impl Session {
    /// Stops the job in progress and hands the worker `request` at the files' `generation`.
    fn submit(&mut self, request: Request, generation: u64) {
        self.cancel.store(true, Ordering::Relaxed);
        self.cancel = Arc::new(AtomicBool::new(false));
        self.last = Some(request);
        self.next += 1;
        // A worker that is gone has said why (it only ends when the page does).
        self.jobs.send_replace(Some(Job {
            id: self.next,
            request,
            generation,
            cancel: self.cancel.clone(),
        }));
    }
}
