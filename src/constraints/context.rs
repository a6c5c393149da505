//! What the conditions compare against: the flat state's angles and lengths (or the loaded
//! 3D state's, when no crease pattern is known), the facet orientations σ of eq. (5), and
//! the fold angles that pick each crease's branch (§2).

use crate::geometry::{fold_angle, sector_angle};
use crate::mesh::{Mesh, Vec3};
use crate::tolerance::{SAME_ANGLE_RADIANS, VERIFIED_RESIDUAL};
use std::f64::consts::PI;

/// Whether a target angle folds the paper over (an odd multiple of π), flipping σ.
pub fn flips(target: f64) -> bool {
    folds_flat(target) == Some(true)
}

/// Whether an edge is folded completely (target ±π) in the flat-folded state: `None` for
/// a partial fold. Merged creases (§4) may target other odd multiples of π, which fold
/// flat as well.
pub fn folds_flat(target: f64) -> Option<bool> {
    let nearest = (target / PI).round();
    if (target - nearest * PI).abs() > SAME_ANGLE_RADIANS {
        return None;
    }
    Some(nearest as i64 % 2 != 0)
}

/// Whether each edge is mirrored across when the pattern is folded flat (a fold of an odd
/// multiple of π that is not the paper's boundary), or the first edge that aims at a
/// partial fold, where the flat-folded state is not what the pattern describes. The
/// layer-order rows and the x-ray (`crate::fab::flat_folded`) both walk by it.
pub fn mirrored_edges(mesh: &Mesh) -> Result<Vec<bool>, usize> {
    mesh.edges()
        .iter()
        .enumerate()
        .map(|(i, e)| {
            folds_flat(e.target)
                .map(|odd| odd && !e.assignment.is_boundary())
                .ok_or(i)
        })
        .collect()
}

/// Reference data for one mesh, computed once.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Sector-angle sum of every vertex in the reference state.
    pub angle_sum: Vec<f64>,
    /// Length of every edge in the reference state.
    pub length: Vec<f64>,
    /// Straight pieces of the perimeter, as edge lists (eq. 3).
    pub boundary_lines: Vec<Vec<usize>>,
    /// σ of each fan face (eq. 5) at interior vertices whose folded creases are even in
    /// number and at least two; `None` elsewhere.
    pub sigma: Vec<Option<Vec<f64>>>,
    /// Fold angles at the last accepted state, for branch tracking.
    pub previous_fold: Vec<f64>,
    /// An interior vertex with an odd number of folded creases, if any.
    pub odd_vertex: Option<usize>,
    /// Mean crease-pattern edge length: the scale of relative position residuals.
    pub mean_length: f64,
    /// The mesh has coincidence groups (§6.4) and they are closed at its positions, so
    /// the default conditions keep them closed.
    pub closed_groups: bool,
    /// The creases joined into chains (curved creases drawn as chords), for the
    /// smoothness family.
    pub chains: Vec<super::chains::CreaseChain>,
    /// Some chain turns in the crease pattern: a curved-crease pattern, which gets the
    /// smoothness family by default.
    pub curved_creases: bool,
    /// The contacts of the flat-folded state the layer-order rows hold
    /// ([`Reference::hold_contacts`]); empty unless asked for.
    pub contacts: Vec<super::Contact>,
}

impl Reference {
    /// Reference of a mesh: the crease pattern when known, else its current 3D form.
    pub fn new(mesh: &Mesh) -> Reference {
        let reference: Vec<Vec3> = match mesh.crease_pattern() {
            Some(f) => f.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect(),
            None => mesh.positions().to_vec(),
        };
        let n = mesh.vertex_count();
        let mut angle_sum = vec![0.0; n];
        for f in mesh.faces() {
            for k in 0..3 {
                angle_sum[f[k]] += sector_angle(&reference, *f, k);
            }
        }
        let length: Vec<f64> = mesh
            .edges()
            .iter()
            .map(|e| (reference[e.vertices[1]] - reference[e.vertices[0]]).norm())
            .collect();
        let (sigma, odd_vertex) = facet_orientations(mesh);
        let previous_fold = initial_folds(mesh);
        let boundary_lines = straight_pieces(mesh, &angle_sum);
        let mean_length = length.iter().sum::<f64>() / length.len().max(1) as f64;
        let x = mesh.positions();
        let closed_groups = !mesh.coincident.is_empty()
            && mesh.coincident.iter().all(|g| {
                g.iter()
                    .all(|&v| (x[v] - x[g[0]]).norm() <= 1e-9 * mean_length)
            });
        let chains = super::chains::crease_chains(mesh);
        let curved_creases = super::chains::has_curved_crease(mesh, &chains, &reference);
        Reference {
            mean_length,
            closed_groups,
            chains,
            curved_creases,
            angle_sum,
            length,
            boundary_lines,
            sigma,
            previous_fold,
            odd_vertex,
            contacts: Vec::new(),
        }
    }

