//! Helpers for the fabrication tests: the bundled designs, A3 options, and the files a
//! run produced.

use crease::fab::Stroke;
use crease::mesh::Vec2;
use crease::pipeline::FabOptions;
use std::path::{Path, PathBuf};

pub fn patterns() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "fold"))
        .collect();
    v.sort();
    assert!(v.len() >= 10);
    v
}

pub fn a3() -> FabOptions {
    FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        ..Default::default()
    }
}

/// The bytes of one file a fabrication run produced.
pub fn output<'a>(out: &'a crease::pipeline::FabOutput, name: &str) -> &'a [u8] {
    &out.files
        .iter()
        .find(|f| f.0 == name)
        .unwrap_or_else(|| panic!("fab wrote no {name}"))
        .1
}

/// One text file a fabrication run produced.
pub fn output_text<'a>(out: &'a crease::pipeline::FabOutput, name: &str) -> &'a str {
    std::str::from_utf8(output(out, name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Distance from `p` to the stroke `s` in the plane.
pub fn distance_to_segment(p: Vec2, s: &Stroke) -> f64 {
    let d = s.to - s.from;
    let t = ((p - s.from).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (s.from + d * t - p).norm()
}

/// Closest distance between two segments in the plane (zero if they cross).
pub fn segment_distance(a: &Stroke, b: &Stroke) -> f64 {
    let cross = |o: Vec2, p: Vec2, q: Vec2| (p - o).perp(&(q - o));
    let crosses = cross(a.from, a.to, b.from) * cross(a.from, a.to, b.to) < 0.0
        && cross(b.from, b.to, a.from) * cross(b.from, b.to, a.to) < 0.0;
    if crosses {
        return 0.0;
    }
    [
        distance_to_segment(a.from, b),
        distance_to_segment(a.to, b),
        distance_to_segment(b.from, a),
        distance_to_segment(b.to, a),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min)
}

/// Every bundled design and every anchor file.
pub fn designs_and_anchors() -> Vec<PathBuf> {
    let anchors = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut designs = patterns();
    for sub in ["fold", "origamisimulator"] {
        for e in std::fs::read_dir(anchors.join(sub)).unwrap() {
            let p = e.unwrap().path();
            if matches!(p.extension().and_then(|e| e.to_str()), Some("fold" | "svg")) {
                designs.push(p);
            }
        }
    }
    designs
}

/// Pairs of strokes whose boxes, grown by `reach`, share a cell of a coarse grid: every
/// pair closer than `reach`, and few more.
pub fn near_pairs(strokes: &[Stroke], reach: f64) -> std::collections::HashSet<(usize, usize)> {
    let cell = 10.0;
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
    for (i, s) in strokes.iter().enumerate() {
        let lo = s.from.inf(&s.to) - Vec2::repeat(reach);
        let hi = s.from.sup(&s.to) + Vec2::repeat(reach);
        for x in (lo.x / cell).floor() as i64..=(hi.x / cell).floor() as i64 {
            for y in (lo.y / cell).floor() as i64..=(hi.y / cell).floor() as i64 {
                grid.entry((x, y)).or_default().push(i);
            }
        }
    }
    let mut near = std::collections::HashSet::new();
    for list in grid.values() {
        for (k, &i) in list.iter().enumerate() {
            for &j in &list[k + 1..] {
                near.insert((i.min(j), i.max(j)));
            }
        }
    }
    near
}

/// The text runs a PDF page shows, in drawing order.
pub fn pdf_texts(page: &printpdf::PdfPage) -> Vec<String> {
    page.ops
        .iter()
        .filter_map(|op| match op {
            printpdf::Op::ShowText { items } => Some(items),
            _ => None,
        })
        .flatten()
        .filter_map(|item| match item {
            printpdf::TextItem::Text(t) => Some(t.clone()),
            _ => None,
        })
        .collect()
}
