//! Clearance in the plane: no dash within the clearance of the cut, of a solid line or of
//! another crease's dash, where the slit between them would be a sliver that tears.

use super::layout::Sheet;
use super::toolpath::{short_marks, ScoreSettings, Stroke};
use crate::mesh::Vec2;

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

/// The stretches of a dash `len` long left outside the `blocked` ones, as (start, end)
/// along it, those at least `min_dash` long.
fn free_pieces(mut blocked: Vec<(f64, f64)>, len: f64, min_dash: f64) -> Vec<(f64, f64)> {
    blocked.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut start = 0.0;
    let mut pieces = Vec::new();
    for (a, b) in blocked.into_iter().chain([(len, len)]) {
        if a - start >= min_dash {
            pieces.push((start, a.min(len)));
        }
        start = start.max(b);
    }
    pieces
}

/// The strokes a dash `d` trimmed to `pieces` becomes. A piece trimmed shorter than a
/// full dash must still read as its kind (a dash laid out short already does). A
/// shorter-dashed kind keeps only the longest piece of a dash cut in two: two short
/// pieces close together read as the longer-dashed kind's pair.
fn read_as_kind(d: &Stroke, mut pieces: Vec<(f64, f64)>, settings: &ScoreSettings) -> Vec<Stroke> {
    let len = d.length();
    let u = (d.to - d.from) / len;
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
    let mut out = Vec::new();
    for (a, b) in pieces {
        let marks = match floor {
            Some(floor) if b - a < len - 1e-9 && b - a < code.cut - 1e-9 => {
                short_marks(b - a, floor, settings.min_dash)
            }
            _ => vec![(0.0, b - a)],
        };
        out.extend(marks.into_iter().map(|(s, e)| Stroke {
            from: d.from + u * (a + s),
            to: d.from + u * (a + e),
            ..*d
        }));
    }
    out
}

/// A line's marks after trimming, each still reading as its kind: for the longer-dashed
/// kind a mark shorter than its lone-dash floor reads right only beside its partner (the
/// close pair [`short_marks`] lays), so one whose partner was trimmed away becomes a pair
/// of its own thirds, or goes if they would be too short to cut.
fn pair_lone_marks(marks: Vec<Stroke>, settings: &ScoreSettings) -> Vec<Stroke> {
    let Some(floor) = marks.first().and_then(|m| settings.lone_dash_floor(m.kind)) else {
        return marks;
    };
    let short = |m: &Stroke| m.length() < floor - 1e-9;
    let partnered = |m: &Stroke| {
        marks.iter().any(|o| {
            o != m
                && short(o)
                && [o.from, o.to].iter().any(|p| {
                    (p - m.from).norm().min((p - m.to).norm()) <= m.length().max(o.length()) + 1e-9
                })
        })
    };
    let mut out = Vec::with_capacity(marks.len());
    for m in &marks {
        if !short(m) || partnered(m) {
            out.push(*m);
            continue;
        }
        let len = m.length();
        let u = (m.to - m.from) / len;
        out.extend(
            short_marks(len, floor, settings.min_dash)
                .into_iter()
                .map(|(s, e)| Stroke {
                    from: m.from + u * s,
                    to: m.from + u * e,
                    ..*m
                }),
        );
    }
    out
}

/// Trims every dash so it keeps `clearance` from the cut, from solid creases and from the
/// dashes of other creases, in the plane. Cuts and solid lines are never trimmed; among
/// dashes the longer crease keeps its dashes and the shorter gives way, and what is left
/// of a dash shorter than `min_dash` goes.
pub fn keep_clear(strokes: Vec<Stroke>, sheet: &Sheet, settings: &ScoreSettings) -> Vec<Stroke> {
    if settings.clearance <= 0.0 || strokes.is_empty() {
        return strokes;
    }
    let c = settings.clearance + settings.rounding_slack();
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
    // box, grown by the clearance, touches. A tiny clearance would make the cells tiny and
    // a long cut cover millions of them: no cell is narrower than 1/512 of the media.
    let cell = (4.0 * c).max(sheet.media.width.max(sheet.media.height) / 512.0);
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
    // A line's dashes are trimmed together (they are neighbours in `dashes`), so a mark
    // left without its partner can be told from the rest of its line.
    for line in dashes.chunk_by(|a, b| a.line == b.line) {
        let mut marks = Vec::new();
        for d in line {
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
            marks.extend(read_as_kind(
                d,
                free_pieces(blocked, len, settings.min_dash),
                settings,
            ));
        }
        for piece in pair_lone_marks(marks, settings) {
            add(piece, &mut kept, &mut grid);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

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
