//! Who may use the server. Listening on 127.0.0.1 keeps other machines out, but not web pages
//! from elsewhere open in the user's own browser: a page may open a WebSocket to any address,
//! and through DNS rebinding even load this page under its own name. So a request must name
//! the server as the user's browser does (`Host`: 127.0.0.1, localhost or [::1] and the port,
//! when it listens on a loopback address), and a WebSocket must come from the server's own page
//! (`Origin`, which browsers always send there, is the `Host`).

use axum::http::{header, HeaderMap};
use std::net::SocketAddr;

/// Names a browser on this machine reaches a loopback server by.
const LOOPBACK_NAMES: &[&str] = &["127.0.0.1", "localhost", "[::1]"];

/// Accepts the request, or says why not.
pub fn check(headers: &HeaderMap, address: SocketAddr) -> Result<(), &'static str> {
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .ok_or("the request names no host")?;
    if address.ip().is_loopback() {
        let (name, port) = host.rsplit_once(':').ok_or("the host has no port")?;
        if !LOOPBACK_NAMES.contains(&name) || port.parse() != Ok(address.port()) {
            return Err("this server answers only to 127.0.0.1, localhost or [::1] and its port");
        }
    }
    match headers.get(header::ORIGIN) {
        None => Ok(()),
        Some(origin) if origin.to_str().ok() == Some(format!("http://{host}").as_str()) => Ok(()),
        Some(_) => Err("requests from other sites' pages are refused"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(host: Option<&str>, origin: Option<&str>) -> HeaderMap {
        let mut headers = HeaderMap::new();
        for (name, value) in [(header::HOST, host), (header::ORIGIN, origin)] {
            if let Some(value) = value {
                headers.insert(name, value.parse().expect("a header value"));
            }
        }
        headers
    }

    #[test]
    fn a_loopback_server_answers_its_own_names() {
        let address: SocketAddr = "127.0.0.1:8765".parse().expect("an address");
        for host in ["127.0.0.1:8765", "localhost:8765", "[::1]:8765"] {
            assert_eq!(check(&headers(Some(host), None), address), Ok(()), "{host}");
            let origin = format!("http://{host}");
            assert_eq!(
                check(&headers(Some(host), Some(&origin)), address),
                Ok(()),
                "{host}"
            );
        }
        for host in [
            None,
            Some("evil.example:8765"),
            Some("127.0.0.1:9999"),
            Some("localhost"),
        ] {
            assert!(check(&headers(host, None), address).is_err(), "{host:?}");
        }
    }

    #[test]
    fn other_sites_pages_are_refused() {
        let address: SocketAddr = "127.0.0.1:8765".parse().expect("an address");
        let refused = headers(Some("127.0.0.1:8765"), Some("http://evil.example"));
        assert!(check(&refused, address).is_err());
    }

    #[test]
    fn a_server_listening_elsewhere_takes_any_name_from_its_own_pages() {
        let address: SocketAddr = "0.0.0.0:8765".parse().expect("an address");
        let named = headers(Some("render-box:8765"), Some("http://render-box:8765"));
        assert_eq!(check(&named, address), Ok(()));
        let cross = headers(Some("render-box:8765"), Some("http://evil.example"));
        assert!(check(&cross, address).is_err());
    }
}
