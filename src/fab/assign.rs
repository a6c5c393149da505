//! Unassigned creases given sides: a crease pattern that says only where the paper
//! folds (U creases, as Flat-Folder's "unassigned" patterns) claims that some
//! mountain/valley folds it flat. The layer search, run with those creases' sides free,
//! finds one ([`super::layers::assign_unassigned`]), or the faces no assignment orders.

use super::budget::Budget;
use super::layers::{LayerConflict, LayerError};
use super::precision::as_drawn;
use crate::mesh::{Assignment, Mesh};
use std::f64::consts::PI;

/// What the search for the sides of a pattern's unassigned creases found.
#[derive(Debug)]
pub enum SideSearch {
    /// The pattern with each unassigned interior crease a mountain or a valley, as a
    /// layer order found with them free has them (targets ±π, drawn flat).
    Found {
        /// The assigned pattern (boxed: a mesh is far larger than the other answers).
        mesh: Box<Mesh>,
        /// How many became mountains.
        mountains: usize,
        /// How many became valleys.
        valleys: usize,
    },
    /// No assignment gives a layer order: these faces admit none.
    NoOrder {
        /// The faces.
        conflict: LayerConflict,
        /// How many creases were unassigned.
        open: usize,
    },
    /// The search stopped (its budget, or a flat-folded state it could not build).
    Stopped(LayerError),
}

/// The sides of a crease pattern whose creases are all unassigned, searched within
/// `budget` at the drawing's precision; `None` for any other design (a 3D design, or a
/// pattern with mountains or valleys, whose U creases stay flat).
pub fn assign_sides(mesh: &Mesh, budget: &Budget) -> Option<SideSearch> {
    let open = unassigned_interior(mesh)?;
    let (_, measured) = as_drawn(mesh);
    let free = with_open_sides(measured.as_ref(), &open);
    let sides = match super::layers::assign_unassigned(&free, budget) {
        Ok(Ok(sides)) => sides,
        Ok(Err(conflict)) => {
            return Some(SideSearch::NoOrder {
                conflict,
                open: open.len(),
            })
        }
        Err(e) => return Some(SideSearch::Stopped(e)),
    };
    let mut assigned = mesh.clone();
    for &(e, side) in &sides {
        let edge = &mut assigned.edges_mut()[e];
        edge.assignment = side;
        edge.target = side.default_target();
        edge.fold_angle = edge.target;
    }
    let mountains = sides
        .iter()
        .filter(|(_, a)| *a == Assignment::Mountain)
        .count();
    Some(SideSearch::Found {
        mesh: Box::new(assigned),
        mountains,
        valleys: sides.len() - mountains,
    })
}

/// `mesh` with its unassigned creases `open` aimed at a full fold, their side left to
/// the layer search.
pub(super) fn with_open_sides(mesh: &Mesh, open: &[usize]) -> Mesh {
    let mut free = mesh.clone();
    for &e in open {
        let edge = &mut free.edges_mut()[e];
        (edge.target, edge.fold_angle) = (PI, PI);
    }
    free
}

/// The interior edges of a crease pattern whose creases are all unassigned, when it has
/// any (`None` for a 3D design or a pattern with mountains or valleys).
pub(super) fn unassigned_interior(mesh: &Mesh) -> Option<Vec<usize>> {
    if mesh.has_3d() || mesh.edges().iter().any(|e| e.assignment.is_folded()) {
        return None;
    }
    let topo = mesh.topology();
    let open: Vec<usize> = (0..mesh.edges().len())
        .filter(|&e| {
            mesh.edges()[e].assignment == Assignment::Unassigned
                && topo.edge_faces[e].iter().all(Option::is_some)
        })
        .collect();
    (!open.is_empty()).then_some(open)
}
