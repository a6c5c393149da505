//! Length conditions: straight pieces of the perimeter (eq. 3) and every edge (simulation
//! mode, §5). Residuals are relative so one tolerance fits any paper size.

use super::{Element, Family, Reference, Rows};
use crate::mesh::{Mesh, Vec3};

/// Eq. (3): Σℓ − Σℓ⁰ over each straight piece of the perimeter, divided by Σℓ⁰.
pub fn boundary_length(mesh: &Mesh, reference: &Reference, x: &[Vec3], rows: &mut Rows) {
    for piece in &reference.boundary_lines {
        let total0: f64 = piece.iter().map(|&e| reference.length[e]).sum();
        let total: f64 = piece
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edges()[e].vertices;
                (x[b] - x[a]).norm()
            })
            .sum();
        let row = rows.push(
            Family::BoundaryLength,
            Element::Edge(piece[0]),
            (total - total0) / total0,
        );
        for &e in piece {
            let [a, b] = mesh.edges()[e].vertices;
            let u = (x[b] - x[a]).normalize();
            rows.add_gradient(row, b, u, 1.0 / total0);
            rows.add_gradient(row, a, u, -1.0 / total0);
        }
    }
}

/// Every edge keeps its reference length: (ℓ − ℓ⁰)/ℓ⁰.
pub fn edge_length(mesh: &Mesh, reference: &Reference, x: &[Vec3], rows: &mut Rows) {
    for (e, edge) in mesh.edges().iter().enumerate() {
        let [a, b] = edge.vertices;
        let l0 = reference.length[e];
        let d = x[b] - x[a];
        let row = rows.push(Family::EdgeLength, Element::Edge(e), (d.norm() - l0) / l0);
        let u = d.normalize();
        rows.add_gradient(row, b, u, 1.0 / l0);
        rows.add_gradient(row, a, u, -1.0 / l0);
    }
}

/// §6.4: each vertex of a coincidence group stays on the group's first vertex,
/// (x_v − x_first) / ℓ̄ per axis, ℓ̄ the mean crease length of the reference.
pub fn coincidence(mesh: &Mesh, reference: &Reference, x: &[Vec3], rows: &mut Rows) {
    let scale = reference.mean_length;
    for group in &mesh.coincident {
        let first = group[0];
        for &v in &group[1..] {
            let d = (x[v] - x[first]) / scale;
            for axis in 0..3 {
                let row = rows.push(Family::Coincidence, Element::Vertex(v), d[axis]);
                let mut unit = Vec3::zeros();
                unit[axis] = 1.0 / scale;
                rows.add_gradient(row, v, unit, 1.0);
                rows.add_gradient(row, first, unit, -1.0);
            }
        }
    }
}
