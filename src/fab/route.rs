//! Ordering strokes to cut less air. One tour per physical tool (kinds that share a pen
//! share a tour: a cutter scores mountains and valleys with one blade), the outline last
//! so the sheet stays held; each tour starts as a nearest-neighbour walk from where the
//! pen is, either way round, and is then improved over the whole tour by 2-opt (reverse a
//! run) and Or-opt (move a run of up to three strokes, either way round), trying only
//! moves that join an end to one of its nearest ends.

use super::lines::LineKind;
use super::score::Stroke;
use crate::mesh::Vec2;
use crate::output::ToolSetting;
use std::collections::{BTreeMap, HashMap};

/// The strokes in groups cut one after another: one per pen, in the order kinds cut
/// ([`LineKind::ALL`]), with the outline always last. A kind without a tool is its own.
fn tool_groups(strokes: &[Stroke], tools: &BTreeMap<LineKind, ToolSetting>) -> Vec<Vec<Stroke>> {
    let mut groups: Vec<(Option<u32>, Vec<Stroke>)> = Vec::new();
    for kind in LineKind::ALL {
        let of_kind = strokes.iter().copied().filter(|s| s.kind == kind);
        let pen = tools
            .get(&kind)
            .map(|t| t.pen)
            .filter(|_| kind != LineKind::Cut);
        match groups.iter_mut().find(|g| pen.is_some() && g.0 == pen) {
            Some(g) => g.1.extend(of_kind),
            None => groups.push((pen, of_kind.collect())),
        }
    }
    // The outline last, whatever its pen.
    groups.sort_by_key(|g| g.1.first().is_some_and(|s| s.kind == LineKind::Cut));
    groups
        .into_iter()
        .map(|g| g.1)
        .filter(|g| !g.is_empty())
        .collect()
}

/// A crease's strokes in order along it, all pointing the same way: the pen goes down
/// the line dash by dash, so the tour orders whole lines.
fn chains(group: &[Stroke]) -> Vec<Vec<Stroke>> {
    let mut by_line: BTreeMap<usize, Vec<Stroke>> = BTreeMap::new();
    for s in group {
        by_line.entry(s.line).or_default().push(*s);
    }
    by_line
        .into_values()
        .map(|mut chain| {
            let d = chain.iter().fold(Vec2::zeros(), |d, s| {
                let v = s.to - s.from;
                if v.dot(&d) < 0.0 {
                    d - v
                } else {
                    d + v
                }
            });
            for s in &mut chain {
                if (s.to - s.from).dot(&d) < 0.0 {
                    *s = s.reversed();
                }
            }
            chain.sort_by(|a, b| a.from.dot(&d).total_cmp(&b.from.dot(&d)));
            chain
        })
        .collect()
}

/// Strokes to cut in order, starting and ending at the origin.
pub fn route(strokes: &[Stroke], tools: &BTreeMap<LineKind, ToolSetting>) -> Vec<Stroke> {
    let groups = tool_groups(strokes, tools);
    let mut out = Vec::with_capacity(strokes.len());
    let mut at = Vec2::zeros();
    let last = groups.len().saturating_sub(1);
    for (k, group) in groups.iter().enumerate() {
        // Each line stands in the tour as one stroke from its first end to its last.
        let lines = chains(group);
        let ends: Vec<Stroke> = lines
            .iter()
            .enumerate()
            .map(|(i, c)| Stroke {
                from: c[0].from,
                to: c[c.len() - 1].to,
                line: i,
                ..c[0]
            })
            .collect();
        let mut order = nearest_neighbour(&ends, at);
        // The last tour ends at home; the others end wherever the next one starts best.
        let home = (k == last).then(Vec2::zeros);
        improve(&mut order, at, home);
        let mut tour = Vec::with_capacity(group.len());
        for e in &order {
            let chain = &lines[e.line];
            if e.from == chain[0].from && e.to == chain[chain.len() - 1].to {
                tour.extend(chain.iter().copied());
            } else {
                tour.extend(chain.iter().rev().map(|s| s.reversed()));
            }
        }
        // Then stroke by stroke, where entering a line part way along gains.
        polish(&mut tour, at, home);
        at = tour.last().map(|s| s.to).unwrap_or(at);
        out.extend(tour);
    }
    out
}

