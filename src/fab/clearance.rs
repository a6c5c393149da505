//! Clearance in the plane: no dash within the clearance of the cut, of a solid line or of
//! another crease's dash, where the slit between them would be a sliver that tears.

use super::curve::FLATTEN_MM;
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
        out.extend(marks.into_iter().map(|(s, e)| d.piece(a + s, a + e)));
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
        out.extend(
            short_marks(m.length(), floor, settings.min_dash)
                .into_iter()
                .map(|(s, e)| m.piece(s, e)),
        );
    }
    out
}

/// Trims every dash so it keeps `clearance` from the cut, from solid creases and from the
/// dashes of other creases, in the plane. Cuts and solid lines are never trimmed; among
/// dashes the longer crease keeps its dashes and the shorter gives way, and what is left
/// of a dash shorter than `min_dash` goes. A bent stroke is measured by its chords
/// ([`Stroke::polyline`]), which the clearance allows for: they are what line-only jobs
/// send, and a Bézier file's curve is within [`FLATTEN_MM`] of them.
pub fn keep_clear(strokes: Vec<Stroke>, sheet: &Sheet, settings: &ScoreSettings) -> Vec<Stroke> {
    if settings.clearance <= 0.0 || strokes.is_empty() {
        return strokes;
    }
    let bent = if strokes.iter().any(|s| s.bend.is_some()) {
        FLATTEN_MM
    } else {
        0.0
    };
    let c = settings.clearance + settings.rounding_slack() + bent;
    let dashed = |s: &Stroke| matches!(settings.codes.get(&s.kind), Some(Some(_)));
    let (mut dashes, fixed): (Vec<Stroke>, Vec<Stroke>) = strokes.into_iter().partition(dashed);
    let lengths: Vec<f64> = sheet.lines.iter().map(|l| l.length()).collect();
    dashes.sort_by(|a, b| {
        let (la, lb) = (lengths[a.line], lengths[b.line]);
        lb.total_cmp(&la).then(a.line.cmp(&b.line))
    });
    let mut kept = Kept::new(c, &sheet.media);
    for s in fixed {
        kept.add(s);
    }
    // A line's dashes are trimmed together (they are neighbours in `dashes`), so a mark
    // left without its partner can be told from the rest of its line.
    for line in dashes.chunk_by(|a, b| a.line == b.line) {
        let mut marks = Vec::new();
        for d in line {
            if d.length() <= 0.0 {
                continue;
            }
            let blocked = kept.blocked(d);
            marks.extend(read_as_kind(
                d,
                free_pieces(blocked, d.length(), settings.min_dash),
                settings,
            ));
        }
        for piece in pair_lone_marks(marks, settings) {
            kept.add(piece);
        }
    }
    kept.strokes
}

/// The strokes kept so far, their chords in a grid of cells a few clearances wide, each
/// listed in every cell its box, grown by the clearance, touches. A tiny clearance would
/// make the cells tiny and a long cut cover millions of them: no cell is narrower than
/// 1/512 of the media.
struct Kept {
    clearance: f64,
    cell: f64,
    strokes: Vec<Stroke>,
    /// Every kept stroke's chords, with the line each belongs to.
    chords: Vec<(Vec2, Vec2, usize)>,
    grid: std::collections::HashMap<(i64, i64), Vec<usize>>,
}

impl Kept {
    fn new(clearance: f64, media: &super::layout::Media) -> Kept {
        Kept {
            clearance,
            cell: (4.0 * clearance).max(media.width.max(media.height) / 512.0),
            strokes: Vec::new(),
            chords: Vec::new(),
            grid: Default::default(),
        }
    }

    fn key(&self, p: Vec2) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    fn add(&mut self, s: Stroke) {
        let grow = Vec2::repeat(self.clearance);
        for w in s.polyline().windows(2) {
            let lo = self.key(w[0].inf(&w[1]) - grow);
            let hi = self.key(w[0].sup(&w[1]) + grow);
            for x in lo.0..=hi.0 {
                for y in lo.1..=hi.1 {
                    self.grid.entry((x, y)).or_default().push(self.chords.len());
                }
            }
            self.chords.push((w[0], w[1], s.line));
        }
        self.strokes.push(s);
    }

    /// The stretches of `d`, as lengths along it, closer than the clearance to a kept
    /// stroke of another line.
    fn blocked(&self, d: &Stroke) -> Vec<(f64, f64)> {
        let points = d.polyline();
        let chord_sum: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        // Chord lengths measured along the chords, scaled to lengths along the stroke.
        let scale = if chord_sum > 0.0 {
            d.length() / chord_sum
        } else {
            1.0
        };
        let mut blocked = Vec::new();
        let mut seen = std::collections::HashSet::new();
        let mut start = 0.0;
        for w in points.windows(2) {
            let len = (w[1] - w[0]).norm();
            if len <= 0.0 {
                continue;
            }
            let u = (w[1] - w[0]) / len;
            let (lo, hi) = (self.key(w[0].inf(&w[1])), self.key(w[0].sup(&w[1])));
            seen.clear();
            for x in lo.0..=hi.0 {
                for y in lo.1..=hi.1 {
                    for &k in self.grid.get(&(x, y)).into_iter().flatten() {
                        let (q0, q1, line) = self.chords[k];
                        if line == d.line || !seen.insert(k) {
                            continue;
                        }
                        if let Some((a, b)) = too_close(w[0], u, len, q0, q1, self.clearance) {
                            blocked.push(((start + a) * scale, (start + b) * scale));
                        }
                    }
                }
            }
            start += len;
        }
        blocked
    }
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
