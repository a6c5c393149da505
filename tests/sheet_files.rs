//! The sheet as other tools read it: DXF through the `dxf` crate, GP-GL and SVG through
//! the tests' own readers, each carrying exactly the toolpath the same way round.

mod common;

use common::fabbing::{a3, output, output_text, patterns};
use crease::fab::LineKind;
use crease::mesh::Vec2;
use crease::output::hpgl;
use crease::pipeline::fabricate;
use crease::plotter::Machine;
use std::path::Path;

#[test]
fn sheet_dxf_read_by_an_independent_parser_carries_exactly_the_toolpath() {
    // The dxf crate (ixmilia) reads sheet.dxf back: one LINE per stroke, on the layer of
    // its operation, ends within a micrometre of the toolpath's (whose y grows upward, as
    // DXF's), in millimetres.
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let bytes = output(&out, "sheet.dxf");
        let drawing = dxf::Drawing::load(&mut &bytes[..])
            .unwrap_or_else(|e| panic!("{}: sheet.dxf does not parse: {e}", path.display()));
        assert_eq!(drawing.header.version, dxf::enums::AcadVersion::R12);
        let lines: Vec<(String, [f64; 4])> = drawing
            .entities()
            .map(|e| match &e.specific {
                dxf::entities::EntityType::Line(l) => {
                    (e.common.layer.clone(), [l.p1.x, l.p1.y, l.p2.x, l.p2.y])
                }
                other => panic!("{}: unexpected entity {other:?}", path.display()),
            })
            .collect();
        let strokes = &out.toolpath.strokes;
        assert_eq!(lines.len(), strokes.len(), "{}", path.display());
        for ((layer, [x1, y1, x2, y2]), s) in lines.iter().zip(strokes) {
            let expected = match s.kind {
                LineKind::Cut => "CUT",
                LineKind::Mountain => "MOUNTAIN",
                LineKind::Valley => "VALLEY",
                LineKind::Flat => "FLAT",
            };
            assert_eq!(layer, expected);
            for (got, want) in [
                (*x1, s.from.x),
                (*y1, s.from.y),
                (*x2, s.to.x),
                (*y2, s.to.y),
            ] {
                assert!(
                    (got - want).abs() <= 1e-4,
                    "{}: {got} vs {want}",
                    path.display()
                );
            }
        }
        // Every layer is declared, with distinct colours.
        let colours: Vec<_> = drawing.layers().map(|l| l.color.index()).collect();
        let mut unique = colours.clone();
        unique.sort();
        unique.dedup();
        assert!(
            colours.len() >= 3 && unique.len() == colours.len(),
            "{colours:?}"
        );
    }
}

/// An independent GP-GL reader: the pen-down segments of a job, as (tool holder, from,
/// to) in cutter steps, (feed, carriage) as written.
fn read_gpgl(job: &str) -> Vec<(u32, [i64; 2], [i64; 2])> {
    let body = job
        .strip_prefix("\u{1b}\u{4}")
        .expect("a GP-GL job starts by resetting the cutter (ESC EOT)");
    assert!(body.ends_with('\u{3}'), "every command ends with ETX");
    let numbers = |s: &str| -> Vec<i64> { s.split(',').map(|n| n.parse().unwrap()).collect() };
    let (mut tool, mut at, mut segments) = (0, [0i64, 0], Vec::new());
    for cmd in body.split('\u{3}').filter(|c| !c.is_empty()) {
        assert!(cmd.bytes().all(|b| (0x20..0x7f).contains(&b)), "{cmd:?}");
        if let Some(rest) = cmd.strip_prefix('J') {
            tool = rest.parse().unwrap();
        } else if let Some(rest) = cmd.strip_prefix('M') {
            let p = numbers(rest);
            at = [p[0], p[1]];
        } else if let Some(rest) = cmd.strip_prefix('D') {
            for p in numbers(rest).chunks(2) {
                segments.push((tool, at, [p[0], p[1]]));
                at = [p[0], p[1]];
            }
        }
    }
    segments
}

