//! The studio's HTTP API, as a pure function from a request to a response so tests can
//! call it without a socket (axum's `fn app()` habit). Every route is documented in the
//! docs/studio.md; bad requests get a 4xx and a one-line message, and the session keeps its design.
//!
//! Only the studio's own page may talk to it ([`admit`]): the `Host` must name the
//! loopback address it listens on (DNS rebinding), a present `Origin` must be its own,
//! and bodies must carry a type no cross-site page can send without a preflight.

use super::assets;
use super::hub::Hub;
use super::session::{
    Command, FabRequest, FitRequest, GenerateRequest, MotionRequest, Reply, Settings,
    TargetPlacement, MAX_UPLOAD,
};
use crate::constraints::Family;
use crate::generate::{Params, PatternKind};
use crate::limits::MAX_WAITING_POLLS;
use serde::de::DeserializeOwned;
use serde::Deserialize;
use serde_json::json;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// A request as the server read it.
pub struct Request<'a> {
    /// GET, POST, …
    pub method: &'a str,
    /// Path without the query.
    pub path: &'a str,
    /// The query string, without `?`.
    pub query: &'a str,
    /// The `Host` header.
    pub host: Option<String>,
    /// The `Origin` header.
    pub origin: Option<String>,
    /// The `Content-Type` header.
    pub content_type: Option<String>,
    /// The body.
    pub body: Vec<u8>,
}

impl<'a> Request<'a> {
    /// A request as the studio's own page at `site` sends it: its `Host` and `Origin`,
    /// and a body typed as the route wants (for in-process callers: tests, benches).
    pub fn from_page(
        site: &Site,
        method: &'a str,
        path: &'a str,
        query: &'a str,
        body: Vec<u8>,
    ) -> Request<'a> {
        let authority = format!("127.0.0.1:{}", site.port);
        let content_type = (method == "POST").then(|| body_type(path).to_string());
        Request {
            method,
            path,
            query,
            origin: Some(format!("http://{authority}")),
            host: Some(authority),
            content_type,
            body,
        }
    }
}

/// Where the studio is served: its port (the only `Host` and `Origin` it answers) and,
/// for development, a folder of page files served before the embedded ones.
#[derive(Clone, Debug, Default)]
pub struct Site {
    /// The port it listens on.
    pub port: u16,
    /// Page files served before the embedded ones.
    pub assets: Option<PathBuf>,
    /// Long-polls waiting for the next frame now (at most [`MAX_WAITING_POLLS`] wait).
    waiting_polls: Arc<AtomicUsize>,
}

impl Site {
    /// The studio on `port`, with page files from `assets` first.
    pub fn new(port: u16, assets: Option<PathBuf>) -> Site {
        Site {
            port,
            assets,
            waiting_polls: Arc::default(),
        }
    }

    /// Whether `authority` (`host:port`) is this studio on a loopback name.
    fn is_own_authority(&self, authority: &str) -> bool {
        let Some((host, port)) = authority.rsplit_once(':') else {
            return false;
        };
        port.parse::<u16>().ok() == Some(self.port)
            && (host == "127.0.0.1" || host == "[::1]" || host.eq_ignore_ascii_case("localhost"))
    }
}

/// The request may reach the studio: its `Host` is the studio's (a page on another name
/// that rebinds its DNS to 127.0.0.1 sends its own name), its `Origin`, when present, is
/// the studio's page, and a POST's body type is one a cross-site page cannot send without
/// a preflight (which the studio never grants). Jupyter Server and Vite refuse foreign
/// `Host` names the same way.
pub fn admit(site: &Site, request: &Request) -> Result<(), Response> {
    let host = request.host.as_deref().unwrap_or("");
    if !site.is_own_authority(host) {
        return Err(Response::error(
            403,
            &format!(
                "refused: Host \"{}\" is not this studio; open http://127.0.0.1:{}/ itself",
                short(host),
                site.port
            ),
        ));
    }
    if let Some(origin) = request.origin.as_deref() {
        let own = origin
            .strip_prefix("http://")
            .is_some_and(|a| site.is_own_authority(a));
        if !own {
            return Err(Response::error(
                403,
                &format!(
                    "refused: a request from the page at \"{}\"; only the studio's own page may talk to it",
                    short(origin)
                ),
            ));
        }
    }
    if request.method == "POST" {
        let wanted = body_type(request.path);
        let given = request
            .content_type
            .as_deref()
            .and_then(|t| t.split(';').next())
            .map(str::trim)
            .unwrap_or("");
        if !given.eq_ignore_ascii_case(wanted) {
            return Err(Response::error(
                415,
                &format!(
                    "{}: the body must be sent as {wanted}, not \"{}\"",
                    request.path,
                    short(given)
                ),
            ));
        }
    }
    Ok(())
}

