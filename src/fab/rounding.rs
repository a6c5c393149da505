//! How far rounding a file's coordinates can move each residual verify computes: the
//! per-element allowance added to its tolerances.

use crate::constraints::{Element, Family};
use crate::mesh::Mesh;

/// What rounding every coordinate of a file to ±`precision` (mm) can do to each residual:
/// a point moves up to √3·p, so the direction of an edge of length ℓ turns by up to
/// δ = 2√3·p/ℓ (both ends move) and its relative length changes by up to δ. A sector
/// angle between two creases changes by at most the sum of their δ, so a vertex sum over
/// its sectors (developability, eq. 1; Kawasaki, eq. 5) changes by at most 2·Σ δ over
/// the vertex's edges — a bound per vertex, not one worst case for the whole file. A fold
/// angle turns with the normals of its two faces, by at most the δ of their edges.
pub struct RoundingBounds {
    pub(super) precision: f64,
    edge: Vec<f64>,
    vertex: Vec<f64>,
}

impl RoundingBounds {
    /// The bounds of `mesh`'s file rounding; `None` for a full-precision file.
    pub fn new(mesh: &Mesh) -> Option<RoundingBounds> {
        let p = mesh.coordinate_precision;
        if p <= 0.0 {
            return None;
        }
        let x = mesh.positions();
        let flat = mesh.crease_pattern();
        let edge: Vec<f64> = mesh
            .edges()
            .iter()
            .map(|e| {
                let [a, b] = e.vertices;
                let mut l = (x[b] - x[a]).norm();
                if let Some(f) = flat {
                    l = l.min((f[b] - f[a]).norm());
                }
                2.0 * 3f64.sqrt() * p / l
            })
            .collect();
        let vertex = mesh
            .topology()
            .fans
            .iter()
            .map(|fan| 2.0 * fan.spokes.iter().map(|&e| edge[e]).sum::<f64>())
            .collect();
        Some(RoundingBounds {
            precision: p,
            edge,
            vertex,
        })
    }

    /// The allowance for one residual row of `family` about `element`.
    pub fn allowance(&self, mesh: &Mesh, family: Family, element: Element) -> f64 {
        match (family, element) {
            (Family::Coincidence, _) => 2.0 * 3f64.sqrt() * self.precision,
            (_, Element::Vertex(v) | Element::Sector(v, _, _, _)) => self.vertex[v],
            (_, Element::Faces(..)) => 0.0,
            (f, Element::Edge(e)) if f.is_length() => 2.0 * self.edge[e],
            (_, Element::Edge(e)) => {
                let topo = mesh.topology();
                topo.edge_faces[e]
                    .iter()
                    .flatten()
                    .flat_map(|&f| topo.face_edges[f])
                    .map(|k| self.edge[k])
                    .sum()
            }
        }
    }
}
