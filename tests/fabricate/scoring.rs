//! Safe scoring on every design and anchor: no dash within the clearance of the cut or of
//! another crease, mountain and valley read apart, and every fold scored or named.

use crate::common;

use common::fabbing::{
    a3, designs_and_anchors, near_pairs, output, output_text, patterns, segment_distance,
};
use crease::fab::{LineKind, Stroke};
use crease::machine::Machine;
use crease::mesh::Vec2;
use crease::pipeline::{fabricate, FabOptions};
use std::path::Path;

#[test]
fn every_fold_is_scored_or_named_in_the_report() {
    // A fold too short for a dash once the junction clearance is kept (a 0.6 mm valley
    // on miura-collapse) used to vanish in silence.
    let machine = Machine::load("generic-hpgl").unwrap();
    let mut named = 0;
    // Scoring only: a draft route (the cutting order is not what is checked here).
    let options = FabOptions {
        route: crease::fab::RouteSearch::Draft,
        ..a3()
    };
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let strokes: Vec<_> = out
            .toolpath
            .strokes
            .iter()
            .chain(out.back.iter().flat_map(|b| &b.strokes))
            .collect();
        let listed = &out.report.sheet.unscored_creases;
        for (i, line) in out.sheet.lines.iter().enumerate() {
            if !matches!(line.kind, LineKind::Mountain | LineKind::Valley) {
                continue;
            }
            let scored = strokes.iter().any(|s| s.line == i);
            let in_report = listed.iter().any(|u| {
                u.kind == line.kind.name()
                    && (u.length_mm - line.length()).abs() < 1e-9
                    && (u.from_mm[0] - line.a.x).abs() < 1e-9
            });
            assert!(
                scored != in_report,
                "{}: line {i} scored {scored}, named {in_report}",
                path.display()
            );
            named += usize::from(in_report);
        }
    }
    assert!(
        named > 0,
        "no design has a fold too short to score: the test checks nothing"
    );
}

#[test]
fn no_dash_comes_within_the_clearance_of_the_cut_or_of_another_creases_dash() {
    // Measured in the plane, pair by pair, on every bundled design and every anchor
    // that fabricates: waterbomb-curved, miura-collapse, plane-crumpled and resch-dome
    // had dashes 0.20-0.46 mm from the cut or from a neighbour's dashes.
    let machine = Machine::load("generic-hpgl").unwrap();
    let clearance = machine.clearance_mm;
    let designs = designs_and_anchors();
    // Fitted to A3, and cut even where verification objects (box.fold, wavy_pleats):
    // scoring is what is measured here.
    // Scoring is measured, not the cutting order: a draft route.
    let options = FabOptions {
        fit: true,
        force: true,
        route: crease::fab::RouteSearch::Draft,
        ..a3()
    };
    let mut pairs = 0usize;
    for path in &designs {
        let mesh = crease::io::read(path).unwrap();
        let out = fabricate(&mesh, &machine, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let strokes = &out.toolpath.strokes;
        let is_dash = |s: &Stroke| matches!(s.kind, LineKind::Mountain | LineKind::Valley);
        // A coarse grid keeps the pairwise check near linear on BoxPleatPyramid.
        let near = near_pairs(strokes, clearance);
        for (i, j) in near {
            let (a, b) = (&strokes[i], &strokes[j]);
            if a.line == b.line || !(is_dash(a) || is_dash(b)) {
                continue;
            }
            pairs += 1;
            let d = segment_distance(a, b);
            assert!(
                d >= clearance - 1e-6,
                "{}: a {} dash of line {} passes {d:.3} mm from a {} stroke of line {}",
                path.display(),
                a.kind.name(),
                a.line,
                b.kind.name(),
                b.line
            );
        }
    }
    assert!(
        pairs > 1000,
        "only {pairs} pairs near each other: the check checks nothing"
    );
}

#[test]
fn mountain_and_valley_read_apart_on_every_crease_however_short() {
    // On BoxPleatPyramid at 180 mm, 512 mountain dashes were 1.53 mm against the valleys'
    // 1.5 mm on the same pen. Now a mountain mark is a dash at least 0.5 mm longer than
    // any valley dash, or a close pair of short dashes, which valleys never make.
    let machine = Machine::load("generic-hpgl").unwrap();
    let settings = machine.score_settings();
    let valley = settings.codes[&LineKind::Valley].unwrap().cut;
    // Scoring is measured, not the cutting order: a draft route.
    let options = FabOptions {
        fit: true,
        force: true,
        route: crease::fab::RouteSearch::Draft,
        ..a3()
    };
    let mut pairs = 0;
    for path in designs_and_anchors() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let strokes = &out.toolpath.strokes;
        // A close pair: two dashes of one line, each under half a valley dash, no further
        // apart than the shorter is long.
        let in_pair = |s: &Stroke| {
            s.length() < valley / 2.0
                && strokes.iter().any(|o| {
                    o != s
                        && o.line == s.line
                        && o.length() < valley / 2.0
                        && [o.from, o.to].iter().any(|p| {
                            (p - s.from).norm().min((p - s.to).norm())
                                <= s.length().max(o.length()) + 1e-6
                        })
                })
        };
        for s in strokes {
            match s.kind {
                LineKind::Mountain => {
                    let long = s.length() >= valley + crease::fab::toolpath::DISTINCT_MM - 1e-6;
                    pairs += usize::from(!long);
                    assert!(
                        long || in_pair(s),
                        "{}: a {:.2} mm mountain dash reads as a valley",
                        path.display(),
                        s.length()
                    );
                }
                LineKind::Valley => assert!(
                    s.length() <= valley + 1e-6 && !in_pair(s),
                    "{}: a {:.2} mm valley dash reads as a mountain",
                    path.display(),
                    s.length()
                ),
                _ => {}
            }
        }
    }
    assert!(
        pairs > 0,
        "no short mountain on any design: the test checks nothing"
    );
}

