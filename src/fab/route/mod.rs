//! Ordering strokes to cut less air. One tour per physical tool (kinds that share a pen
//! share a tour: a cutter scores mountains and valleys with one blade), the outline last
//! so the sheet stays held; each tour starts as a nearest-neighbour walk from where the
//! pen is, either way round, and is then improved over the whole tour by 2-opt (reverse a
//! run) and Or-opt (move a run of up to three strokes, either way round), trying only
//! moves that join an end to one of its nearest ends.

use super::lines::LineKind;
use super::toolpath::Stroke;
use super::toolpath::ToolSetting;
use crate::mesh::Vec2;
use std::collections::{BTreeMap, HashMap};
use tour::improve;

mod tour;

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
/// the line dash by dash, so the tour orders whole lines. A curved line's strokes come
/// from scoring in order along it, pointing along it (no one direction orders a curve).
fn chains(group: &[Stroke]) -> Vec<Vec<Stroke>> {
    let mut by_line: BTreeMap<usize, Vec<Stroke>> = BTreeMap::new();
    for s in group {
        by_line.entry(s.line).or_default().push(*s);
    }
    by_line
        .into_values()
        .map(|mut chain| {
            if chain.iter().any(|s| s.bend.is_some()) {
                return chain;
            }
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

/// How hard [`route_with`] searches for a short pen-up travel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RouteSearch {
    /// 2-opt and Or-opt moves, then iterated local search (double-bridge kicks): the
    /// shortest travel crease finds, about half a second on a sheet of a few hundred
    /// creases.
    #[default]
    Full,
    /// 2-opt and Or-opt moves only: a draft job in a fraction of the time, with more
    /// pen-up travel (for checking a layout, not for the job to cut).
    Draft,
}

/// Strokes to cut in order, starting and ending at the origin ([`RouteSearch::Full`]).
pub fn route(strokes: &[Stroke], tools: &BTreeMap<LineKind, ToolSetting>) -> Vec<Stroke> {
    route_with(strokes, tools, RouteSearch::Full)
}

/// Strokes to cut in order, starting and ending at the origin, searched as `search` says.
pub fn route_with(
    strokes: &[Stroke],
    tools: &BTreeMap<LineKind, ToolSetting>,
    search: RouteSearch,
) -> Vec<Stroke> {
    let kicks = search == RouteSearch::Full;
    let groups = tool_groups(strokes, tools);
    let mut out = Vec::with_capacity(strokes.len());
    let mut at = Vec2::zeros();
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
                bend: None,
                ..c[0]
            })
            .collect();
        let mut order = nearest_neighbour(&ends, at);
        // The last tour ends at home; the others go on to the next tool's nearest stroke.
        let next = groups.get(k + 1).map(|g| EndGrid::new(g));
        let leave = |p: Vec2| match &next {
            None => p.norm(),
            Some(grid) => grid.distance(p),
        };
        improve(&mut order, at, &leave, kicks);
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
        improve(&mut tour, at, &leave, kicks);
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
    let ends = EndGrid::new(group);
    let mut done = vec![false; n];
    let mut out = Vec::with_capacity(n);
    let mut at = start;
    for _ in 0..n {
        let Some((i, reversed)) = ends.nearest_where(at, |i| done[i]) else {
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

/// Both ends of every stroke of a group in a square grid of about one stroke per cell,
/// for the nearest not-yet-drawn end.
struct EndGrid<'a> {
    group: &'a [Stroke],
    lo: Vec2,
    cell: f64,
    cells_per_side: i64,
    /// Stroke and whether it is entered at its `to` end, per cell.
    cells: HashMap<(i64, i64), Vec<(usize, bool)>>,
}

impl<'a> EndGrid<'a> {
    fn new(group: &'a [Stroke]) -> Self {
        let (lo, hi) = group.iter().fold(
            (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
            |(lo, hi), s| (lo.inf(&s.from).inf(&s.to), hi.sup(&s.from).sup(&s.to)),
        );
        let extent = (hi - lo).max().max(1e-9);
        let cells_per_side = ((group.len() as f64).sqrt().ceil() as i64).max(1);
        let mut grid = EndGrid {
            group,
            lo,
            cell: extent / cells_per_side as f64,
            cells_per_side,
            cells: HashMap::new(),
        };
        for (i, s) in group.iter().enumerate() {
            let (from, to) = (grid.key(s.from), grid.key(s.to));
            grid.cells.entry(from).or_default().push((i, false));
            grid.cells.entry(to).or_default().push((i, true));
        }
        grid
    }

    fn key(&self, p: Vec2) -> (i64, i64) {
        (
            ((p.x - self.lo.x) / self.cell).floor() as i64,
            ((p.y - self.lo.y) / self.cell).floor() as i64,
        )
    }

    /// Distance from `at` to the nearest end of any stroke.
    fn distance(&self, at: Vec2) -> f64 {
        self.nearest_where(at, |_| false).map_or(0.0, |(i, to)| {
            let s = &self.group[i];
            (if to { s.to } else { s.from } - at).norm()
        })
    }

    /// The stroke (not `done`) with an end nearest `at`, and whether that end is its `to`.
    /// Rings of cells are searched outwards until the best end found is nearer than any
    /// cell not yet searched.
    fn nearest_where(&self, at: Vec2, done: impl Fn(usize) -> bool) -> Option<(usize, bool)> {
        let (cx, cy) = self.key(at);
        let side = self.cells_per_side;
        let mut best: Option<(f64, usize, bool)> = None;
        // The pen may start far outside the grid (its origin beside a small design): the
        // rings nearer than the grid itself are empty, so the search starts at the grid.
        let outside = |c: i64| (-c).max(c - side).max(0);
        let first_ring = outside(cx).max(outside(cy));
        // Grid keys lie in 0..=side on both axes; only cells there are visited, in the
        // same order as a full sweep of the ring, and only the ring's perimeter.
        let span = |c: i64, ring: i64| (-ring).max(-c)..=ring.min(side - c);
        for ring in first_ring..=first_ring + 2 * side + 2 {
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
                    for &(i, reversed) in self.cells.get(&(cx + dx, cy + dy)).into_iter().flatten()
                    {
                        let end = if reversed {
                            self.group[i].to
                        } else {
                            self.group[i].from
                        };
                        let d = (end - at).norm();
                        if !done(i) && best.is_none_or(|(bd, _, _)| d < bd) {
                            best = Some((d, i, reversed));
                        }
                    }
                }
            }
            // Anything found within `ring` cells is closer than whatever lies beyond it.
            if best.is_some_and(|(d, _, _)| d <= ring as f64 * self.cell) {
                break;
            }
        }
        // The rings cover the whole grid, so an undone stroke is always found; the scan is
        // a guard against a grid that rounding left short.
        best.or_else(|| {
            (0..self.group.len())
                .filter(|&i| !done(i))
                .flat_map(|i| [(i, false), (i, true)])
                .map(|(i, r)| {
                    let end = if r {
                        self.group[i].to
                    } else {
                        self.group[i].from
                    };
                    ((end - at).norm(), i, r)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
        })
        .map(|(_, i, r)| (i, r))
    }
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
        Stroke::straight(LineKind::Valley, Vec2::new(x0, y0), Vec2::new(x1, y1), 0)
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
        let mut rng = crate::random::Rng::new(12345);
        let mut rand = move || rng.range(0.0, 100.0);
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
