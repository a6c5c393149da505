//! Scoring: each crease line becomes cut strokes. Folds are perforated with a dash code
//! (cut length, gap length) per fold type, laid out symmetrically along every span and
//! stopping a clearance short of any point where three or more creases meet, where a
//! perforation would tear; the boundary is cut through. Then, measured in the plane, no
//! dash comes within the clearance of the cut or of another crease's dash: where creases
//! meet at a sharp angle, or run close and nearly parallel, the slit between them would be
//! a sliver that tears.

use super::layout::{Media, Sheet};
use super::lines::LineKind;
use crate::mesh::Vec2;
use std::collections::BTreeMap;

/// Perforation of a fold line: cut `cut` mm, leave `gap` mm, repeat.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct DashCode {
    /// Length of each cut dash (mm).
    pub cut: f64,
    /// Length of paper left between dashes (mm).
    pub gap: f64,
}

/// What a fold too short for any dash gets (a machine profile's `short_folds`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShortFolds {
    /// No cut: it is named in the report, to be creased by hand.
    Nothing,
    /// One dash of its kind's length (at most the fold's), centred on it.
    Dash,
    /// Cut along its whole length.
    Solid,
}

impl ShortFolds {
    /// Parses nothing, dash or solid; the error names the key.
    pub fn parse(s: &str) -> Result<ShortFolds, String> {
        match s {
            "nothing" => Ok(ShortFolds::Nothing),
            "dash" => Ok(ShortFolds::Dash),
            "solid" => Ok(ShortFolds::Solid),
            _ => Err(format!(
                "short_folds = \"{s}\" is not one of nothing, dash, solid"
            )),
        }
    }

    /// How the report says it.
    pub fn name(self) -> &'static str {
        match self {
            ShortFolds::Nothing => "nothing",
            ShortFolds::Dash => "a centred dash",
            ShortFolds::Solid => "a solid cut",
        }
    }
}

/// How each kind of line is cut.
#[derive(Clone, Debug, PartialEq)]
pub struct ScoreSettings {
    /// Per kind: `Some(None)` cuts a solid line, `Some(Some(code))` perforates, a missing
    /// kind is not cut at all.
    pub codes: BTreeMap<LineKind, Option<DashCode>>,
    /// Distance kept from points where three or more creases meet (mm).
    pub clearance: f64,
    /// Shortest dash worth cutting (mm).
    pub min_dash: f64,
    /// What folds too short for any dash get.
    pub short_folds: ShortFolds,
}

impl Default for ScoreSettings {
    fn default() -> Self {
        ScoreSettings {
            codes: BTreeMap::from([
                (LineKind::Cut, None),
                (LineKind::Mountain, Some(DashCode { cut: 3.0, gap: 1.5 })),
                (LineKind::Valley, Some(DashCode { cut: 1.5, gap: 1.5 })),
            ]),
            clearance: 1.0,
            min_dash: 0.3,
            short_folds: ShortFolds::Nothing,
        }
    }
}

/// One pen-down segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// What the stroke is for (selects the tool).
    pub kind: LineKind,
    /// Start (mm on the media).
    pub from: Vec2,
    /// End.
    pub to: Vec2,
    /// The sheet line ([`Sheet::lines`]) it cuts or scores: a crease's dashes share it.
    pub line: usize,
}

impl Stroke {
    /// Length in mm.
    pub fn length(&self) -> f64 {
        (self.to - self.from).norm()
    }

    /// The same stroke drawn the other way.
    pub fn reversed(self) -> Stroke {
        Stroke {
            from: self.to,
            to: self.from,
            ..self
        }
    }
}

/// Ordered strokes for one sheet.
#[derive(Clone, Debug)]
pub struct Toolpath {
    /// The media.
    pub media: Media,
    /// Strokes in cutting order.
    pub strokes: Vec<Stroke>,
}

impl Toolpath {
    /// Pen-up distance from the origin through every stroke and back to the origin (mm).
    pub fn travel(&self) -> f64 {
        let mut at = Vec2::zeros();
        let mut total = 0.0;
        for s in &self.strokes {
            total += (s.from - at).norm();
            at = s.to;
        }
        total + at.norm()
    }

