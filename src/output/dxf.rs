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
    let mut out = Pairs(String::new());
    header(&mut out, toolpath);
    layer_table(&mut out, toolpath);
    entities(&mut out, toolpath);
    out.pair(0, "EOF");
    out.0
}

/// DXF text: each group code on its line, right-aligned in three columns, then its value.
struct Pairs(String);

impl Pairs {
    fn pair(&mut self, code: u16, value: &str) {
        let _ = writeln!(self.0, "{code:>3}\n{value}");
    }
}

/// The header: R12, millimetres, the media's extent.
fn header(out: &mut Pairs, toolpath: &Toolpath) {
    out.pair(0, "SECTION");
    out.pair(2, "HEADER");
    out.pair(9, "$ACADVER");
    out.pair(1, "AC1009");
    out.pair(9, "$INSUNITS");
    out.pair(70, "4"); // millimetres
    out.pair(9, "$EXTMIN");
    out.pair(10, "0.0");
    out.pair(20, "0.0");
    out.pair(9, "$EXTMAX");
    out.pair(10, &num(toolpath.media.width));
    out.pair(20, &num(toolpath.media.height));
    out.pair(0, "ENDSEC");
}

/// The layer table: a layer for each kind of stroke the toolpath has, in its colour.
fn layer_table(out: &mut Pairs, toolpath: &Toolpath) {
    out.pair(0, "SECTION");
    out.pair(2, "TABLES");
    out.pair(0, "TABLE");
    out.pair(2, "LAYER");
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
    out.pair(70, &kinds.len().to_string());
    for kind in kinds {
        let (name, colour) = layer_of(kind);
        out.pair(0, "LAYER");
        out.pair(2, name);
        out.pair(70, "0");
        out.pair(62, &colour.to_string());
        out.pair(6, "CONTINUOUS");
    }
    out.pair(0, "ENDTAB");
    out.pair(0, "ENDSEC");
}

/// The entities: a LINE for each straight stroke, a POLYLINE for each dash of a curve.
fn entities(out: &mut Pairs, toolpath: &Toolpath) {
    out.pair(0, "SECTION");
    out.pair(2, "ENTITIES");
    for s in &toolpath.strokes {
        let (layer, _) = layer_of(s.kind);
        if s.bend.is_some() {
            // A dash of a curved crease: an R12 POLYLINE through its chords (LWPOLYLINE
            // and SPLINE came later, and R12 readers skip them).
            out.pair(0, "POLYLINE");
            out.pair(8, layer);
            out.pair(66, "1");
            out.pair(10, "0.0");
            out.pair(20, "0.0");
            out.pair(30, "0.0");
            out.pair(70, "0");
            for p in s.polyline() {
                out.pair(0, "VERTEX");
                out.pair(8, layer);
                out.pair(10, &num(p.x));
                out.pair(20, &num(p.y));
                out.pair(30, "0.0");
            }
            out.pair(0, "SEQEND");
            out.pair(8, layer);
            continue;
        }
        out.pair(0, "LINE");
        out.pair(8, layer);
        out.pair(10, &num(s.from.x));
        out.pair(20, &num(s.from.y));
        out.pair(30, "0.0");
        out.pair(11, &num(s.to.x));
        out.pair(21, &num(s.to.y));
        out.pair(31, "0.0");
    }
    out.pair(0, "ENDSEC");
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