#[test]
fn the_profile_chooses_what_folds_too_short_to_score_get() {
    // miura-collapse has folds too short for a dash once the junction clearance is kept.
    // With short_folds = "dash" each gets one dash centred on it; with "solid" a cut along
    // it; the report names them either way, with what they got.
    let mesh = crease::io::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-collapse.fold"),
    )
    .unwrap();
    let generic = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml"),
    )
    .unwrap();
    let with = |choice: &str| {
        let text = generic.replace(
            "protocol = \"hpgl\"",
            &format!("protocol = \"hpgl\"\nshort_folds = \"{choice}\""),
        );
        let machine = Machine::parse(&text).unwrap();
        fabricate(&mesh, &machine, &a3()).unwrap()
    };
    let plain = with("nothing");
    let short = plain.report.sheet.unscored_creases.clone();
    assert!(!short.is_empty(), "miura-collapse has short folds");
    let lines_of = |out: &crease::pipeline::FabOutput, i: usize| -> Vec<Stroke> {
        out.toolpath
            .strokes
            .iter()
            .copied()
            .filter(|s| s.line == i)
            .collect()
    };
    let short_lines: Vec<usize> = (0..plain.sheet.lines.len())
        .filter(|&i| {
            matches!(
                plain.sheet.lines[i].kind,
                LineKind::Mountain | LineKind::Valley
            ) && lines_of(&plain, i).is_empty()
        })
        .collect();
    assert_eq!(short_lines.len(), short.len());
    for (choice, given) in [("dash", "a centred dash"), ("solid", "a solid cut")] {
        let out = with(choice);
        let listed = &out.report.sheet.unscored_creases;
        assert_eq!(listed.len(), short.len(), "{choice}: still named");
        assert!(listed.iter().all(|u| u.given == given), "{choice}");
        assert!(
            out.warnings.iter().any(|w| w.contains(given)),
            "{choice}: {:?}",
            out.warnings
        );
        for &i in &short_lines {
            let line = &out.sheet.lines[i];
            let got = lines_of(&out, i);
            assert_eq!(got.len(), 1, "{choice}: one mark on line {i}");
            let s = got[0];
            let middle = (line.a + line.b) / 2.0;
            assert!(((s.from + s.to) / 2.0 - middle).norm() < 1e-9, "centred");
            if choice == "solid" {
                assert!(
                    (s.length() - line.length()).abs() < 1e-9,
                    "solid: the whole fold"
                );
            } else {
                let code = machine_code(line.kind);
                assert!(
                    (s.length() - code.min(line.length())).abs() < 1e-9,
                    "a dash"
                );
            }
        }
    }
}

/// The generic profile's dash length for a kind.
fn machine_code(kind: LineKind) -> f64 {
    Machine::load("generic-hpgl")
        .unwrap()
        .score_settings()
        .codes[&kind]
        .unwrap()
        .cut
}

