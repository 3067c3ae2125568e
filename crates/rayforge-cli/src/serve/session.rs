//! One page's connection: requests in from the WebSocket, jobs out to its render worker,
//! images and messages back; an edit on disk runs the page's last request again.

use super::protocol::{self, Request};
use super::worker::{Job, Outgoing, Worker};
use super::Server;
use axum::extract::ws::{Message, WebSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};

/// How many messages for the page may wait while it is slow to take them: the render waits
/// beyond that (progress messages are dropped instead).
const QUEUE: usize = 8;

/// Serves one page until it goes away.
pub async fn run(mut socket: WebSocket, server: Arc<Server>) {
    let (out, mut outgoing) = tokio::sync::mpsc::channel(QUEUE);
    let (jobs, received) = mpsc::channel();
    let worker = Worker::new(server.config.clone(), server.pool.clone(), out);
    let spawned = std::thread::Builder::new()
        .name("rayforge-serve-render".into())
        .spawn(move || worker.run(received));
    if let Err(e) = spawned {
        let message = protocol::error(None, &format!("cannot start a render thread: {e}"));
        let _ = socket.send(Message::Text(message.into())).await;
        return;
    }
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
            if socket.send(message).await.is_err() {
                break;
            }
        }
    }
    // The worker ends once its job is cancelled and its channel closed.
    session.cancel.store(true, Ordering::Relaxed);
}

/// The page's requests so far.
struct Session {
    /// Where jobs go to the worker.
    jobs: mpsc::Sender<Job>,
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
        let _ = self.jobs.send(Job {
            id: self.next,
            request,
            generation,
            cancel: self.cancel.clone(),
        });
    }
}
