//! crease — design freeform variations of origami (Tachi 2010) and fabricate them.
//!
//! Data flows one way: [`mesh`] → constraints → solver → fabrication → output → plotter.
#![warn(missing_docs)]

pub mod allocator;
pub mod constraints;
pub mod fab;
pub mod fit;
pub mod generate;
pub mod geometry;
pub mod io;
pub mod limits;
pub mod machine;
pub mod mesh;
pub mod output;
pub mod pipeline;
pub mod plotter;
pub mod random;
pub mod solver;
pub mod studio;
pub mod surface;
pub mod tolerance;

#[cfg(test)]
mod architecture {
    //! The import graph drawn from the files' own `crate::` and `super::` paths, in `use`
    //! lines and written inline (comments and `#[cfg(test)]` items left out, wherever in
    //! the file they sit): no two files of the library
    //! may import each other, directly or round a loop (ARCHITECTURE.md).

    use std::collections::{BTreeMap, BTreeSet};
    use std::path::Path;

    /// Module path of a source file: `src/fab/layers/mod.rs` → `fab::layers`.
    fn module_of(rel: &Path) -> Vec<String> {
        let mut parts: Vec<String> = rel
            .with_extension("")
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .collect();
        if matches!(
            parts.last().map(String::as_str),
            Some("mod" | "lib" | "main")
        ) {
            parts.pop();
        }
        parts
    }

