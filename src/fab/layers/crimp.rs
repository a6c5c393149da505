//! One vertex at a time, in linear passes: whether the creases round a vertex can be
//! stacked flat at all, decided by repeated crimps (Demaine & O'Rourke, *Geometric
//! Folding Algorithms*, §12.1: a sector no wider than its two neighbours, bounded by a
//! mountain and a valley, folds as a crimp, and the vertex folds flat exactly when what
//! the crimp leaves does). It runs before the pair search, so a vertex where hundreds of
//! faces stack on one point and no order exists is answered without building the n³
//! transitivity of its faces.

use crate::mesh::{Assignment, Mesh, Vec2};

/// Sector angles (radians, round the vertex) and the crease before each sector
/// (`mountain[i]` bounds sectors i − 1 and i): whether the vertex folds flat. Kawasaki's
/// condition is taken as already checked (the faces close up). Sectors within `tie`
/// (radians) of the narrowest count as narrowest: a file's rounding makes equal sectors
/// differ by about that.
pub(super) fn crimps_flat(sectors: &[f64], mountain: &[bool], tie: f64) -> bool {
    let (mut sectors, mut mountain) = (sectors.to_vec(), mountain.to_vec());
    while sectors.len() > 2 {
        let n = sectors.len();
        let least = sectors.iter().copied().fold(f64::INFINITY, f64::min);
        // A narrowest sector whose two creases differ: crimping it keeps the answer.
        let Some(i) =
            (0..n).find(|&i| sectors[i] <= least + tie && mountain[i] != mountain[(i + 1) % n])
        else {
            // Every narrowest sector is bounded by two creases of one kind: the sector
            // would have to wrap both neighbours the same way, and they are wider.
            return false;
        };
        let (before, after) = ((i + n - 1) % n, (i + 1) % n);
        let merged = sectors[before] - sectors[i] + sectors[after];
        // Remove sector i and its neighbours, put the merged one where `before` was;
        // remove the creases i and i + 1 (those round sector i).
        let mut next_sectors = Vec::with_capacity(n - 2);
        let mut next_mountain = Vec::with_capacity(n - 2);
        for (k, &s) in sectors.iter().enumerate() {
            if k != i && k != after {
                next_sectors.push(if k == before { merged } else { s });
            }
        }
        for (k, &m) in mountain.iter().enumerate() {
            if k != i && k != after {
                next_mountain.push(m);
            }
        }
        // The merged sector is bounded by the crease before `before` and the one after
        // `after`; with i and i + 1 removed the order round the vertex is kept.
        sectors = next_sectors;
        mountain = next_mountain;
    }
    // Two sectors of π: one straight line, folded one way along its whole length.
    sectors.len() < 2 || mountain[0] == mountain[1]
}

/// The first interior vertex whose folded creases cannot be stacked flat, with the faces
/// round it. Lines that stay flat do not bound sectors; a vertex with no folded crease,
/// or with a crease folded to another multiple of π (merged creases, §4), is left to the
/// pair search.
pub(super) fn first_unstackable_vertex(
    mesh: &Mesh,
    folds: impl Fn(usize) -> bool,
) -> Option<(usize, Vec<usize>)> {
    let cp = mesh.crease_pattern()?;
    let topo = mesh.topology();
    for (v, fan) in topo.fans.iter().enumerate() {
        if fan.boundary || fan.faces.is_empty() {
            continue;
        }
        let creased: Vec<usize> = (0..fan.spokes.len())
            .filter(|&k| folds(fan.spokes[k]))
            .collect();
        let merged = creased.iter().any(|&k| {
            mesh.edges()[fan.spokes[k]].target.abs()
                > std::f64::consts::PI + crate::tolerance::SAME_ANGLE_RADIANS
        });
        // A vertex with a crease whose side is open (unassigned) is the pair search's.
        let open = creased
            .iter()
            .any(|&k| mesh.edges()[fan.spokes[k]].assignment == Assignment::Unassigned);
        if creased.len() < 2 || merged || open {
            continue;
        }
        let corner = |f: usize| {
            let face = mesh.faces()[f];
            let k = face.iter().position(|&x| x == v).expect("fan face holds v");
            let (a, b, c) = (cp[face[k]], cp[face[(k + 1) % 3]], cp[face[(k + 2) % 3]]);
            angle_between(b - a, c - a)
        };
        let faces = fan.faces.len();
        let mut sectors = Vec::with_capacity(creased.len());
        for (j, &start) in creased.iter().enumerate() {
            let end = creased[(j + 1) % creased.len()];
            let mut sum = 0.0;
            let mut k = start;
            loop {
                sum += corner(fan.faces[k]);
                k = (k + 1) % faces;
                if k == end {
                    break;
                }
            }
            sectors.push(sum);
        }
        let mountain: Vec<bool> = creased
            .iter()
            .map(|&k| mesh.edges()[fan.spokes[k]].assignment == Assignment::Mountain)
            .collect();
        // What the file's rounding can move a spoke by, as an angle at the vertex.
        let shortest = fan
            .spokes
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edges()[e].vertices;
                (cp[a] - cp[b]).norm()
            })
            .fold(f64::INFINITY, f64::min);
        let tie = 1e-9 + 4.0 * mesh.coordinate_precision / shortest;
        if !crimps_flat(&sectors, &mountain, tie) {
            return Some((v, fan.faces.clone()));
        }
    }
    None
}

fn angle_between(a: Vec2, b: Vec2) -> f64 {
    a.perp(&b).abs().atan2(a.dot(&b))
}

