//! ORIPA `.cp`: one line segment per line, `type x0 y0 x1 y1`, with type 1 cut/boundary,
//! 2 mountain, 3 valley, 0 auxiliary, 4 unassigned.

use super::planar::{mesh_from_segments, Segment};
use super::FileCause;
use crate::mesh::{split_along_cuts, Assignment, Mesh, Vec2};

pub fn parse(text: &str, notes: &mut Vec<String>) -> Result<Mesh, FileCause> {
    let mut segments = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let bad = || {
            format!(
                "line {}: expected \"type x0 y0 x1 y1\", found \"{}\"",
                i + 1,
                crate::limits::short_text(line)
            )
        };
        if fields.len() != 5 {
            return Err(bad().into());
        }
        let Some(assignment) = line_type(fields[0]) else {
            return Err(format!(
                "line {}: unknown line type {} (expected 0–4)",
                i + 1,
                fields[0]
            )
            .into());
        };
        let v: Vec<f64> = fields[1..]
            .iter()
            .map(|f| f.parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(bad)?;
        segments.push(Segment {
            a: Vec2::new(v[0], v[1]),
            b: Vec2::new(v[2], v[3]),
            assignment,
            fold_angle: assignment.default_target(),
        });
    }
    mesh_of_lines(&segments, notes, super::decimal_quantum(text))
}

/// ORIPA's line types, shared by `.cp` and `.opx`: 0 auxiliary (flat), 1 cut/boundary,
/// 2 mountain, 3 valley, 4 unassigned.
pub(super) fn line_type(t: &str) -> Option<Assignment> {
    Some(match t {
        "0" => Assignment::Flat,
        "1" => Assignment::Boundary,
        "2" => Assignment::Mountain,
        "3" => Assignment::Valley,
        "4" => Assignment::Unassigned,
        _ => return None,
    })
}

/// The mesh of ORIPA's drawn lines, its coordinates rounded to ±`precision`.
pub(super) fn mesh_of_lines(
    segments: &[Segment],
    notes: &mut Vec<String>,
    precision: f64,
) -> Result<Mesh, FileCause> {
    let (mut parts, report) = mesh_from_segments(segments)?;
    super::svg_read::report_notes(&report, notes);
    split_along_cuts(&mut parts);
    let mut mesh = Mesh::new(parts)?;
    mesh.coordinate_precision = super::rounding_of(&mesh, precision);
    Ok(mesh)
}

pub fn to_string(mesh: &Mesh) -> Result<String, String> {
    let flat = mesh
        .crease_pattern()
        .ok_or("an ORIPA file needs the flat crease pattern, and this design has none yet")?;
    let mut out = String::new();
    for e in mesh.edges().iter().filter(|e| !e.is_triangulation_line()) {
        let t = match e.assignment {
            Assignment::Boundary | Assignment::Cut => 1,
            Assignment::Mountain => 2,
            Assignment::Valley => 3,
            Assignment::Unassigned => 4,
            Assignment::Flat | Assignment::Join => 0,
        };
        let (a, b) = (flat[e.vertices[0]], flat[e.vertices[1]]);
        out.push_str(&format!("{t} {} {} {} {}\n", a.x, a.y, b.x, b.y));
    }
    Ok(out)
}
