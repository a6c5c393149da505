//! Thick panels: a sheet of thickness `h` folds only as far as its panels let it. The
//! offset-panel technique (Edmondson et al.; Tachi's thick rigid origami; reviewed by
//! Lang et al. 2018) keeps a hinge membrane at one surface and cuts the thick panels
//! apart, each set back from every fold by half a gap `g`, so the panels on the fold's
//! inner side meet only once the fold has turned far enough.
//!
//! **The gap.** Take the hinge line at the membrane, the panels of thickness `h` on the
//! side the fold closes towards, each panel's edge face normal to the sheet and `g/2`
//! from the hinge. Folding by ρ turns each panel by ρ/2 about the hinge; the inner top
//! corner of a panel starts at angle atan2(h, g/2) from the sheet and reaches the
//! mid-plane of the fold, where it meets its neighbour's, when
//! atan2(h, g/2) + ρ/2 = π/2, that is at
//!
//! ```text
//!     ρ_max = 2·atan(g / 2h)        (the dihedral angle between the panels: π − ρ_max)
//! ```
//!
//! so a fold of angle ρ needs a gap `g = 2·h·tan(ρ/2)`. The gap grows without bound as
//! ρ → π: a fold closed flat takes no gap at all, it takes a second hinge, so folds past
//! [`MAX_GAP_FOLD`] are named instead (and get that fold's gap).
//!
//! The panels sit on the sheet's front, the membrane under them. A valley closes towards
//! the front, so its panels meet and it takes the gap; a mountain closes towards the
//! membrane, its panels turn apart, and it takes none.

use super::layout::Sheet;
use crate::mesh::{Mesh, Vec2};
use std::collections::HashMap;

/// The gap (mm) a fold of `fold` radians needs between panels `thickness` mm thick.
pub fn gap(thickness: f64, fold: f64) -> f64 {
    2.0 * thickness * (fold.abs() / 2.0).tan()
}

/// The largest fold (radians) panels `thickness` mm thick, `gap` mm apart, allow.
pub fn largest_fold(thickness: f64, gap: f64) -> f64 {
    2.0 * (gap / (2.0 * thickness)).atan()
}

/// The largest fold a gap is laid out for, 2·atan(2) ≈ 126.9°: there the gap is four
/// times the thickness, and it doubles again by 151.9°.
pub const MAX_GAP_FOLD: f64 = 2.2142974355881813;

/// A panel of the sheet cut out for the offset-panel technique.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Its outline on the sheet, counter-clockwise, set back from every fold by half its
    /// gap (mm).
    pub outline: Vec<Vec2>,
    /// Its faces in the design.
    pub faces: Vec<usize>,
}

/// The panels of a sheet, and what its folds need.
#[derive(Clone, Debug, PartialEq)]
pub struct HingeGaps {
    /// Sheet thickness, mm.
    pub thickness: f64,
    /// For each edge of the design that is a fold: (edge, fold angle (radians), gap (mm)).
    pub folds: Vec<(usize, f64, f64)>,
    /// The panels, outlines set back.
    pub panels: Vec<Panel>,
    /// Valleys folded past [`MAX_GAP_FOLD`], given that fold's gap.
    pub too_far: Vec<usize>,
}