    /// The reference of `mesh` for solving under `set`: [`Reference::new`], with the
    /// layer-order contacts held when `set` has that family (a solver's start and each
    /// remesh both take it so).
    pub fn for_conditions(mesh: &Mesh, set: &super::ConstraintSet) -> Reference {
        let mut reference = Reference::new(mesh);
        if set.families.contains(&super::Family::LayerOrder) {
            reference.hold_contacts(mesh);
        }
        reference
    }

    /// Finds the contacts of the flat-folded state of `mesh` as it stands, for the
    /// layer-order rows to hold: images within [`crate::tolerance::closure_mm`] of each
    /// other count as touching. The image is built from the 3D triangles, so this is the
    /// current design's own crease pattern folded flat even where the stored one is
    /// stale (the studio keeps the pattern it opened while the form is dragged).
    pub fn hold_contacts(&mut self, mesh: &Mesh) {
        let at = mesh.positions();
        let (lo, hi) = crate::mesh::bounds(at);
        let tolerance = crate::tolerance::closure_mm((hi - lo).norm(), mesh.coordinate_precision);
        self.contacts = super::flat_contacts(mesh, at, tolerance);
    }

    /// Whether the assignment can fold flat at all: every interior vertex has an even
    /// number of folded creases.
    pub fn is_flat_foldable(&self) -> bool {
        self.odd_vertex.is_none() && self.sigma.iter().any(Option::is_some)
    }
}

/// σ of eq. (5) for each interior vertex with an even number (at least two) of folded
/// creases, and the first interior vertex with an odd number, if any.
fn facet_orientations(mesh: &Mesh) -> (Vec<Option<Vec<f64>>>, Option<usize>) {
    let topo = mesh.topology();
    let mut sigma = vec![None; mesh.vertex_count()];
    let mut odd_vertex = None;
    for (v, fan) in topo.fans.iter().enumerate() {
        if fan.boundary {
            continue;
        }
        let folded = fan
            .spokes
            .iter()
            .filter(|&&e| flips(mesh.edges()[e].target))
            .count();
        if folded % 2 == 1 {
            odd_vertex.get_or_insert(v);
            continue;
        }
        if folded < 2 {
            continue;
        }
        // Face i lies after spoke i; σ flips across each folded spoke.
        let mut s = 1.0;
        let signs = fan
            .spokes
            .iter()
            .map(|&e| {
                if flips(mesh.edges()[e].target) {
                    s = -s;
                }
                s
            })
            .collect();
        sigma[v] = Some(signs);
    }
    (sigma, odd_vertex)
}

/// The fold angle of every edge at the mesh's own positions: the first branch reference.
fn initial_folds(mesh: &Mesh) -> Vec<f64> {
    let topo = mesh.topology();
    mesh.edges()
        .iter()
        .enumerate()
        .map(|(e, edge)| {
            let raw = fold_angle(mesh.positions(), mesh.faces(), topo, e, edge.vertices);
            // A flat-folded source (|ρ| near π) takes the sign its target asks for.
            if (raw.abs() - PI).abs() < VERIFIED_RESIDUAL && edge.target != 0.0 {
                edge.target.signum() * raw.abs()
            } else {
                raw
            }
        })
        .collect()
}

/// Splits each boundary loop at its corners (reference angle sum ≠ π).
fn straight_pieces(mesh: &Mesh, angle_sum: &[f64]) -> Vec<Vec<usize>> {
    let topo = mesh.topology();
    let mut pieces = Vec::new();
    for lp in &topo.boundary_loops {
        let m = lp.len();
        let corner = |v: usize| (angle_sum[v] - PI).abs() > SAME_ANGLE_RADIANS;
        let start = (0..m).find(|&i| corner(lp[i])).unwrap_or(0);
        let mut current = Vec::new();
        for step in 0..m {
            let (a, b) = (lp[(start + step) % m], lp[(start + step + 1) % m]);
            if let Some(e) = topo.edge_between(a, b) {
                current.push(e);
            }
            if corner(b) || step + 1 == m {
                pieces.push(std::mem::take(&mut current));
            }
        }
    }
    pieces.retain(|p| !p.is_empty());
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_odd_multiples_of_pi_fold_flat() {
        assert_eq!(folds_flat(PI), Some(true));
        assert_eq!(folds_flat(-PI), Some(true));
        assert_eq!(folds_flat(3.0 * PI), Some(true));
        assert_eq!(folds_flat(0.0), Some(false));
        assert_eq!(folds_flat(2.0 * PI), Some(false));
        assert_eq!(folds_flat(PI / 2.0), None);
    }
}
