//! What `fold` may write: a fold that reached almost none of what was asked, or a sheet
//! rolled far enough to pass through itself, is refused (`fold_refusal`); and the
//! flat-folded state as a file of its own, layers and all (`flat_folded_file`).

use super::{ConvertError, DesignOutcome};
use crate::fab::budget::Budget;
use crate::fab::{flat_folded, layer_order_within, LayerConflict, LayerError, LayerOrder};
use crate::mesh::{Mesh, Vec3};

/// A fold that reached less than this share of the amount asked got nowhere: a pattern
/// without folded creases, or one held flat by its fixed vertices.
pub const GOT_NOWHERE: f64 = 0.01;

/// Why a fold's result is not written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FoldRefusal {
    /// It reached almost none of the fold asked for.
    #[error("the fold got nowhere: {:.1}% of the target angles where {:.0}% was asked", 100.0 * reached, 100.0 * asked)]
    GotNowhere {
        /// The creases' mean fraction of their targets reached.
        reached: f64,
        /// The fraction asked for.
        asked: f64,
    },
    /// Faces far apart on the sheet cross in the folded state: rigid panels keep
    /// neighbours from swinging through each other (§2.4), not a sheet rolled far enough
    /// to close through itself elsewhere, and that state cannot be folded.
    #[error("at this amount the sheet passes through itself: {pairs} pairs of faces cross (faces {} and {} first)", first.0, first.1)]
    PassesThrough {
        /// Pairs of faces that cross.
        pairs: usize,
        /// The first pair.
        first: (usize, usize),
    },
}

/// Whether the result of folding by `amount` may be written: `None`, or why not. A fold
/// that got nowhere is refused before its crossings are looked for.
pub fn fold_refusal(outcome: &DesignOutcome, amount: f64) -> Option<FoldRefusal> {
    if let Some(f) = outcome
        .fold
        .as_ref()
        .filter(|f| amount > 0.0 && f.mean_fraction < GOT_NOWHERE * amount)
    {
        return Some(FoldRefusal::GotNowhere {
            reached: f.mean_fraction,
            asked: amount,
        });
    }
    let crossings = crate::fab::self_intersections(&outcome.mesh);
    crossings.first().map(|c| FoldRefusal::PassesThrough {
        pairs: crossings.len(),
        first: c.faces,
    })
}

/// A crease pattern's flat-folded state, ready to write.
#[derive(Debug)]
pub struct FlatFoldedFile {
    /// The pattern with its positions the flat-folded state (z = 0), each crease that
    /// reaches ±π at it and every other line flat.
    pub mesh: Mesh,
    /// Which face lies above which, per overlapping pair (FOLD's `faceOrders`).
    pub orders: Vec<[i64; 3]>,
    /// What was done to the pattern first (the sides given to unassigned creases).
    pub note: Option<String>,
}

/// Why a crease pattern's flat-folded state could not be written.
#[derive(Debug, thiserror::Error)]
pub enum FlatFoldError {
    /// Its unassigned creases could not be given sides.
    #[error("{0}")]
    Sides(#[from] ConvertError),
    /// It does not fold flat at its vertices (or has no crease pattern).
    #[error("{0}")]
    NotFlat(String),
    /// Its layers have no order.
    #[error("it has no layer order: {0}")]
    NoOrder(LayerConflict),
    /// The layer search stopped.
    #[error("{0}")]
    Search(#[from] LayerError),
}

impl FlatFoldError {
    /// The exit code: 1 when the pattern does not fold flat, 3 when the search stopped
    /// undecided, 2 for input that is not a pattern to fold.
    pub fn exit_code(&self) -> u8 {
        match self {
            FlatFoldError::Sides(e) => e.exit_code(),
            FlatFoldError::NoOrder(_) => 1,
            FlatFoldError::Search(e) => e.exit_code(),
            FlatFoldError::NotFlat(_) => 2,
        }
    }
}

/// The flat-folded state of `mesh` as a FOLD folded form beside its crease pattern: a
/// pattern with unassigned creases gets the sides a layer order gives them first (within
/// `budget`), then the state is folded flat and its layers ordered.
pub fn flat_folded_file(mut mesh: Mesh, budget: &Budget) -> Result<FlatFoldedFile, FlatFoldError> {
    let (assigned, note) = super::with_sides_found(mesh, budget)?;
    mesh = assigned;
    let folded = flat_folded(&mesh, None).map_err(|e| FlatFoldError::NotFlat(e.to_string()))?;
    let orders = match layer_order_within(&mesh, budget)? {
        LayerOrder::Found(orders) => orders,
        LayerOrder::Conflict(c) => return Err(FlatFoldError::NoOrder(c)),
    };
    if mesh.crease_pattern().is_none() {
        return Err(FlatFoldError::NotFlat("no crease pattern".into()));
    }
    let positions = folded
        .vertex_images(mesh.faces(), mesh.vertex_count())
        .into_iter()
        .map(|p| Vec3::new(p.x, p.y, 0.0))
        .collect();
    mesh.set_positions(positions);
    // Folded flat, each crease that reaches ±π is at it and every other line is flat:
    // the file's angles describe the state it draws, not the design it came from.
    for edge in mesh.edges_mut() {
        let folded = crate::fab::layers::folds_completely(edge);
        edge.fold_angle = if folded { edge.target } else { 0.0 };
    }
    mesh.source = None;
    Ok(FlatFoldedFile { mesh, orders, note })
}
