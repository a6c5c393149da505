//! Bad input through the real binary: exit status 2, one line naming the file and the
//! cause, never a panic, and no output file left behind.

mod common;

use common::run_crease;
use std::path::{Path, PathBuf};

fn scratch(name: &str, content: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("crease-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

fn assert_bad_input(path: &Path, cause: &str) {
    let out = path.with_file_name(format!(
        "{}-out.fold",
        path.file_name().unwrap().to_string_lossy()
    ));
    for args in [
        vec!["info", path.to_str().unwrap()],
        vec!["convert", path.to_str().unwrap(), out.to_str().unwrap()],
    ] {
        let (code, _, err) = run_crease(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(
            err.contains(path.file_name().unwrap().to_str().unwrap()),
            "names the file: {err}"
        );
        assert!(err.to_lowercase().contains(cause), "says '{cause}': {err}");
        assert!(!out.exists(), "no output written for bad input");
    }
}

#[test]
fn malformed_json() {
    assert_bad_input(
        &scratch("broken.fold", "{\"vertices_coords\": [[0,0],"),
        "json",
    );
}

#[test]
fn index_out_of_range() {
    let fold = r#"{"vertices_coords": [[0,0],[1,0],[0,1]], "faces_vertices": [[0,1,7]],
                   "edges_vertices": [[0,1],[1,2],[2,0]]}"#;
    assert_bad_input(&scratch("range.fold", fold), "vertex 7");
}

#[test]
fn bad_coincidence_groups() {
    let fold = |groups: &str| {
        format!(
            r#"{{"vertices_coords": [[0,0],[1,0],[0,1]], "faces_vertices": [[0,1,2]],
                 "crease:coincidentVertices": {groups}}}"#
        )
    };
    assert_bad_input(&scratch("group-range.fold", &fold("[[0, 9]]")), "vertex 9");
    assert_bad_input(&scratch("group-one.fold", &fold("[[1]]")), "two or more");
    assert_bad_input(
        &scratch("group-twice.fold", &fold("[[0, 1], [1, 2]]")),
        "twice",
    );
}

#[test]
fn non_manifold_mesh() {
    // Three triangles on one edge (0–1).
    let fold = r#"{"vertices_coords": [[0,0,0],[1,0,0],[0,1,0],[0,-1,0],[0,0,1]],
                   "faces_vertices": [[0,1,2],[1,0,3],[0,1,4]]}"#;
    assert_bad_input(&scratch("fin.fold", fold), "non-manifold");
}

#[test]
fn unknown_svg_stroke_colour() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
        <rect x="0" y="0" width="10" height="10" stroke="#000"/>
        <line x1="0" y1="0" x2="10" y2="10" stroke="#123456"/></svg>"##;
    assert_bad_input(&scratch("colour.svg", svg), "#123456");
}

#[test]
fn empty_files() {
    assert_bad_input(&scratch("empty.fold", ""), "empty");
    assert_bad_input(&scratch("empty.svg", ""), "empty");
    assert_bad_input(&scratch("empty.cp", ""), "no crease");
}

#[test]
fn malformed_cp_line() {
    assert_bad_input(&scratch("bad.cp", "1 0 0 1 1\n2 0 0 x 1\n"), "line 2");
}

#[test]
fn missing_file_and_unknown_extension() {
    let (code, _, err) = run_crease(&["info", "/nonexistent/design.fold"]);
    assert_eq!(code, 2);
    assert!(err.contains("/nonexistent/design.fold"));
    assert_bad_input(&scratch("design.stl", "solid x"), "unknown file type");
}

#[test]
fn info_prints_counts() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let (code, out, _) = run_crease(&["info", p.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(out.contains("vertices:     81"), "{out}");
    assert!(
        out.contains("3D folded form: yes, crease pattern: yes"),
        "{out}"
    );
}