    /// Pen-down length per kind (mm).
    pub fn cut_length(&self) -> BTreeMap<LineKind, f64> {
        let mut out = BTreeMap::new();
        for s in &self.strokes {
            *out.entry(s.kind).or_insert(0.0) += s.length();
        }
        out
    }
}

/// How much longer than every other kind's dash a lone dash of the longer-dashed kind
/// must be for a folder to tell them apart (mm).
pub const DISTINCT_MM: f64 = 0.5;

impl ScoreSettings {
    /// For the kind whose dashes are longest (mountains, by default): the shortest lone
    /// dash that still reads as that kind, the other kinds' longest dash plus
    /// [`DISTINCT_MM`]. `None` for other kinds, whose short dashes read as their own.
    pub fn lone_dash_floor(&self, kind: LineKind) -> Option<f64> {
        let own = self.codes.get(&kind).copied().flatten()?;
        let others = self
            .codes
            .iter()
            .filter(|(k, _)| **k != kind)
            .filter_map(|(_, c)| c.map(|c| c.cut))
            .fold(f64::NEG_INFINITY, f64::max);
        (others.is_finite() && own.cut > others).then_some(others + DISTINCT_MM)
    }
}

/// Marks on a stretch of `len` mm too short for a full dash of a kind whose lone dashes
/// must be at least `floor` long: one dash over the stretch if it is that long, else a
/// pair of thirds (a pattern no other kind makes), else nothing (the crease is named).
fn short_marks(len: f64, floor: f64, min_dash: f64) -> Vec<(f64, f64)> {
    if len >= floor {
        vec![(0.0, len)]
    } else if len / 3.0 >= min_dash {
        vec![(0.0, len / 3.0), (2.0 * len / 3.0, len)]
    } else {
        Vec::new()
    }
}

/// Dashes `(start, end)` along a span of length `len`, symmetric about its middle.
pub fn dashes(len: f64, code: DashCode, min_dash: f64) -> Vec<(f64, f64)> {
    if len < min_dash {
        return Vec::new();
    }
    let period = code.cut + code.gap;
    let n = (((len + code.gap) / period).floor() as usize).max(1);
    let dash = code.cut.min(len);
    let used = n as f64 * dash + (n - 1) as f64 * code.gap;
    let start = (len - used) / 2.0;
    (0..n)
        .map(|i| {
            let s = start + i as f64 * period;
            (s, s + dash)
        })
        .collect()
}

/// Turns the sheet's lines into strokes (unordered; see [`super::route`]), every dash
/// clear of the cut and of other creases' dashes ([`keep_clear`]).
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
        let (from, to) = match settings.short_folds {
            ShortFolds::Nothing => continue,
            ShortFolds::Solid => (0.0, len),
            ShortFolds::Dash => {
                let dash = code.cut.min(len);
                ((len - dash) / 2.0, (len + dash) / 2.0)
            }
        };
        let u = (line.b - line.a) / len.max(f64::MIN_POSITIVE);
        strokes.push(Stroke {
            kind: line.kind,
            from: line.a + u * from,
            to: line.a + u * to,
            line: i,
        });
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
        let u = (line.b - line.a) / len;
        let at = |s: f64| line.a + u * s;
        let Some(code) = code else {
            strokes.push(Stroke {
                kind: line.kind,
                from: line.a,
                to: line.b,
                line: index,
            });
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
            for (s, e) in marks {
                strokes.push(Stroke {
                    kind: line.kind,
                    from: at(lo + s),
                    to: at(lo + e),
                    line: index,
                });
            }
        }
    }
    strokes
}

