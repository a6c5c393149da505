//! `cargo bench --bench studio`: what a user sees while dragging in the studio. A pointer
//! moves a vertex of a Miura-ori around a circle at 60 Hz (as a mouse does) while a page
//! long-polls frames, exactly as the browser does but in process; it counts the solver
//! steps the session takes and the frames with new positions the page receives, per
//! second. Run it on one core with `taskset -c 0 cargo bench --bench studio`.

use crease::generate::{generate, Params, PatternKind};
use crease::studio::api::{handle, Request, Site};
use crease::studio::Hub;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn get(hub: &Hub, path: &str) -> serde_json::Value {
    let (path, query) = path.split_once('?').unwrap_or((path, ""));
    let site = Site::default();
    let r = handle(
        hub,
        &site,
        Request::from_page(&site, "GET", path, query, Vec::new()),
    );
    serde_json::from_slice(&r.body).expect("JSON")
}

fn post(hub: &Hub, path: &str, body: serde_json::Value) {
    let site = Site::default();
    let r = handle(
        hub,
        &site,
        Request::from_page(&site, "POST", path, "", body.to_string().into_bytes()),
    );
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
}

/// Drags vertex `v` toward `target(t)` (re-sent at 60 Hz, as a mouse does) for `seconds`
/// while a page long-polls; returns (solver steps/s, frames with new positions shown/s,
/// KiB per frame).
fn measure(
    hub: &Arc<Hub>,
    v: usize,
    seconds: f64,
    target: fn(f64, &[f64; 4]) -> [f64; 3],
    c: [f64; 4],
) -> (f64, f64, f64) {
    let done = Arc::new(AtomicBool::new(false));
    let pointer = {
        let (hub, done) = (Arc::clone(hub), Arc::clone(&done));
        std::thread::spawn(move || {
            let t0 = Instant::now();
            while !done.load(Ordering::Relaxed) {
                let to = target(t0.elapsed().as_secs_f64(), &c);
                post(
                    &hub,
                    "/api/drag",
                    serde_json::json!({"vertex": v, "target": to}),
                );
                std::thread::sleep(Duration::from_millis(16));
            }
        })
    };
    // The page: long-poll, keep the parts it has, count frames with new positions; the
    // first half second (factorisation, first frames) is not counted.
    let (mut version, mut frames, mut bytes) = (0u64, 0usize, 0usize);
    let mut have = String::new();
    let mut last_positions = serde_json::Value::Null;
    let start = Instant::now();
    let mut counted_from = None;
    while start.elapsed().as_secs_f64() < seconds {
        let query = format!("after={version}{have}");
        let site = Site::default();
        let r = handle(
            hub,
            &site,
            Request::from_page(&site, "GET", "/api/frame", &query, Vec::new()),
        );
        let f: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
        version = f["version"].as_u64().unwrap();
        have = format!(
            "&topology={}&pattern={}",
            f["topologyVersion"], f["patternVersion"]
        );
        if f["live"]["positions"] != last_positions {
            last_positions = f["live"]["positions"].clone();
            if counted_from.is_some() {
                frames += 1;
                bytes += r.body.len();
            }
        }
        if counted_from.is_none() && start.elapsed() > Duration::from_millis(500) {
            counted_from = Some(Instant::now());
        }
    }
    let steps = get(hub, "/api/state")["stepsPerSecond"].as_f64().unwrap();
    done.store(true, Ordering::Relaxed);
    pointer.join().unwrap();
    post(hub, "/api/release", serde_json::json!({}));
    let elapsed = counted_from.unwrap().elapsed().as_secs_f64();
    (
        steps,
        frames as f64 / elapsed,
        bytes as f64 / frames.max(1) as f64 / 1024.0,
    )
}

fn main() {
    crease::allocator::set_up();
    println!(
        "{:>9} {:>14} {:>16} {:>11}",
        "vertices", "solver steps/s", "frames shown/s", "KiB/frame"
    );
    for cells in [15usize, 31, 99] {
        let mesh = generate(&Params::square(PatternKind::Miura, cells, 10.0)).unwrap();
        let n = mesh.vertex_count();
        let hub = Hub::start(mesh, "bench");
        let v = n / 2;
        let state = get(&hub, "/api/state");
        let at = |k: usize| state["positions"][v][k].as_f64().unwrap();
        // Around a circle of a twentieth of the sheet's width, once every 6.3 s, lifted
        // by its radius.
        let c = [at(0), at(1), at(2), 0.5 * cells as f64];
        let (steps, shown, kib) = measure(
            &hub,
            v,
            6.0,
            |t, c| [c[0] + c[3] * t.cos(), c[1] + c[3] * t.sin(), c[2] + c[3]],
            c,
        );
        println!("{n:>9} {steps:>14.0} {shown:>16.1} {kib:>11.1}");
        hub.stop();
    }
}
