//! Kirigami: cutting the paper along cut lines so each side of a cut has its own vertices.

use super::{edge_key as key, Assignment, Edge, MeshParts};
use std::collections::{HashMap, HashSet};

/// Separates the faces on the two sides of every cut (and of every boundary line drawn
/// inside the paper): vertices along a cut are duplicated, one copy per side, and each
/// side of the cut becomes a boundary edge. The tip of a slit, where the paper stays
/// connected around the vertex, keeps a single vertex. Returns the number of vertices added.
pub fn split_along_cuts(parts: &mut MeshParts) -> usize {
    let n0 = vertex_count(parts);
    split_along(parts).len() - n0
}

/// [`split_along_cuts`], returning for every vertex after the split the vertex it is a
/// copy of (itself for the originals).
pub(super) fn split_along(parts: &mut MeshParts) -> Vec<usize> {
    let n0 = vertex_count(parts);
    let is_cut = cut_edges(parts);
    if is_cut.is_empty() {
        return (0..n0).collect();
    }
    let on_cut: HashSet<usize> = is_cut.iter().flat_map(|&(a, b)| [a, b]).collect();
    let mut incident: HashMap<usize, Vec<usize>> = HashMap::new();
    for (fi, f) in parts.faces.iter().enumerate() {
        for &v in f {
            if on_cut.contains(&v) {
                incident.entry(v).or_default().push(fi);
            }
        }
    }
    // The vertex each vertex was copied from (itself for the originals).
    let mut origin: Vec<usize> = (0..n0).collect();
    let mut vertices: Vec<usize> = incident.keys().copied().collect();
    vertices.sort_unstable();
    for v in vertices {
        split_vertex(parts, v, &incident[&v], &is_cut, &mut origin);
    }
    parts.edges = edges_after_split(parts, &origin);
    origin
}

fn vertex_count(parts: &MeshParts) -> usize {
    parts
        .flat
        .as_ref()
        .map(|f| f.len())
        .or(parts.positions.as_ref().map(|p| p.len()))
        .unwrap_or(0)
}

/// Boundary and cut lines with a face on each side: the paper is cut along them.
fn cut_edges(parts: &MeshParts) -> HashSet<(usize, usize)> {
    let mut face_count: HashMap<(usize, usize), usize> = HashMap::new();
    for f in &parts.faces {
        for k in 0..3 {
            *face_count.entry(key(f[k], f[(k + 1) % 3])).or_default() += 1;
        }
    }
    parts
        .edges
        .iter()
        .filter(|e| e.assignment.is_boundary() && face_count.get(&e.key()) == Some(&2))
        .map(|e| e.key())
        .collect()
}

/// Gives each group of `faces` around `v` that stays joined across uncut spokes its own
/// copy of `v` (the first group keeps `v`), recording each copy's origin.
fn split_vertex(
    parts: &mut MeshParts,
    v: usize,
    faces: &[usize],
    is_cut: &HashSet<(usize, usize)>,
    origin: &mut Vec<usize>,
) {
    // Union faces that share a spoke v–x which is not cut.
    let mut group = super::UnionFind::new(faces.len());
    for i in 0..faces.len() {
        for j in i + 1..faces.len() {
            let (fi, fj) = (parts.faces[faces[i]], parts.faces[faces[j]]);
            let shared = fi.iter().find(|&&x| x != v && fj.contains(&x));
            if let Some(&x) = shared {
                if !is_cut.contains(&key(v, x)) {
                    group.union(i, j);
                }
            }
        }
    }
    let mut copy_of_root: HashMap<usize, usize> = HashMap::new();
    let first_root = group.find(0);
    for (i, &face) in faces.iter().enumerate() {
        let r = group.find(i);
        if r == first_root {
            continue;
        }
        let nv = *copy_of_root.entry(r).or_insert_with(|| {
            if let Some(p) = parts.positions.as_mut() {
                p.push(p[v]);
            }
            if let Some(p) = parts.flat.as_mut() {
                p.push(p[v]);
            }
            origin.push(v);
            origin.len() - 1
        });
        for c in parts.faces[face].iter_mut() {
            if *c == v {
                *c = nv;
            }
        }
    }
}

/// The edges of the split faces, each carrying the attributes of the edge between its
/// ends' origins; a cut becomes two boundary edges.
fn edges_after_split(parts: &MeshParts, origin: &[usize]) -> Vec<Edge> {
    let by_key: HashMap<(usize, usize), &Edge> = parts.edges.iter().map(|e| (e.key(), e)).collect();
    let mut seen = HashSet::new();
    let mut edges = Vec::with_capacity(parts.edges.len());
    for f in &parts.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            if !seen.insert(key(a, b)) {
                continue;
            }
            if let Some(e) = by_key.get(&key(origin[a], origin[b])) {
                let mut e = (*e).clone();
                e.vertices = [a, b];
                if e.assignment == Assignment::Cut {
                    e.assignment = Assignment::Boundary;
                }
                edges.push(e);
            }
        }
    }
    edges
}