#[test]
fn sheet_gpgl_read_by_an_independent_reader_carries_exactly_the_toolpath() {
    // Graphtec profile: 20 steps per mm, media feed (the sheet's y) first. Every stroke
    // of the toolpath is one cut segment with the kind's tool holder, its ends within
    // one step of the stroke's and its length within one step of the stroke's (rounding
    // both ends to their nearest step alone would allow √2).
    let machine = Machine::load("graphtec-ce").unwrap();
    let units = machine.units_per_mm;
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        assert!(!out.files.iter().any(|f| f.0 == "sheet.hpgl"));
        let job = output_text(&out, "sheet.gpgl");
        let segments = read_gpgl(job);
        // The cutter's origin is the media's top-left corner; the toolpath's y grows up.
        let h = out.toolpath.media.height;
        let step = |p: Vec2| {
            [
                ((h - p.y) * units).round() as i64,
                (p.x * units).round() as i64,
            ]
        };
        let strokes: Vec<_> = out
            .toolpath
            .strokes
            .iter()
            .filter(|s| step(s.from) != step(s.to))
            .collect();
        assert_eq!(segments.len(), strokes.len(), "{}", path.display());
        for ((tool, from, to), s) in segments.iter().zip(&strokes) {
            assert_eq!(*tool, machine.tools[s.kind.name()].pen);
            for (got, want) in [(from, s.from), (to, s.to)] {
                let want = [(h - want.y) * units, want.x * units];
                assert!(
                    (got[0] as f64 - want[0]).abs() < 1.0 && (got[1] as f64 - want[1]).abs() < 1.0,
                    "{}: {got:?} vs {want:?}",
                    path.display()
                );
            }
            let length = |a: [i64; 2], b: [i64; 2]| {
                (((a[0] - b[0]).pow(2) + (a[1] - b[1]).pow(2)) as f64).sqrt()
            };
            let (got, want) = (length(*from, *to), (s.to - s.from).norm() * units);
            assert!(
                (got - want).abs() <= 1.0,
                "{}: length {got} vs {want}",
                path.display()
            );
        }
    }
    // Carriage first (as inkcut sends): the same job with each pair swapped.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/graphtec-ce.toml"),
    )
    .unwrap()
    .replace(
        "axis_order = \"feed-first\"",
        "axis_order = \"carriage-first\"",
    );
    let swapped = Machine::parse(&text).unwrap();
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    let read = |m: &Machine| {
        let out = fabricate(&mesh, m, &a3()).unwrap();
        read_gpgl(output_text(&out, "sheet.gpgl"))
    };
    let flipped: Vec<_> = read(&swapped)
        .into_iter()
        .map(|(t, a, b)| (t, [a[1], a[0]], [b[1], b[0]]))
        .collect();
    assert_eq!(flipped, read(&machine));
}

#[test]
fn a_laser_profile_gets_dxf_and_svg_and_no_cutter_job() {
    let machine = Machine::load("laser-dxf").unwrap();
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    let out = fabricate(&mesh, &machine, &a3()).unwrap();
    let names: Vec<&str> = out.files.iter().map(|f| f.0.as_str()).collect();
    assert!(
        names.contains(&"sheet.dxf") && names.contains(&"sheet.svg"),
        "{names:?}"
    );
    assert!(
        !names
            .iter()
            .any(|n| n.ends_with(".hpgl") || n.ends_with(".gpgl")),
        "{names:?}"
    );
    assert_eq!(out.report["sheet"]["job_files"], serde_json::json!([]));
    assert!(out.report["sheet"]["plotter"].is_null());
}

#[test]
fn every_output_shows_the_sheet_the_same_way_round() {
    // A mirrored file folds into the mirror image of the design. Seen from above with
    // the origin at the media's top-left corner: sheet.svg as drawn (y down), sheet.dxf
    // and sheet.hpgl with y up from the lower edge, sheet.gpgl feed-first from the top.
    // The bird base is laid out asymmetrically enough (its kite lines) that a flip of any
    // one file changes its set of segments.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bird = crease::io::read(&root.join("patterns/bird-base.fold")).unwrap();
    let hpgl_machine = Machine::load("generic-hpgl").unwrap();
    let out = fabricate(&bird, &hpgl_machine, &a3()).unwrap();
    let h = out.toolpath.media.height;
    // The SVG's lines, as drawn.
    let svg = output_text(&out, "sheet.svg");
    let from_svg: Vec<Segment> = svg_segments(svg)
        .into_iter()
        .map(|(_, a, b)| (a, b))
        .collect();
    // The DXF, turned to y down.
    let from_dxf = dxf_lines_y_down(output_text(&out, "sheet.dxf"), h);
    // The HP-GL as the plotter draws it.
    let u = hpgl_machine.units_per_mm;
    let drawn = hpgl::interpret(output_text(&out, "sheet.hpgl"))
        .unwrap()
        .segments;
    let from_hpgl: Vec<Segment> = drawn
        .iter()
        .map(|(_, a, b)| {
            let p = |q: [i64; 2]| [q[0] as f64 / u, h - q[1] as f64 / u];
            (p(*a), p(*b))
        })
        .collect();
    // The GP-GL from the top-left origin, feed (down) first.
    let gpgl_machine = Machine::load("graphtec-ce").unwrap();
    let g = fabricate(&bird, &gpgl_machine, &a3()).unwrap();
    let gu = gpgl_machine.units_per_mm;
    let from_gpgl: Vec<Segment> = read_gpgl(output_text(&g, "sheet.gpgl"))
        .into_iter()
        .map(|(_, a, b)| {
            let p = |q: [i64; 2]| [q[1] as f64 / gu, q[0] as f64 / gu];
            (p(a), p(b))
        })
        .collect();
    // Each segment of `other` lies on one of sheet.svg's, ends within 0.1 mm (the
    // cutters' steps are 0.025–0.05 mm), and the counts agree.
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 0.1;
    let same = |s: &Segment, t: &Segment| {
        (near(s.0, t.0) && near(s.1, t.1)) || (near(s.0, t.1) && near(s.1, t.0))
    };
    let matched = |other: &[Segment]| {
        other
            .iter()
            .filter(|s| from_svg.iter().any(|t| same(s, t)))
            .count()
    };
    let mirrored: Vec<Segment> = from_svg
        .iter()
        .map(|&(p, q)| ([p[0], 2.0 * h - p[1] - h], [q[0], 2.0 * h - q[1] - h]))
        .collect();
    assert!(
        (matched(&mirrored) as f64) < 0.9 * from_svg.len() as f64,
        "the test pattern must not be its own mirror image"
    );
    let agree = |name: &str, other: &Vec<Segment>| {
        assert_eq!(other.len(), from_svg.len(), "{name}");
        assert_eq!(
            matched(other),
            other.len(),
            "{name}: segments off sheet.svg's"
        );
    };
    agree("sheet.dxf", &from_dxf);
    agree("sheet.hpgl", &from_hpgl);
    agree("sheet.gpgl", &from_gpgl);
}