/// The circle through three points, (centre, radius); `None` if they are in line.
fn circle_through(a: Vec2, b: Vec2, c: Vec2) -> Option<(Vec2, f64)> {
    let d = 2.0 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
    if d.abs() < 1e-12 {
        return None;
    }
    let n = |p: Vec2| p.norm_squared();
    let centre = Vec2::new(
        (n(a) * (b.y - c.y) + n(b) * (c.y - a.y) + n(c) * (a.y - b.y)) / d,
        (n(a) * (c.x - b.x) + n(b) * (a.x - c.x) + n(c) * (b.x - a.x)) / d,
    );
    Some((centre, (a - centre).norm()))
}

/// How far `p` lies from the smooth curve a crease chain's vertices sample, judged
/// independently of the crate's spline: from the circle through the three consecutive
/// vertices around the chord nearest `p` (the nearer of the two such circles). Exact for a
/// circular crease; for any smooth crease, what the curve is to second order.
fn off_curve(p: Vec2, points: &[Vec2], closed: bool) -> f64 {
    let n = points.len();
    let chords = if closed { n } else { n - 1 };
    let chord_distance = |k: usize| {
        let (a, b) = (points[k], points[(k + 1) % n]);
        let d = b - a;
        let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        (a + d * t - p).norm()
    };
    let k = (0..chords)
        .min_by(|&i, &j| chord_distance(i).total_cmp(&chord_distance(j)))
        .unwrap();
    // The triples (k-1, k, k+1) and (k, k+1, k+2) where they exist.
    let triples: Vec<[usize; 3]> = [k as isize - 1, k as isize]
        .into_iter()
        .filter(|&s| closed || (s >= 0 && s as usize + 2 < n))
        .map(|s| [0, 1, 2].map(|i| (s + i).rem_euclid(n as isize) as usize))
        .collect();
    triples
        .iter()
        .map(
            |t| match circle_through(points[t[0]], points[t[1]], points[t[2]]) {
                Some((c, r)) => ((p - c).norm() - r).abs(),
                None => chord_distance(k),
            },
        )
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn curved_creases_leave_as_curves_and_every_file_puts_their_dashes_on_the_curve() {
    // A curved crease used to leave as its chords, each scored on its own, straight. Now
    // sheet.svg carries cubic Béziers, and sheet.svg, sheet.hpgl (as the plotter draws
    // it, in its units) and sheet.dxf (read by the dxf crate) all lie within 0.05 mm of
    // the curve, judged against circles through the chain's vertices (for `arc` and
    // `concentric`, the circles the generator laid the creases on). Dashes keep the
    // machine's code measured along the curve.
    let machine = Machine::load("generic-hpgl").unwrap();
    let settings = machine.score_settings();
    let u = machine.units_per_mm;
    for name in ["arc", "concentric", "pleat", "arc-pulled"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{name}.fold"));
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let chains: Vec<(Vec<Vec2>, bool)> = crease::constraints::crease_chains(&mesh)
            .iter()
            .map(|c| {
                let points = c.vertices.iter().map(|&v| out.sheet.vertices[v]).collect();
                (points, c.closed)
            })
            .collect();
        let off = |p: Vec2| {
            chains
                .iter()
                .map(|(points, closed)| off_curve(p, points, *closed))
                .fold(f64::INFINITY, f64::min)
        };
        let mut worst = [0.0f64; 3];
        // sheet.svg: each crease one path of cubics.
        let text = output_text(&out, "sheet.svg");
        let h = out.toolpath.media.height;
        let mut layer = String::new();
        let mut dashes: Vec<(String, Vec<[Vec2; 4]>)> = Vec::new();
        for event in svg::read(text).unwrap() {
            use svg::node::element::path::{Command, Data, Position};
            use svg::node::element::tag::Type;
            use svg::parser::Event;
            match event {
                Event::Tag("g", Type::Start, a) => {
                    layer = a.get("inkscape:label").unwrap().to_string();
                }
                Event::Tag("path", _, a) if layer == "mountain" || layer == "valley" => {
                    let data = Data::parse(&a.get("d").unwrap().to_string()).unwrap();
                    let up = |x: f32, y: f32| Vec2::new(x as f64, h - y as f64);
                    let (mut at, mut cubics) = (Vec2::zeros(), Vec::new());
                    for command in data.iter() {
                        match command {
                            Command::Move(Position::Absolute, p) => at = up(p[0], p[1]),
                            Command::CubicCurve(Position::Absolute, p) => {
                                let c = [at, up(p[0], p[1]), up(p[2], p[3]), up(p[4], p[5])];
                                at = c[3];
                                cubics.push(c);
                            }
                            other => panic!("{name}: a crease's path has {other:?}"),
                        }
                    }
                    dashes.push((layer.clone(), cubics));
                }
                _ => {}
            }
        }
        assert!(!dashes.is_empty(), "{name}: no crease in sheet.svg");
        let bezier = |c: &[Vec2; 4], t: f64| {
            let s = 1.0 - t;
            c[0] * (s * s * s)
                + c[1] * (3.0 * s * s * t)
                + c[2] * (3.0 * s * t * t)
                + c[3] * (t * t * t)
        };
        let length = |c: &[Vec2; 4]| {
            (0..200)
                .map(|i| (bezier(c, (i + 1) as f64 / 200.0) - bezier(c, i as f64 / 200.0)).norm())
                .sum::<f64>()
        };
        let (mut full, mut total, mut even_gaps, mut gaps) = (0, 0, 0, 0);
        for (kind, cubics) in &dashes {
            let kind_is = if kind == "mountain" {
                LineKind::Mountain
            } else {
                LineKind::Valley
            };
            let code = settings.codes[&kind_is].unwrap();
            for c in cubics {
                for k in 0..=16 {
                    worst[0] = worst[0].max(off(bezier(c, k as f64 / 16.0)));
                }
                let len = length(c);
                assert!(len <= code.cut + 0.01, "{name}: a {len:.3} mm {kind} dash");
                total += 1;
                full += usize::from((len - code.cut).abs() < 0.01);
            }
            for w in cubics.windows(2) {
                let gap = (w[1][0] - w[0][3]).norm();
                gaps += 1;
                even_gaps += usize::from((gap - code.gap).abs() < 0.01);
            }
        }
        // Most dashes and gaps are whole (the rest are trimmed at junctions and the cut).
        assert!(
            full * 10 >= total * 8,
            "{name}: {full} of {total} dashes whole"
        );
        assert!(
            even_gaps * 10 >= gaps * 8,
            "{name}: {even_gaps} of {gaps} gaps even"
        );
        // sheet.hpgl as the plotter draws it: every crease segment, at five points.
        let drawn = crease::output::hpgl::interpret(output_text(&out, "sheet.hpgl")).unwrap();
        let crease_pens = [
            machine.tools[&LineKind::Mountain].pen,
            machine.tools[&LineKind::Valley].pen,
        ];
        for (pen, a, b) in &drawn.segments {
            if !crease_pens.contains(pen) {
                continue;
            }
            let (a, b) = (
                Vec2::new(a[0] as f64, a[1] as f64) / u,
                Vec2::new(b[0] as f64, b[1] as f64) / u,
            );
            for k in 0..=4 {
                worst[1] = worst[1].max(off(a + (b - a) * (k as f64 / 4.0)));
            }
        }
        // sheet.dxf read by the dxf crate: every crease polyline's chords.
        let bytes = output(&out, "sheet.dxf");
        let drawing = dxf::Drawing::load(&mut &bytes[..]).unwrap();
        let mut polylines = 0;
        for e in drawing.entities() {
            let creased = matches!(e.common.layer.as_str(), "MOUNTAIN" | "VALLEY");
            match &e.specific {
                dxf::entities::EntityType::Polyline(p) if creased => {
                    polylines += 1;
                    let v: Vec<Vec2> = p
                        .vertices()
                        .map(|v| Vec2::new(v.location.x, v.location.y))
                        .collect();
                    for w in v.windows(2) {
                        for k in 0..=4 {
                            worst[2] = worst[2].max(off(w[0] + (w[1] - w[0]) * (k as f64 / 4.0)));
                        }
                    }
                }
                dxf::entities::EntityType::Line(_) => {
                    assert!(!creased, "{name}: a crease as a straight LINE in sheet.dxf")
                }
                _ => {}
            }
        }
        assert!(polylines > 0, "{name}: no crease polyline in sheet.dxf");
        for (what, w) in ["sheet.svg", "sheet.hpgl", "sheet.dxf"].iter().zip(worst) {
            assert!(w <= 0.05, "{name}: {what} strays {w:.4} mm from the curve");
        }
        eprintln!("{name}: worst distance from the curve svg/hpgl/dxf {worst:.4?} mm, {full} of {total} dashes whole");
    }
}

/// The pieces of each path of `layer` in sheet.svg (read with the svg crate), in mm with
/// y up: straight pieces as cubics with their control points on the line, each tagged
/// with whether the file drew it as a curve.
fn svg_pieces(text: &str, layer: &str, h: f64) -> Vec<Vec<([Vec2; 4], bool)>> {
    use svg::node::element::path::{Command, Data, Position};
    use svg::node::element::tag::Type;
    use svg::parser::Event;
    let (mut current, mut paths) = (String::new(), Vec::new());
    for event in svg::read(text).unwrap() {
        match event {
            Event::Tag("g", Type::Start, a) => {
                current = a.get("inkscape:label").unwrap().to_string();
            }
            Event::Tag("path", _, a) if current == layer => {
                let data = Data::parse(&a.get("d").unwrap().to_string()).unwrap();
                let up = |x: f32, y: f32| Vec2::new(x as f64, h - y as f64);
                let (mut at, mut start, mut pieces) = (Vec2::zeros(), Vec2::zeros(), Vec::new());
                for command in data.iter() {
                    let line = |a: Vec2, b: Vec2| {
                        ([a, a + (b - a) / 3.0, a + (b - a) * 2.0 / 3.0, b], false)
                    };
                    match command {
                        Command::Move(Position::Absolute, p) => {
                            at = up(p[0], p[1]);
                            start = at;
                        }
                        Command::Line(Position::Absolute, p) => {
                            let to = up(p[0], p[1]);
                            pieces.push(line(at, to));
                            at = to;
                        }
                        Command::CubicCurve(Position::Absolute, p) => {
                            let c = [at, up(p[0], p[1]), up(p[2], p[3]), up(p[4], p[5])];
                            at = c[3];
                            pieces.push((c, true));
                        }
                        Command::Close => {
                            pieces.push(line(at, start));
                            at = start;
                        }
                        other => panic!("{layer}: a path has {other:?}"),
                    }
                }
                paths.push(pieces);
            }
            _ => {}
        }
    }
    paths
}

fn bezier_at(c: &[Vec2; 4], t: f64) -> Vec2 {
    let s = 1.0 - t;
    c[0] * (s * s * s) + c[1] * (3.0 * s * s * t) + c[2] * (3.0 * s * t * t) + c[3] * (t * t * t)
}

/// Issue 47, item 7: the concentric bowl's rims were cut as 8 chords with corners beside
/// smooth creases. Read back from sheet.svg: the outline's rims are cubics, and the
/// margin between each rim and the nearest crease stays constant along it (within
/// 0.1 mm; a chord's sag alone is 0.5 mm on the inner rim, 1.3 mm on the outer).
#[test]
fn a_curved_designs_rims_leave_as_curves_a_constant_margin_from_its_creases() {
    let design =
        crease::io::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/concentric.fold"))
            .unwrap();
    let machine = Machine::load("generic-hpgl").unwrap();
    let out = fabricate(&design, &machine, &common::fabbing::a3_draft()).unwrap();
    let text = output_text(&out, "sheet.svg");
    let h = out.toolpath.media.height;
    let outline = svg_pieces(text, "cut", h);
    assert_eq!(outline.len(), 1, "one closed outline");
    let creases: Vec<Vec2> = ["mountain", "valley"]
        .iter()
        .flat_map(|l| svg_pieces(text, l, h))
        .flatten()
        .flat_map(|(c, _)| (0..=16).map(move |k| bezier_at(&c, k as f64 / 16.0)))
        .collect();
    // The outline's curved runs: consecutive cubics.
    let mut rims: Vec<Vec<[Vec2; 4]>> = Vec::new();
    let mut in_rim = false;
    for (c, curved) in &outline[0] {
        match (curved, in_rim) {
            (true, true) => rims.last_mut().unwrap().push(*c),
            (true, false) => rims.push(vec![*c]),
            _ => {}
        }
        in_rim = *curved;
    }
    assert_eq!(
        rims.len(),
        2,
        "the inner and the outer rim are curves: {rims:?}"
    );
    for rim in &rims {
        assert!(rim.len() >= 8, "{} cubics", rim.len());
        let margins: Vec<f64> = rim
            .iter()
            .flat_map(|c| (0..=32).map(move |k| bezier_at(c, k as f64 / 32.0)))
            .map(|p| {
                creases
                    .iter()
                    .map(|q| (p - q).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        let (lo, hi) = margins
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &m| (a.min(m), b.max(m)));
        assert!(hi - lo < 0.1, "the margin runs from {lo:.3} to {hi:.3} mm");
    }
}
