//! The front door stays true: the README is short, names every generator, machine and
//! material the binary knows, and every file it or the guide links to exists.

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The stems of the `.toml` files in `dir`.
fn profiles(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn the_readme_is_short_and_names_every_generator_machine_and_material() {
    let readme = read(&root().join("README.md"));
    let lines = readme.lines().count();
    assert!(lines <= 200, "README.md has {lines} lines");
    let mut missing = Vec::new();
    for kind in crease::generate::PatternKind::ALL {
        if !readme.contains(&format!("`{}`", kind.name())) {
            missing.push(format!("generator {}", kind.name()));
        }
    }
    let machines = profiles(&root().join("machines"));
    let materials = profiles(&root().join("materials"));
    assert!(machines.len() >= 7 && materials.len() >= 4);
    for name in machines.iter().chain(&materials) {
        if !readme.contains(&format!("`{name}`")) {
            missing.push(format!("profile {name}"));
        }
    }
    assert!(missing.is_empty(), "README.md does not name: {missing:?}");
}

/// Relative links (`](path)`) in the README, ARCHITECTURE.md and docs/ point at files
/// that exist.
#[test]
fn every_relative_link_of_the_docs_exists() {
    let mut pages: Vec<PathBuf> = vec![root().join("README.md"), root().join("ARCHITECTURE.md")];
    pages.extend(
        std::fs::read_dir(root().join("docs"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "md")),
    );
    assert!(pages.len() >= 7, "{pages:?}");
    let mut broken = Vec::new();
    let mut links = 0;
    for page in &pages {
        let text = read(page);
        for (i, _) in text.match_indices("](") {
            let rest = &text[i + 2..];
            let target = &rest[..rest.find(')').unwrap_or(0)];
            if target.is_empty() || target.contains("://") || target.starts_with('#') {
                continue;
            }
            links += 1;
            let file = target.split('#').next().unwrap();
            if !page.parent().unwrap().join(file).exists() {
                broken.push(format!("{}: {target}", page.display()));
            }
        }
    }
    assert!(links >= 10, "{links} links");
    assert!(broken.is_empty(), "{broken:?}");
}
