//! `crease studio`: start the local design app, print its address, open a browser, serve
//! until Ctrl-C.

use crease::studio::{Session, Studio, StudioOptions};
use std::io::Write;
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex};

#[derive(clap::Args)]
pub struct StudioArgs {
    /// Pattern file to start from (.fold, .cp, .opx, .svg, .obj); default a generated Miura-ori.
    file: Option<PathBuf>,
    /// Port on 127.0.0.1 (default: a free one).
    #[arg(long)]
    port: Option<u16>,
    /// Do not open a browser.
    #[arg(long)]
    no_open: bool,
    /// Serve the page's files from this folder before the embedded ones (for editing
    /// the page without rebuilding). Default: only the embedded ones.
    #[arg(long, value_name = "DIR")]
    assets: Option<PathBuf>,
}

pub fn studio(args: StudioArgs) -> Result<u8, String> {
    let (mesh, title) = match &args.file {
        Some(path) => {
            let imported = crease::io::read_with_notes(path).map_err(|e| e.to_string())?;
            for note in &imported.notes {
                eprintln!("note: {note}");
            }
            let stem = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "design".into());
            (imported.mesh, stem)
        }
        None => (Session::default_design(), "miura".to_string()),
    };
    if let Some(dir) = &args.assets {
        if !dir.is_dir() {
            return Err(format!("--assets {}: not a folder", dir.display()));
        }
    }
    // Ctrl-C wakes the main thread, which drops the studio: the server stops accepting,
    // the session thread ends, and the process exits 0.
    let stop = Arc::new((Mutex::new(false), Condvar::new()));
    {
        let stop = Arc::clone(&stop);
        ctrlc::set_handler(move || {
            *stop.0.lock().expect("stop lock") = true;
            stop.1.notify_all();
        })
        .map_err(|e| format!("cannot catch Ctrl-C: {e}"))?;
    }
    let options = StudioOptions {
        port: args.port.unwrap_or(0),
        assets: args.assets.clone(),
    };
    let studio = Studio::start(mesh, &title, options).map_err(|e| e.to_string())?;
    {
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "studio: {}", studio.url());
        let _ = out.flush();
    }
    eprintln!("serving {title}; press Ctrl-C to stop");
    if !args.no_open {
        open_browser(studio.url());
    }
    let mut stopped = stop.0.lock().expect("stop lock");
    while !*stopped {
        stopped = stop.1.wait(stopped).expect("stop lock");
    }
    drop(studio);
    eprintln!("studio: stopped");
    Ok(0)
}

/// Opens the system browser; failing to is a note, not an error.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    let spawned = std::process::Command::new(opener)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if spawned.is_err() {
        eprintln!("note: could not open a browser ({opener} failed); open {url} yourself");
    }
}
