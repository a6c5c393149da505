//! Writing FOLD 1.1: the 3D form in frame 0, the crease pattern in a `creasePattern`
//! frame, crease's own fields (`crease:targetAngle`, `crease:alpha`, …) beside FOLD's.
//!
//! A mesh read from a file gives back what the file had ([`SourceRecord`]): its
//! descriptive fields, its unit, its polygon faces (the flat creases crease added to
//! triangulate them are left out again while they lie flat) and, while the geometry is
//! unchanged, its other fields such as `faceOrders`.

use super::source::SourceRecord;
use super::{angle_to_fold, unit_scale};
use crate::mesh::{polygon_faces, Assignment, Mesh};
use crate::tolerance::FLAT_POLYGON_RADIANS;
use std::fmt::Write as _;

/// How far edge `e` may fold and still lie flat: [`FLAT_POLYGON_RADIANS`] plus the rounding
/// bound of its dihedral angle (each edge of its two faces turns by up to 2√3·p/ℓ when
/// coordinates are rounded to ±p, as verify's bound).
fn flat_tolerance(mesh: &Mesh, e: usize) -> f64 {
    let p = mesh.coordinate_precision;
    if p <= 0.0 {
        return FLAT_POLYGON_RADIANS;
    }
    let topo = mesh.topology();
    let x = mesh.positions();
    let turn: f64 = topo.edge_faces[e]
        .iter()
        .flatten()
        .flat_map(|&f| topo.face_edges[f])
        .map(|k| {
            let [a, b] = mesh.edges()[k].vertices;
            2.0 * 3f64.sqrt() * p / (x[b] - x[a]).norm()
        })
        .sum();
    FLAT_POLYGON_RADIANS + turn
}

/// Serialises a mesh as FOLD 1.1 text. Deterministic: the same mesh gives the same bytes.
pub fn to_string(mesh: &Mesh) -> String {
    to_string_with_orders(mesh, None)
}

/// [`to_string`], with a layer order of the mesh's faces (triangles, as
/// [`crate::fab::layer_order`] gives them) written as FOLD `faceOrders` of the faces the
/// file lists: triangles merged into one polygon share their order, so each pair of
/// written faces takes its first triangle pair's.
///
/// A tube is written as its strip with `crease:seam` (see `io::fold::seam`).
pub fn to_string_with_orders(mesh: &Mesh, orders: Option<&[[i64; 3]]>) -> String {
    match super::seam::strip_for_writing(mesh) {
        Some((strip, seam)) => write(&strip, orders, Some(seam), None),
        None => write(mesh, orders, None, None),
    }
}

/// A design as the tools that read only frame 0 open it (Origami Simulator, Rabbit Ear,
/// ORIPA, which refuses a frame 0 not classed `creasePattern`): frame 0 the crease
/// pattern, the 3D form in the frame after it. crease reads both orders. A design without
/// a crease pattern is written as [`to_string`] writes it.
pub fn to_string_crease_pattern_first(mesh: &Mesh) -> String {
    if mesh.crease_pattern().is_none() || !mesh.has_3d() {
        return to_string(mesh);
    }
    match super::seam::strip_for_writing(mesh) {
        Some((strip, seam)) => {
            let states = [strip.positions().to_vec()];
            write(&strip, None, Some(seam), Some(&states))
        }
        None => write(mesh, None, None, Some(&[mesh.positions().to_vec()])),
    }
}

/// A folding motion as a multi-frame FOLD: frame 0 the sheet's crease pattern, then each
/// of `states` (every vertex's 3D position, mm) as a `foldedForm` frame inheriting the
/// edges and faces from frame 0 (FOLD's `frame_inherit`), as ORIPA writes its folded
/// states.
pub fn motion_to_string(sheet: &Mesh, states: &[Vec<crate::mesh::Vec3>]) -> String {
    write(sheet, None, None, Some(states))
}

