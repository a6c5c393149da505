//! A tube in FOLD (issue 31). FOLD has no seam (1.2's `J` joins, `C` cuts), so a tube is
//! written as what other tools can open, the strip it is made from: frame 0 the 3D form
//! (the strip's two seam sides lie on each other), the `creasePattern` frame the strip
//! laid flat, the seam's sides boundary `B`. crease's own `crease:seam` pairs them:
//! `[[a, b], [a2, b2], "M"]` per seam edge, strip vertices `a2`, `b2` being the other
//! copies of `a`, `b`, and the letter the seam crease's own assignment. Reading joins the
//! pairs back into one vertex each: the tube.

use crate::mesh::{edge_key, Assignment, Mesh, MeshParts};
use std::collections::HashMap;

/// One `crease:seam` entry.
pub(super) type SeamEntry = ([usize; 2], [usize; 2], String);

/// A seam crease: its first copy's ends and its assignment.
type SeamCrease = ([usize; 2], Assignment);

/// The strip a tube is written as and its `crease:seam` entries, one JSON array each;
/// `None` when the mesh is not a tube or cannot be cut open (it is then written as it is,
/// closed).
pub(super) fn strip_for_writing(mesh: &Mesh) -> Option<(Mesh, Vec<String>)> {
    if !mesh.is_tube() {
        return None;
    }
    let strip = crate::geometry::unfold::unfold_tube(mesh).ok()?;
    let entries: Vec<String> = strip
        .sides
        .iter()
        .zip(&strip.edges)
        .map(|([[a, b], [c, d]], &e)| {
            let letter = mesh.edges()[e].assignment.fold_letter();
            format!("[[{a}, {b}], [{c}, {d}], \"{letter}\"]")
        })
        .collect();
    Some((strip.sheet, entries))
}

/// Joins the strip's seam sides named by `crease:seam` into a tube: each second copy
/// becomes its first (the two must lie together in the 3D frame), vertices are renumbered
/// without the copies, and the joined edge takes the seam crease's assignment. Returns the
/// tube's parts and its seam as edge keys.
pub(super) fn close(
    parts: MeshParts,
    entries: &[SeamEntry],
) -> Result<(MeshParts, Vec<[usize; 2]>), String> {
    let MeshParts {
        positions,
        faces,
        edges,
        ..
    } = parts;
    let positions =
        positions.ok_or("crease:seam needs the tube's 3D frame (a foldedForm frame)")?;
    let n = positions.len();
    let (mut groups, creases) = join_pairs(&positions, entries)?;
    // Each pair joins into its lower-numbered vertex: a strip written by crease numbers
    // the tube's own vertices first, so the tube reads back with its own numbering.
    let mut lowest = vec![usize::MAX; n];
    for v in 0..n {
        let r = groups.find(v);
        lowest[r] = lowest[r].min(v);
    }
    let into: Vec<usize> = (0..n).map(|v| lowest[groups.find(v)]).collect();
    let crease: HashMap<(usize, usize), Assignment> = creases
        .into_iter()
        .map(|([a, b], assignment)| (edge_key(into[a], into[b]), assignment))
        .collect();
    let mut number = vec![usize::MAX; n];
    let mut kept = Vec::new();
    for v in 0..n {
        if into[v] == v {
            number[v] = kept.len();
            kept.push(positions[v]);
        }
    }
    let renumber = |v: usize| number[into[v]];
    let faces: Vec<[usize; 3]> = faces
        .iter()
        .map(|f| [renumber(f[0]), renumber(f[1]), renumber(f[2])])
        .collect();
    let mut seen = std::collections::HashSet::new();
    let mut joined = Vec::with_capacity(edges.len());
    let mut seam = Vec::new();
    for mut e in edges {
        let [a, b] = e.vertices;
        let after = edge_key(renumber(a), renumber(b));
        if !seen.insert(after) {
            continue;
        }
        if let Some(&assignment) = crease.get(&edge_key(into[a], into[b])) {
            e.assignment = assignment;
            e.target = assignment.default_target();
            e.fold_angle = e.target;
            seam.push([after.0, after.1]);
        }
        e.vertices = [renumber(a), renumber(b)];
        joined.push(e);
    }
    Ok((
        MeshParts {
            positions: Some(kept),
            flat: None,
            faces,
            edges: joined,
        },
        seam,
    ))
}

/// The seam's vertex pairs joined (each pair checked to name vertices that lie together
/// in the 3D frame) and each seam crease's first copy with its assignment.
fn join_pairs(
    positions: &[crate::mesh::Vec3],
    entries: &[SeamEntry],
) -> Result<(crate::mesh::UnionFind, Vec<SeamCrease>), String> {
    let n = positions.len();
    let (lo, hi) = crate::mesh::bounds(positions);
    // The two copies of a seam vertex close up as a walk round the strip would.
    let tolerance = crate::tolerance::WALK_RELATIVE * (hi - lo).norm().max(1.0);
    let mut groups = crate::mesh::UnionFind::new(n);
    let mut creases: Vec<SeamCrease> = Vec::with_capacity(entries.len());
    for (k, (first, second, letter)) in entries.iter().enumerate() {
        for &v in first.iter().chain(second) {
            if v >= n {
                return Err(format!(
                    "crease:seam[{k}] refers to vertex {v}, but there are only {n} vertices"
                ));
            }
        }
        let assignment = Assignment::from_fold(letter)
            .filter(|a| !a.is_boundary())
            .ok_or_else(|| {
                format!(
                    "crease:seam[{k}] has assignment \"{}\"; a seam crease is M, V, F, U or J",
                    crate::limits::short_text(letter)
                )
            })?;
        for (&p, &q) in first.iter().zip(second) {
            let gap = (positions[p] - positions[q]).norm();
            if p == q || gap > tolerance {
                return Err(format!(
                    "crease:seam[{k}] joins vertices {p} and {q}, which lie {gap:.3} mm apart in the 3D frame"
                ));
            }
            groups.union(p, q);
        }
        creases.push((*first, assignment));
    }
    Ok((groups, creases))
}
