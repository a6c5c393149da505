//! Improving a tour of reversible strokes: 2-opt (reverse a run) and Or-opt (move a run
//! of up to three strokes, either way round) between each end's nearest ends, every
//! 2-opt that removes one of the longest jumps, and iterated local search with seeded
//! double-bridge kicks. The tour runs from a fixed start, and leaving it from its last
//! stroke costs what the caller says: the way home, the way on to the next tool's
//! strokes, or nothing.

use super::super::toolpath::Stroke;
use crate::mesh::Vec2;
use std::collections::HashMap;

/// A tour of oriented strokes from a fixed start, with each stroke's position so moves
/// can be found from neighbouring ends.
struct Tour<'a> {
    strokes: Vec<Stroke>,
    /// Position in `strokes` of each stroke by its original index.
    pos: Vec<usize>,
    /// Original index of the stroke at each position.
    id: Vec<usize>,
    start: Vec2,
    /// What leaving the tour from a point costs.
    leave: &'a dyn Fn(Vec2) -> f64,
    /// Longest run a 2-opt may reverse: the whole tour up to 5,000 strokes; on larger
    /// sheets reversals cost a pass O(n) each, so they are kept to what a 100k-stroke
    /// sheet routes in seconds with.
    max_reverse: usize,
}

impl<'a> Tour<'a> {
    /// The strokes in the order given.
    fn new(strokes: Vec<Stroke>, start: Vec2, leave: &'a dyn Fn(Vec2) -> f64) -> Tour<'a> {
        let n = strokes.len();
        Tour {
            strokes,
            pos: (0..n).collect(),
            id: (0..n).collect(),
            start,
            leave,
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

    /// Travel from `p` to the stroke at position `i`, or on from the tour for i = n.
    fn to_next(&self, p: Vec2, i: usize) -> f64 {
        match self.strokes.get(i) {
            Some(s) => (s.from - p).norm(),
            None => (self.leave)(p),
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

    /// Or-opt, first half: the travel saved by taking positions `a..a+len` out of the
    /// tour (the jumps into and out of the run, less the jump that closes the gap).
    fn or_opt_removed(&self, a: usize, len: usize) -> f64 {
        let b = a + len - 1;
        self.gap(a) + self.to_next(self.strokes[b].to, b + 1) - self.to_next(self.before(a), b + 1)
    }

    /// Or-opt, second half: the travel added by putting the run `a..a+len` back just
    /// before position `to` (outside the run), turned round if `flip`. The move gains
    /// `or_opt_removed(a, len) - or_opt_inserted(a, len, to, flip)`.
    fn or_opt_inserted(&self, a: usize, len: usize, to: usize, flip: bool) -> f64 {
        let b = a + len - 1;
        let (first, last) = if flip {
            (self.strokes[b].to, self.strokes[a].from)
        } else {
            (self.strokes[a].from, self.strokes[b].to)
        };
        let p = self.before(to);
        (first - p).norm() + self.to_next(last, to) - self.to_next(p, to)
    }

    /// Tries, for each of the `count` longest jumps, every 2-opt that removes it with any
    /// other jump, and makes the best of each that gains. Returns the strokes at the ends
    /// of the runs it reversed.
    fn remove_long_jumps(&mut self, count: usize) -> Vec<usize> {
        let n = self.strokes.len();
        // Jump k leads into position k; jump n leaves the tour.
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
            // Only the k nearest so far can be among the k nearest: a crease's own dashes
            // crowd the rings around its ends, and kept they made every ring's sort longer.
            let full = |v: &mut Vec<(f64, usize)>| {
                v.sort_by(|a, b| a.0.total_cmp(&b.0));
                v.truncate(k);
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
            // The same for every place the run might go: computed once.
            let removed = tour.or_opt_removed(a, len);
            for to in [j, j + 1] {
                if (a..=a + len).contains(&to) {
                    continue;
                }
                for flip in [false, true] {
                    if removed - tour.or_opt_inserted(a, len, to, flip) > 1e-9 {
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

/// Improves a tour by 2-opt and Or-opt moves until none gains, then, if `kick`, by
/// iterated local search: a seeded random double bridge (three nearby cuts, the two
/// middle runs swapped), a local search around it, kept only if the tour got shorter.
pub(super) fn improve(
    order: &mut Vec<Stroke>,
    start: Vec2,
    leave: &dyn Fn(Vec2) -> f64,
    kick: bool,
) {
    let n = order.len();
    if n < 2 {
        return;
    }
    let input = order.clone();
    let neighbours = nearest_ends(&input, 8);
    let mut tour = Tour::new(input.clone(), start, leave);
    local_search(&mut tour, &input, &neighbours, &mut Worklist::all(n), true);
    // A kick costs about n (a copy and a length) and a local repair of ~0.3 ms: about
    // half a second on a sheet of a few hundred creases, where kicks still find gains
    // after thousands of tries (resch: 1,896 mm with a third of these, 1,863 with them,
    // 1,848 with three times more). A short tour (an outline of a few pieces) is done
    // after a few dozen per stroke.
    let kicks = if kick && n >= 8 {
        (300_000 / n).min(3_000).min(50 * n)
    } else {
        0
    };
    let mut best = tour.length();
    let mut rng = crate::random::Rng::new(0x9e3779b97f4a7c15);
    let mut random = |below: usize| rng.below(below);
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
