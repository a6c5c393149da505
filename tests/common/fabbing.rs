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

/// A3, without the folding guide: the guide's path from flat is a second or so of each
/// run, and its page is its own test's (tests/design/animate.rs).
pub fn a3() -> FabOptions {
    FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        guide: crease::pipeline::Guide::Never,
        ..Default::default()
    }
}

/// A3 with the draft route: for tests that measure what the files carry, not the
/// cutting order (the full search is most of a run's time and changes no stroke).
pub fn a3_draft() -> FabOptions {
    FabOptions {
        route: crease::fab::RouteSearch::Draft,
        ..a3()
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

/// The stroke as chords: itself if straight, else 64 chords of its cubic, evaluated here
/// from the Bernstein form (not by the crate's flattening), each within 0.001 mm of the
/// curve for any dash this tool cuts.
pub fn chords(s: &Stroke) -> Vec<(Vec2, Vec2)> {
    let Some([c1, c2]) = s.bend else {
        return vec![(s.from, s.to)];
    };
    let at = |t: f64| {
        let u = 1.0 - t;
        s.from * (u * u * u) + c1 * (3.0 * u * u * t) + c2 * (3.0 * u * t * t) + s.to * (t * t * t)
    };
    (0..64)
        .map(|i| (at(i as f64 / 64.0), at((i + 1) as f64 / 64.0)))
        .collect()
}

/// The segments a line-only job sends for `strokes`, each with the stroke it belongs to:
/// a straight stroke itself, a bent one its chords ([`Stroke::polyline`]), those whose
/// ends fall on one step of `step` left out (shorter than the machine can move).
pub fn job_pieces(strokes: &[Stroke], step: impl Fn(Vec2) -> [i64; 2]) -> Vec<(Stroke, usize)> {
    let mut pieces = Vec::new();
    for (k, s) in strokes.iter().enumerate() {
        for w in s.polyline().windows(2) {
            if step(w[0]) != step(w[1]) {
                pieces.push((Stroke::straight(s.kind, w[0], w[1], s.line), k));
            }
        }
    }
    pieces
}

/// Distance from `p` to the segment `a`–`b`.
fn point_to_chord(p: Vec2, (a, b): (Vec2, Vec2)) -> f64 {
    let d = b - a;
    if d.norm_squared() == 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (a + d * t - p).norm()
}

/// Distance from `p` to the stroke `s` in the plane (along its curve if it bends).
pub fn distance_to_segment(p: Vec2, s: &Stroke) -> f64 {
    chords(s)
        .into_iter()
        .map(|c| point_to_chord(p, c))
        .fold(f64::INFINITY, f64::min)
}

/// Closest distance between two strokes in the plane (zero if they cross).
pub fn segment_distance(a: &Stroke, b: &Stroke) -> f64 {
    let cross = |o: Vec2, p: Vec2, q: Vec2| (p - o).perp(&(q - o));
    let mut best = f64::INFINITY;
    for (a0, a1) in chords(a) {
        for (b0, b1) in chords(b) {
            let crosses = cross(a0, a1, b0) * cross(a0, a1, b1) < 0.0
                && cross(b0, b1, a0) * cross(b0, b1, a1) < 0.0;
            if crosses {
                return 0.0;
            }
            best = [
                point_to_chord(a0, (b0, b1)),
                point_to_chord(a1, (b0, b1)),
                point_to_chord(b0, (a0, a1)),
                point_to_chord(b1, (a0, a1)),
            ]
            .into_iter()
            .fold(best, f64::min);
        }
    }
    best
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
        // A cubic lies in the hull of its control points.
        let (mut lo, mut hi) = (s.from.inf(&s.to), s.from.sup(&s.to));
        for c in s.bend.into_iter().flatten() {
            (lo, hi) = (lo.inf(&c), hi.sup(&c));
        }
        let (lo, hi) = (lo - Vec2::repeat(reach), hi + Vec2::repeat(reach));
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