/// Plain nearest neighbour per tool (no improvement), for comparison in benchmarks.
pub fn nearest_neighbour_only(
    strokes: &[Stroke],
    tools: &BTreeMap<LineKind, ToolSetting>,
) -> Vec<Stroke> {
    let mut out = Vec::new();
    let mut at = Vec2::zeros();
    for group in tool_groups(strokes, tools) {
        let order = nearest_neighbour(&group, at);
        at = order.last().map(|s| s.to).unwrap_or(at);
        out.extend(order);
    }
    out
}

/// Greedy tour over stroke ends with a uniform grid, so each pick looks only nearby.
fn nearest_neighbour(group: &[Stroke], start: Vec2) -> Vec<Stroke> {
    let n = group.len();
    if n == 0 {
        return Vec::new();
    }
    let (lo, hi) = group.iter().fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), s| (lo.inf(&s.from).inf(&s.to), hi.sup(&s.from).sup(&s.to)),
    );
    let extent = (hi - lo).max().max(1e-9);
    let cells_per_side = ((n as f64).sqrt().ceil() as i64).max(1);
    let cell = extent / cells_per_side as f64;
    let key = |p: Vec2| {
        (
            ((p.x - lo.x) / cell).floor() as i64,
            ((p.y - lo.y) / cell).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64), Vec<(usize, bool)>> = HashMap::new();
    for (i, s) in group.iter().enumerate() {
        grid.entry(key(s.from)).or_default().push((i, false));
        grid.entry(key(s.to)).or_default().push((i, true));
    }
    let mut done = vec![false; n];
    let mut out = Vec::with_capacity(n);
    let mut at = start;
    for _ in 0..n {
        let (cx, cy) = key(at);
        let mut best: Option<(f64, usize, bool)> = None;
        // The pen may start far outside the grid (its origin beside a small design): the
        // rings nearer than the grid itself are empty, so the search starts at the grid.
        let outside = |c: i64| (-c).max(c - cells_per_side).max(0);
        let first_ring = outside(cx).max(outside(cy));
        let mut ring = first_ring;
        // Grid keys lie in 0..=cells_per_side on both axes; only cells there are visited,
        // in the same order as a full sweep of the ring, and only the ring's perimeter.
        let span = |c: i64, ring: i64| (-ring).max(-c)..=ring.min(cells_per_side - c);
        loop {
            for dx in span(cx, ring) {
                let column: Vec<i64> = if dx.abs() == ring {
                    span(cy, ring).collect()
                } else {
                    [-ring, ring]
                        .into_iter()
                        .filter(|dy| span(cy, ring).contains(dy))
                        .collect()
                };
                for dy in column {
                    let Some(list) = grid.get(&(cx + dx, cy + dy)) else {
                        continue;
                    };
                    for &(i, reversed) in list {
                        if done[i] {
                            continue;
                        }
                        let end = if reversed { group[i].to } else { group[i].from };
                        let d = (end - at).norm();
                        if best.is_none_or(|(bd, _, _)| d < bd) {
                            best = Some((d, i, reversed));
                        }
                    }
                }
            }
            // Anything found within `ring` cells is closer than whatever lies beyond it.
            if let Some((d, _, _)) = best {
                if d <= ring as f64 * cell {
                    break;
                }
            }
            ring += 1;
            if ring > first_ring + 2 * cells_per_side + 2 {
                break;
            }
        }
        // The rings cover the whole grid, so an undone stroke is always found; the scan is
        // a guard against a grid that rounding left short.
        let best = best.or_else(|| {
            (0..n)
                .filter(|&i| !done[i])
                .flat_map(|i| [(i, false), (i, true)])
                .map(|(i, r)| {
                    let end = if r { group[i].to } else { group[i].from };
                    ((end - at).norm(), i, r)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
        });
        let Some((_, i, reversed)) = best else {
            break;
        };
        done[i] = true;
        let s = if reversed {
            group[i].reversed()
        } else {
            group[i]
        };
        at = s.to;
        out.push(s);
    }
    out
}

/// A tour of oriented strokes from a fixed start to a fixed end (or a free one), with
/// each stroke's position so moves can be found from neighbouring ends.
struct Tour {
    strokes: Vec<Stroke>,
    /// Position in `strokes` of each stroke by its original index.
    pos: Vec<usize>,
    /// Original index of the stroke at each position.
    id: Vec<usize>,
    start: Vec2,
    end: Option<Vec2>,
    /// Longest run a 2-opt may reverse: the whole tour up to 5,000 strokes; on larger
    /// sheets reversals cost a pass O(n) each, so they are kept to what a 100k-stroke
    /// sheet routes in seconds with.
    max_reverse: usize,
}

impl Tour {
    /// The strokes in the order given.
    fn new(strokes: Vec<Stroke>, start: Vec2, end: Option<Vec2>) -> Tour {
        let n = strokes.len();
        Tour {
            strokes,
            pos: (0..n).collect(),
            id: (0..n).collect(),
            start,
            end,
            max_reverse: n.min((25_000_000 / n.max(1)).max(5_000)),
        }
    }

    /// Where the pen is before position `i` (the start for i = 0).
    fn before(&self, i: usize) -> Vec2 {
        if i == 0 {
            self.start
        } else {
            self.strokes[i - 1].to
        }
    }

    /// Travel from `p` to the stroke at position `i`, or home (free: nothing) for i = n.
    fn to_next(&self, p: Vec2, i: usize) -> f64 {
        match self.strokes.get(i) {
            Some(s) => (s.from - p).norm(),
            None => self.end.map_or(0.0, |e| (e - p).norm()),
        }
    }

    /// Travel into position `i` from what precedes it.
    fn gap(&self, i: usize) -> f64 {
        self.to_next(self.before(i), i)
    }

    /// Reverses positions `a..=b` (each stroke turned round too).
    fn reverse(&mut self, a: usize, b: usize) {
        self.strokes[a..=b].reverse();
        self.id[a..=b].reverse();
        for k in a..=b {
            self.strokes[k] = self.strokes[k].reversed();
            self.pos[self.id[k]] = k;
        }
    }

    /// 2-opt: reversing positions `a..=b` changes the travel into `a` and out of `b`.
    fn two_opt_gain(&self, a: usize, b: usize) -> f64 {
        let p = self.before(a);
        let before = self.gap(a) + self.to_next(self.strokes[b].to, b + 1);
        let after = (self.strokes[b].to - p).norm() + self.to_next(self.strokes[a].from, b + 1);
        before - after
    }

    /// Or-opt: the gain of moving positions `a..a+len` to just before position `to`
    /// (outside the run), turned round if `flip`.
    fn or_opt_gain(&self, a: usize, len: usize, to: usize, flip: bool) -> f64 {
        let b = a + len - 1;
        let (first, last) = if flip {
            (self.strokes[b].to, self.strokes[a].from)
        } else {
            (self.strokes[a].from, self.strokes[b].to)
        };
        let removed = self.gap(a) + self.to_next(self.strokes[b].to, b + 1)
            - self.to_next(self.before(a), b + 1);
        let p = self.before(to);
        let inserted = (first - p).norm() + self.to_next(last, to) - self.to_next(p, to);
        removed - inserted
    }

    /// Tries, for each of the `count` longest jumps, every 2-opt that removes it with any
    /// other jump, and makes the best of each that gains. Returns the strokes at the ends
    /// of the runs it reversed.
    fn remove_long_jumps(&mut self, count: usize) -> Vec<usize> {
        let n = self.strokes.len();
        // Jump k leads into position k; jump n leads home (or nowhere, if the end is free).
        let mut jumps: Vec<(f64, usize)> = (0..=n).map(|k| (self.gap(k), k)).collect();
        jumps.sort_by(|a, b| b.0.total_cmp(&a.0));
        jumps.truncate(count);
        let mut touched = Vec::new();
        for (_, k) in jumps {
            let best = (0..=n)
                .filter(|&m| m != k)
                .map(|m| (k.min(m), k.max(m) - 1))
                .filter(|(a, b)| a <= b && b - a < self.max_reverse)
                .map(|(a, b)| (self.two_opt_gain(a, b), a, b))
                .max_by(|x, y| x.0.total_cmp(&y.0));
            if let Some((_, a, b)) = best.filter(|b| b.0 > 1e-9) {
                self.reverse(a, b);
                touched.extend([self.id[a], self.id[b]]);
            }
        }
        touched
    }

    /// Pen-up travel of the whole tour.
    fn length(&self) -> f64 {
        (0..=self.strokes.len()).map(|k| self.gap(k)).sum()
    }

    /// The strokes at and beside the stroke `s` in the tour.
    fn around(&self, s: usize) -> impl Iterator<Item = usize> + '_ {
        let k = self.pos[s];
        (k.saturating_sub(1)..(k + 2).min(self.strokes.len())).map(|k| self.id[k])
    }

    /// Moves positions `a..a + len` to just before position `to` (outside the run),
    /// turned round if `flip`, shifting only what lies between.
    fn move_run(&mut self, a: usize, len: usize, to: usize, flip: bool) {
        let (lo, hi, at) = if to > a {
            self.strokes[a..to].rotate_left(len);
            self.id[a..to].rotate_left(len);
            (a, to, to - len)
        } else {
            self.strokes[to..a + len].rotate_right(len);
            self.id[to..a + len].rotate_right(len);
            (to, a + len, to)
        };
        if flip {
            self.strokes[at..at + len].reverse();
            self.id[at..at + len].reverse();
            for s in &mut self.strokes[at..at + len] {
                *s = s.reversed();
            }
        }
        for k in lo..hi {
            self.pos[self.id[k]] = k;
        }
    }
}

/// The nearest stroke ends to each stroke end: for stroke i, end 0 is where it starts
/// in the input, end 1 where it ends; each list holds (stroke, end) pairs. The `k` nearest
/// ends of any stroke, and the `k` nearest on other lines: a crease's own dashes crowd
/// its ends, and the moves worth most jump to another crease.
fn nearest_ends(strokes: &[Stroke], k: usize) -> Vec<[Vec<(usize, usize)>; 2]> {
    let points: Vec<Vec2> = strokes.iter().flat_map(|s| [s.from, s.to]).collect();
    let (lo, hi) = points.iter().fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let cells = ((points.len() as f64 / 4.0).sqrt().ceil() as i64).max(1);
    let size = ((hi - lo).max() / cells as f64).max(1e-9);
    let key = |p: Vec2| (((p.x - lo.x) / size) as i64, ((p.y - lo.y) / size) as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in points.iter().enumerate() {
        grid.entry(key(*p)).or_default().push(i);
    }
    let near = |i: usize| -> Vec<(usize, usize)> {
        let (cx, cy) = key(points[i]);
        let line = strokes[i / 2].line;
        let mut any: Vec<(f64, usize)> = Vec::new();
        let mut other: Vec<(f64, usize)> = Vec::new();
        let mut ring = 0;
        // Rings until both lists are full and the next ring cannot hold a nearer end.
        loop {
            for x in cx - ring..=cx + ring {
                for y in cy - ring..=cy + ring {
                    if (x - cx).abs() != ring && (y - cy).abs() != ring {
                        continue;
                    }
                    for &j in grid.get(&(x, y)).into_iter().flatten() {
                        if j / 2 == i / 2 {
                            continue;
                        }
                        let d = (points[j] - points[i]).norm();
                        any.push((d, j));
                        if strokes[j / 2].line != line {
                            other.push((d, j));
                        }
                    }
                }
            }
            let full = |v: &mut Vec<(f64, usize)>| {
                v.sort_by(|a, b| a.0.total_cmp(&b.0));
                v.len() >= k && v[k - 1].0 <= ring as f64 * size
            };
            let (a, b) = (full(&mut any), full(&mut other));
            if (a && b) || ring > cells + 1 {
                break;
            }
            ring += 1;
        }
        any.truncate(k);
        other.truncate(k);
        any.extend(
            other
                .into_iter()
                .filter(|o| !any.contains(o))
                .collect::<Vec<_>>(),
        );
        any.into_iter().map(|(_, j)| (j / 2, j % 2)).collect()
    };
    (0..strokes.len())
        .map(|s| [near(2 * s), near(2 * s + 1)])
        .collect()
}

/// Tries the moves that join end `e` of stroke `s` to end `f` of stroke `t` (ends as in
/// `input`): a 2-opt when both ends lead or both trail their strokes, else an Or-opt that
/// carries a run of up to three strokes at `s` to beside `t`. Makes the first that gains.
fn try_moves(
    tour: &mut Tour,
    input: &[Stroke],
    (s, e): (usize, usize),
    (t, f): (usize, usize),
) -> bool {
    let leads = |tour: &Tour, s: usize, e: usize| {
        let end = if e == 0 { input[s].from } else { input[s].to };
        (tour.strokes[tour.pos[s]].from - end).norm() < 1e-12
    };
    let (i, j) = (tour.pos[s], tour.pos[t]);
    let (lo, hi) = (i.min(j), i.max(j));
    let two_opt = match (leads(tour, s, e), leads(tour, t, f)) {
        // End to end: reverse what lies after the first up to the second.
        (false, false) => Some((lo + 1, hi)),
        // Start to start: reverse from the first up to what lies before the second.
        (true, true) => hi.checked_sub(1).map(|h| (lo, h)),
        _ => None,
    };
    if let Some((a, b)) = two_opt.filter(|(a, b)| a <= b && b - a < tour.max_reverse) {
        if tour.two_opt_gain(a, b) > 1e-9 {
            tour.reverse(a, b);
            return true;
        }
    }
    let n = tour.strokes.len();
    for len in 1..=3usize {
        for a in [i, (i + 1).saturating_sub(len)] {
            if a + len > n || !(a..a + len).contains(&i) || (a..a + len).contains(&j) {
                continue;
            }
            for to in [j, j + 1] {
                if (a..=a + len).contains(&to) {
                    continue;
                }
                for flip in [false, true] {
                    if tour.or_opt_gain(a, len, to, flip) > 1e-9 {
                        tour.move_run(a, len, to, flip);
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Strokes whose ends may still have a move that gains, each listed once.
struct Worklist {
    queue: std::collections::VecDeque<usize>,
    queued: Vec<bool>,
}

impl Worklist {
    fn all(n: usize) -> Worklist {
        Worklist {
            queue: (0..n).collect(),
            queued: vec![true; n],
        }
    }

    /// Lists the strokes at and beside each of `strokes` in the tour again.
    fn revisit(&mut self, tour: &Tour, strokes: &[usize]) {
        for &s in strokes {
            let again: Vec<usize> = tour.around(s).collect();
            for k in again {
                if !self.queued[k] {
                    self.queued[k] = true;
                    self.queue.push_back(k);
                }
            }
        }
    }
}

/// Moves between near ends until none gains, revisiting only strokes next to a change;
/// then every 2-opt that removes one of the longest jumps (near ends cannot see a move
/// whose new jumps are both long), until neither gains. A long-jump round costs
/// `jumps × n`, bounded so a 100k-stroke sheet routes in seconds.
fn local_search(
    tour: &mut Tour,
    input: &[Stroke],
    neighbours: &[[Vec<(usize, usize)>; 2]],
    work: &mut Worklist,
    long_jumps: bool,
) {
    let jumps = (4_000_000 / input.len()).clamp(8, 256);
    for _round in 0..8 {
        while let Some(s) = work.queue.pop_front() {
            work.queued[s] = false;
            let moved = neighbours[s].iter().enumerate().find_map(|(e, near)| {
                near.iter()
                    .find(|&&(t, f)| try_moves(tour, input, (s, e), (t, f)))
                    .map(|&(t, _)| t)
            });
            if let Some(t) = moved {
                work.revisit(tour, &[s, t]);
            }
        }
        let touched = if long_jumps {
            tour.remove_long_jumps(jumps)
        } else {
            Vec::new()
        };
        if touched.is_empty() {
            break;
        }
        work.revisit(tour, &touched);
    }
}

/// Improves a tour by 2-opt and Or-opt moves until none gains (no kicks).
fn polish(order: &mut Vec<Stroke>, start: Vec2, end: Option<Vec2>) {
    let n = order.len();
    if n < 2 {
        return;
    }
    let input = order.clone();
    let neighbours = nearest_ends(&input, 8);
    let mut tour = Tour::new(input.clone(), start, end);
    local_search(&mut tour, &input, &neighbours, &mut Worklist::all(n), true);
    *order = tour.strokes;
}

/// Improves a tour by 2-opt and Or-opt moves until none gains, then by iterated local
/// search: a seeded random double bridge (three nearby cuts, the two middle runs
/// swapped), a local search around it, kept only if the tour got shorter.
fn improve(order: &mut Vec<Stroke>, start: Vec2, end: Option<Vec2>) {
    let n = order.len();
    if n < 2 {
        return;
    }
    let input = order.clone();
    let neighbours = nearest_ends(&input, 8);
    let mut tour = Tour::new(input.clone(), start, end);
    local_search(&mut tour, &input, &neighbours, &mut Worklist::all(n), true);
    // Kicks cost about n each (a copy and a length) and a local repair: kept to about
    // a tenth of a second on a sheet of a thousand creases.
    let kicks = if n >= 8 { (100_000 / n).min(1_000) } else { 0 };
    let mut best = tour.length();
    let mut seed = 0x9e3779b97f4a7c15u64;
    let mut random = |below: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % below as u64) as usize
    };
    for _ in 0..kicks {
        let saved = (tour.strokes.clone(), tour.id.clone());
        let span = 30.min(n / 4).max(1);
        let p1 = 1 + random(n - 3 * span);
        let p2 = p1 + 1 + random(span);
        let p3 = p2 + 1 + random(span);
        tour.strokes[p1..p3].rotate_left(p2 - p1);
        tour.id[p1..p3].rotate_left(p2 - p1);
        for k in p1..p3 {
            tour.pos[tour.id[k]] = k;
        }
        let mut work = Worklist {
            queue: Default::default(),
            queued: vec![false; n],
        };
        let cuts: Vec<usize> = [p1, p1 + p3 - p2, p3]
            .iter()
            .flat_map(|&k| [k - 1, k.min(n - 1)])
            .map(|k| tour.id[k])
            .collect();
        work.revisit(&tour, &cuts);
        // Near moves only: a kick is local, and its repair should cost little.
        local_search(&mut tour, &input, &neighbours, &mut work, false);
        let length = tour.length();
        if length < best - 1e-9 {
            best = length;
        } else {
            (tour.strokes, tour.id) = saved;
            for (k, &i) in tour.id.iter().enumerate() {
                tour.pos[i] = k;
            }
        }
    }
    *order = tour.strokes;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pen for mountains and valleys (as on a cutter), or one each.
    fn tools(shared: bool) -> BTreeMap<LineKind, ToolSetting> {
        let tool = |pen| ToolSetting {
            pen,
            speed: None,
            force: None,
        };
        BTreeMap::from([
            (LineKind::Cut, tool(1)),
            (LineKind::Mountain, tool(2)),
            (LineKind::Valley, tool(if shared { 2 } else { 3 })),
        ])
    }

    fn travel(v: &[Stroke]) -> f64 {
        let mut at = Vec2::zeros();
        let mut t = 0.0;
        for x in v {
            t += (x.from - at).norm();
            at = x.to;
        }
        t + at.norm()
    }

    fn s(x0: f64, y0: f64, x1: f64, y1: f64) -> Stroke {
        Stroke {
            kind: LineKind::Valley,
            from: Vec2::new(x0, y0),
            to: Vec2::new(x1, y1),
            line: 0,
        }
    }

    #[test]
    fn routing_keeps_every_stroke_and_cuts_travel_against_input_order() {
        // A zig-zag of short strokes, each on its own line, given in a scrambled order.
        let mut strokes: Vec<Stroke> = (0..40)
            .map(|i| Stroke {
                line: i,
                ..s(i as f64 * 5.0, 0.0, i as f64 * 5.0, 3.0)
            })
            .collect();
        strokes.reverse();
        strokes.swap(3, 30);
        let routed = route(&strokes, &tools(true));
        assert_eq!(routed.len(), strokes.len());
        for st in &strokes {
            assert!(routed.iter().any(|r| *r == *st || r.reversed() == *st));
        }
        let travel = |v: &[Stroke]| {
            let mut at = Vec2::zeros();
            let mut t = 0.0;
            for x in v {
                t += (x.from - at).norm();
                at = x.to;
            }
            t
        };
        assert!(travel(&routed) < 0.5 * travel(&strokes));
        // Serpentine: alternate strokes go back the other way, so each hop is 5 mm.
        assert!(travel(&routed) < 39.0 * 5.0 + 1.0);
    }

    #[test]
    fn kinds_on_one_pen_are_one_tour_and_the_outline_comes_last() {
        // A checkerboard of short strokes, mountains and valleys alternating, and an
        // outline around it: on one pen the creases are cut in one sweep, on two pens
        // each pen sweeps the whole board.
        let mut strokes = Vec::new();
        for i in 0..12 {
            for j in 0..12 {
                let (x, y) = (10.0 + 5.0 * i as f64, 10.0 + 5.0 * j as f64);
                strokes.push(Stroke {
                    kind: if (i + j) % 2 == 0 {
                        LineKind::Mountain
                    } else {
                        LineKind::Valley
                    },
                    line: 12 * i + j,
                    ..s(x, y, x + 1.0, y + 1.0)
                });
            }
        }
        for (a, b) in [((5.0, 5.0), (75.0, 5.0)), ((75.0, 5.0), (75.0, 75.0))] {
            strokes.push(Stroke {
                kind: LineKind::Cut,
                line: 1000 + strokes.len(),
                ..s(a.0, a.1, b.0, b.1)
            });
        }
        let one = route(&strokes, &tools(true));
        let two = route(&strokes, &tools(false));
        for routed in [&one, &two] {
            assert_eq!(routed.len(), strokes.len());
            let first_cut = routed.iter().position(|r| r.kind == LineKind::Cut).unwrap();
            assert!(routed[first_cut..].iter().all(|r| r.kind == LineKind::Cut));
        }
        // Two pens: all of one kind, then all of the other.
        let changes = |v: &[Stroke]| v.windows(2).filter(|w| w[0].kind != w[1].kind).count();
        assert_eq!(changes(&two), 2);
        assert!(
            changes(&one) > 50,
            "one pen mixes the kinds: {}",
            changes(&one)
        );
        assert!(
            travel(&one) < 0.8 * travel(&two),
            "one tour {:.0} mm, two {:.0} mm",
            travel(&one),
            travel(&two)
        );
    }

    #[test]
    fn improving_the_tour_never_loses_to_nearest_neighbour_and_reaches_the_optimum_on_small_cases()
    {
        // Seeded scatters of strokes: the improved tour is no longer than the greedy one
        // on every seed, and on six strokes (every order and direction tried) it is within
        // 10% of the best tour.
        let mut seed = 12345u64;
        let mut rand = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 100.0
        };
        for case in 0..20 {
            let n = if case < 10 { 6 } else { 200 };
            let strokes: Vec<Stroke> = (0..n)
                .map(|line| {
                    let (x, y) = (rand(), rand());
                    Stroke {
                        line,
                        ..s(x, y, x + rand() / 10.0, y + rand() / 10.0)
                    }
                })
                .collect();
            let routed = route(&strokes, &tools(true));
            let greedy = nearest_neighbour_only(&strokes, &tools(true));
            assert!(travel(&routed) <= travel(&greedy) + 1e-9, "case {case}");
            if n == 6 {
                let best = best_tour(&strokes);
                assert!(
                    travel(&routed) <= 1.1 * best + 1e-9,
                    "case {case}: {:.1} against the best {best:.1}",
                    travel(&routed)
                );
            }
        }
    }

    /// The shortest closed tour from the origin over every order and direction.
    fn best_tour(strokes: &[Stroke]) -> f64 {
        fn go(left: &mut Vec<Stroke>, at: Vec2, so_far: f64, best: &mut f64) {
            if so_far >= *best {
                return;
            }
            if left.is_empty() {
                *best = best.min(so_far + at.norm());
                return;
            }
            for k in 0..left.len() {
                let s = left.remove(k);
                for t in [s, s.reversed()] {
                    go(left, t.to, so_far + (t.from - at).norm(), best);
                }
                left.insert(k, s);
            }
        }
        let mut best = f64::INFINITY;
        go(&mut strokes.to_vec(), Vec2::zeros(), 0.0, &mut best);
        best
    }

    #[test]
    fn a_creases_dashes_form_one_chain_in_order_along_it() {
        // Three creases of five dashes each, the dashes given scrambled and some turned
        // round: each becomes one chain, dash after dash in one direction, so the tour
        // can move and turn whole creases.
        let mut strokes = Vec::new();
        for line in 0..3 {
            for k in [3, 0, 4, 1, 2] {
                let (x, y) = (10.0 + 20.0 * line as f64, 10.0 + 4.0 * k as f64);
                let dash = Stroke {
                    line,
                    ..s(x, y, x, y + 3.0)
                };
                strokes.push(if k % 2 == 0 { dash.reversed() } else { dash });
            }
        }
        let chains = chains(&strokes);
        assert_eq!(chains.len(), 3);
        for run in &chains {
            assert_eq!(run.len(), 5);
            assert!(run.iter().all(|r| r.line == run[0].line), "{run:?}");
            for w in run.windows(2) {
                let hop = (w[1].from - w[0].to).norm();
                assert!((hop - 1.0).abs() < 1e-12, "the next dash along: {hop}");
            }
        }
        let routed = route(&strokes, &tools(true));
        assert_eq!(routed.len(), 15);
    }
}
