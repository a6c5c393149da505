//! The real `crease studio` binary over HTTP: its address line, a taken port, dropped
//! sockets and closed tabs, two clients sharing a design, Ctrl-C. Its API in process is
//! `studio.rs`; the page in a real browser is `studio_browser.rs`.

use crate::studio_process;

use serde_json::{json, Value};
use std::time::{Duration, Instant};
use studio_process::{distance, http, position, StudioProcess};

#[test]
fn the_binary_serves_the_page_and_the_api_on_loopback() {
    let studio = StudioProcess::start(&[]);
    assert!(studio.url.starts_with("http://127.0.0.1:"));
    let (status, page) = studio.request("GET", "/", b"");
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&page).contains("crease studio"));
    let (status, s) = studio.json("GET", "/api/state", "");
    assert_eq!(status, 200);
    assert_eq!(s["vertices"], 81, "without a file: the generated Miura-ori");
    let (status, meta) = studio.json("GET", "/api/meta", "");
    assert_eq!(status, 200);
    // The paper's six starting patterns, the curved-crease ones and the tubes.
    let names: Vec<&str> = meta["patterns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names.len(), 12, "{names:?}");
    assert!(
        names.contains(&"arc") && names.contains(&"concentric") && names.contains(&"pleat"),
        "{names:?}"
    );
    assert!(names.contains(&"waterbomb-tube") && names.contains(&"kresling"));
    assert!(meta["machines"]
        .as_array()
        .unwrap()
        .contains(&json!("generic-hpgl")));
}

#[test]
fn a_taken_port_is_a_clear_error() {
    let studio = StudioProcess::start(&[]);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
        .args(["studio", "--no-open", "--port", &studio.port.to_string()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains(&studio.port.to_string()) && err.contains("--port"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn dropped_sockets_and_closed_tabs_never_stop_the_server_and_two_clients_share_a_design() {
    use std::io::Write;
    let studio = StudioProcess::start(&["patterns/miura.fold"]);
    // A client that sends half a request and goes away.
    {
        let mut s = std::net::TcpStream::connect(("127.0.0.1", studio.port)).unwrap();
        s.write_all(b"POST /api/drag HTTP/1.1\r\nContent-Length: 500\r\n\r\n{\"ver")
            .unwrap();
    }
    // A tab that long-polls and is closed mid-wait.
    {
        let mut s = std::net::TcpStream::connect(("127.0.0.1", studio.port)).unwrap();
        s.write_all(b"GET /api/frame?after=999999 HTTP/1.1\r\nHost: x\r\n\r\n")
            .unwrap();
        std::thread::sleep(Duration::from_millis(100));
    }
    let (status, s1) = studio.json("GET", "/api/state", "");
    assert_eq!(status, 200);
    let p = position(&s1, 40);
    let (status, _) = studio.json(
        "POST",
        "/api/drag",
        &json!({"vertex": 40, "target": [p[0], p[1], p[2] + 6.0]}).to_string(),
    );
    assert_eq!(status, 200);
    let start = Instant::now();
    while studio.json("GET", "/api/state", "").1["settled"] != true {
        assert!(start.elapsed() < Duration::from_secs(30));
        std::thread::sleep(Duration::from_millis(20));
    }
    studio.json("POST", "/api/release", "{}");
    // A second client (another tab) sees the same design.
    let (_, a) = studio.json("GET", "/api/state", "");
    let (_, b) = http(studio.port, "GET", "/api/state", b"");
    let b: Value = serde_json::from_slice(&b).unwrap();
    assert_eq!(a["positions"], b["positions"]);
    assert!(distance(position(&a, 40), p) > 3.0);
}

#[test]
fn ctrl_c_stops_the_studio_cleanly() {
    let mut studio = StudioProcess::start(&[]);
    let status = std::process::Command::new("kill")
        .args(["-INT", &studio.child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let start = Instant::now();
    let code = loop {
        if let Some(s) = studio.child.try_wait().unwrap() {
            break s.code();
        }
        assert!(start.elapsed() < Duration::from_secs(20), "it stops");
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(code, Some(0));
    let err = studio.stderr_at_exit();
    assert!(err.contains("stopped"), "{err}");
}
