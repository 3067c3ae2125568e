//! The server's connections: accepted here rather than by `axum::serve`, which takes every
//! connection and waits on each for as long as its client likes, so that a few thousand sockets
//! that connect and never send (or never read the answer) would hold the server's memory and
//! file descriptors for ever.
//!
//! A connection carries HTTP requests (the page, or the WebSocket's upgrade, after which the
//! page's socket is a [`session`](super::session) of its own, counted by the pages' limit).
//! At most `limit` connections are being answered at once (the `--max-connections` of pages);
//! one past it is answered `503 Service Unavailable`, saying why, and closed. A connection's
//! HTTP life, from its accepting to its upgrade or its end (its requests, their answers and
//! any wait between them), lasts at most `timeout` (`--request-timeout`): one that sends
//! nothing, or never takes its answer, is dropped then. (Keep-alive stays on: a `Connection:
//! close` would replace the `Connection: upgrade` of a WebSocket's handshake.)

use axum::Router;
use hyper::server::conn::http1;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::sync::Arc;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::Semaphore;

/// How long a refused connection is given to take its `503` and close.
const REFUSAL_TIME: Duration = Duration::from_secs(1);

/// Serves `app` on the connections `listener` accepts, until accepting fails for good.
pub async fn serve(
    listener: TcpListener,
    app: Router,
    limit: u32,
    timeout: Duration,
) -> std::io::Result<()> {
    let slots = Arc::new(Semaphore::new(limit as usize));
    loop {
        let stream = match listener.accept().await {
            Ok((stream, _)) => stream,
            // Out of file descriptors, or a connection reset before it was taken: the next
            // may do; a moment's pause keeps a full table from spinning the loop.
            Err(e) if transient(&e) => {
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
            Err(e) => return Err(e),
        };
        let Ok(slot) = slots.clone().try_acquire_owned() else {
            tokio::spawn(refuse(stream, limit));
            continue;
        };
        let service = TowerToHyperService::new(app.clone());
        tokio::spawn(async move {
            let mut http = http1::Builder::new();
            http.timer(TokioTimer::new()).header_read_timeout(timeout);
            let connection = http
                .serve_connection(TokioIo::new(stream), service)
                .with_upgrades();
            // The whole exchange, the answers' sending included (a client that never reads
            // the page would otherwise hold its slot); an upgrade ends it at the handshake.
            let _ = tokio::time::timeout(timeout, connection).await;
            drop(slot);
        });
    }
}

/// Tells a connection past the limit why it is refused, and closes it.
async fn refuse(mut stream: TcpStream, limit: u32) {
    let body = format!(
        "rayforge serve: more than {limit} connections at once (--max-connections); try again in a moment\n"
    );
    let answer = format!(
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain; charset=utf-8\r\n\
         Content-Length: {}\r\nRetry-After: 1\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    let _ = tokio::time::timeout(REFUSAL_TIME, async {
        stream.write_all(answer.as_bytes()).await?;
        stream.shutdown().await?;
        // What the client sent is read and dropped, so that closing with it unread does not
        // reset the connection before the client has read the answer.
        let mut sink = [0u8; 4096];
        while stream.read(&mut sink).await? > 0 {}
        Ok::<(), std::io::Error>(())
    })
    .await;
}

/// Whether accepting failed for this connection only (or for a moment), not for the listener.
fn transient(e: &std::io::Error) -> bool {
    use std::io::ErrorKind;
    matches!(
        e.kind(),
        ErrorKind::ConnectionAborted | ErrorKind::ConnectionReset | ErrorKind::Interrupted
    ) || matches!(
        e.raw_os_error(),
        Some(libc::EMFILE | libc::ENFILE | libc::ENOBUFS | libc::ENOMEM)
    )
}
