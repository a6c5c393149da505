#![allow(dead_code)] // the browser test and the page benchmark use their own parts
//! Headless chromium for the studio's page, driven over WebDriver: chromedriver on a free
//! port (killed on drop), a browser session with WebGL in software and no network beyond
//! loopback, and small helpers to run the page's own JavaScript.
//!
//! It needs `chromium` and `chromium-driver`; `bash tests/run` (the README's test command)
//! installs them. Without them it fails and says so.

use fantoccini::{Client, ClientBuilder};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn which(program: &str) -> Option<PathBuf> {
    std::env::var_os("PATH")?
        .to_str()?
        .split(':')
        .map(|d| Path::new(d).join(program))
        .find(|p| p.is_file())
}

/// chromedriver on a free port, killed on drop.
pub struct Driver {
    child: Child,
    url: String,
}

impl Driver {
    pub fn start() -> Driver {
        let exe = which("chromedriver").unwrap_or_else(|| {
            panic!("chromedriver not found: run `bash tests/run` (it installs chromium and chromium-driver)")
        });
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let child = Command::new(exe)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let start = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "chromedriver listens"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        Driver {
            child,
            url: format!("http://127.0.0.1:{port}"),
        }
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

pub async fn browser(driver: &Driver, profile: &Path) -> Client {
    let chromium = which("chromium").unwrap_or_else(|| {
        panic!(
            "chromium not found: run `bash tests/run` (it installs chromium and chromium-driver)"
        )
    });
    let caps = json!({
        "browserName": "chrome",
        "goog:chromeOptions": {
            "binary": chromium,
            "args": [
                "--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                // WebGL without a GPU.
                "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                // This machine has no network beyond loopback.
                "--disable-background-networking", "--disable-component-update",
                "--disable-sync", "--no-first-run",
                "--window-size=1400,860",
                format!("--user-data-dir={}", profile.display()),
            ],
            // Downloads (Save FOLD, Export) land in the profile's downloads/, unasked.
            "prefs": {
                "download.default_directory": downloads(profile),
                "download.prompt_for_download": false,
            }
        }
    });
    let Value::Object(caps) = caps else {
        unreachable!()
    };
    ClientBuilder::new(hyper_util::client::legacy::connect::HttpConnector::new())
        .capabilities(caps)
        .connect(&driver.url)
        .await
        .expect("a browser session")
}

/// Where the browser of `profile` puts what the page downloads.
pub fn downloads(profile: &Path) -> PathBuf {
    profile.join("downloads")
}

pub async fn eval(client: &Client, script: &str, args: Vec<Value>) -> Value {
    client
        .execute(script, args)
        .await
        .unwrap_or_else(|e| panic!("{script}: {e}"))
}

/// The server's state as the page sees it (`window.crease.state()`).
pub async fn page_state(client: &Client) -> Value {
    eval(client, "return window.crease.state();", vec![]).await
}

/// POSTs `body` as JSON to the studio's `path` from the page itself (same origin, as
/// the page's own requests go); the reply's HTTP status.
pub async fn post_from_page(client: &Client, path: &str, body: Value) -> Value {
    eval(
        client,
        "return fetch(arguments[0], {method: 'POST', headers: {'Content-Type': 'application/json'}, \
         body: JSON.stringify(arguments[1])}).then(r => r.status);",
        vec![Value::from(path), body],
    )
    .await
}

/// Waits up to 60 s for `script` to return true; past that, fails naming `what` and the
/// page's status line (where a refused request shows why).
pub async fn wait_until(client: &Client, what: &str, script: &str) {
    let start = Instant::now();
    while eval(client, script, vec![]).await != Value::Bool(true) {
        if start.elapsed() >= Duration::from_secs(60) {
            let status = eval(
                client,
                "const s = document.getElementById('status'); return s ? s.textContent : null;",
                vec![],
            )
            .await;
            panic!("waiting for {what}; the page's status line: {status}");
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// A browser session (profile in `profile`) on the studio at `url`, once the page has
/// drawn its first frame.
pub async fn open_page(driver: &Driver, profile: &Path, url: &str) -> Client {
    // Now and then headless chromium's renderer hangs before the first load (once in
    // about ten suite runs here, "Timed out receiving message from renderer" after the
    // default five minutes): the load is given 90 s, and a hung browser is replaced by a
    // fresh one, once. A page that does not load twice fails the test.
    let mut client = browser(driver, profile).await;
    let timeouts = fantoccini::wd::TimeoutConfiguration::new(
        None,
        Some(std::time::Duration::from_secs(90)),
        None,
    );
    client
        .update_timeouts(timeouts.clone())
        .await
        .expect("timeouts");
    if let Err(first) = client.goto(url).await {
        eprintln!("the page did not load ({first}); trying a fresh browser");
        let _ = client.close().await;
        client = browser(driver, &profile.with_extension("retry")).await;
        client.update_timeouts(timeouts).await.expect("timeouts");
        client.goto(url).await.expect("the page loads");
    }
    wait_until(
        &client,
        "the first frame",
        "return !!(window.crease && window.crease.ready);",
    )
    .await;
    client
}
