//! The HTTP side: a small synchronous server on `std::net`, bound to 127.0.0.1 only,
//! speaking the bounded HTTP/1.1 of [`super::http`]. Each connection gets a thread of its
//! own, so a long-poll never holds up a drag, up to [`MAX_CONNECTIONS`] at once (past them
//! a connection is answered 503 and closed); a dropped socket ends only its own thread.

use super::api::{self, Request, Site};
use super::http::{self, HttpResponse, Read1, MAX_CONNECTIONS};
use super::hub::Hub;
use crate::mesh::Mesh;
use std::io::{BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long a connection may take to send a request (or idle between two) before it is
/// closed: a client that opens connections and sends nothing holds them this long at most.
const READ_TIMEOUT: Duration = Duration::from_secs(10);
/// How long a reply may take to leave, for a client that stops reading.
const WRITE_TIMEOUT: Duration = Duration::from_secs(30);
/// A connection thread's stack: a request's work runs on the session's thread, so these
/// only read heads and parse JSON bodies (serde_json stops nesting at 128 levels).
const CONNECTION_STACK: usize = 1 << 20;

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
    address: SocketAddr,
    stopping: Arc<AtomicBool>,
    hub: Arc<Hub>,
    accept: Option<JoinHandle<()>>,
}

impl Studio {
    /// Binds 127.0.0.1:`port` and starts serving `mesh`.
    pub fn start(mesh: Mesh, title: &str, options: StudioOptions) -> Result<Studio, StudioError> {
        let bind_error = |e: std::io::Error| {
            if e.kind() == std::io::ErrorKind::AddrInUse {
                StudioError::PortTaken(options.port)
            } else {
                StudioError::Bind {
                    port: options.port,
                    cause: e.to_string(),
                }
            }
        };
        let listener = TcpListener::bind(("127.0.0.1", options.port)).map_err(bind_error)?;
        let address = listener.local_addr().map_err(bind_error)?;
        let hub = Hub::start(mesh, title);
        let site = Arc::new(Site::new(address.port(), options.assets.clone()));
        let stopping = Arc::new(AtomicBool::new(false));
        let accept = {
            let (hub, stopping) = (Arc::clone(&hub), Arc::clone(&stopping));
            std::thread::Builder::new()
                .name("studio-accept".into())
                .spawn(move || accept_loop(&listener, &hub, &site, &stopping))
                .expect("the accept thread starts")
        };
        Ok(Studio {
            url: format!("http://127.0.0.1:{}/", address.port()),
            address,
            stopping,
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
        self.stopping.store(true, Ordering::SeqCst);
        self.hub.stop();
        // Wakes the accept loop, which then sees `stopping`.
        let _ = TcpStream::connect_timeout(&self.address, Duration::from_secs(1));
        if let Some(t) = self.accept.take() {
            let _ = t.join();
        }
    }
}

/// Accepts connections until the studio stops, each on its own thread while fewer than
/// [`MAX_CONNECTIONS`] are open.
fn accept_loop(listener: &TcpListener, hub: &Arc<Hub>, site: &Arc<Site>, stopping: &AtomicBool) {
    let open = Arc::new(AtomicUsize::new(0));
    let closer = Closer::start();
    // The connections' threads, joined once finished: a thread gives its slot back as its
    // work ends but lives on a moment while the system tears it down, and on a loaded
    // machine those moments add up past the cap unless the cap counts threads, not work.
    let mut threads: Vec<JoinHandle<()>> = Vec::new();
    for stream in listener.incoming() {
        if stopping.load(Ordering::SeqCst) {
            return;
        }
        let Ok(mut stream) = stream else {
            // Out of descriptors, or a connection reset before it was taken: wait a
            // moment rather than spin.
            std::thread::sleep(Duration::from_millis(10));
            continue;
        };
        join_finished(&mut threads);
        if threads.len() >= MAX_CONNECTIONS {
            refuse_busy(&mut stream, "the studio has too many connections open");
            closer.close(stream);
            continue;
        }
        open.fetch_add(1, Ordering::SeqCst);
        let slot = Slot(Arc::clone(&open));
        let (hub, site) = (Arc::clone(hub), Arc::clone(site));
        // A second handle on the socket, to answer on if no thread can serve it.
        let spare = stream.try_clone().ok();
        let spawned = std::thread::Builder::new()
            .name("studio-connection".into())
            .stack_size(CONNECTION_STACK)
            .spawn(move || serve_connection(stream, &hub, &site, &slot));
        // A thread the system will not give drops the closure and gives the slot back;
        // the client is told to come back rather than left with a closed socket.
        match (spawned, spare) {
            (Ok(thread), _) => threads.push(thread),
            (Err(_), Some(mut spare)) => {
                refuse_busy(
                    &mut spare,
                    "the studio could not start a thread to serve this",
                );
                closer.close(spare);
            }
            (Err(_), None) => {}
        }
    }
}

/// Joins the connection threads whose work has ended, which waits for the system to
/// finish removing them (a moment at most), and keeps the rest.
fn join_finished(threads: &mut Vec<JoinHandle<()>>) {
    let (finished, running): (Vec<_>, Vec<_>) = threads.drain(..).partition(|t| t.is_finished());
    for thread in finished {
        let _ = thread.join();
    }
    *threads = running;
}

/// One of the open connections, counted while its thread serves it (the count decides
/// whether replies keep their connection open).
struct Slot(Arc<AtomicUsize>);

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Closes refused connections gracefully, off the accept thread: one thread drains what
/// each client still sends (without blocking, for at most [`LINGER`]) until it hangs up,
/// so the refusal is read rather than lost to the reset that closing over unread bytes
/// sends. It holds at most [`MAX_CONNECTIONS`] such connections; past them a refused
/// connection is closed at once.
struct Closer(Option<SyncSender<TcpStream>>);

/// How long a refused connection is drained before it is closed regardless.
const LINGER: Duration = Duration::from_millis(500);

impl Closer {
    fn start() -> Closer {
        let (tx, rx) = sync_channel(MAX_CONNECTIONS);
        let spawned = std::thread::Builder::new()
            .name("studio-closer".into())
            .stack_size(CONNECTION_STACK)
            .spawn(move || drain_refused(&rx));
        Closer(spawned.ok().map(|_| tx))
    }

    /// Hands `stream`, answered and shut for writing, over to be drained and closed.
    fn close(&self, stream: TcpStream) {
        if let Some(tx) = &self.0 {
            let _ = tx.try_send(stream);
        }
    }
}

/// The closer's loop: until the accept loop ends, drains each refused connection until
/// its client hangs up or [`LINGER`] passes.
fn drain_refused(incoming: &Receiver<TcpStream>) {
    let mut closing: Vec<(TcpStream, Instant)> = Vec::new();
    let mut scrap = [0u8; 4096];
    loop {
        let wait = if closing.is_empty() {
            Duration::from_secs(3600)
        } else {
            Duration::from_millis(20)
        };
        match incoming.recv_timeout(wait) {
            Ok(stream) => {
                if stream.set_nonblocking(true).is_ok() {
                    closing.push((stream, Instant::now()));
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => return,
        }
        closing.retain_mut(|(stream, since)| {
            // At most 64 KiB a connection a pass, so a client that keeps sending cannot
            // hold the loop.
            for _ in 0..16 {
                match stream.read(&mut scrap) {
                    Ok(0) => return false,
                    Ok(_) => {}
                    Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                        return since.elapsed() < LINGER
                    }
                    Err(_) => return false,
                }
            }
            since.elapsed() < LINGER
        });
    }
}

/// The 503 for a connection past the cap, written without waiting on the client.
fn refuse_busy(stream: &mut TcpStream, why: &str) {
    let _ = stream.set_write_timeout(Some(Duration::from_millis(200)));
    let body = serde_json::json!({ "error": format!("{why}; try again in a moment") }).to_string();
    let mut reply = with_studio_headers(503, "application/json", None, body.as_bytes());
    reply.headers.push(("Retry-After", "1".into()));
    let _ = http::write_response(stream, &reply, false, false);
    let _ = stream.shutdown(std::net::Shutdown::Write);
}

/// Requests on one connection, in turn, until it closes, idles past [`READ_TIMEOUT`],
/// sends something refused, or asks to close. While half the connections are taken,
/// every reply closes its connection, so clients that hold theirs open after an answer
/// (a flood of long-polls) give their places back at once.
fn serve_connection(stream: TcpStream, hub: &Hub, site: &Site, slot: &Slot) {
    let _ = stream.set_read_timeout(Some(READ_TIMEOUT));
    let _ = stream.set_write_timeout(Some(WRITE_TIMEOUT));
    let _ = stream.set_nodelay(true);
    let Ok(mut writer) = stream.try_clone() else {
        return;
    };
    let mut reader = BufReader::new(stream);
    loop {
        let request = match http::read_request(&mut reader, &mut writer) {
            Read1::Request(request) => request,
            Read1::Ended => return,
            Read1::Refused(status, message) => {
                // Answered, and the connection closed with the rest of the request unread.
                let body = serde_json::json!({ "error": message }).to_string();
                let reply = with_studio_headers(status, "application/json", None, body.as_bytes());
                let _ = http::write_response(&mut writer, &reply, false, false);
                linger(&mut reader);
                return;
            }
        };
        let keep_alive = request.keep_alive && slot.0.load(Ordering::SeqCst) <= MAX_CONNECTIONS / 2;
        if respond(hub, site, request, &mut writer, keep_alive).is_err() || !keep_alive {
            return;
        }
    }
}

/// Closes our side and reads (and drops) what the client is still sending, a bounded
/// amount for a bounded time, before the socket is closed: closing over unread bytes
/// resets the connection, and the reset can reach the client before it has read the
/// refusal it was sent.
fn linger(reader: &mut BufReader<TcpStream>) {
    let stream = reader.get_mut();
    let _ = stream.shutdown(std::net::Shutdown::Write);
    let _ = stream.set_read_timeout(Some(Duration::from_millis(500)));
    let _ = std::io::copy(&mut reader.take(LINGER_BYTES), &mut std::io::sink());
}

/// The most [`linger`] drains.
const LINGER_BYTES: u64 = 256 << 10;

/// Headers every reply carries: no caching, a policy that lets the page load only its
/// own files and no other page frame it, and no type sniffing.
const SECURITY_HEADERS: [(&str, &str); 4] = [
    ("Cache-Control", "no-store"),
    ("X-Content-Type-Options", "nosniff"),
    ("X-Frame-Options", "DENY"),
    ("Referrer-Policy", "no-referrer"),
];

/// Hands `request` to the API and writes its answer.
fn respond(
    hub: &Hub,
    site: &Site,
    request: http::HttpRequest,
    out: &mut impl Write,
    keep_alive: bool,
) -> std::io::Result<()> {
    let (host, origin, content_type) = (
        request.header("Host"),
        request.header("Origin"),
        request.header("Content-Type"),
    );
    let (path, query) = request
        .target
        .split_once('?')
        .unwrap_or((&request.target, ""));
    let response = api::handle(
        hub,
        site,
        Request {
            method: &request.method,
            path,
            query,
            host,
            origin,
            content_type,
            body: request.body,
        },
    );
    let reply = with_studio_headers(
        response.status,
        response.content_type,
        response.download.as_deref(),
        &response.body,
    );
    // A closed tab or dropped socket fails only this write.
    http::write_response(out, &reply, request.method == "HEAD", keep_alive)
}

/// A reply with the studio's headers: its type, the content policy, [`SECURITY_HEADERS`]
/// and, for a download, its file name.
fn with_studio_headers<'a>(
    status: u16,
    content_type: &str,
    download: Option<&str>,
    body: &'a [u8],
) -> HttpResponse<'a> {
    let mut headers = vec![
        ("Content-Type", content_type.to_string()),
        (
            "Content-Security-Policy",
            super::assets::policy().to_string(),
        ),
    ];
    headers.extend(SECURITY_HEADERS.map(|(name, value)| (name, value.to_string())));
    if let Some(name) = download {
        headers.push((
            "Content-Disposition",
            format!("attachment; filename=\"{name}\""),
        ));
    }
    HttpResponse {
        status,
        headers,
        body,
    }
}
