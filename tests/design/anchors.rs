//! Real crease patterns and FOLD files from other projects (`tests/data`):
//! every one imports, counts match the files, and FOLD/SVG round trips keep the graph.

use crease::io::{self, Format};
use crease::mesh::{edge_key, Assignment, Mesh};
use std::path::PathBuf;

fn anchors_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
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
/// The flat lines crease adds to triangulate a polygon are its own, not the file's, and a
/// polygon may be triangulated along other diagonals after a round trip: they are left out.
fn same_graph(a: &Mesh, b: &Mesh) -> Result<(), String> {
    let listed = |m: &Mesh| -> Vec<(usize, usize, Assignment)> {
        let mut v: Vec<_> = m
            .edges()
            .iter()
            .filter(|e| !e.synthetic)
            .map(|e| {
                let (x, y) = edge_key(e.vertices[0], e.vertices[1]);
                (x, y, e.assignment)
            })
            .collect();
        v.sort();
        v
    };
    let (ea, eb) = (listed(a), listed(b));
    if a.vertex_count() != b.vertex_count() || ea.len() != eb.len() {
        return Err(format!(
            "counts differ: {} v / {} e vs {} v / {} e",
            a.vertex_count(),
            ea.len(),
            b.vertex_count(),
            eb.len()
        ));
    }
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
        assert_eq!(m.crease_pattern(), back.crease_pattern(), "{}", p.display());
        same_graph(&m, &back).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        for (x, y) in m.edges().iter().zip(back.edges()) {
            assert!(
                (x.fold_angle - y.fold_angle).abs() < 1e-12 && (x.target - y.target).abs() < 1e-12
            );
        }
    }
}

/// The lines a drawing shows: crease's own triangulation lines are left out of SVG and
/// `.cp` (reading the drawing back triangulates again, maybe along other diagonals).
fn drawn_edges(m: &Mesh) -> Vec<(String, Assignment)> {
    let f = m.crease_pattern().unwrap();
    let mut out: Vec<(String, Assignment)> = m
        .edges()
        .iter()
        .filter(|e| !e.is_triangulation_line())
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
        if m.crease_pattern().is_none() {
            continue; // folded-only files have no crease pattern to draw
        }
        let text = io::to_string(&m, Format::Svg).unwrap();
        let dir = crate::common::Scratch::new("anchor");
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

/// Coordinates of two FOLD `vertices_coords` arrays agree to 1e-9 of the larger (a 2D
/// point is the 3D point at z = 0: a flat file labelled 3D comes back as the 2D pattern).
fn same_coordinates(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    let flat = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .flat_map(|p| {
                let c = p.as_array().unwrap();
                (0..3).map(move |k| c.get(k).map_or(0.0, |x| x.as_f64().unwrap()))
            })
            .collect()
    };
    let (x, y) = (flat(a), flat(b));
    x.len() == y.len()
        && x.iter()
            .zip(&y)
            .all(|(p, q)| (p - q).abs() <= 1e-9 * p.abs().max(q.abs()).max(1.0))
}

/// A FOLD file's edges: ends in order, assignment, and fold angle (clamped into FOLD's
/// range, to 1e-9°), sorted. A file without angles means each assignment's full fold
/// (M −180°, V 180°, others 0), which crease writes out.
fn edge_set(fold: &serde_json::Value) -> Vec<(u64, u64, String, i64)> {
    let ends = fold["edges_vertices"].as_array().unwrap();
    let mut out: Vec<_> = ends
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let (a, b) = (e[0].as_u64().unwrap(), e[1].as_u64().unwrap());
            let assignment = fold["edges_assignment"][i]
                .as_str()
                .unwrap_or("U")
                .to_string();
            let default = match assignment.as_str() {
                "M" => -180.0,
                "V" => 180.0,
                _ => 0.0,
            };
            let angle = fold["edges_foldAngle"][i].as_f64().unwrap_or(default);
            let angle = (angle.clamp(-180.0, 180.0) * 1e9).round() as i64;
            (a.min(b), a.max(b), assignment, angle)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn converting_a_fold_file_to_fold_keeps_everything_it_had() {
    // Every field of the file comes back: its polygon faces (not crease's triangles), its
    // edges in order with assignments and angles, its unit as given (or none), its
    // metadata and its other fields (faceOrders, vertices_flatUnfoldCoords, …).
    for path in anchor_files() {
        if path.extension().unwrap() != "fold" {
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let text = std::fs::read_to_string(&path).unwrap();
        let original: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mesh = io::read(&path).unwrap();
        let written: serde_json::Value =
            serde_json::from_str(&io::to_string(&mesh, Format::Fold).unwrap()).unwrap();
        for (key, value) in original.as_object().unwrap() {
            let back = &written[key];
            match key.as_str() {
                // crease writes its own; the spec version it writes is 1.1.
                "file_spec" | "file_creator" | "file_classes" | "frame_classes" => {}
                "frame_attributes" => {}
                "vertices_coords" => assert!(same_coordinates(value, back), "{name}: {key}"),
                // Edges as a set of (ends, assignment, angle): an edges-only file has its
                // faces found by crease, which lists the same edges in its own order.
                "edges_vertices" | "edges_assignment" | "edges_foldAngle" => {
                    assert_eq!(edge_set(&original), edge_set(&written), "{name}: {key}");
                }
                "faces_vertices" if value.as_array().unwrap().is_empty() => {}
                _ => assert_eq!(value, back, "{name}: {key}"),
            }
        }
        if original.get("frame_unit").is_none() {
            assert!(
                written.get("frame_unit").is_none(),
                "{name}: a unit was invented"
            );
        }
        // Every angle written is within FOLD's range.
        for a in written["edges_foldAngle"].as_array().unwrap() {
            assert!(a.as_f64().unwrap().abs() <= 180.0, "{name}: {a}");
        }
    }
}

#[test]
fn fold_written_by_crease_is_within_range_and_stable() {
    // Every bundled design and every anchor, written twice through FOLD: the second
    // writing equals the first (nothing drifts), and no angle leaves [−180°, 180°].
    let mut files = anchor_files();
    for entry in
        std::fs::read_dir(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("patterns")).unwrap()
    {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "fold") {
            files.push(p);
        }
    }
    for path in files {
        let first = io::to_string(&io::read(&path).unwrap(), Format::Fold).unwrap();
        let again = io::to_string(&io::fold::parse(&first).unwrap(), Format::Fold).unwrap();
        assert!(first == again, "{}: FOLD output drifts", path.display());
        let json: serde_json::Value = serde_json::from_str(&first).unwrap();
        for a in json["edges_foldAngle"].as_array().unwrap() {
            assert!(
                a.as_f64().unwrap().abs() <= 180.0,
                "{}: {a}",
                path.display()
            );
        }
    }
}