/// Writes `mesh`; with `states`, frame 0 is its crease pattern and the states follow it
/// (else frame 0 is its 3D form when it has one and the crease pattern follows).
fn write(
    mesh: &Mesh,
    orders: Option<&[[i64; 3]]>,
    seam: Option<Vec<String>>,
    states: Option<&[Vec<crate::mesh::Vec3>]>,
) -> String {
    let source = SourceRecord::of(mesh);
    let mut w = Fields(String::from("{\n"));
    let scale = write_frame(&mut w, mesh, source, states.is_some());
    let faces = Faces::of(mesh);
    write_edges(&mut w, mesh, &faces);
    if mesh.lock_topology {
        w.field("crease:lockTopology", "true".into());
    }
    if let Some(seam) = seam {
        w.field("crease:seam", list(seam));
    }
    if mesh.coordinate_precision > 0.0 {
        // The rounding of the file the mesh came from (half its last decimal place), in
        // this file's unit: the numbers written here are exact, and without it a
        // converted file would lose the allowance verification gives the original.
        w.field(
            "crease:coordinatePrecision",
            format!("{:?}", mesh.coordinate_precision / scale),
        );
    }
    if !mesh.coincident.is_empty() {
        let groups = mesh.coincident.iter().map(|g| id_list(g)).collect();
        w.field("crease:coincidentVertices", list(groups));
    }
    let polygons = faces.polygons.iter().map(|p| id_list(p)).collect();
    w.field("faces_vertices", list(polygons));
    if let Some(orders) = orders {
        let mut seen = std::collections::HashSet::new();
        let written: Vec<String> = orders
            .iter()
            .filter_map(|&[f, g, s]| {
                let (p, q) = (faces.polygon_of[f as usize], faces.polygon_of[g as usize]);
                (p != q && seen.insert((p.min(q), p.max(q)))).then(|| format!("[{p}, {q}, {s}]"))
            })
            .collect();
        w.field("faceOrders", list(written));
    }
    if let Some(s) = source.filter(|s| faces.as_in_source && s.describes(mesh)) {
        for (name, value) in &s.extras {
            if orders.is_some() && name == "faceOrders" {
                continue;
            }
            w.field(name, serde_json::to_string(value).expect("JSON value"));
        }
    }
    let frames = match (states, mesh.has_3d(), mesh.crease_pattern()) {
        (Some(states), _, _) => {
            let frames: Vec<String> = states.iter().map(|x| state_frame(x, scale)).collect();
            format!("[\n    {}\n  ]", frames.join(",\n    "))
        }
        (None, true, Some(flat)) => format!(
            "[\n    {{\n      \"frame_classes\": [\"creasePattern\"],\n      \"frame_attributes\": [\"2D\"],\n      \"frame_inherit\": true,\n      \"frame_parent\": 0,\n      \"vertices_coords\": [\n        {}\n      ]\n    }}\n  ]",
            flat.iter()
                .map(|p| format!("[{}, {}]", num(p.x / scale), num(p.y / scale)))
                .collect::<Vec<_>>()
                .join(",\n        ")
        ),
        _ => "[]".into(),
    };
    let mut out = w.0;
    let _ = write!(out, "  \"file_frames\": {frames}\n}}\n");
    out
}

/// A 3D state as a frame inheriting everything else from frame 0.
fn state_frame(x: &[crate::mesh::Vec3], scale: f64) -> String {
    let coords = coords_3d(x, scale);
    format!(
        "{{\n      \"frame_classes\": [\"foldedForm\"],\n      \"frame_attributes\": [\"3D\"],\n      \"frame_inherit\": true,\n      \"frame_parent\": 0,\n      \"vertices_coords\": [\n        {}\n      ]\n    }}",
        coords.join(",\n        ")
    )
}

/// Each point as a JSON `[x, y, z]` in the file's unit (`scale` mm).
fn coords_3d(x: &[crate::mesh::Vec3], scale: f64) -> Vec<String> {
    x.iter()
        .map(|p| {
            format!(
                "[{}, {}, {}]",
                num(p.x / scale),
                num(p.y / scale),
                num(p.z / scale)
            )
        })
        .collect()
}

/// The top-level fields of a FOLD object being written, one per line.
struct Fields(String);

impl Fields {
    fn field(&mut self, name: &str, value: String) {
        // A key copied from the input may hold any character: written as JSON writes it.
        let key = serde_json::to_string(name).expect("a string is JSON");
        let _ = writeln!(self.0, "  {key}: {value},");
    }
}

