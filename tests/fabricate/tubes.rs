//! A tube on the sheet (issue 31): one strip with a glue tab, and the report's seam
//! pairing glues it back into the design.

use crate::common;

use common::fabbing::{a3, output_text};
use crease::fab::LineKind;
use crease::machine::Machine;
use crease::mesh::{distance_to_segment, Mesh, UnionFind, Vec2};
use crease::pipeline::{fabricate, FabOptions, FabReport};
use std::collections::HashSet;
use std::path::Path;

fn bent_tube() -> Mesh {
    tube_design("waterbomb-tube-bent")
}

fn tube_design(name: &str) -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{name}.fold"));
    let m = crease::io::read(&path).unwrap();
    assert!(m.is_tube());
    m
}

fn v2(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

/// The index of the smallest of `distances` and that distance.
fn nearest(distances: impl Iterator<Item = f64>) -> (usize, f64) {
    distances
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
}

/// The vertex of `points` at `p` (the report's figures are the sheet's own numbers).
fn vertex_at(points: &[Vec2], p: Vec2) -> usize {
    let (i, d) = nearest(points.iter().map(|q| (q - p).norm()));
    assert!(d < 1e-9, "no strip vertex at {p:?} ({d} mm off)");
    i
}

#[test]
fn a_bent_tube_is_one_strip_that_the_seam_pairing_glues_back_into_its_form() {
    glued_back(&bent_tube());
}

#[test]
fn the_vase_whose_strip_is_a_fan_glues_back_into_its_form() {
    glued_back(&tube_design("waterbomb-tube-vase"));
}

/// Fabricates `tube` on the Cameo and glues its sheet back through the report's pairing.
fn glued_back(tube: &Mesh) {
    let machine = Machine::load("silhouette-cameo").unwrap();
    let out = fabricate(tube, &machine, &a3()).unwrap();
    let report = FabReport::from_text(output_text(&out, "report.json")).unwrap();
    let seam = report.seam.expect("a tube's report pairs its seam");
    assert_eq!(seam.pairs.len(), 8, "one pair per seam edge, rim to rim");
    let scale = report.sheet.scale;
    // The strip as laid out, read back from the file fab wrote: one piece, a disk.
    let strip = crease::io::fold::parse(output_text(&out, "crease-pattern.fold")).unwrap();
    assert!(strip.shape().is_disk, "{:?}", strip.shape());
    let at = strip.crease_pattern().unwrap();
    // Glue: each edge of the glued side onto its partner on the tab's side.
    let mut glue = UnionFind::new(at.len());
    for pair in &seam.pairs {
        for k in 0..2 {
            glue.union(
                vertex_at(at, v2(pair.tab_side[k])),
                vertex_at(at, v2(pair.glued_side[k])),
            );
        }
    }
    // Each glued vertex is one vertex of the tube: found by its 3D place.
    let of_tube: Vec<usize> = (0..at.len())
        .map(|v| {
            let root = glue.find(v);
            let p = strip.positions()[root];
            let (t, d) = nearest(tube.positions().iter().map(|q| (q - p).norm()));
            assert!(d < 1e-9, "strip vertex {v} is no vertex of the tube");
            t
        })
        .collect();
    let classes: HashSet<usize> = of_tube.iter().copied().collect();
    assert_eq!(
        classes.len(),
        tube.vertex_count(),
        "glued, every vertex once"
    );
    // Every edge of the glued sheet is an edge of the tube with its length, within
    // 0.01 mm, and every edge of the tube is made.
    let mut made = HashSet::new();
    let mut worst: f64 = 0.0;
    for e in strip.edges() {
        let [a, b] = e.vertices;
        let (ta, tb) = (of_tube[a], of_tube[b]);
        let te = tube
            .topology()
            .edge_between(ta, tb)
            .unwrap_or_else(|| panic!("glued edge {ta}-{tb} is not in the tube"));
        let sheet = (at[a] - at[b]).norm() / scale;
        let space = (tube.positions()[ta] - tube.positions()[tb]).norm();
        worst = worst.max((sheet - space).abs());
        made.insert(te);
    }
    assert!(worst <= 0.01, "an edge is {worst} mm off its 3D length");
    assert_eq!(made.len(), tube.edges().len());
    // The tab's hinge is scored as a valley and the glued side is cut.
    let near = |p: Vec2, kind: LineKind| {
        out.sheet
            .lines
            .iter()
            .any(|l| l.kind == kind && distance_to_segment(p, l.a, l.b) < 1e-6)
    };
    for pair in &seam.pairs {
        let mid = |s: [[f64; 2]; 2]| (v2(s[0]) + v2(s[1])) / 2.0;
        assert!(
            near(mid(pair.tab_side), LineKind::Valley),
            "pair {}",
            pair.number
        );
        assert!(
            near(mid(pair.glued_side), LineKind::Cut),
            "pair {}",
            pair.number
        );
        let scored = out.toolpath.strokes.iter().any(|s| {
            s.kind == LineKind::Valley
                && distance_to_segment(
                    (s.from + s.to) / 2.0,
                    v2(pair.tab_side[0]),
                    v2(pair.tab_side[1]),
                ) < 1e-6
        });
        assert!(scored, "pair {}: its hinge has a valley dash", pair.number);
    }
    // The tab's outline: the cut lines that do not run between strip vertices, from the
    // hinge's first point round to its last.
    let is_vertex = |p: Vec2| at.iter().any(|q| (q - p).norm() < 1e-9);
    let outline: Vec<(Vec2, Vec2)> = out
        .sheet
        .lines
        .iter()
        .filter(|l| l.kind == LineKind::Cut && !(is_vertex(l.a) && is_vertex(l.b)))
        .map(|l| (l.a, l.b))
        .collect();
    assert_eq!(outline.len(), 3, "chamfer, outer edge, chamfer");
    let first = v2(seam.pairs[0].tab_side[0]);
    let last = v2(seam.pairs[7].tab_side[1]);
    assert!((outline[0].0 - first).norm() < 1e-9 && (outline[2].1 - last).norm() < 1e-9);
    // Its outer edge runs at least the tab's width beyond every point of the hinge.
    let (q0, q1) = outline[1];
    let along = (q1 - q0).normalize();
    for pair in &seam.pairs {
        for p in pair.tab_side {
            let w = along.perp(&(v2(p) - q0)).abs() / scale;
            assert!(w >= 6.0 - 1e-9, "the tab is {w} mm wide at {p:?}");
        }
    }
    // No paper of the strip lies under the tab: no strip vertex inside its polygon.
    let mut polygon = vec![first, outline[0].1, outline[1].1, last];
    // Back along the hinge: each pair's start, the last pair's first, down to the second's.
    polygon.extend(seam.pairs[1..].iter().rev().map(|p| v2(p.tab_side[0])));
    let inside = |p: Vec2| {
        let n = polygon.len();
        let mut winding = false;
        for i in 0..n {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            if distance_to_segment(p, a, b) < 1e-6 {
                return false;
            }
            if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                winding = !winding;
            }
        }
        winding
    };
    for (v, p) in at.iter().enumerate() {
        assert!(!inside(*p), "strip vertex {v} lies under the tab");
    }
}

