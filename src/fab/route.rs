//! Ordering strokes to cut less air: by tool (valleys, mountains, then the outline, so the
//! sheet stays held until last), then nearest neighbour from where the pen is, either way
//! round, improved by 2-opt moves within a window.

use super::lines::LineKind;
use super::score::Stroke;
use crate::mesh::Vec2;
use std::collections::HashMap;

/// Strokes to cut in order, starting and ending at the origin.
pub fn route(strokes: &[Stroke]) -> Vec<Stroke> {
    let mut out = Vec::with_capacity(strokes.len());
    let mut at = Vec2::zeros();
    for kind in LineKind::ALL {
        let group: Vec<Stroke> = strokes.iter().copied().filter(|s| s.kind == kind).collect();
        if group.is_empty() {
            continue;
        }
        let mut order = nearest_neighbour(&group, at);
        two_opt(&mut order, at, 60);
        at = order.last().map(|s| s.to).unwrap_or(at);
        out.extend(order);
    }
    out
}

/// Plain nearest neighbour (no 2-opt), for comparison in benchmarks.
pub fn nearest_neighbour_only(strokes: &[Stroke]) -> Vec<Stroke> {
    let mut out = Vec::new();
    let mut at = Vec2::zeros();
    for kind in LineKind::ALL {
        let group: Vec<Stroke> = strokes.iter().copied().filter(|s| s.kind == kind).collect();
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

/// 2-opt on an open path of strokes: reversing a run also reverses each stroke in it.
/// Only pairs within `window` of each other are tried, which keeps it near linear.
fn two_opt(order: &mut [Stroke], start: Vec2, window: usize) {
    let n = order.len();
    if n < 3 {
        return;
    }
    let end_before = |order: &[Stroke], i: usize| if i == 0 { start } else { order[i - 1].to };
    let mut improved = true;
    let mut passes = 0;
    while improved && passes < 8 {
        improved = false;
        passes += 1;
        for i in 0..n - 1 {
            for j in i + 1..n.min(i + window) {
                // Reverse order[i..=j]: travel into i and out of j change.
                let a = end_before(order, i);
                let before = (order[i].from - a).norm()
                    + if j + 1 < n {
                        (order[j + 1].from - order[j].to).norm()
                    } else {
                        0.0
                    };
                let after = (order[j].to - a).norm()
                    + if j + 1 < n {
                        (order[j + 1].from - order[i].from).norm()
                    } else {
                        0.0
                    };
                if after + 1e-9 < before {
                    order[i..=j].reverse();
                    for s in &mut order[i..=j] {
                        *s = s.reversed();
                    }
                    improved = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // A zig-zag of short strokes given in a scrambled order.
        let mut strokes: Vec<Stroke> = (0..40)
            .map(|i| s(i as f64 * 5.0, 0.0, i as f64 * 5.0, 3.0))
            .collect();
        strokes.reverse();
        strokes.swap(3, 30);
        let routed = route(&strokes);
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
}
