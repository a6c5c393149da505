//! Writes a crease pattern as SVG in Origami Simulator's colour convention, in millimetres,
//! so it re-imports (here or in Origami Simulator) to the same graph.

use crate::mesh::{Assignment, Mesh};
use std::f64::consts::PI;
use svg::node::element::{Group, Line};
use svg::Document;

/// Stroke colour of each crease type (REFERENCE.md).
pub fn colour_of(assignment: Assignment) -> &'static str {
    match assignment {
        Assignment::Boundary => "#000000",
        Assignment::Mountain => "#ff0000",
        Assignment::Valley => "#0000ff",
        Assignment::Cut => "#00ff00",
        Assignment::Flat | Assignment::Join => "#ffff00",
        Assignment::Unassigned => "#ff00ff",
    }
}

const MARGIN_MM: f64 = 5.0;

pub fn to_string(mesh: &Mesh) -> Result<String, String> {
    let flat = mesh
        .crease_pattern()
        .ok_or("an SVG crease pattern needs the flat layout, and this design has none yet")?;
    // SVG's y runs down: the top of the drawing is the pattern's largest y.
    let (lo, hi) = crate::mesh::bounds(flat);
    let (x0, y0) = (lo.x - MARGIN_MM, -hi.y - MARGIN_MM);
    let (w, h) = (hi.x - lo.x + 2.0 * MARGIN_MM, hi.y - lo.y + 2.0 * MARGIN_MM);
    let mut doc = Document::new()
        .set("width", format!("{w}mm"))
        .set("height", format!("{h}mm"))
        .set("viewBox", format!("{x0} {y0} {w} {h}"));
    let order = [
        Assignment::Flat,
        Assignment::Join,
        Assignment::Unassigned,
        Assignment::Valley,
        Assignment::Mountain,
        Assignment::Cut,
        Assignment::Boundary,
    ];
    for kind in order {
        let mut group = Group::new()
            .set("id", format!("crease-{}", kind.fold_letter()))
            .set("stroke", colour_of(kind))
            .set("stroke-width", 0.25)
            .set("fill", "none");
        let mut any = false;
        for e in mesh
            .edges()
            .iter()
            .filter(|e| e.assignment == kind && !e.is_triangulation_line())
        {
            let (a, b) = (flat[e.vertices[0]], flat[e.vertices[1]]);
            let mut line = Line::new()
                .set("x1", a.x)
                .set("y1", -a.y)
                .set("x2", b.x)
                .set("y2", -b.y);
            if kind.is_folded() {
                let opacity = (e.fold_angle.abs() / PI).min(1.0);
                if opacity != 1.0 {
                    line = line.set("opacity", opacity);
                }
            }
            group = group.add(line);
            any = true;
        }
        if any {
            doc = doc.add(group);
        }
    }
    Ok(doc.to_string() + "\n")
}
