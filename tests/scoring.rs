//! Safe scoring on every design and anchor: no dash within the clearance of the cut or of
//! another crease, mountain and valley read apart, and every fold scored or named.

mod common;

use common::fabbing::{a3, designs_and_anchors, near_pairs, patterns, segment_distance};
use crease::fab::{LineKind, Stroke};
use crease::pipeline::{fabricate, FabOptions};
use crease::plotter::Machine;
use std::path::Path;

#[test]
fn every_fold_is_scored_or_named_in_the_report() {
    // A fold too short for a dash once the junction clearance is kept (a 0.6 mm valley
    // on miura-collapse) used to vanish in silence.
    let machine = Machine::load("generic-hpgl").unwrap();
    let mut named = 0;
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let strokes: Vec<_> = out
            .toolpath
            .strokes
            .iter()
            .chain(out.back.iter().flat_map(|b| &b.strokes))
            .collect();
        let listed = out.report["sheet"]["unscored_creases"].as_array().unwrap();
        for (i, line) in out.sheet.lines.iter().enumerate() {
            if !matches!(line.kind, LineKind::Mountain | LineKind::Valley) {
                continue;
            }
            let scored = strokes.iter().any(|s| s.line == i);
            let in_report = listed.iter().any(|u| {
                u["kind"] == line.kind.name()
                    && (u["length_mm"].as_f64().unwrap() - line.length()).abs() < 1e-9
                    && (u["from_mm"][0].as_f64().unwrap() - line.a.x).abs() < 1e-9
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
    let options = FabOptions {
        fit: true,
        force: true,
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
    let options = FabOptions {
        fit: true,
        force: true,
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
    let short = plain.report["sheet"]["unscored_creases"]
        .as_array()
        .unwrap()
        .clone();
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
        let listed = out.report["sheet"]["unscored_creases"].as_array().unwrap();
        assert_eq!(listed.len(), short.len(), "{choice}: still named");
        assert!(listed.iter().all(|u| u["given"] == given), "{choice}");
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
