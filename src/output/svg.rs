//! The scored sheet as SVG at 1:1 (mm), one Inkscape layer per line kind, every dash a real
//! segment: what a cutting plotter's own software would cut.

use crate::fab::{LineKind, Toolpath};
use svg::node::element::{Group, Line, Rectangle};
use svg::Document;

/// Stroke colour per kind on the sheet.
fn colour(kind: LineKind) -> &'static str {
    match kind {
        LineKind::Cut => "#000000",
        LineKind::Mountain => "#ff0000",
        LineKind::Valley => "#0000ff",
        LineKind::Flat => "#c0c0c0",
    }
}

/// Writes the toolpath on its media.
pub fn sheet_to_string(path: &Toolpath) -> String {
    let (w, h) = (path.media.width, path.media.height);
    let mut doc = Document::new()
        .set(
            "xmlns:inkscape",
            "http://www.inkscape.org/namespaces/inkscape",
        )
        .set("width", format!("{w}mm"))
        .set("height", format!("{h}mm"))
        .set("viewBox", format!("0 0 {w} {h}"));
    // The media outline, on its own hidden-from-cutting layer for orientation.
    doc = doc.add(
        Group::new()
            .set("inkscape:groupmode", "layer")
            .set("inkscape:label", "media")
            .set("id", "media")
            .add(
                Rectangle::new()
                    .set("x", 0)
                    .set("y", 0)
                    .set("width", w)
                    .set("height", h)
                    .set("fill", "none")
                    .set("stroke", "#dddddd")
                    .set("stroke-width", 0.1),
            ),
    );
    for kind in LineKind::ALL {
        let mut layer = Group::new()
            .set("inkscape:groupmode", "layer")
            .set("inkscape:label", kind.name())
            .set("id", kind.name())
            .set("stroke", colour(kind))
            .set("stroke-width", 0.2)
            .set("stroke-linecap", "butt")
            .set("fill", "none");
        let mut any = false;
        for s in path.strokes.iter().filter(|s| s.kind == kind) {
            layer = layer.add(
                Line::new()
                    .set("x1", s.from.x)
                    .set("y1", h - s.from.y)
                    .set("x2", s.to.x)
                    .set("y2", h - s.to.y),
            );
            any = true;
        }
        if any {
            doc = doc.add(layer);
        }
    }
    doc.to_string() + "\n"
}
