//! Scoring: each crease line becomes cut strokes. Folds are perforated with a dash code
//! (cut length, gap length) per fold type, laid out symmetrically along every span and
//! stopping a clearance short of any point where three or more creases meet, where a
//! perforation would tear; the boundary is cut through. Then, measured in the plane, no
//! dash comes within the clearance of the cut or of another crease's dash: where creases
//! meet at a sharp angle, or run close and nearly parallel, the slit between them would be
//! a sliver that tears.

use super::clearance::keep_clear;
use super::layout::Sheet;
use super::lines::LineKind;
use super::toolpath::{dashes, short_marks, ScoreSettings, ShortFolds, Stroke};

/// Turns the sheet's lines into strokes (unordered; see [`super::route()`]), every dash
/// clear of the cut and of other creases' dashes ([`super::clearance::keep_clear`]).
pub fn score(sheet: &Sheet, settings: &ScoreSettings) -> Vec<Stroke> {
    score_lines(sheet, settings).0
}

/// [`score`], and the mountain and valley lines too short for any dash, which got what
/// `settings.short_folds` says.
pub fn score_lines(sheet: &Sheet, settings: &ScoreSettings) -> (Vec<Stroke>, Vec<usize>) {
    let mut strokes = keep_clear(dash_lines(sheet, settings), sheet, settings);
    let mut scored = vec![false; sheet.lines.len()];
    for s in &strokes {
        scored[s.line] = true;
    }
    let short: Vec<usize> = (0..sheet.lines.len())
        .filter(|&i| {
            matches!(sheet.lines[i].kind, LineKind::Mountain | LineKind::Valley) && !scored[i]
        })
        .collect();
    for &i in &short {
        let line = &sheet.lines[i];
        let Some(Some(code)) = settings.codes.get(&line.kind) else {
            continue;
        };
        let len = line.length();
        if len <= 0.0 {
            continue;
        }
        match settings.short_folds {
            ShortFolds::Nothing => continue,
            ShortFolds::Solid => strokes.extend(stretch(sheet, i, 0.0, len)),
            ShortFolds::Dash => {
                let cut = code.cut.min(len);
                strokes.push(dash(sheet, i, (len - cut) / 2.0, (len + cut) / 2.0));
            }
        }
    }
    (strokes, short)
}

/// Dashes along each line, kept clear of junctions along the line itself.
fn dash_lines(sheet: &Sheet, settings: &ScoreSettings) -> Vec<Stroke> {
    let mut strokes = Vec::new();
    for (index, line) in sheet.lines.iter().enumerate() {
        let Some(code) = settings.codes.get(&line.kind) else {
            continue;
        };
        let len = line.length();
        if len <= 0.0 {
            continue;
        }
        let Some(code) = code else {
            strokes.extend(stretch(sheet, index, 0.0, len));
            continue;
        };
        // Spans between junctions, each shortened by the clearance at junction ends.
        let mut stops: Vec<f64> = line.junctions.iter().map(|t| t * len).collect();
        stops.extend([0.0, len]);
        stops.sort_by(f64::total_cmp);
        stops.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let is_junction = |s: f64| line.junctions.iter().any(|t| (t * len - s).abs() < 1e-9);
        for w in stops.windows(2) {
            let lo = w[0]
                + if is_junction(w[0]) {
                    settings.clearance
                } else {
                    0.0
                };
            let hi = w[1]
                - if is_junction(w[1]) {
                    settings.clearance
                } else {
                    0.0
                };
            if hi <= lo {
                continue;
            }
            let marks = match settings.lone_dash_floor(line.kind) {
                Some(floor) if hi - lo < code.cut => short_marks(hi - lo, floor, settings.min_dash),
                _ => dashes(hi - lo, *code, settings.min_dash),
            };
            strokes.extend(
                marks
                    .into_iter()
                    .map(|(s, e)| dash(sheet, index, lo + s, lo + e)),
            );
        }
    }
    strokes
}

/// The stretch of sheet line `index` between lengths `a` and `b` along it, cut whole: one
/// straight stroke, or on a curve one exact stroke per chord's piece it crosses.
fn stretch(sheet: &Sheet, index: usize, a: f64, b: f64) -> Vec<Stroke> {
    let line = &sheet.lines[index];
    match &line.curve {
        Some(curve) => curve
            .span(a, b)
            .iter()
            .map(|c| Stroke::along(line.kind, c, index))
            .collect(),
        None => vec![dash(sheet, index, a, b)],
    }
}

/// One dash of sheet line `index` between lengths `a` and `b` along it: a straight
/// stroke, or one cubic along the curve ([`SmoothCurve::cubic_between`]; a dash is one
/// stroke, so it still reads as one mark when clearance trims it).
///
/// [`SmoothCurve::cubic_between`]: super::curve::SmoothCurve::cubic_between
fn dash(sheet: &Sheet, index: usize, a: f64, b: f64) -> Stroke {
    let line = &sheet.lines[index];
    match &line.curve {
        Some(curve) => Stroke::along(line.kind, &curve.cubic_between(a, b), index),
        None => {
            let u = (line.b - line.a) / line.length();
            Stroke::straight(line.kind, line.a + u * a, line.a + u * b, index)
        }
    }
}
