//! Real crease patterns and FOLD files from other projects (`../shared/anchors/data`):
//! every one imports, counts match the files, and FOLD/SVG round trips keep the graph.

use crease::io::{self, Format};
use crease::mesh::{edge_key, Assignment, Mesh};
use std::path::PathBuf;

fn anchors_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/anchors/data")
}

fn anchor_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for sub in ["fold", "origamisimulator"] {
        for entry in std::fs::read_dir(anchors_dir().join(sub)).expect("anchors present") {
            let p = entry.unwrap().path();
            if matches!(p.extension().and_then(|e| e.to_str()), Some("fold" | "svg")) {
                files.push(p);
            }
        }
    }
    files.sort();
    assert!(
        files.len() >= 20,
        "expected the anchor set, found {}",
        files.len()
    );
    files
}

fn anchor(name: &str) -> Mesh {
    let p = anchor_files()
        .into_iter()
        .find(|p| p.file_name().unwrap() == name)
        .unwrap();
    io::read(&p).unwrap()
}

#[test]
fn every_anchor_file_imports_as_a_valid_mesh() {
    for p in anchor_files() {
        let m = io::read(&p).unwrap_or_else(|e| panic!("{e}"));
        assert!(m.faces().len() >= 2, "{}", p.display());
        assert!(
            m.edges().iter().any(|e| e.assignment.is_folded()),
            "{} has creases",
            p.display()
        );
    }
}

#[test]
fn counts_match_the_files() {
    let info = anchor("BoxPleatPyramid.fold").info();
    assert_eq!(info.vertices, 2704);
    assert_eq!(info.source_edges, 5304);
    // 2601 quads, each split in two by one added flat crease.
    assert_eq!(info.added_edges, 2601);
    assert_eq!(info.triangles, 2 * 2601);
    assert!(info.topology.is_disk);

    let info = anchor("box.fold").info();
    assert_eq!((info.vertices, info.source_edges), (39, 80));
    assert!(info.has_3d && !info.has_crease_pattern);

    // Waterbomb base: square, two mountain diagonals, two valley midlines at 90°.
    let m = anchor("waterbombBase.svg");
    let info = m.info();
    assert_eq!(
        (info.vertices, info.interior_vertices, info.triangles),
        (9, 1, 8)
    );
    let count = |a: Assignment| m.edges().iter().filter(|e| e.assignment == a).count();
    assert_eq!(
        (
            count(Assignment::Mountain),
            count(Assignment::Valley),
            count(Assignment::Boundary)
        ),
        (4, 4, 8)
    );
    for e in m
        .edges()
        .iter()
        .filter(|e| e.assignment == Assignment::Valley)
    {
        assert!(
            (e.fold_angle + std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "opacity 0.5 → −90°"
        );
    }

    // Kirigami: the cuts open holes in the paper.
    let t = anchor("honeycombKiri.svg").info().topology;
    assert!(t.holes > 0 && !t.is_disk);
}

#[test]
fn svg_units_become_millimetres() {
    // waterbombBase.svg: a 2016 px square at 96 px per inch.
    let info = anchor("waterbombBase.svg").info();
    let [w, h] = info.size_flat.unwrap();
    assert!((w - 2016.0 * 25.4 / 96.0).abs() < 1e-9 && (h - w).abs() < 1e-9);
}

/// Compares two meshes' crease graphs, vertices matched by index (FOLD keeps their order).
fn same_graph(a: &Mesh, b: &Mesh) -> Result<(), String> {
    if a.vertex_count() != b.vertex_count() || a.edges().len() != b.edges().len() {
        return Err(format!(
            "counts differ: {} v / {} e vs {} v / {} e",
            a.vertex_count(),
            a.edges().len(),
            b.vertex_count(),
            b.edges().len()
        ));
    }
    let map: Vec<usize> = (0..a.vertex_count()).collect();
    let mut ea: Vec<(usize, usize, Assignment)> = a
        .edges()
        .iter()
        .map(|e| {
            let (x, y) = edge_key(map[e.vertices[0]], map[e.vertices[1]]);
            (x, y, e.assignment)
        })
        .collect();
    let mut eb: Vec<(usize, usize, Assignment)> = b
        .edges()
        .iter()
        .map(|e| {
            let (x, y) = e.key();
            (x, y, e.assignment)
        })
        .collect();
    ea.sort();
    eb.sort();
    if ea != eb {
        return Err("edges or assignments differ".into());
    }
    Ok(())
}

#[test]
fn fold_round_trip_keeps_vertices_edges_and_assignments() {
    for p in anchor_files() {
        let m = io::read(&p).unwrap();
        let text = io::to_string(&m, Format::Fold).unwrap();
        let back = io::fold::parse(&text).unwrap();
        // FOLD keeps vertex order, so positions must agree exactly.
        assert_eq!(m.positions(), back.positions(), "{}", p.display());
        assert_eq!(m.flat(), back.flat(), "{}", p.display());
        same_graph(&m, &back).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        for (x, y) in m.edges().iter().zip(back.edges()) {
            assert!(
                (x.fold_angle - y.fold_angle).abs() < 1e-12 && (x.target - y.target).abs() < 1e-12
            );
        }
    }
}

fn drawn_edges(m: &Mesh) -> Vec<(String, Assignment)> {
    let f = m.flat().unwrap();
    let mut out: Vec<(String, Assignment)> = m
        .edges()
        .iter()
        .map(|e| {
            let mut ends = e.vertices.map(|v| format!("{:.4},{:.4}", f[v].x, f[v].y));
            ends.sort();
            (ends.join(" "), e.assignment)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn svg_round_trip_keeps_the_crease_graph() {
    for p in anchor_files() {
        let m = io::read(&p).unwrap();
        if m.flat().is_none() {
            continue; // folded-only files have no crease pattern to draw
        }
        let text = io::to_string(&m, Format::Svg).unwrap();
        let dir = std::env::temp_dir().join(format!("crease-anchor-{}", std::process::id()));
        let out = dir.join(p.with_extension("svg").file_name().unwrap());
        io::write_atomic(&out, text.as_bytes()).unwrap();
        let back = io::read(&out).unwrap();
        // Compare as drawn: kirigami meshes hold two vertices at each point of a cut,
        // which a drawing cannot tell apart, so edges are matched by their end points.
        assert_eq!(m.vertex_count(), back.vertex_count(), "{}", p.display());
        let (before, after) = (drawn_edges(&m), drawn_edges(&back));
        let lost: Vec<_> = before
            .iter()
            .filter(|e| !after.contains(e))
            .take(3)
            .collect();
        let gained: Vec<_> = after
            .iter()
            .filter(|e| !before.contains(e))
            .take(3)
            .collect();
        assert!(
            before == after,
            "{}: lost {lost:?}, gained {gained:?}",
            p.display()
        );
    }
}
