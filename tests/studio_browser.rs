//! The studio in a real headless browser (Debian's chromium, driven by chromedriver over
//! WebDriver) with real pointer events: the page loads a bundled pattern, a vertex is
//! pressed, dragged 40 px and released, and the server's state and saved FOLD are checked.
//! A Shift-click pins a vertex. Screenshots go to `out/`.
//!
//! It needs `chromium` and `chromium-driver`; `bash tests/run` (the README's test command)
//! installs them. Without them this test fails and says so.

#[path = "common/browser.rs"]
mod browser_support;
#[path = "common/js.rs"]
mod js;
#[path = "common/scratch.rs"]
mod scratch;
#[path = "common/studio.rs"]
mod studio_process;

use browser_support::{downloads, eval, open_page, page_state, post_from_page, wait_until, Driver};
use fantoccini::actions::{
    InputSource, KeyAction, KeyActions, MouseActions, PointerAction, MOUSE_BUTTON_LEFT,
};
use fantoccini::key::Key;
use fantoccini::Client;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;
use studio_process::{http, position, StudioProcess};

async fn screen_of(client: &Client, v: usize) -> (f64, f64) {
    let at = eval(
        client,
        "return window.crease.screenOf(arguments[0]);",
        vec![json!(v)],
    )
    .await;
    (at["x"].as_f64().unwrap(), at["y"].as_f64().unwrap())
}