/// The stretch `(lo, hi)` of the segment `p + t·u`, `t` in `[0, len]`, that lies closer
/// than `c` to the segment `q0 q1`: the segment's intersection with the capsule around
/// `q0 q1`, which is convex, so one interval (or none). It is the hull of the segment's
/// intersections with the two end discs and the rectangle between them.
fn too_close(p: Vec2, u: Vec2, len: f64, q0: Vec2, q1: Vec2, c: f64) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for q in [q0, q1] {
        let w = q - p;
        let along = w.dot(&u);
        let off2 = w.norm_squared() - along * along;
        if off2 < c * c {
            let h = (c * c - off2).sqrt();
            lo = lo.min(along - h);
            hi = hi.max(along + h);
        }
    }
    let d = q1 - q0;
    let l = d.norm();
    if l > 0.0 {
        let v = d / l;
        let n = Vec2::new(-v.y, v.x);
        // Clip the line against 0 ≤ (x − q0)·v ≤ l and |(x − q0)·n| ≤ c (Liang–Barsky).
        let (mut a, mut b) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut empty = false;
        for (dir, min, max) in [(v, 0.0, l), (n, -c, c)] {
            let at = (p - q0).dot(&dir);
            let rate = u.dot(&dir);
            if rate.abs() < 1e-15 {
                empty |= at < min || at > max;
            } else {
                let (t0, t1) = ((min - at) / rate, (max - at) / rate);
                a = a.max(t0.min(t1));
                b = b.min(t0.max(t1));
            }
        }
        if !empty && a <= b {
            lo = lo.min(a);
            hi = hi.max(b);
        }
    }
    let (lo, hi) = (lo.max(0.0), hi.min(len));
    (lo < hi).then_some((lo, hi))
}