/// The type a POST to `path` must carry: file bytes for `/api/open`, JSON elsewhere
/// (neither is a type a cross-site page may send without a preflight).
pub fn body_type(path: &str) -> &'static str {
    if path == "/api/open" || path == "/api/target" {
        "application/octet-stream"
    } else {
        "application/json"
    }
}

use crate::limits::short_text as short;

/// A response to send.
#[derive(Debug)]
pub struct Response {
    /// HTTP status.
    pub status: u16,
    /// Content type.
    pub content_type: &'static str,
    /// Body.
    pub body: Vec<u8>,
    /// A file name to offer as a download.
    pub download: Option<String>,
}

impl Response {
    fn json(status: u16, value: &serde_json::Value) -> Response {
        Response {
            status,
            content_type: "application/json",
            body: value.to_string().into_bytes(),
            download: None,
        }
    }

    fn error(status: u16, message: &str) -> Response {
        Response::json(status, &json!({"error": message}))
    }
}

/// How long a long-poll for the next frame waits before answering with the current one.
pub const LONG_POLL: Duration = Duration::from_secs(10);

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DragBody {
    vertex: usize,
    target: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PinBody {
    vertex: usize,
    pinned: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FoldBody {
    amount: f64,
}

fn parse<T: DeserializeOwned>(path: &str, body: &[u8]) -> Result<T, Response> {
    serde_json::from_slice(body).map_err(|e| {
        Response::error(
            400,
            &format!("{path}: the request body is not what this route takes: {e}"),
        )
    })
}

fn query_value<'a>(query: &'a str, key: &str) -> Option<&'a str> {
    query
        .split('&')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v)
}

fn query_number(query: &str, key: &str) -> Result<Option<u64>, Response> {
    query_value(query, key)
        .map(|v| {
            v.parse().map_err(|_| {
                Response::error(400, &format!("query {key}={v} is not a whole number"))
            })
        })
        .transpose()
}

