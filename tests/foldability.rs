//! Foldability verdicts a maker can trust (issue #15): Maekawa judged where a vertex folds
//! flat as drawn, tolerances bounded by what the file's rounding can really explain.

mod common;

use common::run_crease;
use std::path::PathBuf;

fn scratch(name: &str, content: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("crease-foldability-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// A 2 × 2 square with four creases from its centre (vertex 8) to the side midpoints:
/// every sector is 90°, so Kawasaki holds for any assignment; `assignments` gives the
/// creases to the midpoints of the bottom, right, top and left sides, and `degrees` the
/// fold angle every crease is drawn at.
fn four_crease_vertex(assignments: [&str; 4], degrees: f64) -> String {
    let sign = |a: &str| if a == "V" { degrees } else { -degrees };
    format!(
        r#"{{"file_spec": 1.1, "frame_classes": ["creasePattern"],
 "vertices_coords": [[0,0],[1,0],[2,0],[2,1],[2,2],[1,2],[0,2],[0,1],[1,1]],
 "edges_vertices": [[0,1],[1,2],[2,3],[3,4],[4,5],[5,6],[6,7],[7,0],[8,1],[8,3],[8,5],[8,7]],
 "edges_assignment": ["B","B","B","B","B","B","B","B","{}","{}","{}","{}"],
 "edges_foldAngle": [0,0,0,0,0,0,0,0,{},{},{},{}],
 "faces_vertices": [[8,7,0,1],[8,1,2,3],[8,3,4,5],[8,5,6,7]]}}"#,
        assignments[0],
        assignments[1],
        assignments[2],
        assignments[3],
        sign(assignments[0]),
        sign(assignments[1]),
        sign(assignments[2]),
        sign(assignments[3]),
    )
}

#[test]
fn two_mountains_and_two_valleys_at_a_flat_vertex_fail_on_maekawa() {
    let bad = scratch(
        "2m2v.fold",
        &four_crease_vertex(["M", "V", "M", "V"], 180.0),
    );
    let (code, out, err) = run_crease(&["verify", bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.contains("verdict: FAIL — maekawa at vertex 8"), "{out}");
    // Kawasaki holds there: the failure is Maekawa's alone.
    let (_, json, _) = run_crease(&["verify", bad.to_str().unwrap(), "--json"]);
    let report: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(report["families"]["flat-foldability"]["violations"], 0);
    assert_eq!(report["families"]["maekawa"]["violations"], 1);
    assert_eq!(report["families"]["maekawa"]["judged"], true);

    // Three mountains and one valley: |M − V| = 2, the vertex folds flat.
    let good = scratch(
        "3m1v.fold",
        &four_crease_vertex(["M", "V", "M", "M"], 180.0),
    );
    let (code, out, err) = run_crease(&["verify", good.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");

    // The same 2M + 2V drawn at 90°: a partial fold claims nothing about folding flat, so
    // it is reported, not judged.
    let partial = scratch(
        "2m2v-90.fold",
        &four_crease_vertex(["M", "V", "M", "V"], 90.0),
    );
    let (code, json, err) = run_crease(&["verify", partial.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{json}{err}");
    let report: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(report["families"]["maekawa-partial"]["violations"], 1);
    assert_eq!(report["families"]["maekawa-partial"]["judged"], false);
}