/// Trims every dash so it keeps `clearance` from the cut, from solid creases and from the
/// dashes of other creases, in the plane. Cuts and solid lines are never trimmed; among
/// dashes the longer crease keeps its dashes and the shorter gives way, and what is left
/// of a dash shorter than `min_dash` goes.
pub fn keep_clear(strokes: Vec<Stroke>, sheet: &Sheet, settings: &ScoreSettings) -> Vec<Stroke> {
    let c = settings.clearance;
    if c <= 0.0 || strokes.is_empty() {
        return strokes;
    }
    let dashed = |s: &Stroke| matches!(settings.codes.get(&s.kind), Some(Some(_)));
    let (mut dashes, fixed): (Vec<Stroke>, Vec<Stroke>) = strokes.into_iter().partition(dashed);
    dashes.sort_by(|a, b| {
        let (la, lb) = (sheet.lines[a.line].length(), sheet.lines[b.line].length());
        lb.total_cmp(&la).then(a.line.cmp(&b.line))
    });
    // Kept strokes in a grid of cells a few clearances wide, each listed in every cell its
    // box, grown by the clearance, touches.
    let cell = 4.0 * c;
    let key = |p: Vec2| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
    let mut kept: Vec<Stroke> = Vec::with_capacity(fixed.len() + dashes.len());
    let add = |s: Stroke, kept: &mut Vec<Stroke>, grid: &mut std::collections::HashMap<_, _>| {
        let lo = key(s.from.inf(&s.to) - Vec2::repeat(c));
        let hi = key(s.from.sup(&s.to) + Vec2::repeat(c));
        for x in lo.0..=hi.0 {
            for y in lo.1..=hi.1 {
                grid.entry((x, y)).or_insert_with(Vec::new).push(kept.len());
            }
        }
        kept.push(s);
    };
    for s in fixed {
        add(s, &mut kept, &mut grid);
    }
    for d in dashes {
        let len = d.length();
        if len <= 0.0 {
            continue;
        }
        let u = (d.to - d.from) / len;
        let (lo, hi) = (key(d.from.inf(&d.to)), key(d.from.sup(&d.to)));
        let mut blocked: Vec<(f64, f64)> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for x in lo.0..=hi.0 {
            for y in lo.1..=hi.1 {
                for &k in grid.get(&(x, y)).into_iter().flatten() {
                    let o = kept[k];
                    if o.line == d.line || !seen.insert(k) {
                        continue;
                    }
                    blocked.extend(too_close(d.from, u, len, o.from, o.to, c));
                }
            }
        }
        blocked.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut start = 0.0;
        let mut pieces = Vec::new();
        for (a, b) in blocked.into_iter().chain([(len, len)]) {
            if a - start >= settings.min_dash {
                pieces.push((start, a.min(len)));
            }
            start = start.max(b);
        }
        // A piece trimmed shorter than a full dash must still read as its kind (a dash
        // laid out short already does). A shorter-dashed kind keeps only the longest
        // piece of a dash cut in two: two short pieces close together read as the
        // longer-dashed kind's pair.
        let code = settings.codes[&d.kind].expect("a dash has a code");
        let floor = settings.lone_dash_floor(d.kind);
        if floor.is_none() && pieces.len() > 1 {
            let longest = pieces
                .iter()
                .copied()
                .max_by(|x, y| (x.1 - x.0).total_cmp(&(y.1 - y.0)))
                .expect("pieces");
            pieces = vec![longest];
        }
        for (a, b) in pieces {
            let marks = match floor {
                Some(floor) if b - a < len - 1e-9 && b - a < code.cut - 1e-9 => {
                    short_marks(b - a, floor, settings.min_dash)
                }
                _ => vec![(0.0, b - a)],
            };
            for (s, e) in marks {
                let piece = Stroke {
                    from: d.from + u * (a + s),
                    to: d.from + u * (a + e),
                    ..d
                };
                add(piece, &mut kept, &mut grid);
            }
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dashes_are_symmetric_and_keep_the_code() {
        let code = DashCode { cut: 3.0, gap: 1.5 };
        let d = dashes(20.0, code, 0.3);
        // floor((20 + 1.5) / 4.5) = 4 dashes: 4·3 + 3·1.5 = 16.5, margins 1.75 each side.
        assert_eq!(d.len(), 4);
        assert!((d[0].0 - 1.75).abs() < 1e-12 && (20.0 - d[3].1 - 1.75).abs() < 1e-12);
        for w in d.windows(2) {
            assert!((w[1].0 - w[0].1 - 1.5).abs() < 1e-12);
        }
        assert!(d.iter().all(|(s, e)| (e - s - 3.0).abs() < 1e-12));
    }

    #[test]
    fn short_spans_get_one_short_dash_or_none() {
        let code = DashCode { cut: 3.0, gap: 1.5 };
        assert_eq!(dashes(2.0, code, 0.3), vec![(0.0, 2.0)]);
        assert!(dashes(0.2, code, 0.3).is_empty());
    }

    #[test]
    fn the_stretch_too_close_to_a_segment_matches_sampled_distances() {
        // Against distances sampled finely along the segment, for segments crossing,
        // passing at an angle, running parallel and ending short of the obstacle.
        let dist = |x: Vec2, q0: Vec2, q1: Vec2| {
            let d = q1 - q0;
            let t = ((x - q0).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (q0 + d * t - x).norm()
        };
        let cases = [
            (
                Vec2::new(-5.0, 0.3),
                Vec2::new(5.0, 0.3),
                Vec2::new(0.0, -2.0),
                Vec2::new(0.0, 2.0),
            ),
            (
                Vec2::new(-5.0, 1.0),
                Vec2::new(5.0, -0.2),
                Vec2::new(1.0, 0.0),
                Vec2::new(3.0, 0.5),
            ),
            (
                Vec2::new(0.0, 0.5),
                Vec2::new(10.0, 0.5),
                Vec2::new(2.0, 0.0),
                Vec2::new(6.0, 0.0),
            ),
            (
                Vec2::new(0.0, 0.0),
                Vec2::new(3.0, 0.0),
                Vec2::new(3.5, 0.2),
                Vec2::new(8.0, 3.0),
            ),
            (
                Vec2::new(0.0, 5.0),
                Vec2::new(3.0, 5.0),
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
            ),
        ];
        for (p0, p1, q0, q1) in cases {
            let len = (p1 - p0).norm();
            let u = (p1 - p0) / len;
            let got = too_close(p0, u, len, q0, q1, 1.0);
            let inside: Vec<f64> = (0..=10000)
                .map(|i| len * i as f64 / 10000.0)
                .filter(|&t| dist(p0 + u * t, q0, q1) < 1.0)
                .collect();
            match (got, inside.first(), inside.last()) {
                (None, None, None) => {}
                (Some((a, b)), Some(&first), Some(&last)) => {
                    let step = len / 10000.0;
                    assert!(
                        // Sampling puts the ends up to a step inside the true ones.
                        (a - first).abs() <= 1.5 * step && (b - last).abs() <= 1.5 * step,
                        "{got:?} vs {first}..{last}"
                    );
                }
                other => panic!("{other:?}"),
            }
        }
    }
}