/// Undoes `%XX` escapes and `+` of a query value (a file name).
fn percent_decode(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => {
                let hex = |b: u8| (b as char).to_digit(16);
                match (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                    (Some(h), Some(l)) => {
                        out.push((h * 16 + l) as u8);
                        i += 3;
                        continue;
                    }
                    _ => out.push(b'%'),
                }
            }
            b'+' => out.push(b' '),
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Static facts the page needs once: condition families, patterns with defaults, machines.
fn meta() -> serde_json::Value {
    let patterns: Vec<serde_json::Value> = PatternKind::ALL
        .iter()
        .map(|&k| {
            let d = Params::defaults(k);
            json!({"name": k.name(), "nx": d.nx, "ny": d.ny, "size": d.size,
                   "angle": d.angle_deg, "fold": d.fold, "closedForm": k.has_closed_form_3d()})
        })
        .collect();
    json!({
        "families": Family::ALL.iter().map(|f| f.name()).collect::<Vec<_>>(),
        "patterns": patterns,
        "machines": crate::machine::known_machines(),
        "formats": ["fold", "cp", "svg", "obj"],
    })
}

/// Answers one request, once [`admit`] lets it in.
pub fn handle(hub: &Hub, site: &Site, request: Request) -> Response {
    if let Err(refused) = admit(site, &request) {
        return refused;
    }
    let Request {
        method,
        path,
        query,
        body,
        ..
    } = request;
    if !path.starts_with("/api/") {
        return page(method, path, site.assets.as_ref());
    }
    let command = match (method, &path[4..]) {
        ("GET", "/frame") => return frame(hub, site, query),
        ("GET", "/meta") => return Response::json(200, &meta()),
        (method, route) => match command_for(method, route, path, query, body) {
            Ok(command) => command,
            Err(response) => return response,
        },
    };
    match hub.ask(command) {
        Ok(Reply::Json(v)) => Response::json(200, &v),
        Ok(Reply::File { name, bytes }) => Response {
            status: 200,
            content_type: assets::content_type(&name),
            body: bytes,
            download: Some(name),
        },
        Err(refusal) => Response::error(refusal.status, &refusal.message),
    }
}

/// A page or asset of the app (GET or HEAD only).
fn page(method: &str, path: &str, assets_dir: Option<&PathBuf>) -> Response {
    if method != "GET" && method != "HEAD" {
        return Response::error(405, &format!("{method} {path}: pages are read with GET"));
    }
    match assets::lookup(path, assets_dir) {
        Some((content_type, bytes)) => Response {
            status: 200,
            content_type,
            body: bytes,
            download: None,
        },
        None => Response::error(404, &format!("no page at {path}")),
    }
}

/// `GET /api/frame`: the long poll for the next frame after `?after=N`. At most
/// [`MAX_WAITING_POLLS`] wait at once; the others are answered with the current frame at
/// once, so polls a client holds open cannot take every connection the server has.
fn frame(hub: &Hub, site: &Site, query: &str) -> Response {
    let numbers = (|| {
        Ok::<_, Response>((
            query_number(query, "after")?.unwrap_or(0),
            query_number(query, "topology")?,
            query_number(query, "pattern")?,
            query_number(query, "instance")?,
        ))
    })();
    match numbers {
        Ok((after, topology, pattern, instance)) => {
            // A page that knew another session (the studio restarted on this port) has
            // versions that mean nothing here: it gets everything, at once.
            let (after, topology, pattern) = match instance {
                Some(i) if i != hub.instance() => (0, None, None),
                _ => (after, topology, pattern),
            };
            let waiting = site.waiting_polls.fetch_add(1, Ordering::SeqCst);
            let wait = if waiting < MAX_WAITING_POLLS {
                LONG_POLL
            } else {
                Duration::ZERO
            };
            let frame = hub.frame_after(after, wait);
            site.waiting_polls.fetch_sub(1, Ordering::SeqCst);
            Response {
                status: 200,
                content_type: "application/json",
                body: frame
                    .to_json_for(topology, pattern, hub.instance())
                    .into_bytes(),
                download: None,
            }
        }
        Err(r) => r,
    }
}

/// The `?name=` of an uploaded file (its extension picks the format), or the 400 that
/// says `missing`, or a 413 for a file past [`MAX_UPLOAD`].
fn upload_name(query: &str, body: &[u8], missing: &str) -> Result<String, Response> {
    let Some(name) = query_value(query, "name").map(percent_decode) else {
        return Err(Response::error(400, missing));
    };
    if body.len() > MAX_UPLOAD {
        return Err(Response::error(
            413,
            &format!("{name}: larger than {} MiB", MAX_UPLOAD >> 20),
        ));
    }
    Ok(name)
}

/// The session command an API request asks for, or the 4xx that says why it is none.
fn command_for(
    method: &str,
    route: &str,
    path: &str,
    query: &str,
    body: Vec<u8>,
) -> Result<Command, Response> {
    Ok(match (method, route) {
        ("GET", "/state") => Command::State,
        ("GET", "/design.fold") => Command::SaveFold,
        ("GET", r) if r.starts_with("/fab/") => Command::FabFile(r["/fab/".len()..].to_string()),
        ("POST", "/motion") => Command::Motion(parse::<MotionRequest>(path, &body)?),
        ("GET", "/motion/export") => Command::MotionFile(
            query_value(query, "format")
                .map(percent_decode)
                .ok_or_else(|| {
                    Response::error(400, "/api/motion/export needs ?format=glb, fold or png")
                })?,
        ),
        ("POST", "/drag") => {
            let b = parse::<DragBody>(path, &body)?;
            Command::Drag {
                vertex: b.vertex,
                target: b.target,
            }
        }
        ("POST", "/release") => Command::Release,
        ("POST", "/pin") => {
            let b = parse::<PinBody>(path, &body)?;
            Command::Pin {
                vertex: b.vertex,
                pinned: b.pinned,
            }
        }
        ("POST", "/undo") => Command::Undo,
        ("POST", "/redo") => Command::Redo,
        ("POST", "/settings") => Command::Settings(parse::<Settings>(path, &body)?),
        ("POST", "/fold") => Command::Fold {
            amount: parse::<FoldBody>(path, &body)?.amount,
        },
        #[cfg(test)]
        ("POST", "/panic") => Command::Panic,
        ("POST", "/generate") => Command::Generate(parse::<GenerateRequest>(path, &body)?),
        ("POST", "/fabricate") => Command::Fabricate(parse::<FabRequest>(path, &body)?),
        ("POST", "/open") => {
            let name = upload_name(
                query,
                &body,
                "/api/open needs ?name=FILE (its extension picks the format)",
            )?;
            // Read here, on the connection's thread: parsing a large file on the
            // session's would hold up every other request until it ends.
            let imported = crate::io::read_bytes(std::path::Path::new(&name), body)
                .map_err(|e| Response::error(400, &e.to_string()))?;
            Command::Open {
                name,
                imported: Box::new(imported),
            }
        }
        ("POST", "/target") => {
            let name = upload_name(query, &body, "/api/target needs ?name=FILE (.obj or .stl)")?;
            let surface = crate::io::read_target_bytes(std::path::Path::new(&name), &body)
                .map_err(|e| Response::error(400, &e.to_string()))?;
            Command::LoadTarget {
                name,
                surface: Box::new(surface),
            }
        }
        ("GET", "/target") => Command::TargetMesh,
        ("POST", "/target/place") => Command::PlaceTarget(parse::<TargetPlacement>(path, &body)?),
        ("POST", "/target/clear") => Command::ClearTarget,
        ("POST", "/fit") => Command::Fit(parse::<FitRequest>(path, &body)?),
        ("POST", "/fit/stop") => Command::StopFit,
        (_, r) => {
            return Err(Response::error(
                404,
                &format!("no route {method} /api{r} (see docs/studio.md, the studio API)"),
            ))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_a_request_is_a_500_and_the_session_keeps_its_design() {
        let mesh = crate::studio::session::Session::default_design();
        let hub = Hub::start(mesh, "miura");
        let site = Site::default();
        let ask = |method, path: &str, body: &[u8]| {
            handle(
                &hub,
                &site,
                Request::from_page(&site, method, path, "", body.to_vec()),
            )
        };
        let before = ask("GET", "/api/state", b"");
        assert_eq!(before.status, 200);
        let r = ask("POST", "/api/panic", b"{}");
        assert_eq!(r.status, 500);
        let message = String::from_utf8_lossy(&r.body).to_string();
        assert!(message.contains("the design is kept"), "{message}");
        for _ in 0..2 {
            let state = ask("GET", "/api/state", b"");
            assert_eq!(state.status, 200, "the session still answers");
            let (a, b): (serde_json::Value, serde_json::Value) = (
                serde_json::from_slice(&before.body).unwrap(),
                serde_json::from_slice(&state.body).unwrap(),
            );
            assert_eq!(a["positions"], b["positions"]);
            let saved = ask("GET", "/api/design.fold", b"");
            assert_eq!(saved.status, 200);
            assert!(crate::io::fold::parse(&String::from_utf8(saved.body).unwrap()).is_ok());
        }
        hub.stop();
    }

    #[test]
    fn only_loopback_names_on_the_studios_port_are_its_own() {
        let site = Site::new(8123, None);
        for own in [
            "127.0.0.1:8123",
            "localhost:8123",
            "LocalHost:8123",
            "[::1]:8123",
        ] {
            assert!(site.is_own_authority(own), "{own}");
        }
        for foreign in [
            "127.0.0.1",
            "127.0.0.1:8124",
            "evil.example:8123",
            "127.0.0.1.evil.example:8123",
            "localhost.:8123",
            "127.0.0.2:8123",
            "",
            ":8123",
        ] {
            assert!(!site.is_own_authority(foreign), "{foreign}");
        }
    }

    #[test]
    fn query_values_are_found_and_decoded() {
        assert_eq!(query_value("after=3&topology=1", "topology"), Some("1"));
        assert_eq!(query_value("after=3", "pattern"), None);
        assert_eq!(percent_decode("my%20design+v2.fold"), "my design v2.fold");
        assert_eq!(percent_decode("bad%zzname%"), "bad%zzname%");
        assert_eq!(percent_decode("%é%"), "%é%");
    }
}
