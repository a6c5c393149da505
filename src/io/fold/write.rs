//! Writing FOLD 1.1: the 3D form in frame 0, the crease pattern in a `creasePattern`
//! frame, crease's own fields (`crease:targetAngle`, `crease:alpha`, …) beside FOLD's.

use super::angle_to_fold;
use crate::mesh::{Edge, Mesh};
use std::fmt::Write as _;

/// Serialises a mesh as FOLD 1.1 text. Deterministic: the same mesh gives the same bytes.
pub fn to_string(mesh: &Mesh) -> String {
    let num = |x: f64| {
        let x = if x == 0.0 { 0.0 } else { x };
        serde_json::to_string(&x).expect("finite number")
    };
    let list = |items: Vec<String>| -> String {
        if items.is_empty() {
            return "[]".into();
        }
        format!("[\n    {}\n  ]", items.join(",\n    "))
    };
    let mut out = String::from("{\n");
    let mut field = |name: &str, value: String| {
        let _ = writeln!(out, "  \"{name}\": {value},");
    };
    field("file_spec", "1.1".into());
    field("file_creator", "\"crease\"".into());
    field("file_classes", "[\"singleModel\"]".into());
    if !mesh.title.is_empty() {
        field("frame_title", serde_json::to_string(&mesh.title).unwrap());
    }
    let (class, attr) = if mesh.has_3d() {
        ("foldedForm", "3D")
    } else {
        ("creasePattern", "2D")
    };
    field("frame_classes", format!("[\"{class}\"]"));
    field("frame_attributes", format!("[\"{attr}\"]"));
    field("frame_unit", "\"mm\"".into());
    let coords: Vec<String> = if mesh.has_3d() {
        mesh.positions()
            .iter()
            .map(|p| format!("[{}, {}, {}]", num(p.x), num(p.y), num(p.z)))
            .collect()
    } else {
        mesh.flat()
            .expect("a mesh without 3D data has a crease pattern")
            .iter()
            .map(|p| format!("[{}, {}]", num(p.x), num(p.y)))
            .collect()
    };
    field("vertices_coords", list(coords));
    let edges = mesh.edges();
    field(
        "edges_vertices",
        list(
            edges
                .iter()
                .map(|e| format!("[{}, {}]", e.vertices[0], e.vertices[1]))
                .collect(),
        ),
    );
    field(
        "edges_assignment",
        format!(
            "[{}]",
            edges
                .iter()
                .map(|e| format!("\"{}\"", e.assignment.fold_letter()))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    );
    let angles = |f: &dyn Fn(&Edge) -> f64| {
        format!(
            "[{}]",
            edges
                .iter()
                .map(|e| num(angle_to_fold(f(e))))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    field("edges_foldAngle", angles(&|e| e.fold_angle));
    field("crease:targetAngle", angles(&|e| e.target));
    field(
        "crease:alpha",
        format!(
            "[{}]",
            edges
                .iter()
                .map(|e| num(e.alpha))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    );
    if mesh.lock_topology {
        field("crease:lockTopology", "true".into());
    }
    if !mesh.coincident.is_empty() {
        field(
            "crease:coincidentVertices",
            list(
                mesh.coincident
                    .iter()
                    .map(|g| {
                        let ids: Vec<String> = g.iter().map(|v| v.to_string()).collect();
                        format!("[{}]", ids.join(", "))
                    })
                    .collect(),
            ),
        );
    }
    field(
        "faces_vertices",
        list(
            mesh.faces()
                .iter()
                .map(|f| format!("[{}, {}, {}]", f[0], f[1], f[2]))
                .collect(),
        ),
    );
    let frames = match (mesh.has_3d(), mesh.flat()) {
        (true, Some(flat)) => format!(
            "[\n    {{\n      \"frame_classes\": [\"creasePattern\"],\n      \"frame_attributes\": [\"2D\"],\n      \"frame_inherit\": true,\n      \"frame_parent\": 0,\n      \"vertices_coords\": [\n        {}\n      ]\n    }}\n  ]",
            flat.iter()
                .map(|p| format!("[{}, {}]", num(p.x), num(p.y)))
                .collect::<Vec<_>>()
                .join(",\n        ")
        ),
        _ => "[]".into(),
    };
    let _ = write!(out, "  \"file_frames\": {frames}\n}}\n");
    out
}