#[test]
fn the_tab_width_is_the_makers_and_a_tab_too_wide_is_refused() {
    let tube = bent_tube();
    let machine = Machine::load("silhouette-cameo").unwrap();
    let wide = |tab: f64| {
        fabricate(
            &tube,
            &machine,
            &FabOptions {
                tab: Some(tab),
                ..a3()
            },
        )
    };
    let narrow = wide(3.0).unwrap();
    let default = fabricate(&tube, &machine, &a3()).unwrap();
    let width = |o: &crease::pipeline::FabOutput| o.sheet.size[0].max(o.sheet.size[1]);
    assert_eq!(narrow.report.seam.as_ref().unwrap().tab_mm, 3.0);
    assert!(width(&default) > width(&narrow));
    let Err(e) = wide(100.0) else {
        panic!("a 100 mm tab cannot fit")
    };
    let flag = |o: crease::fab::FabOption| format!("--{}", o.word());
    let e = e.naming(&flag);
    assert!(e.contains("glue tab") && e.contains("--tab"), "{e}");
    let Err(e) = wide(0.0) else {
        panic!("no tab at all is refused")
    };
    let e = e.naming(&flag);
    assert!(e.contains("--tab"), "{e}");
}

#[test]
fn the_template_numbers_each_seam_edge_on_the_tab_and_across_the_sheet() {
    let tube = bent_tube();
    let machine = Machine::load("silhouette-cameo").unwrap();
    let out = fabricate(&tube, &machine, &a3()).unwrap();
    let seam = out.report.seam.as_ref().unwrap();
    // Each number twice on the printed page: beside the tab's hinge and beside the edge
    // glued onto it; the page says how to glue.
    let pdf = common::fabbing::output(&out, "sheet.pdf");
    let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
    let texts = common::fabbing::pdf_texts(&doc.pages[0]);
    for k in 1..=seam.pairs.len() {
        let n = texts.iter().filter(|t| **t == k.to_string()).count();
        assert_eq!(n, 2, "number {k} is printed {n} times");
    }
    assert!(texts.join(" ").contains("glue tab"), "{texts:?}");
    // On the sheet: each number on the right of its edge (the tab beyond the hinge, the
    // paper beyond the glued side), within the tab's width of the edge's middle.
    let scale = out.sheet.scale;
    for pair in &seam.pairs {
        let text = pair.number.to_string();
        let labels: Vec<Vec2> = out
            .sheet
            .labels
            .iter()
            .filter(|l| l.text == text)
            .map(|l| l.at)
            .collect();
        assert_eq!(labels.len(), 2);
        for side in [pair.tab_side, pair.glued_side] {
            let (a, b) = (v2(side[0]), v2(side[1]));
            let near = labels.iter().any(|&p| {
                let mid = (a + b) / 2.0;
                (b - a).perp(&(p - a)) < 0.0 && (p - mid).norm() <= 6.0 * scale
            });
            assert!(near, "pair {}: no number beside {side:?}", pair.number);
        }
    }
}

