//! `cargo bench --bench studio_page`: what a user sees in a real browser. Headless
//! chromium (Debian's, through chromedriver; `bash tests/run` installs both) shows the
//! studio on a Miura-ori of about 1k and 10k vertices while the page drags a vertex round
//! a circle for five seconds; the page counts the frames it draws with new positions.
//! Run it with `RAYON_NUM_THREADS=1` for the solver on one core, as `--bench studio`.

#[path = "../tests/common/browser.rs"]
mod browser_support;
#[path = "../tests/common/studio.rs"]
mod studio_process;

use browser_support::{eval, open_page, Driver};
use serde_json::json;
use std::time::{Duration, Instant};
use studio_process::StudioProcess;

#[tokio::main(flavor = "current_thread")]
async fn main() {
    let driver = Driver::start();
    let dir = std::env::temp_dir().join(format!("crease-page-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    println!(
        "{:>9} {:>14} {:>16} {:>9}",
        "vertices", "frames shown/s", "frames received/s", "seconds"
    );
    for cells in [31usize, 99] {
        let pattern = dir.join(format!("miura-{cells}.fold"));
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
            .args(["generate", "miura", "--nx", &cells.to_string(), "--ny"])
            .arg(cells.to_string())
            .args(["--size", "10", "-o"])
            .arg(&pattern)
            .output()
            .expect("crease generates");
        assert!(status.status.success());
        let studio = StudioProcess::start(&[pattern.to_str().unwrap()]);
        let profile = dir.join(format!("profile-{cells}"));
        let client = open_page(&driver, &profile, &studio.url).await;
        let v = (cells / 2) * (cells + 1) + cells / 2;
        // The page's own drag requests, one at a time as its pointer handler sends them (at
        // most 60 a second), the target circling 20 mm round the vertex every two seconds
        // (WebDriver's pointer actions cannot keep up with 60 moves a second), while the
        // page draws what the server publishes.
        let start = eval(
            &client,
            "const v = arguments[0]; \
             return window.crease.state().then(s => { \
               const p = s.positions[v]; const t0 = performance.now(); window.benchRunning = true; \
               (async () => { while (window.benchRunning) { \
                 const a = (performance.now() - t0) / 1000 * Math.PI; \
                 await fetch('/api/drag', {method: 'POST', headers: {'Content-Type': 'application/json'}, \
                   body: JSON.stringify({vertex: v, target: [p[0] + 20 * Math.sin(a), p[1], p[2] + 20 * (1 - Math.cos(a))]})}); \
                 await new Promise(r => setTimeout(r, 16)); } })(); \
               return [window.crease.framesShown(), window.crease.framesApplied()]; });",
            vec![json!(v)],
        )
        .await;
        let started = Instant::now();
        tokio::time::sleep(Duration::from_secs(5)).await;
        let after = eval(
            &client,
            "window.benchRunning = false; \
             return fetch('/api/release', {method: 'POST', headers: {'Content-Type': 'application/json'}, body: '{}'}) \
               .then(() => [window.crease.framesShown(), window.crease.framesApplied()]);",
            vec![],
        )
        .await;
        let seconds = started.elapsed().as_secs_f64();
        let shown = after[0].as_f64().unwrap() - start[0].as_f64().unwrap();
        let applied = after[1].as_f64().unwrap() - start[1].as_f64().unwrap();
        println!(
            "{:>9} {:>14.1} {:>16.1} {:>9.1}",
            (cells + 1) * (cells + 1),
            shown / seconds,
            applied / seconds,
            seconds
        );
        let _ = client.close().await;
        drop(studio);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
