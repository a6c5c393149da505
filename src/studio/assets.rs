//! The page's files, embedded in the binary (one `include_bytes!` per file, rerun's
//! habit) so `crease studio` needs nothing beside it. `--assets DIR` serves files from DIR
//! first, so the page can be edited without rebuilding.
//!
//! three.js is vendored under `assets/vendor/three/` at version 0.187.0 (MIT, its LICENSE
//! beside it); the README says how to update it.

use std::path::{Path, PathBuf};

/// The vendored three.js version.
pub const THREE_VERSION: &str = "0.187.0";

const FILES: &[(&str, &[u8])] = &[
    ("index.html", include_bytes!("assets/index.html")),
    ("studio.css", include_bytes!("assets/studio.css")),
    ("studio.js", include_bytes!("assets/studio.js")),
    ("view3d.js", include_bytes!("assets/view3d.js")),
    ("panes.js", include_bytes!("assets/panes.js")),
    ("panel.js", include_bytes!("assets/panel.js")),
    (
        "vendor/three/three.module.js",
        include_bytes!("assets/vendor/three/three.module.js"),
    ),
    (
        "vendor/three/three.core.js",
        include_bytes!("assets/vendor/three/three.core.js"),
    ),
    (
        "vendor/three/OrbitControls.js",
        include_bytes!("assets/vendor/three/OrbitControls.js"),
    ),
    (
        "vendor/three/LICENSE",
        include_bytes!("assets/vendor/three/LICENSE"),
    ),
];

/// The content type for a file name, by extension.
pub fn content_type(name: &str) -> &'static str {
    match Path::new(name).extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js") => "text/javascript; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("svg") => "image/svg+xml",
        Some("pdf") => "application/pdf",
        Some("json") | Some("fold") => "application/json",
        Some("png") => "image/png",
        _ => "text/plain; charset=utf-8",
    }
}

/// The file at a URL path (`/` is the page), from `dir` when it has it, else embedded.
pub fn lookup(path: &str, dir: Option<&PathBuf>) -> Option<(&'static str, Vec<u8>)> {
    let name = path.trim_start_matches('/');
    let name = if name.is_empty() { "index.html" } else { name };
    if name.split('/').any(|part| part == ".." || part.is_empty()) {
        return None;
    }
    if let Some(bytes) = dir.and_then(|d| std::fs::read(d.join(name)).ok()) {
        return Some((content_type(name), bytes));
    }
    FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(n, b)| (content_type(n), b.to_vec()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_and_three_js_are_embedded_and_paths_cannot_climb_out() {
        let (ty, page) = lookup("/", None).expect("the page");
        assert!(ty.starts_with("text/html"));
        assert!(String::from_utf8(page).unwrap().contains("studio.js"));
        let (_, three) = lookup("/vendor/three/three.module.js", None).expect("three.js");
        assert!(three.len() > 100_000);
        let core = lookup("/vendor/three/three.core.js", None)
            .expect("three core")
            .1;
        let core = String::from_utf8(core).unwrap();
        assert!(core.contains(&format!("REVISION = '{}'", &THREE_VERSION[2..5])));
        assert!(lookup("/../Cargo.toml", None).is_none());
        assert!(lookup("/nothing.js", None).is_none());
    }
}
