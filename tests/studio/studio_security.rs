//! The studio as an attacker's page or a hostile file meets it, over real HTTP to the
//! real binary: only its own page may talk to it, nothing a request carries opens a file,
//! and a design that is hard to analyse never stops it answering.

use crate::studio_process;

use serde_json::{json, Value};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};
use studio_process::{http_with, StudioProcess};

/// Every route, with a body it accepts.
fn routes() -> Vec<(&'static str, &'static str, Vec<u8>)> {
    let j = |v: Value| v.to_string().into_bytes();
    let miura = std::fs::read("patterns/miura.fold").unwrap();
    vec![
        ("GET", "/", Vec::new()),
        ("GET", "/studio.js", Vec::new()),
        ("GET", "/api/state", Vec::new()),
        ("GET", "/api/meta", Vec::new()),
        ("GET", "/api/frame?after=999999", Vec::new()),
        ("GET", "/api/design.fold", Vec::new()),
        ("GET", "/api/fab/sheet.svg", Vec::new()),
        (
            "POST",
            "/api/drag",
            j(json!({"vertex": 0, "target": [0, 0, 5]})),
        ),
        ("POST", "/api/release", j(json!({}))),
        ("POST", "/api/pin", j(json!({"vertex": 3, "pinned": true}))),
        ("POST", "/api/undo", j(json!({}))),
        ("POST", "/api/redo", j(json!({}))),
        ("POST", "/api/settings", j(json!({"mode": "simulation"}))),
        ("POST", "/api/fold", j(json!({"amount": 0.5}))),
        ("POST", "/api/generate", j(json!({"pattern": "plane"}))),
        (
            "POST",
            "/api/fabricate",
            j(json!({"machine": "generic-hpgl"})),
        ),
        ("POST", "/api/open?name=other.fold", miura),
    ]
}

fn content_type_for(path: &str) -> &'static str {
    crease::studio::api::body_type(path.split('?').next().unwrap_or(path))
}

fn unchanged(studio: &StudioProcess, before: &Value) {
    let (status, after) = studio.json("GET", "/api/state", "");
    assert_eq!(status, 200);
    assert_eq!(after["positions"], before["positions"]);
    assert_eq!(after["title"], before["title"]);
    assert_eq!(after["mode"], before["mode"]);
    assert_eq!(after["pinned"], before["pinned"]);
    assert_eq!(after["undo"], 0, "nothing refused entered the history");
}

#[test]
fn a_foreign_host_a_foreign_origin_and_a_simple_post_are_refused_on_every_route() {
    let studio = StudioProcess::start(&["patterns/miura.fold"]);
    let (_, before) = studio.json("GET", "/api/state", "");
    let own = format!("127.0.0.1:{}", studio.port);
    let port = studio.port;
    for (method, path, body) in routes() {
        let kind = content_type_for(path);
        // DNS rebinding: the page's own name in Host, or none at all.
        for host in [
            Some("evil.example".to_string()),
            Some(format!("evil.example:{port}")),
            Some(format!("127.0.0.1:{}", port.wrapping_add(1))),
            None,
        ] {
            let mut headers = vec![("Content-Type", kind)];
            if let Some(h) = host.as_deref() {
                headers.push(("Host", h));
            }
            let (status, reply) = http_with(port, method, path, &headers, &body);
            assert_eq!(status, 403, "{method} {path} Host {host:?}");
            let text = String::from_utf8_lossy(&reply);
            assert!(text.contains("Host") && !text.contains('\n'), "{text}");
        }
        // A cross-site page: its Origin, even with the right Host.
        for origin in [
            "http://evil.example",
            "null",
            &format!("http://evil.example:{port}"),
            &format!("https://127.0.0.1:{port}"),
        ] {
            let headers = [
                ("Host", own.as_str()),
                ("Origin", origin),
                ("Content-Type", kind),
            ];
            let (status, _) = http_with(port, method, path, &headers, &body);
            assert_eq!(status, 403, "{method} {path} Origin {origin}");
        }
        // A simple request (no preflight): text/plain or a form, from anywhere.
        if method == "POST" {
            for simple in [
                "text/plain",
                "application/x-www-form-urlencoded",
                "multipart/form-data; boundary=x",
            ] {
                let headers = [("Host", own.as_str()), ("Content-Type", simple)];
                let (status, _) = http_with(port, method, path, &headers, &body);
                assert_eq!(status, 415, "{method} {path} as {simple}");
            }
            let (status, _) = http_with(port, method, path, &[("Host", own.as_str())], &body);
            assert_eq!(status, 415, "{method} {path} without a type");
        }
    }
    unchanged(&studio, &before);
    // The page's own requests still work, from each loopback name.
    for host in [own.clone(), format!("localhost:{port}")] {
        let origin = format!("http://{host}");
        let headers = [
            ("Host", host.as_str()),
            ("Origin", origin.as_str()),
            ("Content-Type", "application/json"),
        ];
        let (status, _) = http_with(port, "POST", "/api/undo", &headers, b"{}");
        assert_eq!(status, 409, "nothing to undo, but admitted");
    }
}

/// The response head of a GET as the page sends it.
fn head_of(port: u16, path: &str) -> String {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).unwrap();
    let text = String::from_utf8_lossy(&raw).to_string();
    text.split("\r\n\r\n").next().unwrap().to_ascii_lowercase()
}

