//! The HTTP side: a small synchronous server (tiny_http) bound to 127.0.0.1 only. Each
//! request gets a thread of its own, so a long-poll never holds up a drag; a dropped
//! socket ends only its own thread.

use super::api::{self, Request, Site};
use super::hub::Hub;
use crate::mesh::Mesh;
use std::io::Read;
use std::path::PathBuf;
use std::sync::Arc;
use std::thread::JoinHandle;

/// Why the studio could not start.
#[derive(Debug, thiserror::Error)]
pub enum StudioError {
    /// The asked-for port is in use.
    #[error("port {0} on 127.0.0.1 is taken by another program: choose another with --port, or leave --port out to take a free one")]
    PortTaken(u16),
    /// Binding failed otherwise.
    #[error("cannot listen on 127.0.0.1:{port}: {cause}")]
    Bind {
        /// The port.
        port: u16,
        /// The cause.
        cause: String,
    },
}

/// Where and how to serve.
#[derive(Clone, Debug, Default)]
pub struct StudioOptions {
    /// The port; 0 picks a free one.
    pub port: u16,
    /// Serve page files from here before the embedded ones (development).
    pub assets: Option<PathBuf>,
}

/// A running studio. Dropping it stops the server and the session.
#[must_use = "the studio stops when this value is dropped"]
pub struct Studio {
    url: String,
    server: Arc<tiny_http::Server>,
    hub: Arc<Hub>,
    accept: Option<JoinHandle<()>>,
}

impl Studio {
    /// Binds 127.0.0.1:`port` and starts serving `mesh`.
    pub fn start(mesh: Mesh, title: &str, options: StudioOptions) -> Result<Studio, StudioError> {
        let server = tiny_http::Server::http(("127.0.0.1", options.port)).map_err(|e| {
            let in_use = e
                .downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::AddrInUse);
            if in_use {
                StudioError::PortTaken(options.port)
            } else {
                StudioError::Bind {
                    port: options.port,
                    cause: e.to_string(),
                }
            }
        })?;
        let port = server
            .server_addr()
            .to_ip()
            .map(|a| a.port())
            .unwrap_or(options.port);
        let server = Arc::new(server);
        let hub = Hub::start(mesh, title);
        let site = Arc::new(Site {
            port,
            assets: options.assets.clone(),
        });
        let accept = {
            let (server, hub) = (Arc::clone(&server), Arc::clone(&hub));
            std::thread::Builder::new()
                .name("studio-accept".into())
                .spawn(move || {
                    for request in server.incoming_requests() {
                        let (hub, site) = (Arc::clone(&hub), Arc::clone(&site));
                        let _ = std::thread::Builder::new()
                            .name("studio-request".into())
                            .spawn(move || respond(&hub, &site, request));
                    }
                })
                .expect("the accept thread starts")
        };
        Ok(Studio {
            url: format!("http://127.0.0.1:{port}/"),
            server,
            hub,
            accept: Some(accept),
        })
    }

    /// `http://127.0.0.1:PORT/`.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The session, for in-process callers.
    pub fn hub(&self) -> &Arc<Hub> {
        &self.hub
    }
}

impl Drop for Studio {
    fn drop(&mut self) {
        self.server.unblock();
        self.hub.stop();
        if let Some(t) = self.accept.take() {
            let _ = t.join();
        }
    }
}

/// The value of header `name`, if the request has it once (a repeated `Host` or
/// `Origin` is refused as absent or foreign).
fn header(request: &tiny_http::Request, name: &'static str) -> Option<String> {
    let mut values = request
        .headers()
        .iter()
        .filter(|h| h.field.equiv(name))
        .map(|h| h.value.as_str().to_string());
    let first = values.next();
    match values.next() {
        Some(_) => Some(String::new()),
        None => first,
    }
}

/// Headers every reply carries: no caching, a policy that lets the page load only its
/// own files and no other page frame it, and no type sniffing.
const SECURITY_HEADERS: [(&str, &str); 4] = [
    ("Cache-Control", "no-store"),
    ("X-Content-Type-Options", "nosniff"),
    ("X-Frame-Options", "DENY"),
    ("Referrer-Policy", "no-referrer"),
];

fn respond(hub: &Hub, site: &Site, mut request: tiny_http::Request) {
    let mut body = Vec::new();
    let limit = super::session::MAX_UPLOAD as u64 + 1;
    if request
        .as_reader()
        .take(limit)
        .read_to_end(&mut body)
        .is_err()
    {
        // The client went away mid-request.
        return;
    }
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    let method = request.method().as_str().to_string();
    let (host, origin, content_type) = (
        header(&request, "Host"),
        header(&request, "Origin"),
        header(&request, "Content-Type"),
    );
    let response = api::handle(
        hub,
        site,
        Request {
            method: &method,
            path,
            query,
            host,
            origin,
            content_type,
            body,
        },
    );
    let mut reply = tiny_http::Response::from_data(response.body)
        .with_status_code(response.status)
        .with_header(
            tiny_http::Header::from_bytes("Content-Type", response.content_type)
                .expect("valid header"),
        )
        .with_header(
            tiny_http::Header::from_bytes("Content-Security-Policy", super::assets::policy())
                .expect("valid header"),
        );
    for (name, value) in SECURITY_HEADERS {
        reply =
            reply.with_header(tiny_http::Header::from_bytes(name, value).expect("valid header"));
    }
    if let Some(name) = response.download {
        let value = format!("attachment; filename=\"{name}\"");
        if let Ok(h) = tiny_http::Header::from_bytes("Content-Disposition", value) {
            reply = reply.with_header(h);
        }
    }
    // A closed tab or dropped socket fails only this write.
    let _ = request.respond(reply);
}