/// Panels are the faces joined by flat lines: the union of faces across every edge that
/// is not a fold and not the boundary.
fn panel_faces(mesh: &Mesh, is_fold: &[bool]) -> Vec<Vec<usize>> {
    let mut uf = crate::mesh::UnionFind::new(mesh.faces().len());
    for (e, sides) in mesh.topology().edge_faces.iter().enumerate() {
        if let [Some(a), Some(b)] = *sides {
            if !is_fold[e] {
                uf.union(a, b);
            }
        }
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for f in 0..mesh.faces().len() {
        groups.entry(uf.find(f)).or_default().push(f);
    }
    let mut panels: Vec<Vec<usize>> = groups.into_values().collect();
    panels.sort();
    panels
}

/// The outline of a panel on the sheet as a loop of (vertex, edge to the next vertex);
/// `None` when the panel's boundary is not one simple loop (a hole, or two corners that
/// touch).
fn outline_loop(mesh: &Mesh, faces: &[usize]) -> Option<Vec<(usize, usize)>> {
    let inside: std::collections::HashSet<usize> = faces.iter().copied().collect();
    let topology = mesh.topology();
    let mut next: HashMap<usize, (usize, usize)> = HashMap::new();
    for &f in faces {
        let [a, b, c] = mesh.faces()[f];
        for (k, (from, to)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
            let e = topology.face_edges[f][k];
            let across = topology.edge_faces[e]
                .iter()
                .flatten()
                .any(|&g| g != f && inside.contains(&g));
            if !across && next.insert(from, (to, e)).is_some() {
                return None;
            }
        }
    }
    let &start = next.keys().min()?;
    let mut out = Vec::new();
    let mut v = start;
    loop {
        let (to, e) = next[&v];
        out.push((v, e));
        v = to;
        if v == start {
            break;
        }
        if out.len() > next.len() {
            return None;
        }
    }
    (out.len() == next.len()).then_some(out)
}

/// `points` (a closed polygon) with each edge `i` (from point `i` to `i + 1`) moved
/// inwards by `offsets[i]`; `None` if an edge would turn round or vanish (the panel is too
/// small for its gaps). Consecutive edges along one line are merged first, keeping the
/// larger offset.
pub fn inset(points: &[Vec2], offsets: &[f64]) -> Option<Vec<Vec2>> {
    let n = points.len();
    let area: f64 = (0..n)
        .map(|i| points[i].perp(&points[(i + 1) % n]))
        .sum::<f64>()
        / 2.0;
    // Counter-clockwise: inwards is the left of each edge.
    let sign = if area > 0.0 { 1.0 } else { -1.0 };
    let mut lines: Vec<(Vec2, Vec2, f64)> = Vec::new(); // (point, unit direction, offset)
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        let d = (b - a).normalize();
        match lines.last_mut() {
            Some((_, dl, off)) if dl.perp(&d).abs() < 1e-9 && dl.dot(&d) > 0.0 => {
                *off = off.max(offsets[i]);
            }
            _ => lines.push((a, d, offsets[i])),
        }
    }
    if lines.len() > 1 {
        let (first, last) = (lines[0], lines[lines.len() - 1]);
        if first.1.perp(&last.1).abs() < 1e-9 && first.1.dot(&last.1) > 0.0 {
            lines[0] = (last.0, first.1, first.2.max(last.2));
            lines.pop();
        }
    }
    let m = lines.len();
    if m < 3 {
        return None;
    }
    let moved: Vec<(Vec2, Vec2)> = lines
        .iter()
        .map(|&(p, d, off)| (p + Vec2::new(-d.y, d.x) * (sign * off), d))
        .collect();
    let meet = |(p, d): (Vec2, Vec2), (q, e): (Vec2, Vec2)| -> Option<Vec2> {
        let den = d.perp(&e);
        (den.abs() > 1e-12).then(|| p + d * ((q - p).perp(&e) / den))
    };
    let corners: Vec<Vec2> = (0..m)
        .map(|i| meet(moved[(i + m - 1) % m], moved[i]))
        .collect::<Option<_>>()?;
    // Every edge keeps its direction and some length.
    for i in 0..m {
        let along = corners[(i + 1) % m] - corners[i];
        if along.dot(&moved[i].1) <= 1e-6 {
            return None;
        }
    }
    Some(corners)
}

