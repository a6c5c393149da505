//! DXF for laser cutters and CAD: AutoCAD R12 ASCII, the dialect every program reads.
//! Millimetres, one LINE entity per stroke of the toolpath (a dash is its own segment:
//! laser software draws a dashed line style solid; a dash of a curved crease is a
//! POLYLINE through chords within 0.005 mm of its curve), on a layer per operation (CUT,
//! MOUNTAIN, VALLEY, FLAT; only those the sheet has) in the colour every file gives it
//! ([`super::colour`]), so each operation gets its own power and speed.

use crate::fab::{LineKind, Toolpath};
use std::fmt::Write as _;

/// Layer name and AutoCAD colour index of a stroke kind.
pub fn layer_of(kind: LineKind) -> (&'static str, u8) {
    let name = match kind {
        LineKind::Cut => "CUT",
        LineKind::Mountain => "MOUNTAIN",
        LineKind::Valley => "VALLEY",
        LineKind::Flat => "FLAT",
    };
    (name, super::colour::aci(kind))
}

/// The toolpath as DXF R12 text. The toolpath's y grows upward from the media's lower
/// edge, as DXF's does (and HP-GL's and the PDF's), so coordinates go across unchanged.
pub fn to_string(toolpath: &Toolpath) -> String {
    let mut out = String::new();
    let mut pair = |code: u16, value: &str| {
        let _ = writeln!(out, "{code:>3}\n{value}");
    };
    pair(0, "SECTION");
    pair(2, "HEADER");
    pair(9, "$ACADVER");
    pair(1, "AC1009");
    pair(9, "$INSUNITS");
    pair(70, "4"); // millimetres
    pair(9, "$EXTMIN");
    pair(10, "0.0");
    pair(20, "0.0");
    pair(9, "$EXTMAX");
    pair(10, &num(toolpath.media.width));
    pair(20, &num(toolpath.media.height));
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "TABLES");
    pair(0, "TABLE");
    pair(2, "LAYER");
    // No empty layer: laser software lists each as an operation to set up.
    let kinds: Vec<LineKind> = [
        LineKind::Cut,
        LineKind::Mountain,
        LineKind::Valley,
        LineKind::Flat,
    ]
    .into_iter()
    .filter(|&k| toolpath.strokes.iter().any(|s| s.kind == k))
    .collect();
    pair(70, &kinds.len().to_string());
    for kind in kinds {
        let (name, colour) = layer_of(kind);
        pair(0, "LAYER");
        pair(2, name);
        pair(70, "0");
        pair(62, &colour.to_string());
        pair(6, "CONTINUOUS");
    }
    pair(0, "ENDTAB");
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    for s in &toolpath.strokes {
        let (layer, _) = layer_of(s.kind);
        if s.bend.is_some() {
            // A dash of a curved crease: an R12 POLYLINE through its chords (LWPOLYLINE
            // and SPLINE came later, and R12 readers skip them).
            pair(0, "POLYLINE");
            pair(8, layer);
            pair(66, "1");
            pair(10, "0.0");
            pair(20, "0.0");
            pair(30, "0.0");
            pair(70, "0");
            for p in s.polyline() {
                pair(0, "VERTEX");
                pair(8, layer);
                pair(10, &num(p.x));
                pair(20, &num(p.y));
                pair(30, "0.0");
            }
            pair(0, "SEQEND");
            pair(8, layer);
            continue;
        }
        pair(0, "LINE");
        pair(8, layer);
        pair(10, &num(s.from.x));
        pair(20, &num(s.from.y));
        pair(30, "0.0");
        pair(11, &num(s.to.x));
        pair(21, &num(s.to.y));
        pair(31, "0.0");
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    out
}

/// Micrometre resolution, no exponent (R12 readers expect plain decimals).
fn num(x: f64) -> String {
    let s = format!("{x:.4}");
    if s == "-0.0000" {
        "0.0000".into()
    } else {
        s
    }
}
