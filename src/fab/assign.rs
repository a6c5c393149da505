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

/// The sides of a crease pattern's unassigned interior creases, searched within `budget`
/// at the drawing's precision, its mountains and valleys kept. `None` for a design with
/// none, a 3D design, or a pattern with a partial fold (whose U lines are free).
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

/// The interior unassigned creases of a crease pattern meant to fold flat, when it has
/// any: a flat pattern (no 3D form) whose mountains and valleys, if it has any, all aim
/// at a full fold and are drawn at one (an Origami Simulator SVG's opacity draws a
/// partial fold). There a `U` crease is what FOLD calls it, a crease whose side is
/// unknown (a line that stays unfolded is `F`), as Flat-Folder and "Box Pleating is
/// Hard"'s unassigned patterns read it. `None` for a 3D design, or a pattern with a
/// partial fold, whose `U` lines are free (the rulings of a curved fold, Resch's tucks).
pub(super) fn unassigned_interior(mesh: &Mesh) -> Option<Vec<usize>> {
    let full = |angle| crate::constraints::folds_flat(angle) == Some(true);
    let partial =
        |e: &crate::mesh::Edge| e.assignment.is_folded() && !(full(e.target) && full(e.fold_angle));
    if mesh.has_3d() || mesh.edges().iter().any(partial) {
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
