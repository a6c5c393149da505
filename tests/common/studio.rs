#![allow(dead_code)] // each test crate uses its own part of these helpers
//! A running `crease studio` for tests: the real binary on a free port, its URL read from
//! its first line of output, killed on drop; and a minimal HTTP/1.1 client over a TCP
//! socket, enough to call the studio's API.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The studio binary, running.
pub struct StudioProcess {
    pub child: Child,
    pub url: String,
    pub port: u16,
    /// Everything the studio has written to standard error so far, read by a thread of
    /// its own so that the pipe never fills, and shown when a request fails.
    stderr: Arc<Mutex<String>>,
    /// The thread that reads it: done once the studio has exited and the pipe closed.
    stderr_reader: Option<std::thread::JoinHandle<()>>,
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
        let stderr = Arc::new(Mutex::new(String::new()));
        let mut pipe = child.stderr.take().expect("stderr");
        let sink = Arc::clone(&stderr);
        let stderr_reader = std::thread::spawn(move || {
            let mut buffer = [0u8; 4096];
            while let Ok(n @ 1..) = pipe.read(&mut buffer) {
                sink.lock()
                    .unwrap()
                    .push_str(&String::from_utf8_lossy(&buffer[..n]));
            }
        });
        StudioProcess {
            child,
            url,
            port,
            stderr,
            stderr_reader: Some(stderr_reader),
        }
    }

    /// What the studio has written to standard error so far.
    pub fn stderr(&self) -> String {
        self.stderr.lock().unwrap().clone()
    }

    /// Everything the studio wrote to standard error, once it has exited: waits for the
    /// reader to reach the pipe's end.
    pub fn stderr_at_exit(&mut self) -> String {
        if let Some(reader) = self.stderr_reader.take() {
            reader.join().expect("the standard-error reader ends");
        }
        self.stderr()
    }

    /// `METHOD path` with a body: status and body. A request that gets no HTTP answer
    /// fails the test with the studio's process state and standard error, which say
    /// whether it died (and of what) or only dropped the connection.
    pub fn request(&self, method: &str, path: &str, body: &[u8]) -> (u16, Vec<u8>) {
        match try_http(self.port, method, path, body) {
            Ok(answer) => answer,
            Err(e) => {
                std::thread::sleep(Duration::from_millis(200));
                // A process that died is a zombie ("Z") until the test reaps it.
                let state = std::fs::read_to_string(format!("/proc/{}/stat", self.child.id()))
                    .ok()
                    .and_then(|stat| stat.rsplit_once(") ")?.1.chars().next())
                    .unwrap_or('?');
                panic!(
                    "{method} {path}: {e}; the studio's process state: {state}; its standard error:\n{}",
                    self.stderr()
                )
            }
        }
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
    try_http(port, method, path, body).unwrap_or_else(|e| panic!("{method} {path}: {e}"))
}

/// As [`http`], with the failure to get an answer returned.
pub fn try_http(
    port: u16,
    method: &str,
    path: &str,
    body: &[u8],
) -> Result<(u16, Vec<u8>), String> {
    let host = format!("127.0.0.1:{port}");
    let mut headers = vec![("Host", host.as_str())];
    if method == "POST" {
        let route = path.split('?').next().unwrap_or(path);
        headers.push(("Content-Type", crease::studio::api::body_type(route)));
    }
    try_http_with(port, method, path, &headers, body)
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
    try_http_with(port, method, path, headers, body)
        .unwrap_or_else(|e| panic!("{method} {path}: {e}"))
}

fn try_http_with(
    port: u16,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: &[u8],
) -> Result<(u16, Vec<u8>), String> {
    let mut s = TcpStream::connect(("127.0.0.1", port))
        .map_err(|e| format!("cannot connect to the studio: {e}"))?;
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut head = format!("{method} {path} HTTP/1.1\r\n");
    for (name, value) in headers {
        head.push_str(&format!("{name}: {value}\r\n"));
    }
    head.push_str(&format!(
        "Connection: close\r\nContent-Length: {}\r\n\r\n",
        body.len()
    ));
    s.write_all(head.as_bytes())
        .map_err(|e| format!("cannot send the request's head: {e}"))?;
    // A refusal may close the connection before the body is sent; its answer is read below.
    let sent = s.write_all(body);
    let mut raw = Vec::new();
    s.read_to_end(&mut raw)
        .map_err(|e| format!("no response ({e}); sending the body: {sent:?}"))?;
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .ok_or_else(|| {
            format!(
                "the response's headers do not end ({} bytes: {:?}); sending the body: {sent:?}",
                raw.len(),
                String::from_utf8_lossy(&raw[..raw.len().min(200)])
            )
        })?;
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| format!("no status code in {head:?}"))?;
    let mut body = raw[split + 4..].to_vec();
    if head
        .to_ascii_lowercase()
        .contains("transfer-encoding: chunked")
    {
        body = dechunk(&body);
    }
    Ok((status, body))
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