#[test]
fn every_reply_forbids_framing_sniffing_and_foreign_scripts() {
    let studio = StudioProcess::start(&[]);
    for path in ["/", "/studio.js", "/api/state", "/api/nothing"] {
        let head = head_of(studio.port, path);
        let csp = head
            .lines()
            .find(|l| l.starts_with("content-security-policy:"))
            .unwrap_or_else(|| panic!("{path}: no CSP in {head}"));
        assert!(csp.contains("default-src 'self'"), "{csp}");
        assert!(csp.contains("frame-ancestors 'none'"), "{csp}");
        assert!(!csp.contains("unsafe-inline"), "{csp}");
        assert!(head.contains("x-content-type-options: nosniff"), "{path}");
        assert!(head.contains("x-frame-options: deny"), "{path}");
        assert!(
            !head.contains("access-control-allow-origin"),
            "{path}: no CORS grant"
        );
    }
}

#[test]
fn fabricate_takes_machine_names_only_and_never_opens_a_path() {
    let dir = crate::scratch::Scratch::new("canary");
    let canary = "canary-7f3a91";
    // A file that would fail as a profile and be quoted back if it were read.
    let planted = dir.join("cutter.toml");
    std::fs::write(
        &planted,
        format!("{canary} = \"{canary}\"\nexport {canary}\n"),
    )
    .unwrap();
    let studio = StudioProcess::start(&["patterns/miura.fold"]);
    let path = planted.display().to_string();
    let stem = dir.join("cutter").display().to_string();
    let relative = format!("../../../../../..{path}");
    for machine in [
        path.as_str(),
        stem.as_str(),
        relative.as_str(),
        "~/.bashrc",
        "/etc/passwd",
    ] {
        let (status, bytes) = studio.request(
            "POST",
            "/api/fabricate",
            json!({ "machine": machine }).to_string().as_bytes(),
        );
        let reply = String::from_utf8_lossy(&bytes);
        assert_eq!(status, 400, "{machine}: {reply}");
        assert!(
            !reply.contains(canary),
            "{machine}: the file was read: {reply}"
        );
        assert!(
            reply.contains("generic-hpgl"),
            "names the studio's machines: {reply}"
        );
        // Whether the file exists is not told either: the same answer for a missing one.
        let missing = machine.replace("cutter", "absent");
        let (_, other) = studio.request(
            "POST",
            "/api/fabricate",
            json!({ "machine": missing }).to_string().as_bytes(),
        );
        let other = String::from_utf8_lossy(&other).replace("absent", "cutter");
        assert_eq!(other, reply, "an existence oracle");
    }
    let (status, _) = studio.json("POST", "/api/fabricate", r#"{"machine": "generic-hpgl"}"#);
    assert_eq!(status, 200, "a listed machine still works");
}

/// A fan of `n` triangles at one vertex, creases alternating mountain and valley (a FOLD).
fn fan(n: usize) -> Vec<u8> {
    let mut coords = vec![json!([0.0, 0.0])];
    let (mut edges, mut kinds, mut angles, mut faces) = (vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        coords.push(json!([100.0 * a.cos(), 100.0 * a.sin()]));
        faces.push(json!([0, 1 + i, 1 + (i + 1) % n]));
        edges.push(json!([0, 1 + i]));
        kinds.push(if i % 2 == 0 { "V" } else { "M" });
        angles.push(if i % 2 == 0 { 180 } else { -180 });
    }
    for i in 0..n {
        edges.push(json!([1 + i, 1 + (i + 1) % n]));
        kinds.push("B");
        angles.push(0);
    }
    json!({"file_spec": 1.1, "vertices_coords": coords, "faces_vertices": faces,
           "edges_vertices": edges, "edges_assignment": kinds, "edges_foldAngle": angles})
    .to_string()
    .into_bytes()
}

/// `lines` full lines through the centre of a square, alternating M and V (a `.cp`).
fn star(lines: usize) -> Vec<u8> {
    let r = 100.0;
    let mut out = String::new();
    for (x1, y1, x2, y2) in [
        (-r, -r, r, -r),
        (r, -r, r, r),
        (r, r, -r, r),
        (-r, r, -r, -r),
    ] {
        out.push_str(&format!("1 {x1} {y1} {x2} {y2}\n"));
    }
    for i in 0..2 * lines {
        let a = std::f64::consts::PI * i as f64 / lines as f64;
        let t = r / a.cos().abs().max(a.sin().abs());
        out.push_str(&format!(
            "{} 0 0 {:.12} {:.12}\n",
            2 + i % 2,
            t * a.cos(),
            t * a.sin()
        ));
    }
    out.into_bytes()
}

/// The studio's peak resident memory so far (kB), from the kernel.
fn peak_kb(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .expect("VmHWM")
}

#[test]
fn heavy_files_never_stop_the_studio_answering() {
    let studio = StudioProcess::start(&[]);
    for (name, bytes) in [("fan.fold", fan(2000)), ("star.cp", star(59))] {
        let (status, reply) = studio.request("POST", &format!("/api/open?name={name}"), &bytes);
        assert_eq!(status, 200, "{name}: {}", String::from_utf8_lossy(&reply));
        let start = Instant::now();
        let mut judged = None;
        while start.elapsed() < Duration::from_secs(6) {
            let asked = Instant::now();
            let (status, s) = studio.json("GET", "/api/state", "");
            let took = asked.elapsed();
            assert_eq!(status, 200);
            assert!(
                took < Duration::from_secs(1),
                "{name}: /api/state took {took:?}"
            );
            judged = Some(s);
            std::thread::sleep(Duration::from_millis(100));
        }
        let s = judged.unwrap();
        assert_eq!(s["title"], name.split('.').next().unwrap(), "{s}");
        let peak = peak_kb(studio.child.id());
        assert!(peak < 1_500_000, "{name}: peak {peak} kB");
    }
}