/// A number as JSON, with no negative zero.
fn num(x: f64) -> String {
    let x = if x == 0.0 { 0.0 } else { x };
    serde_json::to_string(&x).expect("finite number")
}

/// A JSON array of `items`, one per line.
fn list(items: Vec<String>) -> String {
    if items.is_empty() {
        return "[]".into();
    }
    format!("[\n    {}\n  ]", items.join(",\n    "))
}

/// A JSON array of indices on one line.
fn id_list(ids: &[usize]) -> String {
    let ids: Vec<String> = ids.iter().map(|v| v.to_string()).collect();
    format!("[{}]", ids.join(", "))
}

/// The file's description, frame 0's classes and unit, and the vertices in that unit;
/// returns the unit in millimetres. An unchanged mesh keeps the file's own frame
/// description and coordinates. With `crease_pattern`, frame 0 is the crease pattern
/// whatever else the mesh has.
fn write_frame(
    w: &mut Fields,
    mesh: &Mesh,
    source: Option<&SourceRecord>,
    crease_pattern: bool,
) -> f64 {
    let as_3d = mesh.has_3d() && !crease_pattern;
    w.field("file_spec", "1.1".into());
    w.field("file_creator", "\"crease\"".into());
    w.field("file_classes", "[\"singleModel\"]".into());
    for (name, value) in source.iter().flat_map(|s| &s.metadata) {
        w.field(name, serde_json::to_string(value).expect("JSON value"));
    }
    if !mesh.title.is_empty() {
        w.field("frame_title", serde_json::to_string(&mesh.title).unwrap());
    }
    let (class, attr) = if as_3d {
        ("foldedForm", "3D")
    } else {
        ("creasePattern", "2D")
    };
    let verbatim = source.filter(|s| s.describes(mesh) && !s.frame.is_empty() && !crease_pattern);
    let given = |name: &str| {
        verbatim
            .and_then(|s| s.frame.iter().find(|(n, _)| n == name))
            .map(|(_, v)| serde_json::to_string(v).expect("JSON value"))
    };
    w.field(
        "frame_classes",
        given("frame_classes").unwrap_or(format!("[\"{class}\"]")),
    );
    w.field(
        "frame_attributes",
        given("frame_attributes").unwrap_or(format!("[\"{attr}\"]")),
    );
    // Millimetres inside; a file's own unit (or none) is given back as it was.
    let unit = match source {
        Some(s) => s.unit.clone(),
        None => Some("mm".to_string()),
    };
    if let Some(u) = &unit {
        w.field("frame_unit", serde_json::to_string(u).unwrap());
    }
    let scale = unit_scale(unit.as_deref()).unwrap_or(1.0);
    let coords: Vec<String> = if as_3d {
        coords_3d(mesh.positions(), scale)
    } else {
        mesh.crease_pattern()
            .expect("a mesh without 3D data has a crease pattern")
            .iter()
            .map(|p| format!("[{}, {}]", num(p.x / scale), num(p.y / scale)))
            .collect()
    };
    // The file's coordinates when they say something ours do not (other axes or
    // dimension); ours, in crease's layout, when they are the same numbers.
    let ours = format!("[{}]", coords.join(","));
    let same = |text: &str| {
        serde_json::from_str::<serde_json::Value>(text).ok()
            == serde_json::from_str::<serde_json::Value>(&ours).ok()
    };
    match given("vertices_coords").filter(|t| !same(t)) {
        Some(text) => w.field("vertices_coords", text),
        None => w.field("vertices_coords", list(coords)),
    }
    scale
}