/// A line segment on the sheet, in mm from its top-left corner, y down.
type Segment = ([f64; 2], [f64; 2]);

/// A DXF's LINE entities, turned from y up to y down on a sheet `h` mm high.
fn dxf_lines_y_down(dxf: &str, h: f64) -> Vec<Segment> {
    let drawing = dxf::Drawing::load(&mut dxf.as_bytes()).unwrap();
    drawing
        .entities()
        .filter_map(|e| match &e.specific {
            dxf::entities::EntityType::Line(l) => {
                Some(([l.p1.x, h - l.p1.y], [l.p2.x, h - l.p2.y]))
            }
            _ => None,
        })
        .collect()
}

/// The segments of a sheet.svg's paths: (layer, from, to) as drawn (y down), closing
/// segments of `Z` included.
fn svg_segments(svg: &str) -> Vec<(String, [f64; 2], [f64; 2])> {
    let mut out = Vec::new();
    for layer in svg.split("<g ").skip(1) {
        let name = layer
            .split("id=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        for path in layer.split("<path d=\"").skip(1) {
            let d = path.split('"').next().unwrap();
            let mut tokens = d.split_whitespace();
            let (mut at, mut start) = ([0.0; 2], [0.0; 2]);
            while let Some(t) = tokens.next() {
                let (op, x) = t.split_at(1);
                if op == "Z" {
                    out.push((name.to_string(), at, start));
                    at = start;
                    continue;
                }
                let p = [x.parse().unwrap(), tokens.next().unwrap().parse().unwrap()];
                match op {
                    "M" => start = p,
                    "L" => out.push((name.to_string(), at, p)),
                    other => panic!("unexpected path command {other}"),
                }
                at = p;
            }
        }
    }
    out
}

#[test]
fn sheet_svg_holds_only_what_is_cut_or_scored_one_path_per_line() {
    // What cutter and laser software take: no media frame, hairlines, one colour per
    // layer; the outline one closed path; each crease's dashes one path element; and,
    // segment by segment, exactly the toolpath.
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let svg = output_text(&out, "sheet.svg");
        let name = path.display();
        assert!(!svg.contains("<rect") && !svg.contains("<line"), "{name}");
        // Every layer drawn in hairlines.
        assert_eq!(
            svg.matches("stroke-width=\"0.0254\"").count(),
            svg.matches("<g ").count(),
            "{name}"
        );
        let strokes = &out.toolpath.strokes;
        for kind in [LineKind::Cut, LineKind::Mountain, LineKind::Valley] {
            let layer = svg.split(&format!("id=\"{}\"", kind.name())).nth(1);
            let ours: Vec<_> = strokes.iter().filter(|s| s.kind == kind).collect();
            let Some(layer) = layer else {
                assert!(ours.is_empty(), "{name}: no {} layer", kind.name());
                continue;
            };
            let layer = layer.split("</g>").next().unwrap();
            let paths = layer.matches("<path").count();
            if kind == LineKind::Cut {
                assert_eq!(paths, 1, "{name}: the outline is one path");
                let d = layer
                    .split("d=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap();
                assert_eq!(
                    d.matches('M').count(),
                    d.matches('Z').count(),
                    "{name}: every loop of the outline is closed"
                );
            } else {
                let mut lines: Vec<usize> = ours.iter().map(|s| s.line).collect();
                lines.sort_unstable();
                lines.dedup();
                assert_eq!(
                    paths,
                    lines.len(),
                    "{name}: one path per {} crease",
                    kind.name()
                );
            }
        }
        // Segment by segment the toolpath (the SVG's y runs down the sheet).
        let h = out.toolpath.media.height;
        let drawn = svg_segments(svg);
        assert_eq!(drawn.len(), strokes.len(), "{name}");
        let near = |a: [f64; 2], b: Vec2| (a[0] - b.x).hypot(a[1] - (h - b.y)) < 1e-3;
        for s in strokes {
            assert!(
                drawn.iter().any(|(layer, a, b)| layer == s.kind.name()
                    && ((near(*a, s.from) && near(*b, s.to))
                        || (near(*a, s.to) && near(*b, s.from)))),
                "{name}: stroke {s:?} missing from sheet.svg"
            );
        }
    }
}
