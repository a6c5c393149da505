//! The scored sheet as SVG at 1:1 (mm), what a cutter's or laser's own software takes:
//! nothing but what is cut or scored (no media frame: it would be cut), one Inkscape
//! layer and one colour per operation, hairline strokes, the outline as one closed path
//! and each crease's dashes as one path element (every dash a real segment: laser
//! software draws a dashed stroke style solid).

use crate::fab::{LineKind, Stroke, Toolpath};
use crate::mesh::Vec2;
use std::collections::HashMap;
use std::fmt::Write as _;
use svg::node::element::{Group, Path};
use svg::Document;

/// A hairline: 0.001 in, what Epilog and Universal laser drivers take as "cut this
/// vector" and thin enough that no cutter software reads it as an area.
const HAIRLINE_MM: f64 = 0.0254;

/// How `sheet.svg` groups its strokes into layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layers {
    /// One layer per line kind (cut, mountain, valley, flat), for laser and cutter
    /// software that assigns an operation per colour or layer.
    ByKind,
    /// One layer per operation, named as Cricut Design Space names them: "Cut" (the
    /// outline) and "Score" (every crease, mountains red and valleys blue within it).
    ByOperation,
}

impl Layers {
    /// Layer labels and the kinds each holds.
    fn groups(self) -> Vec<(&'static str, Vec<LineKind>)> {
        match self {
            Layers::ByKind => LineKind::ALL.iter().map(|&k| (k.name(), vec![k])).collect(),
            Layers::ByOperation => vec![
                (
                    "Score",
                    vec![LineKind::Valley, LineKind::Mountain, LineKind::Flat],
                ),
                ("Cut", vec![LineKind::Cut]),
            ],
        }
    }
}

/// Writes the toolpath on its media.
pub fn sheet_to_string(path: &Toolpath, layers: Layers) -> String {
    with_layers(page(path), path, HAIRLINE_MM, layers).to_string() + "\n"
}

/// A Cricut Print Then Cut file: a "Print" layer (the paper's face in `fill`, if given,
/// and every crease line whole, in its colour, as the printer draws it) under the "Score"
/// and "Cut" layers of [`Layers::ByOperation`], all in one frame, so Design Space keeps
/// them in register once they are attached.
pub fn print_then_cut_to_string(
    path: &Toolpath,
    sheet: &crate::fab::Sheet,
    faces: &[[usize; 3]],
    fill: Option<[u8; 3]>,
) -> String {
    let h = path.media.height;
    let xy = |p: Vec2| format!("{} {}", round(p.x), round(h - p.y));
    let mut print = Group::new()
        .set("inkscape:groupmode", "layer")
        .set("inkscape:label", "Print")
        .set("id", "Print")
        .set("stroke-width", PRINTED_LINE_MM)
        .set("stroke-linecap", "round");
    if let Some([r, g, b]) = fill {
        let mut d = String::new();
        for f in faces {
            let [a, b2, c] = f.map(|i| sheet.vertices[i]);
            let _ = write!(d, "M{} L{} L{} Z ", xy(a), xy(b2), xy(c));
        }
        print = print.add(
            Path::new()
                .set("d", d.trim_end())
                .set("fill", format!("#{r:02x}{g:02x}{b:02x}"))
                .set("stroke", "none"),
        );
    }
    for kind in LineKind::ALL {
        let mut d = String::new();
        for l in sheet.lines.iter().filter(|l| l.kind == kind) {
            let _ = write!(d, "M{} ", xy(l.a));
            match &l.curve {
                Some(curve) => {
                    for c in curve.pieces() {
                        let _ = write!(d, "C{} {} {} ", xy(c.c1), xy(c.c2), xy(c.p3));
                    }
                }
                None => {
                    let _ = write!(d, "L{} ", xy(l.b));
                }
            }
        }
        if !d.is_empty() {
            print = print.add(
                Path::new()
                    .set("d", d.trim_end())
                    .set("fill", "none")
                    .set("stroke", super::colour::hex(kind))
                    .set("class", kind.name()),
            );
        }
    }
    with_layers(
        page(path).add(print),
        path,
        HAIRLINE_MM,
        Layers::ByOperation,
    )
    .to_string()
        + "\n"
}

/// Width of a printed crease line, mm: visible on paper, thinner than a dash's kerf.
const PRINTED_LINE_MM: f64 = 0.3;

/// An empty page the size of the toolpath's media, in mm, declaring Inkscape's layers.
fn page(path: &Toolpath) -> Document {
    // 12 in is 304.79999999999995 mm in floating point: written as 304.8.
    let (w, h) = (round(path.media.width), round(path.media.height));
    Document::new()
        .set(
            "xmlns:inkscape",
            "http://www.inkscape.org/namespaces/inkscape",
        )
        .set("width", format!("{w}mm"))
        .set("height", format!("{h}mm"))
        .set("viewBox", format!("0 0 {w} {h}"))
}

