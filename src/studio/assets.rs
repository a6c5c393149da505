//! The page's files, embedded in the binary (one `include_bytes!` per file, rerun's
//! habit) so `crease studio` needs nothing beside it. `--assets DIR` serves files from DIR
//! first, so the page can be edited without rebuilding.
//!
//! three.js is vendored under `assets/vendor/three/` at version 0.187.0 (MIT, its LICENSE
//! beside it); `docs/studio.md` says how to update it.

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
    ("fit.js", include_bytes!("assets/fit.js")),
    ("motion.js", include_bytes!("assets/motion.js")),
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
        Some("glb") => "model/gltf-binary",
        _ => "text/plain; charset=utf-8",
    }
}

/// The file at a URL path (`/` is the page): one of the page's own files, from `dir`
/// when it has it (development), else embedded. A request names only which of those
/// files it wants; no other path is ever opened.
pub fn lookup(path: &str, dir: Option<&PathBuf>) -> Option<(&'static str, Vec<u8>)> {
    let name = path.trim_start_matches('/');
    let name = if name.is_empty() { "index.html" } else { name };
    let &(name, embedded) = FILES.iter().find(|(n, _)| *n == name)?;
    let bytes = dir
        .and_then(|d| std::fs::read(d.join(name)).ok())
        .unwrap_or_else(|| embedded.to_vec());
    Some((content_type(name), bytes))
}

/// The page's import map, the one inline script it has (three.js is imported by name).
fn import_map() -> &'static str {
    let page = std::str::from_utf8(FILES[0].1).expect("index.html is UTF-8");
    let open = r#"<script type="importmap">"#;
    let start = page.find(open).expect("the page has an import map") + open.len();
    let len = page[start..]
        .find("</script>")
        .expect("the import map ends");
    &page[start..start + len]
}

/// The `Content-Security-Policy` of every reply: scripts, styles, images and requests
/// only from the studio itself (plus the page's import map, by its SHA-256), no plugin,
/// no base or form target elsewhere, and no page may frame the studio.
pub fn policy() -> &'static str {
    use base64::Engine;
    use sha2::Digest;
    static POLICY: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    POLICY.get_or_init(|| {
        let digest = sha2::Sha256::digest(import_map().as_bytes());
        let hash = base64::engine::general_purpose::STANDARD.encode(digest);
        format!(
            "default-src 'self'; script-src 'self' 'sha256-{hash}'; object-src 'none'; \
             base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
        )
    })
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

    #[test]
    fn a_development_folder_serves_only_the_pages_own_files() {
        let dir = std::env::temp_dir().join(format!("crease-assets-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("studio.css"), "body{}").unwrap();
        std::fs::write(dir.join("secret.txt"), "precious").unwrap();
        let served = lookup("/studio.css", Some(&dir))
            .expect("the page's own file")
            .1;
        assert_eq!(served, b"body{}");
        assert!(lookup("/secret.txt", Some(&dir)).is_none());
        assert!(lookup("/../secret.txt", Some(&dir)).is_none());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_policy_admits_the_import_map_by_its_hash_and_nothing_inline_else() {
        let page = String::from_utf8(lookup("/", None).unwrap().1).unwrap();
        // One inline script (the import map); no inline style attribute or handler.
        assert_eq!(page.matches("<script").count(), 2);
        assert!(!page.contains("style=") && !page.contains(" onclick="));
        let p = policy();
        assert!(p.starts_with("default-src 'self'") && p.contains("frame-ancestors 'none'"));
        // SHA-256 in base64 is 44 characters ending in '='.
        let hash = p
            .split("'sha256-")
            .nth(1)
            .unwrap()
            .split('\'')
            .next()
            .unwrap();
        assert_eq!(hash.len(), 44);
        assert!(hash.ends_with('='));
        assert!(import_map().contains("three.module.js"));
    }
}
