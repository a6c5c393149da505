//! The studio's HTTP side against requests no page sends, over real sockets to the real
//! binary run under an address-space limit: a body announced past any memory, a flood of
//! held long-polls, chunked bodies cut short. None may stop it answering its own page.

use crate::studio_process;

use serde_json::Value;
use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::time::{Duration, Instant};
use studio_process::StudioProcess;

/// The address space the studio runs in here: 4 GB (the idle studio maps under 2 GB, and
/// a buffer the size of an announced terabyte cannot be had), plus the workspace faer's
/// dense matrix products reserve on every thread that runs one. Its kernels
/// (private-gemm-x86) take twice the CPU's L3 cache per thread, uninitialised, and keep it
/// for the thread's life: 520 MiB each on a 260 MiB L3, where a fit's Cholesky runs on its
/// own thread and both workers (its address space rose 1.6 GB in the fit below). Without
/// that room the fit's third workspace was refused now and then, and the allocation's
/// failure aborted the studio mid-request (an empty reply).
fn address_space_kb() -> u64 {
    const GEMM_THREADS: u64 = 4;
    let l3_kb = std::fs::read_to_string("/sys/devices/system/cpu/cpu0/cache/index3/size")
        .ok()
        .and_then(|size| size.trim().strip_suffix('K')?.parse::<u64>().ok())
        .unwrap_or(0);
    4_000_000 + GEMM_THREADS * 2 * l3_kb
}

/// Sends `raw` on a fresh connection, closes the sending side, and returns what came back
/// (empty when the studio closed without a word).
fn exchange(port: u16, raw: &[u8]) -> String {
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    // The studio may answer and close before reading all of it.
    let _ = s.write_all(raw);
    let _ = s.shutdown(Shutdown::Write);
    let mut reply = Vec::new();
    let _ = s.read_to_end(&mut reply);
    String::from_utf8_lossy(&reply).into_owned()
}

/// `/api/state` answers 200 within a second, and the process is alive.
fn still_answering(studio: &mut StudioProcess) -> Value {
    assert!(
        studio.child.try_wait().unwrap().is_none(),
        "the studio process ended"
    );
    let asked = Instant::now();
    let (status, state) = studio.json("GET", "/api/state", "");
    assert_eq!(status, 200, "{state}");
    assert!(
        asked.elapsed() < Duration::from_secs(1),
        "{:?}",
        asked.elapsed()
    );
    state
}

/// A field of `/proc/PID/status`, in its own unit.
fn proc_status(pid: u32, field: &str) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    status
        .lines()
        .find_map(|l| l.strip_prefix(field))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or_else(|| panic!("{field} in /proc/{pid}/status"))
}

/// The names of `pid`'s threads with how many carry each, for a failure message.
fn thread_names(pid: u32) -> String {
    let mut names = std::collections::BTreeMap::<String, usize>::new();
    for task in std::fs::read_dir(format!("/proc/{pid}/task"))
        .into_iter()
        .flatten()
        .flatten()
    {
        let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        *names.entry(comm.trim().to_string()).or_default() += 1;
    }
    format!("{names:?}")
}

#[test]
fn a_body_announced_past_any_memory_is_refused_unread_and_the_studio_goes_on() {
    let mut studio = StudioProcess::start_limited(&["patterns/miura.fold"], address_space_kb());
    let port = studio.port;
    let host = format!("Host: 127.0.0.1:{port}\r\n");
    for (head, host) in [
        ("GET / HTTP/1.1\r\nContent-Length: 1000000000000\r\n", ""),
        ("GET / HTTP/1.1\r\nContent-Length: 1000000000000\r\n", host.as_str()),
        ("POST /api/open?name=x.fold HTTP/1.1\r\nContent-Type: application/octet-stream\r\nContent-Length: 3000000000\r\n", host.as_str()),
        ("POST /api/drag HTTP/1.1\r\nExpect: 100-continue\r\nContent-Length: 1500000000\r\n", host.as_str()),
    ] {
        let reply = exchange(port, format!("{head}{host}\r\nsome of it").as_bytes());
        assert!(
            reply.starts_with("HTTP/1.1 413 "),
            "{head:?}: refused as too large, got {reply:?}"
        );
        assert!(!reply.contains("100 Continue"), "{reply}");
        still_answering(&mut studio);
    }
    // A 64 MiB body, the most the studio takes, is read; a byte more is not.
    let mut big = format!(
        "POST /api/open?name=big.fold HTTP/1.1\r\n{host}Content-Type: application/octet-stream\r\nContent-Length: {}\r\n\r\n",
        crease::limits::MAX_UPLOAD + 1
    )
    .into_bytes();
    big.extend(std::iter::repeat_n(b' ', 16 << 10));
    assert!(exchange(port, &big).starts_with("HTTP/1.1 413 "));
    still_answering(&mut studio);
}