#[cfg(test)]
mod tests {
    use super::crimps_flat;
    use std::f64::consts::PI;

    /// Brute force: a vertex folds flat when some order of its sectors' layers keeps
    /// every crease's side and no two creases' bends cross (single-vertex layer
    /// ordering, checked on every permutation of a few sectors).
    fn brute(sectors: &[f64], mountain: &[bool]) -> bool {
        let n = sectors.len();
        // Folded positions: sector i spans [s_i, s_i + ±θ_i] on a line (angles unrolled).
        let mut start = vec![0.0; n + 1];
        for i in 0..n {
            let dir = if i % 2 == 0 { 1.0 } else { -1.0 };
            start[i + 1] = start[i] + dir * sectors[i];
        }
        if start[n].abs() > 1e-9 {
            return false;
        }
        let span = |i: usize| (start[i].min(start[i + 1]), start[i].max(start[i + 1]));
        let mut order: Vec<usize> = (0..n).collect();
        permutations(&mut order, 0, &mut |level: &[usize]| {
            let mut height = vec![0; n];
            for (h, &f) in level.iter().enumerate() {
                height[f] = h;
            }
            // Crease c joins sector c − 1 and c at folded position start[c]; sector i
            // faces up when i is even. Mountain: with the sector before face up, the next
            // lies below it.
            for (c, &m) in mountain.iter().enumerate() {
                let (a, b) = ((c + n - 1) % n, c);
                let a_up = a % 2 == 0;
                let b_below = m == a_up;
                if (height[b] < height[a]) != b_below {
                    return false;
                }
            }
            // Bends at one position, on one side, must nest; a sector passing the
            // position may not lie between a bend's two sectors.
            for c in 0..n {
                let (a, b) = ((c + n - 1) % n, c);
                let (lo, hi) = (height[a].min(height[b]), height[a].max(height[b]));
                for (f, &h) in height.iter().enumerate() {
                    if f == a || f == b {
                        continue;
                    }
                    let (s0, s1) = span(f);
                    let inside = h > lo && h < hi;
                    if inside && s0 < start[c] - 1e-12 && s1 > start[c] + 1e-12 {
                        return false;
                    }
                }
                for d in c + 1..n {
                    if (start[c] - start[d]).abs() > 1e-12 {
                        continue;
                    }
                    let (e, g) = ((d + n - 1) % n, d);
                    let same_side = (span(a).0 + span(a).1 - 2.0 * start[c]).signum()
                        == (span(e).0 + span(e).1 - 2.0 * start[d]).signum();
                    let (lo2, hi2) = (height[e].min(height[g]), height[e].max(height[g]));
                    let cross =
                        (lo < lo2 && lo2 < hi && hi < hi2) || (lo2 < lo && lo < hi2 && hi2 < hi);
                    if same_side && cross {
                        return false;
                    }
                }
            }
            true
        })
    }

    fn permutations(v: &mut Vec<usize>, k: usize, ok: &mut dyn FnMut(&[usize]) -> bool) -> bool {
        if k == v.len() {
            return ok(v);
        }
        for i in k..v.len() {
            v.swap(k, i);
            if permutations(v, k + 1, ok) {
                v.swap(k, i);
                return true;
            }
            v.swap(k, i);
        }
        false
    }

    #[test]
    fn crimps_agree_with_brute_force_on_small_vertices() {
        // Degree-4 and degree-6 vertices satisfying Kawasaki, every assignment.
        let cases: Vec<Vec<f64>> = vec![
            vec![0.5 * PI; 4],
            vec![0.4, 0.4, PI - 0.4, PI - 0.4],
            vec![0.3, 0.9, PI - 0.3, PI - 0.9],
            vec![PI / 3.0; 6],
            vec![0.4, 0.6, 0.9, 0.7, PI - 1.3, PI - 1.3],
            vec![0.5, 0.5, 0.7, 0.5, PI - 1.2, PI - 1.0],
        ];
        let mut compared = 0;
        for sectors in cases {
            let n = sectors.len();
            let alternating: f64 = sectors
                .iter()
                .enumerate()
                .map(|(i, s)| if i % 2 == 0 { *s } else { -*s })
                .sum();
            let total: f64 = sectors.iter().sum();
            if alternating.abs() > 1e-9 || (total - 2.0 * PI).abs() > 1e-9 {
                continue;
            }
            for bits in 0..1u32 << n {
                let mountain: Vec<bool> = (0..n).map(|k| bits >> k & 1 == 1).collect();
                assert_eq!(
                    crimps_flat(&sectors, &mountain, 1e-9),
                    brute(&sectors, &mountain),
                    "sectors {sectors:?}, mountain {mountain:?}"
                );
                compared += 1;
            }
        }
        assert_eq!(compared, 3 * 16 + 3 * 64, "a case broke Kawasaki");
    }

    #[test]
    fn a_wide_fan_alternating_mountain_and_valley_is_refused_fast() {
        // 2,000 equal sectors, M V M V …: Maekawa's |M − V| = 2 fails, and so must the
        // crimps (they pair off every crease and leave two of opposite kinds).
        let n = 2000;
        let sectors = vec![2.0 * PI / n as f64; n];
        let alternating: Vec<bool> = (0..n).map(|k| k % 2 == 0).collect();
        assert!(!crimps_flat(&sectors, &alternating, 1e-9));
        // One valley turned to a mountain: M − V = 2, and it folds.
        let mut one_more = alternating.clone();
        one_more[1] = true;
        assert!(crimps_flat(&sectors, &one_more, 1e-9));
    }
}