    fn sources(dir: &Path, root: &Path, out: &mut BTreeMap<Vec<String>, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                sources(&path, root, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                out.insert(
                    module_of(path.strip_prefix(root).unwrap()),
                    without_test_items(&text),
                );
            }
        }
    }

    /// `text` without its `#[cfg(test)]` items (a `mod tests;` line, or an item up to the
    /// brace that closes it): the code before and after each is read, not just the
    /// code before the first (a test module in mid-file once hid what followed it).
    /// Braces inside string and character literals and comments are not counted.
    fn without_test_items(text: &str) -> String {
        let mut kept = String::new();
        let mut rest = text;
        while let Some(at) = rest.find("#[cfg(test)]") {
            kept.push_str(&rest[..at]);
            rest = &rest[at + "#[cfg(test)]".len()..];
            rest = &rest[item_end(rest)..];
        }
        kept.push_str(rest);
        kept
    }

    /// Where the item at the start of `code` ends: after its `;` when that comes before
    /// any brace, else after the brace that closes its first one.
    fn item_end(code: &str) -> usize {
        let bytes = code.as_bytes();
        let (mut depth, mut i) = (0usize, 0usize);
        while i < bytes.len() {
            match bytes[i] {
                b'/' if bytes.get(i + 1) == Some(&b'/') => {
                    i = code[i..].find('\n').map_or(bytes.len(), |k| i + k);
                    continue;
                }
                b'"' => {
                    i += 1;
                    while i < bytes.len() && bytes[i] != b'"' {
                        i += if bytes[i] == b'\\' { 2 } else { 1 };
                    }
                }
                // A character literal ('{', '\''); a lifetime ('a) has no closing quote.
                b'\'' if bytes.get(i + 2) == Some(&b'\'') => i += 2,
                b'\'' if bytes.get(i + 1) == Some(&b'\\') => {
                    i += code[i + 2..].find('\'').map_or(bytes.len(), |k| k + 2);
                }
                b';' if depth == 0 => return i + 1,
                b'{' => depth += 1,
                b'}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        return i + 1;
                    }
                }
                _ => {}
            }
            i += 1;
        }
        bytes.len()
    }

    #[test]
    fn test_items_are_left_out_and_the_code_after_them_is_read() {
        let text = "use crate::a;\n#[cfg(test)]\nmod tests;\nuse crate::b;\n\
                    #[cfg(test)]\nmod inline {\n    use crate::c;\n    fn f() -> char { '}' }\n    \
                    const S: &str = \"}}\";\n    // }\n    fn g<'a>(x: &'a str) -> &'a str { x }\n}\n\
                    fn h() { crate::d::run() }\n";
        let kept = without_test_items(text);
        for (path, read) in [("crate::a", true), ("crate::b", true), ("crate::c", false)] {
            assert_eq!(kept.contains(path), read, "{path}: {kept}");
        }
        assert!(kept.contains("crate::d::run"), "{kept}");
        assert!(!kept.contains("fn g"), "{kept}");
    }

    /// Every `crate::…` or `super::…` path on a line of code (in a `use` or written out
    /// inline, as `super::angles::FoldAngles::new`).
    fn paths_in(line: &str) -> Vec<&str> {
        let mut found = Vec::new();
        for start in ["crate::", "super::"] {
            for (i, _) in line.match_indices(start) {
                let before = line[..i].chars().next_back();
                if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                    continue;
                }
                let end = line[i..]
                    .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                    .map_or(line.len(), |k| i + k);
                found.push(&line[i..end]);
            }
        }
        found
    }

    /// Each file's references to other files (`use` lines and paths written inline),
    /// resolved to the longest module path named.
    fn graph() -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = BTreeMap::new();
        sources(&root, &root, &mut files);
        let mut edges = BTreeMap::new();
        for (me, text) in &files {
            let mut deps = BTreeSet::new();
            let code = text
                .lines()
                .map(str::trim_start)
                .filter(|l| !l.starts_with("//"));
            for line in code {
                for path in paths_in(line) {
                    let mut segments = path.split("::").filter(|s| !s.is_empty());
                    let mut full: Vec<String> = match segments.next() {
                        Some("crate") => Vec::new(),
                        Some("super") => me[..me.len().saturating_sub(1)].to_vec(),
                        _ => continue,
                    };
                    for s in segments {
                        if s == "super" {
                            full.pop();
                        } else {
                            full.push(s.to_string());
                        }
                    }
                    while !full.is_empty() {
                        if files.contains_key(&full) {
                            if &full != me {
                                deps.insert(full.clone());
                            }
                            break;
                        }
                        full.pop();
                    }
                }
            }
            edges.insert(me.clone(), deps);
        }
        edges
    }

    #[test]
    fn no_file_of_the_library_imports_another_that_imports_it_back() {
        let edges = graph();
        assert!(edges.len() > 100, "read {} files", edges.len());
        // Every file reachable from each file; a loop is a file reaching itself.
        let mut loops = Vec::new();
        for start in edges.keys() {
            let mut seen = BTreeSet::new();
            let mut stack: Vec<&Vec<String>> = edges[start].iter().collect();
            while let Some(m) = stack.pop() {
                if m == start {
                    loops.push(start.join("::"));
                    break;
                }
                if seen.insert(m) {
                    stack.extend(edges.get(m).into_iter().flatten());
                }
            }
        }
        assert!(loops.is_empty(), "files in an import cycle: {loops:?}");
    }

    /// The library's top-level modules by layer, lowest first (ARCHITECTURE.md, "Layers"):
    /// a module may use only modules of lower layers; modules of one layer do not use
    /// each other.
    const LAYERS: [&[&str]; 12] = [
        &["limits", "allocator", "tolerance", "random"],
        &["mesh"],
        &["geometry", "surface"],
        &["generate", "io"],
        &["constraints"],
        &["solver", "fab"],
        &["fit", "output"],
        &["machine"],
        &["plotter"],
        &["pipeline"],
        &["studio"],
        // The binary's files (and lib.rs, which only declares the modules).
        &["cli", "main", "lib"],
    ];

    #[test]
    fn no_module_imports_one_of_its_own_layer_or_above() {
        let layer = |m: &str| LAYERS.iter().position(|l| l.contains(&m));
        let mut against = Vec::new();
        for (file, deps) in graph() {
            let Some(from) = file.first() else { continue };
            let from_layer = layer(from).unwrap_or_else(|| panic!("{from} has no layer"));
            for dep in deps {
                let to = &dep[0];
                if to == from {
                    continue;
                }
                let to_layer = layer(to).unwrap_or_else(|| panic!("{to} has no layer"));
                if to_layer >= from_layer {
                    against.push(format!("{} uses {}", file.join("::"), dep.join("::")));
                }
            }
        }
        assert!(
            against.is_empty(),
            "imports against the layers: {against:#?}"
        );
    }

    /// `fab`'s two halves (ARCHITECTURE.md): what judges a design and what lays it out
    /// and cuts it. They share the module but not code: the pipeline composes them.
    const FAB_VERIFICATION: [&str; 8] = [
        "verify",
        "assign",
        "budget",
        "flat_fold",
        "intersect",
        "layers",
        "precision",
        "rounding",
    ];
    const FAB_FABRICATION: [&str; 13] = [
        "advice",
        "clearance",
        "curve",
        "glue_tab",
        "hinge",
        "labels",
        "layout",
        "lines",
        "print_and_cut",
        "registration",
        "route",
        "score",
        "toolpath",
    ];

    /// Which half of `fab` a submodule is in: 0 verification, 1 fabrication.
    fn fab_half(module: &str) -> usize {
        if FAB_VERIFICATION.contains(&module) {
            0
        } else if FAB_FABRICATION.contains(&module) {
            1
        } else {
            panic!("fab::{module} is in neither half (FAB_VERIFICATION, FAB_FABRICATION)")
        }
    }

    #[test]
    fn fabs_verification_and_fabrication_halves_do_not_use_each_other() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = BTreeMap::new();
        sources(&root, &root, &mut files);
        // What fab/mod.rs re-exports, by item: `crate::fab::Budget` is budget's.
        let mod_rs = &files[&vec!["fab".to_string()]];
        let mut owner: BTreeMap<&str, &str> = BTreeMap::new();
        for statement in mod_rs.split(';') {
            let Some(rest) = statement.trim().strip_prefix("pub use ") else {
                continue;
            };
            let (module, items) = rest.split_once("::").expect("pub use module::items");
            for item in items.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                if !item.is_empty() {
                    owner.insert(item, module);
                }
            }
        }
        let mut crossings = Vec::new();
        let mut checked = 0;
        for (file, deps) in graph() {
            if file.len() < 2 || file[0] != "fab" {
                continue;
            }
            let half = fab_half(&file[1]);
            checked += 1;
            let mut used: Vec<String> = deps
                .iter()
                .filter(|d| d.len() >= 2 && d[0] == "fab")
                .map(|d| d[1].clone())
                .collect();
            // Items named through the re-exports: `crate::fab::X`, and `super::X` from
            // a file directly in fab/.
            let text = &files[&file];
            let mut prefixes = vec!["crate::fab::"];
            if file.len() == 2 {
                prefixes.push("super::");
            }
            for prefix in prefixes {
                for (i, _) in text.match_indices(prefix) {
                    let rest = &text[i + prefix.len()..];
                    let names = match rest.strip_prefix('{') {
                        Some(list) => &list[..list.find('}').unwrap_or(list.len())],
                        None => rest,
                    };
                    for name in names.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                        if let Some(module) = owner.get(name) {
                            used.push(module.to_string());
                        }
                        if names.as_ptr() == rest.as_ptr() {
                            break; // a single path: only its first segment
                        }
                    }
                }
            }
            for module in used {
                if fab_half(&module) != half {
                    crossings.push(format!("{} uses fab::{module}", file.join("::")));
                }
            }
        }
        assert!(checked > 20, "only {checked} fab files read");
        crossings.sort();
        crossings.dedup();
        assert!(
            crossings.is_empty(),
            "fab's halves use each other: {crossings:#?}"
        );
    }

    #[test]
    fn the_graph_reader_sees_a_known_import() {
        let edges = graph();
        let score = vec!["fab".to_string(), "score".to_string()];
        let toolpath = vec!["fab".to_string(), "toolpath".to_string()];
        assert!(edges[&score].contains(&toolpath), "{:?}", edges[&score]);
    }
}