#[test]
fn fab_tells_the_maker_how_to_glue_a_tube_and_takes_the_tab_width() {
    let dir = common::Scratch::new("fab-tube");
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/waterbomb-tube-bent.fold");
    let (code, _, err) = common::run_crease(&[
        "fab",
        design.to_str().unwrap(),
        "--machine",
        "silhouette-cameo",
        "--tab",
        "8",
        "--draft-route",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("8 mm glue tab") && err.contains("8 numbered edges"),
        "{err}"
    );
    let report =
        FabReport::from_text(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report.seam.unwrap().tab_mm, 8.0);
    // A tab that cannot be: refused naming the option, exit 2, nothing written.
    let bad = dir.join("bad");
    let (code, _, err) = common::run_crease(&[
        "fab",
        design.to_str().unwrap(),
        "--tab",
        "0",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--tab"), "{err}");
    assert!(!bad.exists());
}

/// A run of text on the page and its box (lower left, upper right), mm.
type PrintedText = (String, Vec2, Vec2);

/// The seam numbers as the printed page shows them: each figure run's box from its text
/// cursor and font size with Helvetica's own metrics (figures 0.556 em wide, 0.718 em
/// high), and every straight piece of every path the page draws, all in mm.
fn printed_numbers_and_lines(pdf: &[u8]) -> (Vec<PrintedText>, Vec<(Vec2, Vec2)>) {
    let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
    let mm = |pt: f32| f64::from(pt) * 25.4 / 72.0;
    let (mut cursor, mut size) = (Vec2::zeros(), 0.0);
    let (mut numbers, mut segments) = (Vec::new(), Vec::new());
    for op in &doc.pages[0].ops {
        match op {
            printpdf::Op::SetTextCursor { pos } => cursor = Vec2::new(mm(pos.x.0), mm(pos.y.0)),
            printpdf::Op::SetFont { size: s, .. } => size = mm(s.0),
            printpdf::Op::ShowText { items } => {
                for item in items {
                    let printpdf::TextItem::Text(t) = item else {
                        continue;
                    };
                    if !t.is_empty() && t.chars().all(|c| c.is_ascii_digit()) {
                        let hi = cursor + Vec2::new(0.556 * size * t.len() as f64, 0.718 * size);
                        numbers.push((t.clone(), cursor, hi));
                    }
                }
            }
            printpdf::Op::DrawLine { line } => {
                // Béziers' control points included: the hull holds the curve.
                let points: Vec<Vec2> = line
                    .points
                    .iter()
                    .map(|p| Vec2::new(mm(p.p.x.0), mm(p.p.y.0)))
                    .collect();
                segments.extend(points.windows(2).map(|w| (w[0], w[1])));
            }
            _ => {}
        }
    }
    (numbers, segments)
}

/// Whether segment `p`–`q` meets the box `lo`–`hi` (sampled finely: the boxes are 2 mm,
/// the samples 0.01 mm apart).
fn segment_meets_box(p: Vec2, q: Vec2, lo: Vec2, hi: Vec2) -> bool {
    let n = ((q - p).norm() / 0.01).ceil().max(1.0) as usize;
    (0..=n).any(|i| {
        let x = p + (q - p) * (i as f64 / n as f64);
        x.x > lo.x && x.x < hi.x && x.y > lo.y && x.y < hi.y
    })
}

/// Issue 47, item 6: on the tubes' printed templates no seam number overlaps another or
/// touches a line (on `waterbomb-tube-bent` 8 sat on 7, 6 on 5 and 4 on 3).
#[test]
fn the_seam_numbers_are_printed_clear_of_each_other_and_of_every_line() {
    let machine = Machine::load("silhouette-cameo").unwrap();
    for name in [
        "waterbomb-tube-bent",
        "waterbomb-tube-vase",
        "waterbomb-tube",
    ] {
        let out = fabricate(&tube_design(name), &machine, &a3()).unwrap();
        let pairs = out.report.seam.as_ref().unwrap().pairs.len();
        let (numbers, segments) =
            printed_numbers_and_lines(common::fabbing::output(&out, "sheet.pdf"));
        assert_eq!(numbers.len(), 2 * pairs, "{name}: {numbers:?}");
        for (i, (t, lo, hi)) in numbers.iter().enumerate() {
            for (u, lo2, hi2) in &numbers[i + 1..] {
                let overlap = lo.x < hi2.x && lo2.x < hi.x && lo.y < hi2.y && lo2.y < hi.y;
                assert!(!overlap, "{name}: {t} at {lo:?} overlaps {u} at {lo2:?}");
            }
            for (p, q) in &segments {
                assert!(
                    !segment_meets_box(*p, *q, *lo, *hi),
                    "{name}: the line {p:?}–{q:?} crosses {t} at {lo:?}"
                );
            }
        }
    }
}
