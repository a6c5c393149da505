#![allow(dead_code)] // each test crate uses its own part of these helpers
//! A running `crease studio` for tests: the real binary on a free port, its URL read from
//! its first line of output, killed on drop; and a minimal HTTP/1.1 client over a TCP
//! socket, enough to call the studio's API.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// The studio binary, running.
pub struct StudioProcess {
    pub child: Child,
    pub url: String,
    pub port: u16,
}

impl StudioProcess {
    /// Starts `crease studio ARGS --no-open` and waits for its address line.
    pub fn start(args: &[&str]) -> StudioProcess {
        let mut command = Command::new(env!("CARGO_BIN_EXE_crease"));
        command.arg("studio").args(args).arg("--no-open");
        Self::spawn(command)
    }

    /// As [`StudioProcess::start`], under an address-space limit of `kb` kilobytes
    /// (`ulimit -v`): an allocation past it fails as it would on a system that does not
    /// overcommit, instead of being granted and never touched.
    pub fn start_limited(args: &[&str], kb: u64) -> StudioProcess {
        let mut command = Command::new("sh");
        command
            .arg("-c")
            .arg(format!(
                "ulimit -v {kb} && exec \"$0\" studio \"$@\" --no-open"
            ))
            .arg(env!("CARGO_BIN_EXE_crease"))
            .args(args);
        Self::spawn(command)
    }

    fn spawn(mut command: Command) -> StudioProcess {
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("crease studio starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut line)
            .expect("the studio prints its address");
        let url = line
            .trim()
            .strip_prefix("studio: ")
            .unwrap_or_else(|| panic!("first line is the address, got {line:?}"))
            .to_string();
        let port = url
            .trim_end_matches('/')
            .rsplit(':')
            .next()
            .and_then(|p| p.parse().ok())
            .expect("a port in the URL");
        StudioProcess { child, url, port }
    }

    /// `METHOD path` with a body: status and body.
    pub fn request(&self, method: &str, path: &str, body: &[u8]) -> (u16, Vec<u8>) {
        http(self.port, method, path, body)
    }

    /// A JSON request: status and parsed body.
    pub fn json(&self, method: &str, path: &str, body: &str) -> (u16, serde_json::Value) {
        let (status, bytes) = self.request(method, path, body.as_bytes());
        let value = serde_json::from_slice(&bytes).unwrap_or_else(|e| {
            panic!(
                "{method} {path}: not JSON ({e}): {}",
                String::from_utf8_lossy(&bytes)
            )
        });
        (status, value)
    }
}

impl Drop for StudioProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One HTTP/1.1 request on its own connection (`Connection: close`), as the studio's
/// page sends it: its own `Host`, and a POST body typed as the route wants.
pub fn http(port: u16, method: &str, path: &str, body: &[u8]) -> (u16, Vec<u8>) {
    let host = format!("127.0.0.1:{port}");
    let mut headers = vec![("Host", host.as_str())];
    if method == "POST" {
        let route = path.split('?').next().unwrap_or(path);
        headers.push(("Content-Type", crease::studio::api::body_type(route)));
    }
    http_with(port, method, path, &headers, body)
}

/// One HTTP/1.1 request with exactly these headers (besides `Connection` and
/// `Content-Length`).
pub fn http_with(
    port: u16,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: &[u8],
) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect to the studio");
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut head = format!("{method} {path} HTTP/1.1\r\n");
    for (name, value) in headers {
        head.push_str(&format!("{name}: {value}\r\n"));
    }
    head.push_str(&format!(
        "Connection: close\r\nContent-Length: {}\r\n\r\n",
        body.len()
    ));
    s.write_all(head.as_bytes()).unwrap();
    s.write_all(body).unwrap();
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).expect("a response");
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("response headers end");
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .expect("a status code");
    let mut body = raw[split + 4..].to_vec();
    if head
        .to_ascii_lowercase()
        .contains("transfer-encoding: chunked")
    {
        body = dechunk(&body);
    }
    (status, body)
}

fn dechunk(mut data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line_end = data.windows(2).position(|w| w == b"\r\n").unwrap_or(0);
        let size = usize::from_str_radix(
            std::str::from_utf8(&data[..line_end]).unwrap_or("0").trim(),
            16,
        )
        .unwrap_or(0);
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&data[line_end + 2..line_end + 2 + size]);
        data = &data[line_end + 2 + size + 2..];
    }
}

/// Vertex `v`'s position in a state the studio sent.
pub fn position(s: &serde_json::Value, v: usize) -> [f64; 3] {
    [0, 1, 2].map(|k| s["positions"][v][k].as_f64().unwrap())
}

/// Distance between two points (mm).
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}