/// The gaps a design's folds need in a sheet `thickness` mm thick (each fold's angle
/// from the design's 3D form, or its stated angle for a flat pattern), and its panels
/// laid out on `sheet` with their outlines set back by half a gap from every fold. A
/// panel the gaps would swallow, or whose outline is not one loop, is an error naming it.
pub fn hinge_gaps(mesh: &Mesh, sheet: &Sheet, thickness: f64) -> Result<HingeGaps, String> {
    use super::lines::LineKind;
    let angles = if mesh.has_3d() {
        crate::geometry::fold_angles(mesh)
    } else {
        mesh.edges().iter().map(|e| e.fold_angle).collect()
    };
    let kinds = LineKind::of_mesh(mesh);
    let is_fold: Vec<bool> = kinds
        .iter()
        .map(|k| matches!(k, LineKind::Mountain | LineKind::Valley))
        .collect();
    let mut folds = Vec::new();
    let mut too_far = Vec::new();
    let mut gap_of = vec![0.0; mesh.edges().len()];
    for (e, &fold) in is_fold.iter().enumerate() {
        if !fold {
            continue;
        }
        let rho = angles[e].abs();
        // Only a valley closes towards the panels.
        let g = if kinds[e] == LineKind::Valley {
            if rho > MAX_GAP_FOLD {
                too_far.push(e);
            }
            gap(thickness, rho.min(MAX_GAP_FOLD))
        } else {
            0.0
        };
        gap_of[e] = g;
        folds.push((e, rho, g));
    }
    let mut panels = Vec::new();
    for (n, faces) in panel_faces(mesh, &is_fold).into_iter().enumerate() {
        let ring = outline_loop(mesh, &faces).ok_or_else(|| {
            format!("panel {n} (faces from {}) has a hole or touches itself at a corner: its gaps cannot be laid out", faces[0])
        })?;
        let points: Vec<Vec2> = ring.iter().map(|&(v, _)| sheet.vertices[v]).collect();
        let offsets: Vec<f64> = ring.iter().map(|&(_, e)| gap_of[e] / 2.0).collect();
        let outline = inset(&points, &offsets).ok_or_else(|| {
            format!(
                "panel {n} (faces from {}) is too small for the hinge gaps of {thickness} mm thick sheet: use a thinner material, or fold less",
                faces[0]
            )
        })?;
        panels.push(Panel { outline, faces });
    }
    Ok(HingeGaps {
        thickness,
        folds,
        panels,
        too_far,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: two panels `h` thick on the inner side of a hinge, their edge faces
    /// `g/2` from it, turned ρ/2 each towards the other; the largest ρ at which the
    /// right panel's rectangle stays clear of the mirror plane (its neighbour's mirror).
    fn largest_fold_by_sweep(h: f64, g: f64) -> f64 {
        let corners = [Vec2::new(g / 2.0, 0.0), Vec2::new(g / 2.0, h)];
        let mut rho: f64 = 0.0;
        let step = 1e-5;
        while rho < std::f64::consts::PI {
            let t = rho / 2.0;
            // Turned counter-clockwise about the hinge at the origin.
            let clear = corners.iter().all(|p| p.x * t.cos() - p.y * t.sin() >= 0.0);
            if !clear {
                return rho - step;
            }
            rho += step;
        }
        std::f64::consts::PI
    }

    #[test]
    fn the_gap_formula_matches_a_sweep_of_the_panels() {
        for (h, g) in [(3.0, 1.0), (3.0, 6.0), (0.5, 0.2), (2.0, 12.0)] {
            let swept = largest_fold_by_sweep(h, g);
            assert!(
                (largest_fold(h, g) - swept).abs() < 2e-5,
                "h {h}, g {g}: {} against {swept}",
                largest_fold(h, g)
            );
            assert!((gap(h, largest_fold(h, g)) - g).abs() < 1e-9);
        }
        assert!((MAX_GAP_FOLD - 2.0 * 2.0f64.atan()).abs() < 1e-15);
        assert!((gap(1.0, MAX_GAP_FOLD) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn a_square_insets_by_its_offsets_and_a_tiny_one_is_refused() {
        let sq = [
            Vec2::new(0.0, 0.0),
            Vec2::new(10.0, 0.0),
            Vec2::new(10.0, 10.0),
            Vec2::new(0.0, 10.0),
        ];
        let out = inset(&sq, &[1.0, 0.0, 2.0, 0.5]).unwrap();
        let want = [
            Vec2::new(0.5, 1.0),
            Vec2::new(10.0, 1.0),
            Vec2::new(10.0, 8.0),
            Vec2::new(0.5, 8.0),
        ];
        for w in want {
            assert!(out.iter().any(|p| (p - w).norm() < 1e-12), "{out:?}");
        }
        // Clockwise input insets the same way.
        let mut cw = sq;
        cw.reverse();
        let out = inset(&cw, &[2.0, 0.0, 1.0, 0.5]).unwrap();
        for w in want {
            assert!(out.iter().any(|p| (p - w).norm() < 1e-12), "{out:?}");
        }
        assert!(inset(&sq, &[6.0, 0.0, 6.0, 0.0]).is_none());
        // A side split in two along one line is one side.
        let split = [
            Vec2::new(0.0, 0.0),
            Vec2::new(5.0, 0.0),
            Vec2::new(10.0, 0.0),
            Vec2::new(10.0, 10.0),
            Vec2::new(0.0, 10.0),
        ];
        let out = inset(&split, &[1.0, 0.5, 0.0, 0.0, 0.0]).unwrap();
        assert_eq!(out.len(), 4);
        assert!(out.iter().any(|p| (p - Vec2::new(0.0, 1.0)).norm() < 1e-12));
    }
}