/// The edges the file keeps (synthetic flat ones inside a written polygon are left out):
/// their vertices, assignments, fold angles (FOLD's degrees, valley positive), targets
/// and twist allowances.
fn write_edges(w: &mut Fields, mesh: &Mesh, faces: &Faces) {
    let edges: Vec<usize> = (0..mesh.edges().len())
        .filter(|&e| faces.keeps_edge(mesh, e))
        .collect();
    let per_edge = |value: &dyn Fn(usize) -> String| {
        format!(
            "[{}]",
            edges
                .iter()
                .map(|&e| value(e))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let ends = edges
        .iter()
        .map(|&e| {
            let [a, b] = mesh.edges()[e].vertices;
            format!("[{a}, {b}]")
        })
        .collect();
    w.field("edges_vertices", list(ends));
    w.field(
        "edges_assignment",
        per_edge(&|e| format!("\"{}\"", mesh.edges()[e].assignment.fold_letter())),
    );
    // FOLD's range is [−180°, 180°], and lines that do not fold carry 0 (twist of a
    // facet line is in the coordinates, and its allowance in crease:alpha).
    w.field(
        "edges_foldAngle",
        per_edge(&|e| {
            let edge = &mesh.edges()[e];
            let degrees = match edge.assignment {
                Assignment::Mountain | Assignment::Valley | Assignment::Unassigned => {
                    angle_to_fold(edge.fold_angle).clamp(-180.0, 180.0)
                }
                _ => 0.0,
            };
            num(degrees)
        }),
    );
    w.field(
        "crease:targetAngle",
        per_edge(&|e| num(angle_to_fold(mesh.edges()[e].target))),
    );
    w.field("crease:alpha", per_edge(&|e| num(mesh.edges()[e].alpha)));
    // FOLD has no curved edges (fold#15): a curved crease stays its chords, and which
    // edges form one curve, in order along it, is said here (derived on every write, so
    // never stale).
    if let Some(flat) = mesh.crease_pattern() {
        let index: std::collections::HashMap<usize, usize> =
            edges.iter().enumerate().map(|(i, &e)| (e, i)).collect();
        let curves: Vec<String> = crate::mesh::curve_runs(mesh, flat)
            .iter()
            .filter_map(|run| {
                let along: Option<Vec<usize>> = crate::mesh::run_edges(mesh, run)
                    .iter()
                    .map(|e| index.get(e).copied())
                    .collect();
                along.map(|a| id_list(&a))
            })
            .collect();
        if !curves.is_empty() {
            w.field("crease:curves", list(curves));
        }
    }
}

/// The faces written: polygons merged back across flat synthetic edges.
struct Faces {
    polygons: Vec<Vec<usize>>,
    /// Per mesh face, the polygon it belongs to.
    polygon_of: Vec<usize>,
    /// The polygons are exactly the source file's, in its order and vertex order.
    as_in_source: bool,
}

impl Faces {
    fn of(mesh: &Mesh) -> Faces {
        let fold = if mesh.has_3d() {
            crate::geometry::fold_angles(mesh)
        } else {
            vec![0.0; mesh.edges().len()]
        };
        let merged = polygon_faces(mesh, &fold, |e| flat_tolerance(mesh, e));
        let mut polygon_of = vec![0; mesh.faces().len()];
        for (k, (_, group)) in merged.iter().enumerate() {
            for &f in group {
                polygon_of[f] = k;
            }
        }
        let mut polygons: Vec<Vec<usize>> = merged.into_iter().map(|(p, _)| p).collect();
        // Give back the file's own vertex order where the polygon is the file's.
        let source = SourceRecord::of(mesh).map(|s| &s.polygons);
        let mut as_in_source = source.is_some_and(|s| s.len() == polygons.len());
        if let Some(src) = source.filter(|_| as_in_source) {
            for (p, s) in polygons.iter_mut().zip(src) {
                if same_cycle(p, s) {
                    p.clone_from(s);
                } else {
                    as_in_source = false;
                }
            }
        }
        Faces {
            polygons,
            polygon_of,
            as_in_source,
        }
    }

    /// An edge is written unless it is a synthetic edge inside one written polygon.
    fn keeps_edge(&self, mesh: &Mesh, e: usize) -> bool {
        if !mesh.edges()[e].synthetic {
            return true;
        }
        match mesh.topology().edge_faces[e] {
            [Some(a), Some(b)] => self.polygon_of[a] != self.polygon_of[b],
            _ => true,
        }
    }
}

/// The same cyclic sequence of vertices, in either direction.
fn same_cycle(a: &[usize], b: &[usize]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let Some(start) = b.iter().position(|&v| v == a[0]) else {
        return false;
    };
    let n = a.len();
    let forward = (0..n).all(|k| a[k] == b[(start + k) % n]);
    let backward = (0..n).all(|k| a[k] == b[(start + n - k) % n]);
    forward || backward
}