/// Where vertex `v` is once the view has stopped moving: the same point on two reads a
/// frame apart and inside the window. Read too early (the layout still settling, the
/// camera still framing the sheet), a press landed outside the window now and then and
/// WebDriver refused it (MoveTargetOutOfBounds).
async fn settled_screen_of(client: &Client, v: usize) -> (f64, f64) {
    let mut last = (f64::NAN, f64::NAN);
    for _ in 0..100 {
        let at = screen_of(client, v).await;
        let size = eval(
            client,
            "return [window.innerWidth, window.innerHeight];",
            vec![],
        )
        .await;
        let (w, h) = (size[0].as_f64().unwrap(), size[1].as_f64().unwrap());
        let inside = at.0 > 0.0 && at.1 > 60.0 && at.0 < w && at.1 < h;
        if inside && (at.0 - last.0).hypot(at.1 - last.1) < 0.5 {
            return at;
        }
        last = at;
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    panic!("vertex {v} never settled inside the window: last at {last:?}");
}

fn out_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("out");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[tokio::test(flavor = "current_thread")]
async fn dragging_a_vertex_with_the_mouse_moves_it_and_every_condition_still_holds() {
    let driver = Driver::start();
    let studio = StudioProcess::start(&["patterns/miura.fold"]);
    let profile = scratch::Scratch::new("chromium");
    let client = open_page(&driver, &profile, &studio.url).await;
    // The 3D view draws with WebGL (three.js asked the canvas for a WebGL 2 context).
    let webgl = eval(
        &client,
        "const c = document.querySelector('#view3d canvas'); return c.getContext('webgl2') !== null;",
        vec![],
    )
    .await;
    assert_eq!(webgl, json!(true), "the 3D view has a WebGL context");

    let before = page_state(&client).await;
    assert_eq!(before["vertices"], 81);
    assert_eq!(before["pass"], true);
    let v = 40; // the middle of the sheet: an interior vertex
    let (x, y) = settled_screen_of(&client, v).await;
    drag_with_mouse(&client, (x, y), (x, y - 40.0)).await;
    wait_until(
        &client,
        "the drag to end",
        "return window.crease.state().then(s => s.dragging === null && s.settled);",
    )
    .await;
    // The marker rides on the dragged vertex, not where the press began.
    let marker = eval(&client, "return window.crease.markerScreen();", vec![]).await;
    let (vx, vy) = screen_of(&client, v).await;
    let off = (marker["x"].as_f64().unwrap() - vx).hypot(marker["y"].as_f64().unwrap() - vy);
    assert!(off < 3.0, "the marker is {off:.1} px from vertex {v}");
    assert!((vy - y).abs() > 10.0, "vertex {v} moved on screen");
    let after = page_state(&client).await;
    let moved = (0..3)
        .map(|k| (position(&after, v)[k] - position(&before, v)[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(moved > 1.0, "vertex {v} moved only {moved:.3} mm");
    assert_eq!(after["pass"], true, "{}", after["residuals"]);
    assert!(
        after["undo"].as_u64().unwrap() >= 1,
        "the drag can be undone"
    );

    // The saved design passes `crease verify`.
    assert_saved_design_verifies(studio.port);

    // Shift-click pins a vertex (a modifier-click with real key and pointer events).
    let (cx, cy) = settled_screen_of(&client, 0).await;
    shift_click(&client, (cx, cy)).await;
    wait_until(
        &client,
        "vertex 0 to be pinned",
        "return window.crease.state().then(s => s.pinned.includes(0));",
    )
    .await;

    fabricate_and_see_the_preview(&client).await;
    let png = client.screenshot().await.expect("a screenshot");
    std::fs::write(out_dir().join("studio.png"), png).unwrap();
    play_and_export_the_folding_motion(&client, &profile).await;

    fit_to_a_dome_by_pressing_fit(&client, &before).await;
    let png = client.screenshot().await.expect("a screenshot");
    std::fs::write(out_dir().join("studio-fit.png"), png).unwrap();
    a_new_design_starts_clean(&client).await;
    let _ = client.close().await;
}

/// Presses the left button at `from`, moves to `to` over 400 ms, pauses and releases:
/// real pointer events, as a hand on a mouse sends them.
async fn drag_with_mouse(client: &Client, from: (f64, f64), to: (f64, f64)) {
    let press = MouseActions::new("mouse".into())
        .then(PointerAction::MoveTo {
            duration: None,
            x: from.0,
            y: from.1,
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::MoveTo {
            duration: Some(Duration::from_millis(400)),
            x: to.0,
            y: to.1,
        })
        .then(PointerAction::Pause {
            duration: Duration::from_millis(300),
        })
        .then(PointerAction::Up {
            button: MOUSE_BUTTON_LEFT,
        });
    client
        .perform_actions(press)
        .await
        .expect("pointer actions");
}

/// A click at `at` with Shift held (key and pointer events in one action chain).
async fn shift_click(client: &Client, at: (f64, f64)) {
    let keys = KeyActions::new("keyboard".into())
        .then(KeyAction::Down {
            value: Key::Shift.into(),
        })
        .then(KeyAction::Pause {
            duration: Duration::ZERO,
        })
        .then(KeyAction::Pause {
            duration: Duration::ZERO,
        })
        .then(KeyAction::Up {
            value: Key::Shift.into(),
        });
    let click = MouseActions::new("mouse".into())
        .then(PointerAction::MoveTo {
            duration: None,
            x: at.0,
            y: at.1,
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::Up {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::Pause {
            duration: Duration::ZERO,
        });
    client
        .perform_actions(fantoccini::actions::Actions::from(keys).and(click))
        .await
        .expect("shift-click");
}

/// The studio's saved design (`/api/design.fold`) passes `crease verify`.
fn assert_saved_design_verifies(port: u16) {
    let (status, fold) = http(port, "GET", "/api/design.fold", b"");
    assert_eq!(status, 200);
    let file = out_dir().join("studio-dragged.fold");
    std::fs::write(&file, fold).unwrap();
    let verify = Command::new(env!("CARGO_BIN_EXE_crease"))
        .args(["verify", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        verify.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&verify.stdout)
    );
}

/// The page loads a dome as its target (the request the target picker sends), places it
/// under the sheet, and the Fit button is pressed with a real click: the fit runs to its
/// goal and the design still holds every condition.
async fn fit_to_a_dome_by_pressing_fit(client: &Client, before: &Value) {
    // The pin of the Shift-click above would hold a corner off the dome.
    let status = post_from_page(client, "/api/pin", json!({"vertex": 0, "pinned": false})).await;
    assert_eq!(status, json!(200));
    assert_eq!(page_state(client).await["pinned"], json!([]));
    let dome = crease::surface::shapes::Shape::Cap { radius: 250.0 }
        .surface(300.0, 30)
        .unwrap()
        .to_obj("a dome");
    let n = before["vertices"].as_u64().unwrap() as usize;
    let middle: Vec<f64> = (0..3)
        .map(|k| (0..n).map(|v| position(before, v)[k]).sum::<f64>() / n as f64)
        .collect();
    let status = eval(
        client,
        "return fetch('/api/target?name=dome.obj', {method: 'POST', \
         headers: {'Content-Type': 'application/octet-stream'}, body: arguments[0]}) \
         .then(r => r.status);",
        vec![json!(dome)],
    )
    .await;
    assert_eq!(status, json!(200));
    let status = post_from_page(client, "/api/target/place", json!({"shift": middle})).await;
    assert_eq!(status, json!(200));
    wait_until(
        client,
        "the Fit button to be enabled",
        "return !document.getElementById('fit-go').disabled;",
    )
    .await;
    client
        .find(fantoccini::Locator::Id("fit-go"))
        .await
        .expect("the Fit button")
        .click()
        .await
        .expect("a click on Fit");
    wait_until(
        client,
        "the fit to end",
        "return window.crease.state().then(s => s.fit !== null && !s.fit.running);",
    )
    .await;
    let s = page_state(client).await;
    assert!(
        s["fit"]["largest"].as_f64().unwrap() <= s["fit"]["goal"].as_f64().unwrap(),
        "{}",
        s["fit"]
    );
    assert_eq!(s["pass"], true, "{}", s["residuals"]);
    // The page shows the fit's figures.
    let shown = eval(
        client,
        "return document.getElementById('fit-progress').textContent;",
        vec![],
    )
    .await;
    assert!(
        shown.as_str().unwrap().contains("largest distance"),
        "{shown}"
    );
}

/// Fabricate with "fit" ticked (real clicks): the preview is drawn where a maker sees it,
/// strokes covering a visible share of the sheet's pixels.
async fn fabricate_and_see_the_preview(client: &Client) {
    for id in ["fab-fit", "fabricate"] {
        client
            .find(fantoccini::Locator::Id(id))
            .await
            .unwrap_or_else(|e| panic!("#{id}: {e}"))
            .click()
            .await
            .unwrap_or_else(|e| panic!("a click on #{id}: {e}"));
    }
    wait_until(
        client,
        "the preview to load",
        "const i = document.getElementById('fab-preview'); return !!(i && i.complete && i.naturalWidth > 0);",
    )
    .await;
    // Drawn onto a canvas as the page shows it (same origin: the pixels can be read).
    let counts = eval(
        client,
        "const i = document.getElementById('fab-preview'); \
         const c = document.createElement('canvas'); c.width = i.clientWidth; c.height = i.clientHeight; \
         const g = c.getContext('2d'); g.drawImage(i, 0, 0, c.width, c.height); \
         const d = g.getImageData(0, 0, c.width, c.height).data; let sheet = 0, ink = 0; \
         for (let k = 0; k < d.length; k += 4) { if (d[k + 3] < 128) continue; sheet++; \
           if (d[k] < 200 || d[k + 1] < 200 || d[k + 2] < 200) ink++; } \
         return {sheet, ink, width: c.width};",
        vec![],
    )
    .await;
    let (sheet, ink) = (
        counts["sheet"].as_f64().unwrap(),
        counts["ink"].as_f64().unwrap(),
    );
    assert!(counts["width"].as_f64().unwrap() > 200.0, "{counts}");
    assert!(
        ink > 0.02 * sheet,
        "strokes cover {ink} of {sheet} pixels: {counts}"
    );
}

/// The 3D view's pixels as a data URL (the renderer keeps its drawing buffer).
async fn view_pixels(client: &Client) -> String {
    let url = eval(
        client,
        "return document.querySelector('#view3d canvas').toDataURL('image/png');",
        vec![],
    )
    .await;
    url.as_str().unwrap().to_string()
}

/// A real click on the range input `id` at `fraction` of its width from the left.
async fn click_range_at(client: &Client, id: &str, fraction: f64) {
    let slider = client.find(fantoccini::Locator::Id(id)).await.unwrap();
    let width = eval(
        client,
        "return document.getElementById(arguments[0]).getBoundingClientRect().width;",
        vec![json!(id)],
    )
    .await
    .as_f64()
    .unwrap();
    let click = MouseActions::new("mouse".into())
        .then(PointerAction::MoveToElement {
            element: slider,
            duration: Some(Duration::from_millis(50)),
            x: (fraction - 0.5) * (width - 4.0),
            y: 0.0,
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::Up {
            button: MOUSE_BUTTON_LEFT,
        });
    client
        .perform_actions(click)
        .await
        .expect("a click on the slider");
    client.release_actions().await.expect("actions released");
}

/// Issue 49: Play (a real click) folds the design from flat and plays every frame in the
/// 3D view; the slider, clicked at its two ends, shows the flat sheet and the design (two
/// different pictures); Export (a real click) downloads the motion as .glb, which the
/// Khronos glTF validator passes with no error and no warning.
async fn play_and_export_the_folding_motion(client: &Client, profile: &Path) {
    client
        .find(fantoccini::Locator::Id("motion-play"))
        .await
        .unwrap()
        .click()
        .await
        .expect("a click on Play");
    wait_until(
        client,
        "the motion to play to its end",
        "return window.crease.motion().played >= 1;",
    )
    .await;
    let state = eval(client, "return window.crease.motion();", vec![]).await;
    let frames = state["frames"].as_u64().unwrap();
    assert!(frames > 2, "{state}");
    assert_eq!(
        state["shown"].as_u64(),
        Some(frames - 1),
        "played to the end: {state}"
    );
    assert!(
        state["framesDrawn"].as_u64().unwrap() >= frames,
        "every frame drawn: {state}"
    );
    assert_eq!(state["showing"], false, "back to the design: {state}");
    let info = eval(
        client,
        "return document.getElementById('motion-info').textContent;",
        vec![],
    )
    .await;
    assert!(info.as_str().unwrap().contains("path from flat"), "{info}");

    click_range_at(client, "motion-frame", 0.0).await;
    let first = eval(client, "return window.crease.motion();", vec![]).await;
    assert_eq!(first["shown"], 0, "{first}");
    assert_eq!(first["showing"], true, "{first}");
    tokio::time::sleep(Duration::from_millis(200)).await;
    let flat = view_pixels(client).await;
    click_range_at(client, "motion-frame", 1.0).await;
    let last = eval(client, "return window.crease.motion();", vec![]).await;
    assert_eq!(last["shown"].as_u64(), Some(frames - 1), "{last}");
    tokio::time::sleep(Duration::from_millis(200)).await;
    assert_ne!(
        flat,
        view_pixels(client).await,
        "the flat sheet and the design differ on screen"
    );

    let dir = downloads(profile);
    client
        .find(fantoccini::Locator::Id("motion-export"))
        .await
        .unwrap()
        .click()
        .await
        .expect("a click on Export");
    let start = std::time::Instant::now();
    let file = loop {
        let done = std::fs::read_dir(&dir).ok().and_then(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .find(|p| p.extension().is_some_and(|e| e == "glb"))
        });
        if let Some(f) = done {
            break f;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no .glb downloaded into {}",
            dir.display()
        );
        tokio::time::sleep(Duration::from_millis(100)).await;
    };
    let report = js::node("validate-gltf.mjs", &file);
    assert_eq!(report["errors"], 0, "{report}");
    assert_eq!(report["warnings"], 0, "{report}");
    assert_eq!(report["animations"], 1, "{report}");
}

/// Issue 47, item 5: after a fit, simulation mode chosen with a click and New pressed on
/// waterbomb-tube (real clicks), the studio starts clean: no target, no fit, design mode,
/// and the pattern list, read from the new title, shows waterbomb-tube (a prefix match
/// picked waterbomb).
async fn a_new_design_starts_clean(client: &Client) {
    client
        .find(fantoccini::Locator::Css(
            "input[name=mode][value=simulation]",
        ))
        .await
        .expect("the simulation radio")
        .click()
        .await
        .expect("a click on simulation");
    wait_until(
        client,
        "simulation mode",
        "return window.crease.state().then(s => s.mode === 'simulation');",
    )
    .await;
    // And the page has drawn that frame (it sets the pattern list as it does).
    wait_until(
        client,
        "the page to show simulation mode",
        "return document.querySelector('input[name=mode][value=simulation]').checked;",
    )
    .await;
    let s = page_state(client).await;
    assert!(
        !s["target"].is_null(),
        "the dome is still the target before New"
    );
    // The list set without a change event, as the page leaves it when the maker has not
    // picked: the page then names the pattern from the new design's title itself.
    eval(
        client,
        "document.getElementById('pattern').value = 'waterbomb-tube'; return true;",
        vec![],
    )
    .await;
    // A frame arrives before the click, as frames do (the request the mode radio sends
    // publishes one): it must leave the list as it was. It did not, once, in CI: every
    // frame named the list afresh, New sent no pattern and the design never came.
    let applied = eval(client, "return window.crease.framesApplied();", vec![]).await;
    let status = post_from_page(client, "/api/settings", json!({"mode": "simulation"})).await;
    assert_eq!(status, json!(200));
    wait_until(
        client,
        "a frame after the list was set",
        &format!("return window.crease.framesApplied() > {applied};"),
    )
    .await;
    let listed = eval(
        client,
        "return document.getElementById('pattern').value;",
        vec![],
    )
    .await;
    assert_eq!(listed, "waterbomb-tube", "a frame changed the list");
    client
        .find(fantoccini::Locator::Id("generate"))
        .await
        .expect("the New button")
        .click()
        .await
        .expect("a click on New");
    wait_until(
        client,
        "the new design",
        "return window.crease.state().then(s => s.title.startsWith('waterbomb-tube '));",
    )
    .await;
    let s = page_state(client).await;
    assert!(s["target"].is_null(), "{}", s["target"]);
    assert!(s["fit"].is_null(), "{}", s["fit"]);
    assert_eq!(s["mode"], "design");
    wait_until(
        client,
        "the page to show the new state",
        "return document.querySelector('input[name=mode][value=design]').checked \
         && document.getElementById('fit-go').disabled;",
    )
    .await;
    let shown = eval(
        client,
        "return [document.getElementById('pattern').value, \
                 document.getElementById('target-name').textContent];",
        vec![],
    )
    .await;
    assert_eq!(shown[0], "waterbomb-tube", "{shown}");
    assert!(
        shown[1].as_str().unwrap().starts_with("no target"),
        "{shown}"
    );
}
