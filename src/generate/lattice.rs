//! Building blocks shared by the generators: strips of triangles between rows of points,
//! edge lists from faces.

use crate::mesh::{edge_key, Assignment, Edge, MeshParts, Vec2};
use std::collections::HashMap;

/// Triangulates the strips between consecutive rows of points (row `j` at height
/// `j · row_height`, x positions sorted).
/// Returns the points, row after row, and counter-clockwise triangles.
pub fn rows_zipper(rows: &[Vec<f64>], row_height: f64) -> (Vec<Vec2>, Vec<[usize; 3]>) {
    let mut points = Vec::new();
    let mut start = Vec::with_capacity(rows.len());
    for (j, row) in rows.iter().enumerate() {
        start.push(points.len());
        points.extend(row.iter().map(|&x| Vec2::new(x, j as f64 * row_height)));
    }
    let mut faces = Vec::new();
    for j in 0..rows.len() - 1 {
        let (lo, up) = (&rows[j], &rows[j + 1]);
        let (lo0, up0) = (start[j], start[j + 1]);
        let (mut i, mut k) = (0, 0);
        while i + 1 < lo.len() || k + 1 < up.len() {
            // Advance the row whose step adds the shorter diagonal (the Delaunay choice
            // between two rows); at a row's end only the other can advance.
            let advance_lower = k + 1 == up.len()
                || (i + 1 < lo.len() && (lo[i + 1] - up[k]).abs() <= (up[k + 1] - lo[i]).abs());
            if advance_lower {
                faces.push([lo0 + i, lo0 + i + 1, up0 + k]);
                i += 1;
            } else {
                faces.push([lo0 + i, up0 + k + 1, up0 + k]);
                k += 1;
            }
        }
    }
    (points, faces)
}

/// Edges of the faces in first-seen order: boundary edges (one face) are `B`, the others
/// as `classify` says from their end points; flat creases get twist allowance `alpha`.
pub fn build(
    flat: Vec<Vec2>,
    faces: Vec<[usize; 3]>,
    classify: impl Fn(Vec2, Vec2) -> Assignment,
    alpha: f64,
) -> MeshParts {
    let edges = face_edges(&faces, |a, b| classify(flat[a], flat[b]), alpha);
    MeshParts {
        positions: None,
        flat: Some(flat),
        faces,
        edges,
    }
}

/// Edges of `faces` in first-seen order: boundary edges (one face) are `B`, the others as
/// `classify` says from their end vertices; flat creases get twist allowance `alpha`.
pub fn face_edges(
    faces: &[[usize; 3]],
    classify: impl Fn(usize, usize) -> Assignment,
    alpha: f64,
) -> Vec<Edge> {
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    let mut order = Vec::new();
    for f in faces {
        for k in 0..3 {
            let key = edge_key(f[k], f[(k + 1) % 3]);
            let c = count.entry(key).or_insert(0);
            if *c == 0 {
                order.push(key);
            }
            *c += 1;
        }
    }
    order
        .into_iter()
        .map(|(a, b)| {
            let assignment = if count[&(a, b)] == 1 {
                Assignment::Boundary
            } else {
                classify(a, b)
            };
            let mut e = Edge::new(a, b, assignment);
            if assignment == Assignment::Flat {
                e.alpha = alpha;
            }
            e
        })
        .collect()
}