#[test]
fn a_thousand_held_long_polls_leave_it_answering_in_bounded_threads_and_memory() {
    let mut studio = StudioProcess::start_limited(&["patterns/miura.fold"], address_space_kb());
    let (port, pid) = (studio.port, studio.child.id());
    still_answering(&mut studio);
    let (threads_before, rss_before) = (proc_status(pid, "Threads:"), proc_status(pid, "VmRSS:"));
    // Polls for a frame that will not come for ten seconds, held open and never read.
    let poll = format!("GET /api/frame?after=999999 HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n");
    let mut held = Vec::new();
    for _ in 0..1000 {
        let Ok(mut s) = TcpStream::connect(("127.0.0.1", port)) else {
            continue;
        };
        let _ = s.write_all(poll.as_bytes());
        held.push(s);
    }
    assert!(held.len() >= 900, "only {} connections opened", held.len());
    // The page's own requests are answered while the polls are held (a 503 at once is
    // the answer past the cap; it must clear within a couple of seconds).
    let start = Instant::now();
    let mut answered = 0;
    while start.elapsed() < Duration::from_secs(4) {
        let asked = Instant::now();
        let (status, reply) = studio.request("GET", "/api/state", b"");
        assert!(
            asked.elapsed() < Duration::from_secs(1),
            "{:?}",
            asked.elapsed()
        );
        assert!(
            status == 200 || status == 503,
            "{status}: {}",
            String::from_utf8_lossy(&reply)
        );
        answered += usize::from(status == 200);
        let threads = proc_status(pid, "Threads:");
        assert!(
            threads <= threads_before + crease::limits::MAX_CONNECTIONS as u64 + 2,
            "{threads} threads (from {threads_before}): {}",
            thread_names(pid)
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(answered >= 10, "only {answered} states answered in 4 s");
    // What the connections cost at their worst: their threads' stacks and buffers.
    let peak = proc_status(pid, "VmHWM:");
    assert!(
        peak < rss_before + 64_000,
        "peak {peak} kB against {rss_before} kB before the flood"
    );
    drop(held);
    still_answering(&mut studio);
}

#[test]
fn a_chunked_body_cut_short_changes_nothing() {
    let mut studio = StudioProcess::start(&["patterns/miura.fold"]);
    let port = studio.port;
    let before = still_answering(&mut studio);
    assert_ne!(before["mode"], "simulation");
    let body = br#"{"mode": "simulation"}"#;
    let head = format!(
        "POST /api/settings HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n"
    );
    let chunked = |chunks: &[Vec<u8>]| {
        let mut raw = head.clone().into_bytes();
        for c in chunks {
            raw.extend(c);
        }
        raw
    };
    let whole = [
        format!("{:X}\r\n", body.len()).into_bytes(),
        body.to_vec(),
        b"\r\n0\r\n\r\n".to_vec(),
    ];
    for (what, raw) in [
        (
            "a chunk claiming 4 GiB",
            chunked(&[b"FFFFFFFF\r\n".to_vec(), body.to_vec()]),
        ),
        ("the body without its last chunk", chunked(&whole[..2])),
        (
            "the last chunk without its blank line",
            chunked(&[whole[0].clone(), whole[1].clone(), b"\r\n0\r\n".to_vec()]),
        ),
    ] {
        let reply = exchange(port, &raw);
        assert!(!reply.starts_with("HTTP/1.1 200"), "{what}: {reply}");
        let now = still_answering(&mut studio);
        assert_eq!(now["mode"], before["mode"], "{what} changed the mode");
    }
    // The same body whole is taken: chunked requests are read, not refused.
    let reply = exchange(port, &chunked(&whole));
    assert!(reply.starts_with("HTTP/1.1 200"), "{reply}");
    assert_eq!(still_answering(&mut studio)["mode"], "simulation");
}

/// Runs `request` on its own thread while `/api/state` is asked every 100 ms; each
/// answer must come within a second. Returns the request's status and body.
fn answering_while(
    studio: &mut StudioProcess,
    request: impl FnOnce(u16) -> (u16, Vec<u8>) + Send + 'static,
) -> (u16, String) {
    let port = studio.port;
    let worker = std::thread::spawn(move || request(port));
    while !worker.is_finished() {
        still_answering(studio);
        std::thread::sleep(Duration::from_millis(100));
    }
    still_answering(studio);
    let (status, body) = worker.join().unwrap();
    (status, String::from_utf8_lossy(&body).into_owned())
}

#[test]
fn hostile_uploads_and_a_fit_to_a_degenerate_target_leave_it_answering_within_a_second() {
    let mut studio = StudioProcess::start_limited(&["patterns/miura.fold"], address_space_kb());
    // One face of 30,000 corners (ear clipping took 18 s) and 80,000 overlapping pieces of
    // one line (the arrangement took 27 s): refused at once, the design unchanged.
    let face = crate::hostile_inputs::one_face_fold(30_000, 1.0);
    let cp = crate::hostile_inputs::collinear_pile_cp(80_000);
    // 3,000 long lines crossing about a million times (21 s and 600 MB).
    let svg = crate::hostile_inputs::crossing_lines_svg(3000);
    let before = still_answering(&mut studio);
    for (name, bytes) in [("face.fold", face), ("pile.cp", cp), ("zigzag.svg", svg)] {
        let path = format!("/api/open?name={name}");
        let (status, body) = answering_while(&mut studio, move |port| {
            studio_process::http(port, "POST", &path, bytes.as_bytes())
        });
        assert!((400..500).contains(&status), "{name}: {status} {body}");
        let now = still_answering(&mut studio);
        assert_eq!(
            now["vertices"], before["vertices"],
            "{name} changed the design"
        );
    }
    // Item 3's small files of huge memory, built on a 60 × 60 Miura-ori: 3,000 nested
    // coordinate keys before the real array and 2,000 inheriting frames open as the
    // design; 3 million faceOrders are refused as they are read.
    let mut params = crease::generate::Params::defaults(crease::generate::PatternKind::Miura);
    (params.nx, params.ny) = (60, 60);
    let miura = crease::io::fold::to_string(&crease::generate::generate(&params).unwrap());
    let vertices = serde_json::from_str::<Value>(&miura).unwrap()["vertices_coords"]
        .as_array()
        .unwrap()
        .len();
    let at = miura.find("\"vertices_coords\"").unwrap();
    let junk: Vec<String> = (0..3000)
        .map(|i| format!("\"k{i}\": {{\"vertices_coords\": 0}}"))
        .collect();
    let keys = format!(
        "{}\"crease:junk\": {{{}}}, {}",
        &miura[..at],
        junk.join(","),
        &miura[at..]
    );
    let mut fold: Value = serde_json::from_str(&miura).unwrap();
    for _ in 0..2000 {
        fold["file_frames"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!(
                {"frame_inherit": true, "frame_parent": 1, "frame_classes": ["foldedForm"]}
            ));
    }
    let frames = fold.to_string();
    let mut fold: Value = serde_json::from_str(&miura).unwrap();
    fold["faceOrders"] = vec![serde_json::json!([0, 1, 1]); 3_000_000].into();
    let orders = fold.to_string();
    for (name, bytes, opens) in [
        ("keys.fold", keys, true),
        ("frames.fold", frames, true),
        ("orders.fold", orders, false),
    ] {
        let path = format!("/api/open?name={name}");
        let (status, body) = answering_while(&mut studio, move |port| {
            studio_process::http(port, "POST", &path, bytes.as_bytes())
        });
        assert_eq!(status == 200, opens, "{name}: {status} {body}");
        let now = still_answering(&mut studio);
        if opens {
            assert_eq!(now["vertices"], vertices, "{name}");
        }
    }
    // 400,000 copies of one triangle as the target: a fit's steps took seconds each and
    // Stop 9.6 s; kept once, the fit runs and stops while the page is answered.
    let mut obj = String::from("v 0 0 0\nv 100 0 0\nv 0 100 0\n");
    obj.push_str(&"f 1 2 3\n".repeat(400_000));
    let (status, body) = answering_while(&mut studio, move |port| {
        studio_process::http(port, "POST", "/api/target?name=copies.obj", obj.as_bytes())
    });
    assert_eq!(status, 200, "{body}");
    let (status, fit) = studio.json("POST", "/api/fit", r#"{"steps": 400}"#);
    assert_eq!(status, 200, "{fit}");
    for _ in 0..10 {
        still_answering(&mut studio);
        std::thread::sleep(Duration::from_millis(100));
    }
    let stopping = Instant::now();
    let (status, stopped) = studio.json("POST", "/api/fit/stop", "{}");
    assert_eq!(status, 200, "{stopped}");
    assert!(
        stopping.elapsed() < Duration::from_secs(1),
        "stop took {:?}",
        stopping.elapsed()
    );
    still_answering(&mut studio);
}