/// The toolpath as a picture for a screen: the media drawn as a white sheet with a grey
/// edge, and every stroke in its kind's colour at a width that shows when the whole
/// sheet fits a panel a few hundred pixels wide (1/300 of the media's longer side). Not a
/// job: `sheet.svg` is what a cutter takes.
pub fn preview_to_string(path: &Toolpath) -> String {
    let (w, h) = (path.media.width, path.media.height);
    let stroke = w.max(h) / 300.0;
    let sheet = svg::node::element::Rectangle::new()
        .set("x", 0)
        .set("y", 0)
        .set("width", w)
        .set("height", h)
        .set("fill", "#ffffff")
        .set("stroke", "#9a9a9a")
        .set("stroke-width", stroke);
    with_layers(page(path).add(sheet), path, stroke, Layers::ByKind).to_string() + "\n"
}

/// The layers `layers` asks for, strokes `width` mm wide in their kind's colour; a layer
/// with nothing on it is left out.
fn with_layers(mut doc: Document, path: &Toolpath, width: f64, layers: Layers) -> Document {
    let h = path.media.height;
    for (label, kinds) in layers.groups() {
        let mut layer = Group::new()
            .set("inkscape:groupmode", "layer")
            .set("inkscape:label", label)
            .set("id", label)
            .set("stroke-width", width)
            .set("stroke-linecap", "butt")
            .set("stroke-linejoin", "round")
            .set("fill", "none");
        if let [kind] = kinds[..] {
            layer = layer.set("stroke", super::colour::hex(kind));
        }
        let mut empty = true;
        for &kind in &kinds {
            let strokes: Vec<&Stroke> = path.strokes.iter().filter(|s| s.kind == kind).collect();
            // The outline (and any hole) is one path; a crease's dashes are one path each.
            let mut groups: Vec<Vec<&Stroke>> = Vec::new();
            let mut group_of: HashMap<usize, usize> = HashMap::new();
            for s in strokes {
                let key = if kind == LineKind::Cut { 0 } else { s.line };
                let g = *group_of.entry(key).or_insert_with(|| {
                    groups.push(Vec::new());
                    groups.len() - 1
                });
                groups[g].push(s);
            }
            for group in groups {
                let mut element = Path::new().set("d", path_data(&group, h));
                if kinds.len() > 1 {
                    element = element
                        .set("stroke", super::colour::hex(kind))
                        .set("class", kind.name());
                }
                layer = layer.add(element);
                empty = false;
            }
        }
        if !empty {
            doc = doc.add(layer);
        }
    }
    doc
}

/// SVG path data for strokes: joined strokes become one subpath (`M … L …`, a bent
/// stroke a cubic `C`), a subpath that returns to its start is closed (`Z`). The sheet's
/// y grows up, SVG's down.
fn path_data(strokes: &[&Stroke], h: f64) -> String {
    let mut d = String::new();
    let xy = |p: Vec2| format!("{} {}", round(p.x), round(h - p.y));
    for chain in chains(strokes) {
        let first = chain[0].from;
        let closed = chain.len() > 1 && (first - chain[chain.len() - 1].to).norm() < 1e-6;
        let _ = write!(d, "M{} ", xy(first));
        for (i, s) in chain.iter().enumerate() {
            match s.bend {
                Some([c1, c2]) => {
                    let _ = write!(d, "C{} {} {} ", xy(c1), xy(c2), xy(s.to));
                }
                // A straight closing stroke is the `Z` itself.
                None if closed && i == chain.len() - 1 => {}
                None => {
                    let _ = write!(d, "L{} ", xy(s.to));
                }
            }
        }
        if closed {
            d.push_str("Z ");
        }
    }
    d.trim_end().to_string()
}

/// Micrometre precision: ends that meet in the toolpath meet in the file.
fn round(v: f64) -> f64 {
    let r = (v * 1e4).round() / 1e4;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// Strokes joined end to end, in either direction, into runs, each stroke turned to run
/// on from the one before.
fn chains(strokes: &[&Stroke]) -> Vec<Vec<Stroke>> {
    let key = |p: Vec2| ((p.x * 1e6).round() as i64, (p.y * 1e6).round() as i64);
    let mut at: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, s) in strokes.iter().enumerate() {
        at.entry(key(s.from)).or_default().push(i);
        at.entry(key(s.to)).or_default().push(i);
    }
    let mut used = vec![false; strokes.len()];
    // An unused stroke with an end at `p`, turned to start there.
    let next_from = |p: Vec2, used: &mut Vec<bool>| -> Option<Stroke> {
        let i = *at.get(&key(p))?.iter().find(|&&i| !used[i])?;
        used[i] = true;
        let s = *strokes[i];
        Some(if key(s.from) == key(p) {
            s
        } else {
            s.reversed()
        })
    };
    let mut out = Vec::new();
    for i in 0..strokes.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        let mut chain = vec![*strokes[i]];
        while let Some(s) = next_from(chain[chain.len() - 1].to, &mut used) {
            chain.push(s);
        }
        // Strokes before this one in the run: walk back from its start.
        let mut before = Vec::new();
        let mut cursor = chain[0].from;
        while let Some(s) = next_from(cursor, &mut used) {
            cursor = s.to;
            before.push(s.reversed());
        }
        if !before.is_empty() {
            before.reverse();
            before.extend(chain);
            chain = before;
        }
        out.push(chain);
    }
    out
}
